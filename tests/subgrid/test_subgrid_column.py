"""Thermal column against exact half-space solutions (thesis §7.2, digest §10 cases 1-5, 11, 12)."""

import math

import numpy as np
import pytest

from shockfriction.friction.subgrid import analytic
from shockfriction.friction.subgrid.column import (ThermalColumns, heat_matrix, make_grid, thomas_apply,
                                                   thomas_factor, thomas_solve)
from shockfriction.materials.library import get_material

AL = get_material("Al5083-H111")
TI = get_material("Ti-6Al-4V")


def column(mat, h, M, n=1, grading=1.0):
    return ThermalColumns(n, h, M, mat.conductivity, mat.rho0, mat.heat_capacity, T0=300.0, grading=grading)


@pytest.mark.parametrize("mat, fo", [(AL, 30.6), (get_material("AISI321"), 2.55)])
def test_thomas_matches_dense_solve_on_the_thesis_matrix(mat, fo):
    z = make_grid(20e-6, 500)
    a, b, c = heat_matrix(z, mat.diffusivity, 1e-9)
    assert -c[1] == pytest.approx(fo, rel=2e-3)  # Fo = alpha dt/dz^2 of digest §5.2
    rng = np.random.default_rng(1)
    d = rng.normal(size=z.size)
    K = np.diag(b) + np.diag(a[1:], -1) + np.diag(c[:-1], 1)
    ref = np.linalg.solve(K, d)
    x = thomas_solve(a, b, c, d)
    mult, inv_bp = thomas_factor(a, b, c)
    y = np.empty_like(d)
    thomas_apply(mult, inv_bp, c, d, y)
    assert np.max(np.abs(x - ref)) / np.max(np.abs(ref)) < 1e-13
    assert np.max(np.abs(y - ref)) / np.max(np.abs(ref)) < 1e-13


def test_constant_flux_surface_and_depth_profile_match_the_half_space():
    """theta(0,t) - T0 = 2 q sqrt(t/pi)/e (eq. 7.33); ierfc profile (eq. 7.28).

    Backward Euler started on the sqrt(t) singularity has a relative start-up error
    close to 0.125 dt/t (first order in dt/t): below 0.5% from step 30 (30 ns) on.
    """
    q, dt, nsteps = 1e10, 1e-9, 1000
    col = column(AL, 100e-6, 2500)  # dz = 40 nm, h >> 2 sqrt(alpha t) = 14 um at 1 us
    worst, scaled = 0.0, []
    for n in range(1, nsteps + 1):
        col.step(dt, q)
        exact = analytic.surface_rise_constant_flux(q, n * dt, AL.conductivity, AL.diffusivity)
        err = abs(col.theta[0, 0] - 300.0 - exact) / exact
        if n >= 30:
            worst = max(worst, err)
        if n >= 5:
            scaled.append(err * n)
    print(f"\nconstant flux: worst surface error from step 30 {worst:.3e}; n * error in "
          f"[{min(scaled):.3f}, {max(scaled):.3f}]; at 1 us rise {col.theta[0, 0] - 300:.2f} K vs {exact:.2f} K")
    assert exact == pytest.approx(674.3, rel=1e-3)  # digest §10 case 1
    assert worst < 5e-3
    assert max(scaled) < 0.13  # error <= 0.13 dt/t: first order in dt/t from the start
    prof = analytic.profile_constant_flux(q, col.z, nsteps * dt, AL.conductivity, AL.diffusivity)
    err = np.max(np.abs(col.theta[0] - 300.0 - prof)) / prof[0]
    print(f"depth profile: max error / surface rise {err:.3e}")
    assert err < 5e-3


def test_flux_switched_off_follows_the_two_term_superposition():
    """Flux q on [0, t1], zero after (eq. 7.54-7.55): FD column within 1% of the peak rise (from step 30)."""
    q, dt, t1, t_end = 6.12e9, 1e-9, 1.0e-6, 3.0e-6
    col = column(TI, 20e-6, 500)
    peak = analytic.surface_rise_constant_flux(q, t1, TI.conductivity, TI.diffusivity)
    worst = 0.0
    for n in range(1, int(round(t_end / dt)) + 1):
        t = n * dt
        col.step(dt, q if t <= t1 + 1e-15 else 0.0)
        exact = analytic.profile_piecewise_flux([q], [0.0, t1], col.z, t, TI.conductivity, TI.diffusivity)
        if n >= 30:
            worst = max(worst, np.max(np.abs(col.theta[0] - 300.0 - exact)) / peak)
    print(f"\nswitch-off: worst profile error / peak rise {worst:.3e}")
    assert worst < 1e-2


