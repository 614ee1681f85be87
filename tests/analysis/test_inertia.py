"""Layer stability with shear inertia (N2 > 0), which the thesis leaves out (docs/theory/analyses.md).

The cubic of stability.inertial_growth_rate is checked against the 4x4 Fourier system
of the linearised equations written out directly (its determinant must vanish at each
root), against eq. 6.48 in the quasi-static limit, and against its short-wave limit
and Routh-Hurwitz threshold.
"""

import numpy as np
import pytest

from shockfriction.analysis.stability import (
    SQRT3, ScgConstants, growth_rate, inertial_critical_wavenumber, inertial_growth_limit,
    inertial_growth_rate, max_stable_strain, scg_moduli,
)
from shockfriction.materials import get_material

AL, ST = get_material("Al5083-H111"), get_material("AISI321")


def fourier_matrix(c, eps0, theta, P, k, s, rho, rate):
    """Rows: momentum, kinematics, yield (6.28), heat (6.29); unknowns (dv, deps, dtheta, dtau)."""
    m = scg_moduli(c, eps0, theta, P)
    tau0 = float(m.Y) / SQRT3
    return np.array([
        [rho * s, 0.0, 0.0, -1j * k],
        [1j * k, -SQRT3 * s, 0.0, 0.0],
        [0.0, float(m.Y_eps), float(m.Y_theta), -SQRT3],
        [0.0, -SQRT3 * tau0 * s, c.rho_c * s + c.kappa * k * k, -SQRT3 * rate],
    ], dtype=complex)


@pytest.mark.parametrize("material, theta, P", [(AL, 600.0, 0.0), (ST, 1500.0, 40e9)])
@pytest.mark.parametrize("k", [1e4, 1e6, 1e8])
@pytest.mark.parametrize("rate", [0.0, 1e6])
def test_root_annuls_the_fourier_system(material, theta, P, k, rate):
    c = ScgConstants.of(material)
    eps = 0.5 * float(max_stable_strain(c, theta, P))
    s = inertial_growth_rate(c, eps, theta, P, k, material.rho0, rate)
    M = fourier_matrix(c, eps, theta, P, k, s, material.rho0, rate)
    sv = np.linalg.svd(M / np.abs(M).max(axis=1, keepdims=True), compute_uv=False)
    assert sv[-1] / sv[0] < 1e-9


def test_quasi_static_root_tends_to_6_48():
    c = ScgConstants.of(AL)
    eps, theta, k = 0.5 * float(max_stable_strain(c, 800.0, 0.0)), 800.0, 1e5
    expected = float(growth_rate(c, eps, theta, 0.0, k))
    m = scg_moduli(c, eps, theta, 0.0)
    rho = 1e-9
    coeffs = [3 * rho * c.rho_c, 3 * rho * c.kappa * k * k,
              (c.rho_c * float(m.Y_eps) + float(m.Y * m.Y_theta)) * k * k, c.kappa * float(m.Y_eps) * k**4]
    real_roots = [r.real for r in np.roots(coeffs) if abs(r.imag) < 1e-6 * abs(r)]
    assert min(abs(r - expected) for r in real_roots) < 1e-6 * abs(expected)


def test_short_waves_grow_below_the_quasi_static_limit():
    """Thermoplastic shear waves grow even where eq. 6.56 says 'stable' (margin > 0)."""
    c = ScgConstants.of(AL)
    theta, rho = 600.0, AL.rho0
    eps = 0.5 * float(max_stable_strain(c, theta, 0.0))
    limit = float(inertial_growth_limit(c, eps, theta, 0.0, rho))
    rates = [inertial_growth_rate(c, eps, theta, 0.0, k, rho).real for k in (1e4, 1e6, 1e8, 1e10)]
    print("inertial growth rates", rates, "short-wave limit", limit)
    assert all(r > 0 for r in rates) and rates == sorted(rates)
    assert rates[-1] == pytest.approx(limit, rel=1e-4)
    # with a base plastic rate, waves longer than 2 pi/k_c are stable (Routh-Hurwitz)
    rate = 1e8
    kc = float(inertial_critical_wavenumber(c, eps, theta, 0.0, rate))
    assert inertial_growth_rate(c, eps, theta, 0.0, 0.9 * kc, rho, rate).real < 0
    assert inertial_growth_rate(c, eps, theta, 0.0, 1.1 * kc, rho, rate).real > 0


def test_wave_growth_does_not_vanish_with_inertia():
    """In the adiabatic-wave regime k << c_p/alpha the wave growth tends to
    (alpha k^2/2) (-Y Y_theta/rho c)/(Y_eps + Y Y_theta/rho c), whatever rho: the quasi-static
    limit N2 -> 0 is singular for the rate-independent layer."""
    c = ScgConstants.of(AL)
    theta = 600.0
    eps = 0.5 * float(max_stable_strain(c, theta, 0.0))
    m = scg_moduli(c, eps, theta, 0.0)
    soft = -float(m.Y * m.Y_theta) / c.rho_c
    k = 1e4
    expected = 0.5 * (c.kappa / c.rho_c) * k * k * soft / (float(m.Y_eps) - soft)
    for rho in (AL.rho0, AL.rho0 / 100, AL.rho0 / 1e4):
        assert inertial_growth_rate(c, eps, theta, 0.0, k, rho).real == pytest.approx(expected, rel=1e-3)
