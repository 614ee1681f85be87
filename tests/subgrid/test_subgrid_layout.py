"""Column-innermost layout and the fused sweep (docs/theory/subgrid-layout.md).

The sweep of ThermalColumns (columns stored (n_nodes, n_columns), the affine update of the last step
applied on the fly, sources only in the first rows, idle columns left alone) against one Thomas solve
per column; the melt check against a brute-force scan; reading ``theta`` (which applies the pending
update) changes nothing; a checkpoint taken in the lazy state restores bit for bit.
"""

import h5py
import numpy as np
import pytest

from shockfriction.friction.subgrid.column import ThermalColumns, heat_matrix, melt_check, sweep_columns, thomas_solve
from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.io.checkpoint import load_object, save_object
from shockfriction.materials.library import get_material

AL, ST = get_material("Al5083-H111"), get_material("AISI321")


def columns(n=11, cells=90):
    return ThermalColumns(n, 20e-6, cells, AL.conductivity, AL.rho0, AL.heat_capacity, grading=1.01)


def test_lazy_sweep_with_sources_and_idle_columns_equals_thomas_per_column():
    """theta = X + q u (pending), then K theta_ad = theta + f p (p in the first 13 rows only): per column,
    a direct Thomas solve to a few ulp (the two differ only in the order of the factored operations); idle columns exactly unchanged; the block suffix maxima exact."""
    rng = np.random.default_rng(4)
    col = columns()
    n, nn = col.n_columns, col.n_nodes
    dt = 0.8e-9
    col.prepare(dt)
    col.X[...] = 300.0 + rng.uniform(0.0, 600.0, size=col.X.shape)
    idle = np.array([2, 3, 9])
    col.X[:, idle] = 300.0
    col.active[:] = True
    col.active[idle] = False
    q = rng.uniform(1e9, 3e10, n)
    q[idle] = 0.0
    col.set_flux(q)
    theta = col.X.T + q[:, None] * col.theta_unit[None, :]  # what the pending update gives (eq. 7.70)
    src = np.zeros((nn, n))
    src[:13] = rng.uniform(0.0, 1e8, size=(13, n))
    src[:, idle] = 0.0
    flags = np.any(src != 0.0, axis=0)
    factor = 1.0 / col.rho_c
    dep = src.copy()
    X = col.advance(dt, dep, 13, factor, src_flags=flags)
    a, b, c = heat_matrix(col.z, col.alpha, dt)
    for j in range(n):
        expected = theta[j] if j in idle else thomas_solve(a, b, c, theta[j] + src[:, j] * factor)
        if j in idle:
            assert np.array_equal(X[:, j], expected)
        else:
            assert np.max(np.abs(X[:, j] - expected)) < 1e-12  # measured 3.4e-13 K (3 ulp at 900 K)
    np.testing.assert_allclose(col._deposited, col.weights @ src, rtol=1e-14)
    assert np.all(col._clipped == 0.0)  # no melt limit given
    sfx = np.maximum.accumulate(X[::-1], axis=0)[::-1]
    assert np.array_equal(col._sfx, sfx[::8]) and np.array_equal(col.col_max, X.max(axis=0))


@pytest.mark.parametrize("lazy", [True, False])
def test_sweep_of_the_busy_span_equals_the_full_sweep_bit_for_bit(lazy):
    """Only the columns between the first and last busy one are swept (idle ones outside keep their value,
    their suffix maxima are theta(0)), the source only in its own span: every output as the full sweep's."""
    rng = np.random.default_rng(7)
    col = columns(n=14)
    n, nn = col.n_columns, col.n_nodes
    dt = 0.7e-9
    col.prepare(dt)
    col.X[...] = 300.0 + rng.uniform(0.0, 600.0, size=col.X.shape)
    idle = np.array([0, 1, 2, 6, 12, 13])
    col.X[:, idle] = 300.0 + np.arange(idle.size)  # uniform idle columns
    col.active[:] = True
    col.active[idle] = False
    if lazy:
        q = rng.uniform(1e9, 3e10, n)
        q[idle] = 0.0
        col.set_flux(q)
    src = np.zeros((nn, n))
    src[:20, 4:10] = rng.uniform(0.0, 1e9, size=(20, 6))
    src[:3, 8] = 1e12  # clipped by the melt guard
    flags = np.any(src != 0.0, axis=0)
    factor = 1.0 / col.rho_c
    ref = (col.X.copy(), src.copy(), np.zeros(n), np.zeros(n), np.zeros_like(col._sfx))
    sweep_columns(ref[0], col.q_lazy, col.unit_lazy, col.lazy, ref[1], 20, factor, col.rho_c, 1000.0, col.weights,
                  ref[2], ref[3], col.mult, col.inv_bp, col.c, np.flatnonzero(~(col.active | flags)), np.empty(n), ref[4],
                  0, -1, 0, -1)
    X = col.advance(dt, src, 20, factor, 1000.0, src_flags=flags, src_span=(4, 10))
    assert (col._span(flags, (4, 10))[:2]) == (3, 12)
    for got, want in zip((X, src, col._clipped, col._deposited, col._sfx), ref):
        assert np.array_equal(got, want)
    assert col._clipped[8] > 0.0