def test_duhamel_sum_matches_fd_for_a_multistage_flux_with_variable_steps():
    """Prakash-like multi-stage flux, steps alternating 0.6/1.4 ns: Duhamel (eq. 7.56) vs FD within 1%."""
    steps = np.tile([0.6e-9, 1.4e-9], 1650)
    t = np.cumsum(steps)
    fluxes = np.where(t <= 1.8e-6 + 1e-15, 6.12e9, 2.88e9) * 0.2
    fluxes[(t > 2.6e-6)] = 0.5e9
    duh = analytic.duhamel_surface(fluxes, steps, TI.conductivity, TI.diffusivity)
    col = column(TI, 20e-6, 500)
    fd = np.empty(t.size)
    for n, (dt, q) in enumerate(zip(steps, fluxes)):
        col.step(dt, q)
        fd[n] = col.theta[0, 0] - 300.0
    err = np.max(np.abs(fd[10:] - duh[10:])) / np.max(duh)
    print(f"\nDuhamel vs FD, variable steps: max error / max rise {err:.3e}; "
          f"{col.factorisations} factorisations for {steps.size} steps")
    assert err < 1e-2
    assert col.factorisations == 2  # two distinct steps, each factored once
    # the general sum reduces to the Toeplitz/FFT form for a constant step
    qu = np.linspace(1e9, 3e9, 300)
    a = analytic.duhamel_surface(qu, np.full(300, 1e-9), TI.conductivity, TI.diffusivity)
    b = analytic.duhamel_surface_uniform(qu, 1e-9, TI.conductivity, TI.diffusivity)
    assert np.max(np.abs(a - b)) / np.max(a) < 1e-12


def test_affine_map_reproduces_a_direct_solve():
    """theta = theta_ad + q theta_unit (eq. 7.67-7.70) equals a direct solve with the flux in the rhs."""
    rng = np.random.default_rng(7)
    col = column(AL, 20e-6, 500, n=3, grading=1.01)
    col.theta[...] = 300.0 + rng.uniform(0.0, 500.0, size=col.theta.shape)
    col.active[:] = True
    src = rng.uniform(0.0, 1e18, size=col.theta.shape)
    dt = 1e-9
    q = rng.uniform(1e9, 3e10, size=3)
    old = col.theta.copy()
    new = col.affine(col.adiabatic(dt, src), q)
    a, b, c = heat_matrix(col.z, col.alpha, dt)
    worst = 0.0
    for j in range(3):
        rhs = old[j] + dt * src[j] / col.rho_c
        rhs[0] += dt * q[j] / (col.rho_c * col.weights[0])
        direct = thomas_solve(a, b, c, rhs)
        worst = max(worst, np.max(np.abs(new[j] - direct)) / np.max(np.abs(direct - old[j])))
    print(f"\naffine vs direct: {worst:.2e}")
    assert worst < 1e-12


def _smooth_run(M, dt, T=0.4e-6, h=20e-6, grading=1.0):
    col = column(AL, h, M, grading=grading)
    n = int(round(T / dt))
    for k in range(1, n + 1):
        t = k * dt
        col.step(dt, 2e10 * math.sin(0.5 * math.pi * t / T) ** 2)
    return col.theta[0, 0]


def test_backward_euler_is_first_order_in_time():
    vals = [_smooth_run(400, dt) for dt in (4e-9, 2e-9, 1e-9, 0.5e-9)]
    d = np.abs(np.diff(vals))
    orders = np.log2(d[:-1] / d[1:])
    print(f"\nobserved orders in dt: {orders}")
    assert np.all(np.abs(orders - 1.0) < 0.15)


@pytest.mark.parametrize("grading", [1.0, 1.002])
def test_space_discretisation_is_second_order(grading):
    """Same dt on every grid, so successive differences isolate the spatial error (graded: r^(1/2) per halving)."""
    Ms = (25, 50, 100, 200)
    vals = [_smooth_run(M, 2e-9, grading=grading ** (25 / M)) for M in Ms]
    d = np.abs(np.diff(vals))
    orders = np.log2(d[:-1] / d[1:])
    print(f"\nobserved orders in dz (grading {grading}): {orders}")
    assert np.all(np.abs(orders - 2.0) < 0.15)


