"""The viscoplastic kernel's cost measures (docs/theory/viscoplastic.md, "Cost"): the closed-form first iterate of
the return map, the step left out on linear columns, and the parallel column blocks, each against the plain
computation it replaces."""

import math

import numpy as np
import pytest

from shockfriction.friction.subgrid import inertial_column
from shockfriction.friction.subgrid.viscoplastic import SQRT3, ViscoplasticColumns, return_map


def newton_reference(s_abs, G, eta_dt, eps, y_start, k_fac, Y0, beta, n, Ymax):
    """The return map as it was: Newton from x = 0 with the hardening slope by its own pow (pure Python)."""
    if G <= 0.0:
        return 0.0, 0.0
    if s_abs <= y_start * k_fac:
        return 0.0, 1.0
    c = G + eta_dt
    x = dk = 0.0
    for _ in range(100):
        hb = 1.0 + beta * (eps + x / SQRT3)
        y = Y0 * hb ** n
        if y >= Ymax:
            k, dk = Ymax * k_fac, 0.0
        else:
            k = y * k_fac
            dk = Y0 * n * beta * hb ** (n - 1.0) * k_fac / SQRT3
        dx = (s_abs - c * x - k) / (c + dk)
        x += dx
        if abs(dx) <= 1e-15 * x:
            break
    return x, (eta_dt + dk) / (c + dk)


@pytest.mark.parametrize("eps", [0.0, 1e-3, 0.3, 5.0])
@pytest.mark.parametrize("over", [1.0001, 1.5, 20.0])
@pytest.mark.parametrize("eta_dt", [0.0, 5e10])
def test_return_map_matches_newton(eps, over, eta_dt):
    G0, Y0, beta, n, Ymax = 2.7e10, 1.5e8, 400.0, 0.1, 4.8e8  # an Al-like SCG set
    G = 0.8 * G0
    k_fac = G / G0 / SQRT3
    y_start = min(Ymax, Y0 * (1.0 + beta * eps) ** n)
    s = over * y_start * k_fac
    x, d = return_map(s, G, eta_dt, eps, y_start, k_fac, beta, n, Ymax)
    xr, dr = newton_reference(s, G, eta_dt, eps, y_start, k_fac, Y0, beta, n, Ymax)
    # within 1e-13, or within the root's round-off: one ulp of the yield (the series against the pow, "The return map
    # without pow") moves x by ~1e-16 s/(G + eta_vp/dt), 1e-12 of x at an overstress of 1e-4 (measured 6.9e-19)
    assert math.isclose(x, xr, rel_tol=1e-13, abs_tol=1e-15 * s / (G + eta_dt))
    assert math.isclose(d, dr, rel_tol=1e-12, abs_tol=1e-300)
    # the root of the return equation
    hb = 1.0 + beta * (eps + x / SQRT3)
    y = min(Ymax, Y0 * hb ** n)
    assert abs(s - (G + eta_dt) * x - y * k_fac) <= 1e-14 * s


def run(ncol, threads, monkeypatch, steps=25, f=0.7):
    monkeypatch.setattr(inertial_column, "get_num_threads", lambda: threads)
    c = ViscoplasticColumns(ncol, "Al5083-H111", beta_T=0.5, thickness=4e-6, n_cells=100, f=f, other="AISI321")
    v = np.linspace(50.0, 250.0, ncol)
    for _ in range(steps):
        c.step(10e9, v, v, 0.0, 3e9, 1e-9)
    return c


