"""EOS and per-cell strength kernels against independent formulas."""

import numpy as np
import pytest
from scipy.optimize import brentq

from shockfriction.hydro import matprops as mp
from shockfriction.hydro.eos import eos_ab, sound_speed2, temperature
from shockfriction.hydro.plasticity import radial_return, rotate_deviator
from shockfriction.hydro.setup import material_row
from shockfriction.deck.run import Body
from shockfriction.materials.library import get_material
from shockfriction.materials.strength import scg_yield


def _row(**kw):
    body = Body.model_validate({"name": "b", "material": "Al6061-T6",
                                "mesh": {"corners": [["0 m", "0 m"], ["1 m", "0 m"], ["1 m", "1 m"], ["0 m", "1 m"]],
                                         "nx": 1, "ny": 1}, **kw})
    row, table = material_row(body, "test")
    return row.reshape(1, -1), table.reshape(1, -1)


@pytest.mark.parametrize("up", [50.0, 125.0, 500.0, 2000.0])
def test_mie_gruneisen_reproduces_its_hugoniot(up):
    props, _ = _row()
    al = get_material("Al6061-T6")
    us = al.eos_c0 + al.eos_s * up
    rho = al.rho0 * us / (us - up)
    e_h = 0.5 * up * up  # Rankine-Hugoniot energy jump from rest
    a, b, _ = eos_ab(rho, props, 0)
    assert a + b * e_h == pytest.approx(al.rho0 * us * up, rel=1e-12)


def test_sound_speed_is_the_isentropic_derivative():
    props, _ = _row()
    rho, e = 3000.0, 2.0e5
    a, b, _ = eos_ab(rho, props, 0)
    p = a + b * e
    # along an isentrope de = P/rho^2 drho: central difference of P(rho, e(rho))
    h = 1e-3
    pp = eos_ab(rho + h, props, 0)[0] + eos_ab(rho + h, props, 0)[1] * (e + p / rho**2 * h)
    pm = eos_ab(rho - h, props, 0)[0] + eos_ab(rho - h, props, 0)[1] * (e - p / rho**2 * h)
    assert sound_speed2(rho, p, props, 0) == pytest.approx((pp - pm) / (2 * h), rel=1e-6)
    assert np.sqrt(sound_speed2(2703.0, 0.0, props, 0)) == pytest.approx(5240.0, rel=1e-12)


def test_temperature_is_T0_on_the_reference_isentrope_and_rises_by_e_over_cv():
    props, table = _row(temperature="300 K")
    al = get_material("Al6061-T6")
    # integrate the isentrope independently with a fine trapezoid rule to mu = 0.2
    mus = np.linspace(0.0, 0.2, 20001)
    e = 0.0
    for m0, m1 in zip(mus[:-1], mus[1:]):
        r0, r1 = al.rho0 * (1 + m0), al.rho0 * (1 + m1)
        a0, b0, _ = eos_ab(r0, props, 0)
        # de = -P dv with v = 1/rho; predictor-corrector for the linear ODE
        dv = 1 / r1 - 1 / r0
        e_pred = e - (a0 + b0 * e) * dv
        a1, b1, _ = eos_ab(r1, props, 0)
        e = e - 0.5 * ((a0 + b0 * e) + (a1 + b1 * e_pred)) * dv
    rho = al.rho0 * 1.2
    assert temperature(rho, e, props, table, 0) == pytest.approx(300.0, abs=0.05)
    assert temperature(rho, e + 885.0 * 10, props, table, 0) - temperature(rho, e, props, table, 0) == \
        pytest.approx(10.0 * 885.0 / al.heat_capacity, rel=1e-12)


