"""Chapter-6 stability limit: SCG moduli, eq. 6.56/6.71/6.72 and the reference table.

The moduli are checked against finite differences of the library's SCG
(``materials.strength.yield_stress``, an independent implementation); the limit
against the digest's recomputation of eq. 6.72 (thesis-part2 section 4.8) and the
thesis's own statements (Al: 0.8 < eps < 1.2 away from melting; marginal at saturation).
"""

import math

import numpy as np
import pytest

from shockfriction.analysis.stability import (
    ScgConstants, growth_rate, max_stable_strain, scg_moduli, shear_modulus_and_slope, stability_margin,
    strain_limit_unclipped,
)
from shockfriction.materials import get_material
from shockfriction.materials.strength import shear_modulus, yield_stress

AL, ST = get_material("Al5083-H111"), get_material("AISI321")


@pytest.mark.parametrize("material", [AL, ST])
@pytest.mark.parametrize("eps, theta, P", [(0.01, 300.0, 0.0), (0.3, 700.0, 10e9), (1.5, 1000.0, 40e9),
                                            (0.05, 1150.0, 5e9)])
def test_moduli_match_finite_differences_of_the_library_scg(material, eps, theta, P):
    c = ScgConstants.of(material)
    m = scg_moduli(c, eps, theta, P)
    assert float(m.Y) == pytest.approx(float(yield_stress(material, eps, P, theta)), rel=1e-13)
    de, dt = 1e-6 * (1 + eps), 1e-3
    fd_eps = (yield_stress(material, eps + de, P, theta) - yield_stress(material, eps - de, P, theta)) / (2 * de)
    fd_theta = (yield_stress(material, eps, P, theta + dt) - yield_stress(material, eps, P, theta - dt)) / (2 * dt)
    fd_G = (shear_modulus(material, P, theta + dt) - shear_modulus(material, P, theta - dt)) / (2 * dt)
    assert float(m.Y_eps) == pytest.approx(float(fd_eps), rel=1e-7)
    assert float(m.Y_theta) == pytest.approx(float(fd_theta), rel=1e-7)
    assert float(m.dG_dtheta) == pytest.approx(float(fd_G), rel=1e-7)
    assert m.Y_eps >= 0 and m.Y_theta <= 0                       # digest 8.10


def test_two_forms_of_dG_dtheta_agree_and_xi_zero_gives_minus_G0_h():
    c = ScgConstants.of(AL)
    theta, P = np.linspace(300, 1210, 50), 20e9
    G, dG = shear_modulus_and_slope(c, theta, P)
    melt = np.exp(-c.xi * theta / (c.T_melt - theta))
    first_form = (-c.G0 * c.h * melt
                  - c.G0 * (1 + c.g * P - c.h * (theta - 300)) * c.xi * c.T_melt / (c.T_melt - theta) ** 2 * melt)
    np.testing.assert_allclose(dG, first_form, rtol=1e-13)      # (6.65) first line == second line
    _, dG0 = shear_modulus_and_slope(ScgConstants.of(AL, xi=0.0), theta, P)
    np.testing.assert_allclose(dG0, -c.G0 * c.h, rtol=1e-14)    # footnote (6.66)


def test_positivity_bound_h_theta():
    assert AL.scg_h * (AL.melting_temperature - 300) == pytest.approx(0.567, abs=5e-4)
    assert ST.scg_h * (ST.melting_temperature - 300) == pytest.approx(0.946, abs=5e-4)


def test_xi_zero_limit_is_independent_of_temperature_and_pressure():
    """Digest 8.12: 1.171 (Al) and 1.887 (steel) for xi = 0, any theta and F_N."""
    theta = np.linspace(300, 1200, 10)
    for m, ref in ((AL, 1.171), (ST, 1.887)):
        c = ScgConstants.of(m, xi=0.0)
        for P in (0.0, 40e9):
            np.testing.assert_allclose(max_stable_strain(c, theta, P), ref, atol=5e-4)
        # closed form with dG/dtheta = -G0 h: ((n beta rho c/(Y0 h))^(1/(n+1)) - 1)/beta
        closed = ((c.n * c.beta * c.rho_c / (c.Y0 * c.h)) ** (1 / (c.n + 1)) - 1) / c.beta
        assert float(max_stable_strain(c, 500.0, 0.0)) == pytest.approx(closed, rel=1e-13)


# digest section 4.8: recomputation of (6.72) with xi = 0.001 (3 decimals)
TABLE = {
    ("Al", 0.0): {300: 1.169, 600: 1.167, 900: 1.161, 1000: 1.151, 1100: 1.110, 1150: 1.012, 1200: 0.424},
    ("Al", 40e9): {300: 1.162, 600: 1.153, 900: 1.110, 1000: 1.051, 1100: 0.852, 1150: 0.565, 1200: 0.091},
    ("St", 0.0): {300: 1.885, 1000: 1.885, 1500: 1.885, 2000: 1.883, 2200: 1.874, 2300: 1.828, 2350: 1.562},
    ("St", 40e9): {300: 1.884, 600: 1.883, 900: 1.882, 1100: 1.881, 1500: 1.876, 2000: 1.838, 2200: 1.695,
                   2300: 1.233, 2350: 0.475},
}


