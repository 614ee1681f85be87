"""The elasto-viscoplastic layer's linear system (analysis/viscoplastic_stability.py) against its limits.

- eta -> 0 without inertia: the growth rate tends to eq. 6.48 (rate-independent, quasi-static, thesis ch. 6);
- eta -> 0, G -> infinity with inertia: the cubic of stability.inertial_growth_rate (rigid-plastic inertial
  Fourier system);
- a stable elastic layer (no plastic flow, F = 0) has purely imaginary eigenvalues +-i k sqrt(G/rho).
"""

import math

import numpy as np
import pytest

from shockfriction.analysis import viscoplastic_stability as vs
from shockfriction.analysis.stability import (SQRT3, ScgConstants, growth_rate, inertial_growth_rate,
                                              scg_moduli)
from shockfriction.materials.library import get_material


@pytest.fixture(scope="module")
def base():
    m = get_material("Al5083-H111")
    c = ScgConstants.of(m)
    eps0, theta, P = 0.05, 600.0, 1e9
    mod = scg_moduli(c, eps0, theta, P)
    return m, c, eps0, theta, P, mod


def _kw(m, c, mod, eta, G, gp0=0.0, inertia=True):
    Y, Y_eps, Y_theta = float(mod.Y), float(mod.Y_eps), float(mod.Y_theta)
    return dict(rho=m.rho0, G=G, rho_c=c.rho_c, kappa=c.kappa, chi=1.0, tau0=Y / SQRT3 + eta * gp0, gp0=gp0,
                inertia=inertia, **vs.overstress_partials(eta, Y_eps, Y_theta))


@pytest.mark.parametrize("k", [1e5, 1e6, 1e7])
def test_quasistatic_rate_independent_limit_is_eq_6_48(base, k):
    m, c, eps0, theta, P, mod = base
    s = vs.growth_rate(k, **_kw(m, c, mod, eta=1e-9, G=float(mod.G), inertia=False))
    ref = float(growth_rate(c, eps0, theta, P, k))
    assert abs(s.real - ref) <= 1e-5 * abs(ref)


@pytest.mark.parametrize("k", [1e5, 1e7])
def test_rigid_plastic_inertial_limit_is_the_cubic(base, k):
    m, c, eps0, theta, P, mod = base
    # eta -> 0 and G -> infinity is a singular limit: eta = 1e-7 Pa s, G = 1e15 Pa (errors ~1e-4 of Re s)
    s = vs.growth_rate(k, **_kw(m, c, mod, eta=1e-7, G=1e15))
    ref = inertial_growth_rate(c, eps0, theta, P, k, m.rho0, 0.0)
    print("inertial limit", k, s, ref)
    assert abs(s.real - ref.real) <= 1e-3 * abs(ref.real)
    assert abs(abs(s.imag) - ref.imag) <= 1e-5 * abs(ref.imag)


def test_elastic_layer_carries_undamped_shear_waves(base):
    m, c, eps0, theta, P, mod = base
    G = float(mod.G)
    kw = _kw(m, c, mod, eta=1.0, G=G)
    kw.update(F_tau=0.0, F_eps=0.0, F_theta=0.0)
    k = 1e6
    eig = np.linalg.eigvals(vs.layer_matrix(k, **kw))
    omega = k * math.sqrt(G / m.rho0)
    waves = eig[np.abs(eig.imag) > 0.5 * omega]
    assert len(waves) == 2
    assert max(abs(waves.real)) <= 1e-9 * omega
    assert np.allclose(sorted(waves.imag), [-omega, omega], rtol=1e-12)
    diffusion = eig[np.abs(eig.imag) <= 0.5 * omega]
    assert np.allclose(sorted(diffusion.real), [-c.kappa * k * k / c.rho_c, 0.0], atol=1e-9 * omega)
