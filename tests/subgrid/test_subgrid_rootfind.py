"""Brent's bracketed root finder (reverse communication) and convergence of the coupled interface model."""

import math

import numpy as np
from numba import njit

from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.friction.subgrid.rootfind import B, BRENT_STATE, C, FB, FC, brent_feed, brent_next, brent_start
from shockfriction.materials.library import get_material


@njit(cache=True)
def _solve(kind, lo, hi, xtol):
    st = np.empty(BRENT_STATE)

    def f(x):
        if kind == 0:
            return x ** 3 - 2.0
        # the melt factor's steep approach to zero, as in the friction law near T_F
        return (x - 1000.0) - 200.0 * math.exp(-1.22 / (1220.0 - x)) if x < 1220.0 else x - 1000.0

    brent_start(lo, f(lo), hi, f(hi), xtol, st)
    n = 0
    while True:
        done, x = brent_next(st)
        if done:
            break
        brent_feed(st, f(x))
        n += 1
        if n > 200:
            break
    return st[B], st[FB], st[C], st[FC], n


def test_brent_finds_a_cubic_root_superlinearly():
    b, fb, c, fc, n = _solve(0, 0.0, 3.0, 1e-12)
    assert abs(b - 2 ** (1 / 3)) < 1e-12 and fb * fc <= 0.0
    assert n <= 12


def test_brent_keeps_the_bracket_on_a_steep_melt_factor():
    b, fb, c, fc, n = _solve(1, 300.0, 1220.0, 1e-9)
    root = b if abs(fb) < abs(fc) else c
    assert 1180.0 < root < 1220.0 and fb * fc <= 0.0 and abs(b - c) < 1e-8
    print(f"\nsteep residual: root {root:.9f} K in {n} iterations")
    assert n <= 60


def _ball(dt, cells, t_end=0.25e-6, model="thermoelastic"):
    sg = SubgridInterface(1, get_material("Al5083-H111"), get_material("AISI321"), n_cells=cells, model=model,
                          mu0=0.3, f=0.3)
    for _ in range(int(round(t_end / dt))):
        sg.step(10e9, 200.0, 200.0, np.inf, np.inf, 1.0, dt)
    return sg.theta_interface[0], sg.tau[0]


def test_thermoelastic_interface_converges_first_order_in_dt_second_in_dz():
    """Ball case at 0.25 us: successive differences give the observed orders (digest §10 case 12)."""
    T_dt = [_ball(dt, 500)[0] for dt in (2e-9, 1e-9, 0.5e-9)]
    p_t = math.log2(abs(T_dt[0] - T_dt[1]) / abs(T_dt[1] - T_dt[2]))
    T_dz = [_ball(0.5e-9, M)[0] for M in (50, 100, 200)]
    p_z = math.log2(abs(T_dz[0] - T_dz[1]) / abs(T_dz[1] - T_dz[2]))
    print(f"\nthermoelastic: Theta(0, 0.25 us) = {T_dt[1]:.3f} K (dt 1 ns, M 500); dt-halving change "
          f"{T_dt[1] - T_dt[2]:.3f} K, observed order in dt {p_t:.3f}, in dz {p_z:.3f}")
    assert abs(p_t - 1.0) < 0.1
    assert abs(p_z - 2.0) < 0.1
    assert abs(T_dt[1] - T_dt[2]) < 0.5  # 1 ns is converged to plotting accuracy (Fig. 7.7)


def test_thermoelastoplastic_interface_self_converges():
    """The closed-form (rate-independent) strain makes the first step yield the whole layer at once
    (digest §9 item 17), a one-step plastic slip whose size does not shrink with dt: the
    asymptotic orders are irregular, so only monotone self-convergence is asserted (orders printed)."""
    T_dt = [_ball(dt, 500, model="thermoelastoplastic")[0] for dt in (2e-9, 1e-9, 0.5e-9, 0.25e-9)]
    d_t = np.abs(np.diff(T_dt))
    T_dz = [_ball(0.5e-9, M, model="thermoelastoplastic")[0] for M in (50, 100, 200, 400)]
    d_z = np.abs(np.diff(T_dz))
    print(f"\nthermoelastoplastic: Theta(0, 0.25 us) = {T_dt[1]:.3f} K; dt changes {d_t} (orders "
          f"{np.log2(d_t[:-1] / d_t[1:])}); dz changes {d_z} (orders {np.log2(d_z[:-1] / d_z[1:])})")
    assert np.all(np.diff(d_t) < 0) and np.all(np.diff(d_z) < 0)
    assert d_t[-1] < 0.2 and d_z[-1] < 0.2