@pytest.mark.parametrize("key", list(TABLE))
def test_limit_reproduces_the_recomputed_table(key):
    c = ScgConstants.of(AL if key[0] == "Al" else ST)
    theta = np.array(list(TABLE[key]))
    expected = np.array(list(TABLE[key].values()))
    np.testing.assert_allclose(max_stable_strain(c, theta, key[1]), expected, atol=5.01e-4)


def test_thesis_statement_for_aluminium_and_the_steel_discrepancy():
    """Al: 0.8 < eps_max < 1.2 away from melting (theta <= 1100 K) at 0 and 40 GPa (thesis 6.3.4).
    Steel: the thesis says 'the same', eq. 6.72 gives 1.88 (erratum, docs/theory/analyses.md)."""
    theta = np.linspace(300, 1100, 81)
    for P in (0.0, 40e9):
        lim = max_stable_strain(ScgConstants.of(AL), theta, P)
        assert np.all((lim > 0.8) & (lim < 1.2))
        steel = max_stable_strain(ScgConstants.of(ST), np.linspace(300, 2000, 50), P)
        assert np.all((steel > 1.83) & (steel < 1.89))


def test_criterion_forms_6_56_6_71_6_72_are_equivalent():
    for m in (AL, ST):
        c = ScgConstants.of(m)
        for theta, P in ((300.0, 0.0), (900.0, 40e9), (0.97 * m.melting_temperature, 10e9)):
            lim = float(strain_limit_unclipped(c, theta, P))
            if lim <= 0:
                continue
            # (6.56): margin changes sign at the limit
            assert stability_margin(c, lim * (1 - 1e-6), theta, P) > 0
            assert stability_margin(c, lim * (1 + 1e-6), theta, P) < 0
            # (6.71): the left-hand side equals 1 at the limit
            _, dG = shear_modulus_and_slope(c, theta, P)
            lhs = -(c.Y0 / c.G0) * dG * (1 + c.beta * lim) ** (c.n + 1) / (c.n * c.beta * c.rho_c)
            assert float(lhs) == pytest.approx(1.0, rel=1e-12)


def test_growth_rate_sign_saturation_and_k_squared():
    c = ScgConstants.of(ST)
    lim = float(max_stable_strain(c, 600.0, 0.0))
    k = np.array([1e5, 2e5, 4e5])
    stable = growth_rate(c, 0.5 * lim, 600.0, 0.0, k)
    unstable = growth_rate(c, 1.5 * lim, 600.0, 0.0, k)
    assert np.all(stable < 0) and np.all(unstable > 0)
    np.testing.assert_allclose(stable / stable[0], (k / k[0]) ** 2, rtol=1e-13)   # ~ k^2 (6.48)
    assert float(growth_rate(c, 0.5 * lim, 600.0, 0.0, 0.0)) == 0.0               # marginal at k = 0
    sat = c.saturation_strain
    assert float(scg_moduli(c, 1.01 * sat, 600.0, 0.0).Y_eps) == 0.0
    assert float(growth_rate(c, 1.01 * sat, 600.0, 0.0, 1e5)) == 0.0              # marginal at saturation


def test_limit_is_clipped_and_undefined_at_melt():
    c = ScgConstants.of(AL)
    just_below = c.T_melt - 0.5
    assert float(strain_limit_unclipped(c, just_below, 0.0)) < 0
    assert float(max_stable_strain(c, just_below, 0.0)) == 0.0     # no plastic state is stable
    assert math.isnan(float(max_stable_strain(c, c.T_melt, 0.0)))   # no strength at/after melt
    assert math.isnan(float(max_stable_strain(c, c.T_melt + 10, 0.0)))
    # saturation caps the strictly stable range for a made-up low-Ymax material
    low = ScgConstants(**{**c.__dict__, "Ymax": 1.05 * c.Y0})
    assert float(max_stable_strain(low, 300.0, 0.0)) == pytest.approx(low.saturation_strain, rel=1e-14)


def test_documented_artefact_within_a_kelvin_of_melting():
    """Within ~0.3 K of T_F, dG/dtheta -> 0 with G (exp(-xi T/(T_F - T)) flattens), so eq. 6.72
    rises again; the minimum sits about xi theta/2 ~ 0.6 K below T_F (docs/theory/analyses.md)."""
    for m in (AL, ST):
        c = ScgConstants.of(m)
        gaps = np.geomspace(20.0, 0.01, 400)
        lim = strain_limit_unclipped(c, c.T_melt - gaps, 0.0)
        i_min = int(np.argmin(lim))
        assert 0.3 < gaps[i_min] < 2.0
        assert lim[-1] > lim[0] > lim[i_min]


def test_material_convenience_broadcasts_over_temperature_and_pressure():
    theta = np.array([[300.0], [1100.0]])
    P = np.array([0.0, 40e9])
    from shockfriction.analysis.stability import stable_strain_limit
    lim = stable_strain_limit(AL, theta, P)
    assert lim.shape == (2, 2)
    np.testing.assert_allclose(lim, [[1.169, 1.162], [1.110, 0.852]], atol=5.01e-4)