def test_energy_balance_holds_at_every_step_with_sources_and_variable_steps():
    """rho c int (theta - T0) dz = sum dt (q_in + int s dz) to 1e-10 relative (digest §10 case 11)."""
    rng = np.random.default_rng(3)
    col = column(AL, 20e-6, 300, n=4, grading=1.01)
    put_in = np.zeros(4)
    worst = 0.0
    for n in range(400):
        dt = rng.uniform(0.5e-9, 2e-9)
        q = rng.uniform(0.0, 2e10, size=4)
        src = np.where(rng.uniform(size=col.theta.shape) < 0.1, rng.uniform(0, 1e17, size=col.theta.shape), 0.0)
        col.step(dt, q, src)
        put_in += dt * (q + src @ col.weights)
        worst = max(worst, np.max(np.abs(col.heat_content() - put_in) / put_in))
    print(f"\nenergy balance: worst relative error {worst:.2e}")
    assert worst < 1e-10


def test_graded_grid_is_accurate_with_fewer_cells():
    """A graded 100-cell column reproduces the half-space surface rise like the uniform 500-cell one."""
    q, dt = 1e10, 1e-9
    col = column(AL, 20e-6, 100, grading=1.03)
    for n in range(300):
        col.step(dt, q)
    exact = analytic.surface_rise_constant_flux(q, 300 * dt, AL.conductivity, AL.diffusivity)
    err = abs(col.theta[0, 0] - 300 - exact) / exact
    print(f"\ngraded grid (dz0 = {col.z[1]:.2e} m): surface error {err:.2e}")
    assert col.z[1] < 20e-6 / 500
    assert err < 5e-3


def test_blocked_batched_solve_matches_column_by_column_with_idle_columns():
    """19 columns (blocks of 8 plus a remainder), some idle: each equals its own Thomas solve."""
    rng = np.random.default_rng(2)
    col = column(AL, 20e-6, 120, n=19)
    col.theta[...] = 300.0 + rng.uniform(0.0, 100.0, size=col.theta.shape)
    col.active[:] = rng.uniform(size=19) < 0.6
    col.theta[~col.active] = 300.0
    dt = 0.7e-9
    ad = col.adiabatic(dt).copy()
    a, b, c = heat_matrix(col.z, col.alpha, dt)
    for j in range(19):
        expected = thomas_solve(a, b, c, col.theta[j]) if col.active[j] else col.theta[j]
        assert np.max(np.abs(ad[j] - expected)) < 1e-12 * 400.0


def test_column_sums_are_the_books_weighted_sums_in_node_order():
    """column_sums (the books' per-area sums, one thread, no BLAS) against math.fsum per column: the sequential sum
    of 501 terms within 1.07e-16 of the sum of magnitudes (measured; the order is fixed, so this is reproducible)."""
    import math

    from shockfriction.friction.subgrid.column import column_sums

    rng = np.random.default_rng(3)
    w = rng.uniform(0.0, 1e-8, 501)
    X = np.asfortranarray(rng.uniform(-1e9, 1e9, (501, 40)))
    got = column_sums(w, X)
    exact = np.array([math.fsum(w * X[:, j]) for j in range(40)])
    scale = np.array([math.fsum(np.abs(w * X[:, j])) for j in range(40)])
    assert np.max(np.abs(got - exact) / scale) <= 2e-16
    assert np.array_equal(column_sums(w, np.ascontiguousarray(X)), got)  # the same order whatever the layout


@pytest.mark.parametrize("h, M, r", [(20e-6, 500, 1.0), (20e-6, 500, 1.01), (2e-6, 200, 1.2), (20e-6, 100, 1.05)])
def test_smallest_cell_is_the_grids_first_cell(h, M, r):
    """``smallest_cell`` (what the decks check against MIN_CELL) is make_grid's first cell, bit for bit where graded."""
    from shockfriction.friction.subgrid.column import smallest_cell

    z = make_grid(h, M, r)
    if r > 1.0:
        assert smallest_cell(h, M, r) == z[1] - z[0] == np.min(np.diff(z))
    else:  # linspace's cells differ from h/M by round-off
        assert np.min(np.diff(z)) == pytest.approx(smallest_cell(h, M, r), rel=1e-9)


def test_a_grading_whose_first_cell_underflows_is_refused():
    """r^M beyond a float (2^2000): smallest_cell says 0 and make_grid refuses with a message (it raised
    OverflowError, which the command line reported as an internal error)."""
    from shockfriction.friction.subgrid.column import smallest_cell

    assert smallest_cell(2e-6, 2000, 2.0) == 0.0
    with pytest.raises(ValueError, match="underflows"):
        make_grid(2e-6, 2000, 2.0)