def test_rotation_keeps_invariants_exactly():
    s = (1.0e8, -3.0e7, 4.0e7)
    r = rotate_deviator(*s, 1.3e6, 1e-7)
    inv0 = s[0] ** 2 + s[1] ** 2 + 2 * s[2] ** 2
    inv1 = r[0] ** 2 + r[1] ** 2 + 2 * r[2] ** 2
    assert inv1 == pytest.approx(inv0, rel=1e-14)
    assert r[0] + r[1] == pytest.approx(s[0] + s[1], rel=1e-14)


def _seq(sxx, syy, sxy):
    szz = -(sxx + syy)
    return np.sqrt(1.5 * (sxx**2 + syy**2 + szz**2 + 2 * sxy**2))


def test_perfectly_plastic_return_lands_on_the_yield_surface():
    props, _ = _row(strength="elastic-perfectly-plastic", yield_stress="0.3 GPa")
    g = props[0, mp.P_G0]
    trial = (4e8, -3e8, 1e8)
    sxx, syy, sxy, deps, y = radial_return(*trial, 0.0, g, 1.0, props, 0)
    assert y == 3e8
    assert _seq(sxx, syy, sxy) == pytest.approx(3e8, rel=1e-14)
    assert deps == pytest.approx((_seq(*trial) - 3e8) / (3 * g), rel=1e-14)
    assert sxx / trial[0] == pytest.approx(sxy / trial[2], rel=1e-14)  # radial
    # elastic trial stays
    assert radial_return(1e7, -1e7, 0.0, 0.0, g, 1.0, props, 0)[:3] == (1e7, -1e7, 0.0)


@pytest.mark.parametrize("eps0", [0.0, 0.01, 0.3])
def test_scg_return_solves_the_hardening_equation(eps0):
    props, _ = _row(strength="scg")
    al = get_material("Al6061-T6")
    p, t = 2e9, 500.0
    ratio = scg_yield(0.0, p, t, al.scg_params()) / min(al.Ymax, al.Y0)
    g = al.G0 * ratio
    trial = (1.5e9, -0.9e9, 0.4e9)
    seq = _seq(*trial)
    sxx, syy, sxy, deps, y = radial_return(*trial, eps0, g, ratio, props, 0)

    def f(d):
        return seq - 3 * g * d - scg_yield(eps0 + d, p, t, al.scg_params())

    exact = brentq(f, 0.0, seq / (3 * g), xtol=1e-16, rtol=1e-14)
    print(f"eps0 = {eps0}: d_eps = {deps:.12e} (brentq {exact:.12e})")
    assert deps == pytest.approx(exact, rel=1e-10)
    assert y == pytest.approx(scg_yield(eps0 + exact, p, t, al.scg_params()), rel=1e-10)
    assert _seq(sxx, syy, sxy) == pytest.approx(y, rel=1e-12)


def test_melted_cell_has_no_deviator():
    props, _ = _row(strength="scg")
    sxx, syy, sxy, deps, y = radial_return(1e8, -1e8, 1e7, 0.0, 0.0, 0.0, props, 0)
    assert (sxx, syy, sxy, y) == (0.0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", ["Al5083-H111", "AISI321", "Cu-OFHC"])
def test_scalar_hardening_is_the_shared_scg_module(name):
    """The return mapping's scalar hardening (value and slope) is the shared SCG law."""
    from shockfriction.hydro.plasticity import hardening
    from shockfriction.materials.strength import scg_hardening

    m = get_material(name)
    p = m.scg_params()
    for eps in (0.0, 1e-4, 0.01, 0.1, 1.0, 5.0):
        h, dh = hardening(eps, m.Y0, m.scg_beta, m.scg_n, m.Ymax)
        assert h == pytest.approx(scg_hardening(eps, p), rel=1e-14)
        d = 1e-7 * (1 + eps)
        slope = (scg_hardening(eps + d, p) - scg_hardening(max(eps - d, 0.0), p)) / (eps + d - max(eps - d, 0.0))
        if h < m.Ymax * (1 - 1e-6):
            assert dh == pytest.approx(slope, rel=1e-5)