def test_public_adiabatic_keeps_the_state_and_equals_the_in_place_sweep():
    rng = np.random.default_rng(8)
    col = columns()
    col.prepare(1e-9)
    col.active[:] = True
    col.X[...] = 300.0 + rng.uniform(0.0, 300.0, size=col.X.shape)
    col.set_flux(rng.uniform(0.0, 1e10, col.n_columns))
    before = (col.X.copy(), col.lazy, col._sfx.copy())
    ad = col.adiabatic(1e-9).copy()
    assert np.array_equal(col.X, before[0]) and col.lazy == before[1] and np.array_equal(col._sfx, before[2])
    assert np.array_equal(ad, col.advance(1e-9).T)


def test_melt_check_finds_the_first_node_a_brute_force_scan_finds():
    rng = np.random.default_rng(1)
    nn, n = 40, 9
    unit = np.exp(-np.linspace(0.0, 8.0, nn)) * 1e-8
    for trial in range(200):
        X = 300.0 + rng.uniform(0.0, 900.0, size=(nn, n))
        q = rng.uniform(-2e9, 3e10, n)
        limit = rng.uniform(900.0, 1500.0)
        theta = X + q[None, :] * unit[:, None]
        bad = np.argwhere(~(theta.T < limit))  # (column, node) pairs in column-major scan order
        expected = -1 if bad.size == 0 else int(bad[0, 0] * nn + bad[0, 1])
        assert melt_check(X, q, unit, unit.max(), X.max(axis=0), limit) == expected


@pytest.mark.parametrize("model", ["thermoelastic", "thermoelastoplastic"])
def test_reading_theta_every_step_changes_nothing(model):
    """``theta`` applies the pending affine update in place; the next sweep then skips it: same bits."""
    sig = np.linspace(1e9, 12e9, 7)
    v = np.linspace(50.0, 350.0, 7)
    a, b = (SubgridInterface(7, AL, ST, n_cells=120, model=model, mu0=0.3, f=0.3) for _ in range(2))
    for n in range(60):
        dt = 1e-9 * (1.0 + 0.5 * (n % 2))
        ra, rb = a.step(sig, v, v, np.inf, np.inf, 1.0, dt), b.step(sig, v, v, np.inf, np.inf, 1.0, dt)
        assert np.array_equal(ra[0], rb[0]) and np.array_equal(ra[1], rb[1])
        a.theta  # noqa: B018 -- materialises a's state
    assert a.columns.lazy is False and b.columns.lazy is True
    assert np.array_equal(a.theta, b.theta) and np.array_equal(a.eps_p, b.eps_p)
    assert a.theta.shape == (7, 121)


@pytest.mark.parametrize("model", ["thermoelastic", "thermoelastoplastic"])
def test_checkpoint_in_the_lazy_state_restores_bit_for_bit(model, tmp_path):
    sig = np.linspace(2e9, 12e9, 5)
    v = np.linspace(80.0, 300.0, 5)
    make = lambda: SubgridInterface(5, AL, ST, n_cells=100, model=model, mu0=0.3, f=0.3)  # noqa: E731
    ref = make()
    for _ in range(30):
        ref.step(sig, v, v, np.inf, np.inf, 1.0, 1e-9)
    assert ref.columns.lazy
    with h5py.File(tmp_path / "c.h5", "w") as h5:
        save_object(h5.create_group("sg"), ref)
    back = make()
    with h5py.File(tmp_path / "c.h5", "r") as h5:
        load_object(h5["sg"], back, "sg")
    for _ in range(30):
        r1, r2 = ref.step(sig, v, v, np.inf, np.inf, 1.0, 1e-9), back.step(sig, v, v, np.inf, np.inf, 1.0, 1e-9)
        assert np.array_equal(r1[0], r2[0])
    for name in ("theta", "eps_p", "theta_interface", "plastic_work", "heat_plastic", "melt_energy"):
        assert np.array_equal(getattr(ref, name), getattr(back, name)), name