def test_parallel_blocks_bit_identical(monkeypatch):
    """Columns in parallel blocks (8 blocks of 18 columns) give the same bytes as one block."""
    a = run(18, 1, monkeypatch)
    b = run(18, 2, monkeypatch)
    for name in ("v", "ge", "Gs", "eps", "e", "T", "energy", "tau", "_v_half", "T_other", "iterations"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.max(np.abs(a.energy_residual())) <= 1e-10


@pytest.mark.parametrize("f, plastic_deep", [(0.3, False), (0.7, True)])
def test_mechanics_window_gives_the_full_columns_answer(f, plastic_deep):
    """The mechanics on a window with the linear far field condensed onto it (an exact Schur complement, grown when a
    far cell flows) against the whole column in the Newton (the window forced to the full depth before every step):
    Ball loading, 4 columns x 500 cells, 30 steps; f = 0.3 (the window ~26 of 500 cells), f = 0.7 (the plastic front
    runs through the column: the window grows inside the steps).  Measured: tau within 8.3e-15 (f = 0.3) / 8.0e-15
    (f = 0.7), Theta(0) within 2.2e-11 / 2.4e-11 K, the same Picard sweeps (the Newton's iterates differ, not its
    answer); the deepest plastic cell 2-17 at f = 0.3, 84 after the first step at f = 0.7."""
    v = np.linspace(150.0, 250.0, 4)
    cols = [ViscoplasticColumns(4, "Al5083-H111", beta_T=0.5, f=f, other="AISI321") for _ in range(2)]
    full, windowed = cols
    M = full.dz.size
    reach = []
    for _ in range(30):
        full._reach[:] = M
        for c in cols:
            c.step(10e9, v, v, 0.0, 3e9, 1e-9)
        reach.append(windowed._reach.max())
        assert np.max(np.abs(windowed.tau / full.tau - 1.0)) <= 3e-14
        assert np.max(np.abs(windowed.T[0] - full.T[0])) <= 1e-10
    assert np.array_equal(windowed.iterations, full.iterations)
    if plastic_deep:
        assert reach[0] < M // 2 and reach[-1] == M  # the front crossed the column: the window grew
    else:
        assert max(reach) <= 25  # a thin plastic layer: the far field condensed throughout


def test_newton_stops_on_its_quadratic_estimate_only_where_it_is_trusted():
    """The mechanics Newton stops where its correction r <= mech_tol, or where the next correction of a quadratic
    convergence, nq r^2, is, after a full step on an unchanged plastic set with r <= NEWTON_TRUST and nq measured
    (docs/theory/viscoplastic.md, "The mechanics Newton's last iteration"; measured nq ~ 1e-5 to 4e-5)."""
    from shockfriction.friction.subgrid.inertial_column import NEWTON_TRUST, _newton_converged

    mtol, nq = 1e-13, 8e-6
    assert NEWTON_TRUST == 1e-5
    assert _newton_converged(5e-14, -1.0, False, mtol)            # the correction itself
    assert _newton_converged(8.6e-7, nq, True, mtol)              # next ~6e-18
    assert not _newton_converged(8.6e-7, -1.0, True, mtol)        # nq not measured yet
    assert not _newton_converged(8.6e-7, nq, False, mtol)         # a damped step or a changed plastic set
    assert not _newton_converged(2e-5, 1e-10, True, mtol)         # beyond NEWTON_TRUST
    assert not _newton_converged(1e-5, 1e-2, True, mtol)          # next ~1e-12: not yet


@pytest.mark.parametrize("n", [0.1, 0.27, 0.5, 1.0, 2.0])
def test_binomial_power_is_the_power_where_the_return_map_uses_it(n):
    """(1 + u)^n by the series to u^8 for |u| <= BINOMIAL_U = 1e-2 (the return map's hardening, "The return map
    without pow"): measured within one ulp (2.2e-16) of the power."""
    from shockfriction.friction.subgrid.viscoplastic import BINOMIAL_U, binomial_power

    u = np.linspace(-BINOMIAL_U, BINOMIAL_U, 4001)
    series = np.array([binomial_power(x, n) for x in u])
    assert np.max(np.abs(series / (1.0 + u) ** n - 1.0)) < 4.5e-16



@pytest.mark.parametrize("layout", ["mixed", "dense"])
def test_cells_pass_against_the_return_map_cell_by_cell(layout):
    """The cells' pass (trial states of all cells, the linear ones directly; the plastic ones' return maps in one
    vectorised loop of two corrections and the estimate of the next, a cell outside the tolerance redone by
    ``return_map``: "The return maps across the cells") against ``_cell_state`` cell by cell, 4000 cells with
    strain increments from 1e-9 to 1e-1 over the step, cold and from a guess 1e-3 off: "mixed" elastic, plastic,
    saturated and molten cells in any order (the plastic ones gathered), "dense" every cell plastic (the column's
    own arrays).  The plastic increments and stresses within 1e-14 relative (or 1e-15 of the terms they are the
    differences of, G |ge|, G dt |gamma_dot|), the stiffnesses within 1e-13, the strain rates within 4.5e-16 (by 1/dz; measured: stresses
    and stiffnesses 2.2e-16, strain rates one ulp, increments 3.3e-13 where they are at the root's round-off)."""
    from shockfriction.friction.subgrid.inertial_column import _cells
    from shockfriction.friction.subgrid.viscoplastic import _cell_state
    from shockfriction.materials.library import get_material
    from shockfriction.materials.strength import scg_hardening_power

    m = get_material("Al5083-H111")
    Y0, beta, n, Ymax = m.Y0, m.scg_beta, m.scg_n, m.Ymax
    rng = np.random.default_rng(3)
    M, dt, eta_vp = 4000, 1e-9, 50.0
    dense = layout == "dense"
    dz = rng.uniform(2e-8, 6e-8, M)
    eps = rng.choice([0.0, 1e-4, 0.1, 3.0, 40.0], M) * rng.random(M)
    r = rng.uniform(0.3, 1.0, M)
    if not dense:
        r[rng.random(M) < 0.05] = 0.0  # molten
    G = m.G0 * r
    kf = r / SQRT3
    eta = np.where(r > 0.0, 0.0, rng.uniform(1e-3, 1.0, M))
    yh = np.minimum(Ymax, [scg_hardening_power(e, Y0, beta, n) for e in eps])
    dgam = 10.0 ** rng.uniform(-9.0, -1.0, M) * rng.choice([-1.0, 1.0], M)
    if dense:  # at yield, loaded further
        ge = yh * kf / G * np.sign(dgam)
    else:
        ge = yh * kf / np.maximum(G, 1.0) * rng.uniform(-1.2, 1.2, M)
    sold = G * ge
    vt = np.concatenate([np.cumsum((dgam * dz / dt)[::-1])[::-1], [0.0]])
    for guess in (False, True):
        out = [np.zeros(M + 2), np.zeros(M), np.zeros(M), np.zeros(M), np.zeros(M)]
        ref = []
        for c in range(M):
            ref.append(_cell_state(0.0, vt[c] - vt[c + 1], dz[c], dt, G[c], ge[c], eps[c], yh[c], eta[c], kf[c],
                                   sold[c], beta, n, Ymax, eta_vp, 1.0))
        if guess:  # the last pass's increments, 1e-3 off
            out[4][:] = [dg * (1.0 + 1e-3 * rng.standard_normal()) if G[c] > 0.0 else 0.0
                         for c, (_, _, dg, _, _) in enumerate(ref)]
        scratch = [np.empty(M) for _ in range(8)]
        npl, deep = _cells(vt, M, 1.0 / dz, dt, G, ge, eps, yh, eta, kf, beta, n, Ymax, eta_vp, *out,
                           np.empty(M, dtype=np.int64), *scratch)
        S, Kc, gdm, snew, dgp = out
        plastic = 0
        for c, (gd, sn, dg, Sm, K) in enumerate(ref):
            scale = abs(Sm) + abs(sn) + G[c] * (abs(ge[c]) + abs(dt * gd))  # (s' = G (ge + dt gd) - G x)
            assert abs(dgp[c] - dg) <= 1e-14 * abs(dg) + 1e-15 * scale / (G[c] + eta_vp / dt), c
            assert abs(snew[c] - sn) <= 1e-14 * abs(sn) + 1e-15 * scale, c
            assert abs(S[c + 1] - Sm) <= 1e-14 * abs(Sm) + 1e-15 * scale, c
            assert abs(Kc[c] - K) <= 1e-13 * abs(K), c
            assert abs(gdm[c] - gd) <= 4.5e-16 * abs(gd), c
            plastic += dg != 0.0 and G[c] > 0.0
        assert npl == plastic and 0 < plastic
        assert plastic == M if dense else plastic < M
        assert deep == max(c + 1 for c in range(M) if ref[c][2] != 0.0 and G[c] > 0.0)
