"""The Mie-Grueneisen tension branch: linear (default) or cubic (docs/theory/spall-and-tension.md).

Cubic: A(mu) = rho0 c0^2 mu [1 + b2 mu + b3 mu^2], b2 = 2s - 1 - Gamma0/2, b3 = (s - 1)(3s - 1 - Gamma0),
the expansion of the compression branch P_H(eta)(1 - Gamma0 eta/2), eta = mu/(1 + mu), to O(mu^3).
"""

import numpy as np
import pytest

from shockfriction.hydro.api import run_dict
from shockfriction.hydro.eos import eos_ab_s, tension_cubic
from shockfriction.hydro.matprops import EOS_MG_CUBIC, EOS_MIE_GRUNEISEN
from shockfriction.materials.library import get_material

MATS = ["Cu-OFHC", "Al6061-T6", "Ti-6Al-4V"]


def _a(mu, kind, m):
    rho = m.rho0 * (1.0 + mu)
    return eos_ab_s(rho, kind, m.rho0, m.eos_c0, m.eos_s, m.eos_gamma0, 0.0)


@pytest.mark.parametrize("name", MATS)
def test_cubic_branch_equals_the_formula(name):
    m = get_material(name)
    k0, s, g = m.rho0 * m.eos_c0**2, m.eos_s, m.eos_gamma0
    for mu in (-1e-4, -0.01, -0.05, -0.1, -0.2):
        a, b, da_drho = _a(mu, EOS_MG_CUBIC, m)
        exact = k0 * (mu + (2 * s - 1 - g / 2) * mu**2 + (s - 1) * (3 * s - 1 - g) * mu**3)
        slope = k0 * (1 + 2 * (2 * s - 1 - g / 2) * mu + 3 * (s - 1) * (3 * s - 1 - g) * mu**2) / m.rho0
        assert a == pytest.approx(exact, rel=1e-10)  # mu = rho/rho0 - 1 round-off
        assert da_drho == pytest.approx(slope, rel=1e-10)
        assert b == pytest.approx(g * m.rho0, rel=1e-15)
        # the linear branch (default) is unchanged: A = rho0 c0^2 mu
        assert _a(mu, EOS_MIE_GRUNEISEN, m)[0] == pytest.approx(k0 * mu, rel=1e-10)


@pytest.mark.parametrize("name", MATS)
def test_both_branches_are_continuous_at_mu_zero(name):
    """Value and slope (both branches), and curvature (cubic) match the compression side."""
    m = get_material(name)
    k0 = m.rho0 * m.eos_c0**2
    h = 1e-4
    for kind in (EOS_MIE_GRUNEISEN, EOS_MG_CUBIC):
        a0 = _a(0.0, kind, m)[0]
        assert a0 == 0.0
        ap, am = _a(h, kind, m)[0], _a(-h, kind, m)[0]
        # value: A(+-h) = +-k0 h to O(h^2); slope: dA/dmu -> k0 from both sides
        assert abs(ap / (k0 * h) - 1.0) < 3 * h and abs(am / (-k0 * h) - 1.0) < 3 * h
        assert _a(-1e-12, kind, m)[2] * m.rho0 == pytest.approx(k0, rel=1e-9)  # dA/dmu at 0-
        assert _a(1e-12, kind, m)[2] * m.rho0 == pytest.approx(k0, rel=1e-9)  # dA/dmu at 0+
        # curvature from each side: A''(0+-) ~ 2 (A(+-h) -+ k0 h)/h^2 (to O(h))
        cp, cm = 2 * (ap - k0 * h) / h**2 / k0, 2 * (am + k0 * h) / h**2 / k0
        b2 = 2 * m.eos_s - 1 - m.eos_gamma0 / 2
        assert cp == pytest.approx(2 * b2, abs=50 * h)
        if kind == EOS_MG_CUBIC:
            assert cm == pytest.approx(2 * b2, abs=50 * h)  # C^2 at mu = 0
        else:
            assert abs(cm) < 1e-6  # the linear branch: A'' = 0 below, 2 b2 k0 above
    # the cubic tension branch stays monotone (positive sound speed) down to mu = -0.4
    mus = np.linspace(-0.4, 0.0, 401)
    assert all(tension_cubic(mu, k0, m.eos_s, m.eos_gamma0)[1] > 0.0 for mu in mus)


def test_cubic_tension_in_a_plate_impact(make_strip):
    """Same strip as the pressure-floor test: with the cubic branch the tension is softer (A''
    > 0 makes A(mu) less negative); the shock state is the same; energy is conserved."""
    lin = run_dict(make_strip(ny_flyer=20, ny_target=40, end="1.6 us"))
    cub = run_dict(make_strip(ny_flyer=20, ny_target=40, end="1.6 us", extra_body={"eos_tension": "cubic"}))
    pl, pc = lin.probes["mid.p"], cub.probes["mid.p"]
    print(f"peak {pl.max() / 1e9:.4f} / {pc.max() / 1e9:.4f} GPa, min {pl.min() / 1e9:.4f} / {pc.min() / 1e9:.4f} GPa")
    assert pc.max() == pytest.approx(pl.max(), rel=1e-12)  # compression untouched
    assert pl.min() < pc.min() < 0.0
    assert cub.summary["relative_energy_error"] < 2e-3
