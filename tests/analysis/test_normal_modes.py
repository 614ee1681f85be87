"""The closed-form stability limit (eq. 6.72) against numerically computed growth rates.

The linearised layer (6.26-6.29) is discretised by Chebyshev collocation on a finite
layer and its eigenvalues computed (analysis.normal_modes).  The largest growth rate
of the non-uniform modes must change sign exactly at the analytic limit, and the
discrete growth rates of the first modes cos(j pi z/h) must equal eq. 6.48.
"""

import numpy as np
import pytest

from shockfriction.analysis.normal_modes import chebyshev_nodes_and_matrix, layer_modes
from shockfriction.analysis.stability import (
    SQRT3, ScgConstants, growth_rate, max_stable_strain, scg_moduli, strain_limit_unclipped,
)
from shockfriction.materials import get_material

AL, ST = get_material("Al5083-H111"), get_material("AISI321")
DEPTH = 2e-6


def modes_at(c, eps, theta, P, depth=DEPTH, n=32, plastic_rate=0.0):
    m = scg_moduli(c, eps, theta, P)
    return layer_modes(float(m.Y_eps), float(m.Y_theta), float(m.Y) / SQRT3, c.rho_c, c.kappa, depth, n,
                       plastic_rate)


def largest_growth(c, eps, theta, P, **kw):
    return modes_at(c, eps, theta, P, **kw).nonuniform().max()


def test_chebyshev_derivative_is_spectrally_accurate():
    errors = []
    for n in (8, 16, 24):
        x, D = chebyshev_nodes_and_matrix(n)
        errors.append(np.max(np.abs(D @ np.exp(2 * x) - 2 * np.exp(2 * x))))
    print("Chebyshev derivative errors", errors)
    assert errors[1] < 1e-7 and errors[2] < 1e-11 and errors[0] > errors[1] > errors[2]


PARAMETER_SETS = [
    (AL, None, 900.0, 0.0),
    (AL, None, 1100.0, 40e9),
    (AL, 0.0, 300.0, 0.0),
    (ST, None, 600.0, 10e9),
    (ST, None, 2300.0, 40e9),
]


@pytest.mark.parametrize("material, xi, theta, P", PARAMETER_SETS)
def test_sign_of_largest_growth_rate_changes_at_the_analytic_limit(material, xi, theta, P):
    c = ScgConstants.of(material, xi)
    analytic = float(max_stable_strain(c, theta, P))
    assert 0 < analytic < c.saturation_strain
    # the sign of the numerical largest rate flips within 1e-5 (relative) of the analytic limit.
    # Closer than ~1e-6 the denominator of (6.48) vanishes, the pencil is near-singular and
    # the QZ algorithm returns the physical modes as infinite: the limit itself is ill-posed.
    for gap in (1e-1, 1e-2, 1e-3, 1e-4, 1e-5):
        below = largest_growth(c, analytic * (1 - gap), theta, P)
        above = largest_growth(c, analytic * (1 + gap), theta, P)
        print(f"{material.name} theta={theta} P={P:g} eps_max={analytic:.6f} gap {gap:g}: "
              f"largest growth {below:.3e} / {above:.3e} 1/s")
        assert below < 0 < above


@pytest.mark.parametrize("factor", [0.5, 0.99, 1.01, 2.0])
def test_discrete_growth_rates_equal_the_dispersion_relation(factor):
    """Neumann modes cos(j pi z/h), k = j pi/h: s_j from (6.48) for j = 1..6, to 1e-8."""
    c = ScgConstants.of(AL)
    theta, P = 1000.0, 20e9
    eps = factor * float(max_stable_strain(c, theta, P))
    modes = modes_at(c, eps, theta, P, n=40)
    assert np.max(np.abs(modes.imaginary)) <= 1e-9 * np.max(np.abs(modes.growth_rates))  # no oscillation
    k = np.arange(1, 7) * np.pi / DEPTH
    expected = growth_rate(c, eps, theta, P, k)
    rates = modes.nonuniform()
    for s in expected:
        assert np.min(np.abs(rates - s)) <= 1e-8 * abs(s)
    # the uniform mode (k = 0) is neutral
    uniform = np.setdiff1d(modes.growth_rates, rates)
    assert uniform.size == 1 and abs(uniform[0]) <= 1e-9 * abs(expected[0])


def test_limit_independent_of_resolution_layer_depth_and_base_plastic_rate():
    c = ScgConstants.of(ST)
    theta, P = 2200.0, 40e9
    lim = float(strain_limit_unclipped(c, theta, P))
    for kw in ({"n": 16}, {"n": 48}, {"depth": 20e-6}, {"plastic_rate": 1e6}):
        assert largest_growth(c, lim * (1 - 1e-5), theta, P, **kw) < 0
        assert largest_growth(c, lim * (1 + 1e-5), theta, P, **kw) > 0
    # the base plastic rate enters only through dtau, which vanishes: identical spectra
    a = modes_at(c, 0.5 * lim, theta, P).growth_rates
    b = modes_at(c, 0.5 * lim, theta, P, plastic_rate=1e7).growth_rates
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.max(np.abs(a)))
