"""The per-step API the slide line calls: caps of Table 6.1, signs, momentum, idle nodes, errors."""

import numpy as np
import pytest

from shockfriction.errors import SimulationError
from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.materials.library import get_material

AL = get_material("Al5083-H111")
ST = get_material("AISI321")


def make(n=1, model="thermoelastic", **kw):
    kw.setdefault("mu0", 0.3)
    kw.setdefault("f", 0.3)
    return SubgridInterface(n, AL, ST, model=model, **kw)


@pytest.mark.parametrize("model", ["thermoelastic", "thermoelastoplastic"])
def test_coulomb_cap_binds_with_large_f(model):
    sg = make(model=model, mu0=0.05, f=50.0)
    ms, mg, S, dt, sigma, v = 2e-6, 6e-6, 1e-8, 1e-9, 2e9, -150.0
    tau, slip = sg.step(sigma, v, v, ms, mg, S, dt)
    assert tau[0] == pytest.approx(0.05 * sigma, rel=1e-15)
    expected = v + tau[0] * S * dt * (1 / ms + 1 / mg)  # friction opposes the (negative) free slip
    assert slip[0] == pytest.approx(expected, rel=1e-14)
    assert -150.0 < slip[0] < 0.0


@pytest.mark.parametrize("model", ["thermoelastic", "thermoelastoplastic"])
def test_sticking_cap_uses_the_reduced_mass_and_stops_the_slip(model):
    sg = make(model=model, mu0=0.3, f=1e3)
    ms, mg, S, dt, v = 1e-9, 3e-9, 1e-8, 1e-9, 2.0
    tau, slip = sg.step(10e9, v, v, ms, mg, S, dt)
    tau_stick = ms * mg / (ms + mg) * abs(v) / dt / S   # F* = m_r [V*]/dt (eq. 6.82), per area
    assert tau_stick < 0.3 * 10e9
    assert tau[0] == pytest.approx(tau_stick, rel=1e-12)
    assert abs(slip[0]) < 1e-12 * abs(v)


def test_impulses_conserve_momentum_and_oppose_the_free_slip():
    """Apply the documented impulses to two nodes: momentum is conserved and the slip is the returned one."""
    rng = np.random.default_rng(5)
    n = 64
    ms, mg = rng.uniform(1e-9, 1e-8, n), rng.uniform(1e-9, 1e-8, n)
    vs, vg = rng.normal(0, 100, n), rng.normal(0, 100, n)
    S, dt = rng.uniform(5e-9, 2e-8, n), 1e-9
    sigma = rng.uniform(-1e9, 10e9, n)
    sg = make(n, mu0=0.2, f=0.5)
    v_free = vs - vg
    tau, slip = sg.step(sigma, v_free, v_free, ms, mg, S, dt)
    J = -np.sign(v_free) * tau * S * dt     # impulse on the slave node
    vs1, vg1 = vs + J / ms, vg - J / mg
    assert np.allclose(ms * vs1 + mg * vg1, ms * vs + mg * vg, rtol=1e-12, atol=1e-18)
    assert np.allclose(vs1 - vg1, slip, rtol=1e-12, atol=1e-10)
    assert np.all(np.abs(slip) <= np.abs(v_free) + 1e-12)
    assert np.all(slip * v_free >= 0.0)     # never reversed
    assert np.all(tau[sigma <= 0] == 0.0) and np.all(tau[sigma > 0] > 0.0)
    assert np.all(tau <= 0.2 * np.maximum(sigma, 0.0) + 1e-6)


def test_only_slipping_nodes_in_contact_heat():
    sg = make(4, model="thermoelastoplastic")
    sigma = np.array([10e9, -1e9, 10e9, 0.0])
    v = np.array([200.0, 200.0, 0.0, 200.0])
    for _ in range(20):
        tau, slip = sg.step(sigma, v, v, np.inf, np.inf, 1.0, 1e-9)
    assert tau[0] > 0 and np.all(tau[1:] == 0.0)
    assert sg.theta_interface[0] > 500.0
    assert np.all(sg.theta[1:] == 300.0) and np.all(sg.flux_in[1:] == 0.0) and np.all(sg.eps_p[1:] == 0.0)
    assert list(sg.columns.active) == [True, False, False, False]


def test_a_batch_equals_the_columns_run_one_by_one():
    rng = np.random.default_rng(11)
    n = 6
    sigma, v = rng.uniform(1e9, 10e9, n), rng.uniform(-300, 300, n)
    ms, mg, S = rng.uniform(1e-9, 1e-8, n), rng.uniform(1e-9, 1e-8, n), 1e-8
    batch = make(n, model="thermoelastoplastic")
    singles = [make(1, model="thermoelastoplastic") for _ in range(n)]
    vb = v.copy()
    vs = [np.array([x]) for x in v]
    for _ in range(30):
        tau_b, vb = batch.step(sigma, v, vb, ms, mg, S, 1e-9)
        for j, sj in enumerate(singles):
            tau_j, vs[j] = sj.step(sigma[j], v[j], vs[j], ms[j], mg[j], S, 1e-9)
            assert tau_j[0] == tau_b[j]
    for j, sj in enumerate(singles):
        assert np.array_equal(sj.theta[0], batch.theta[j])


@pytest.mark.parametrize("model", ["thermoelastic", "thermoelastoplastic"])
def test_time_step_change_reuses_factors_and_keeps_energy(model):
    sg = make(2, model=model, f=0.35)
    for dt in [1e-9] * 10 + [0.5e-9] * 10 + [1e-9] * 10 + [0.3e-9] * 5:
        sg.step(5e9, 100.0, 100.0, np.inf, np.inf, 1.0, dt)
        assert np.allclose(sg.heat_stored, sg.heat_interface + sg.heat_plastic, rtol=1e-12)
        assert np.allclose(sg.friction_work, sg.heat_interface / sg.beta_T + sg.plastic_work, rtol=1e-12)
    assert sg.columns.factorisations == 3
    if model == "thermoelastoplastic":
        assert sg.heat_plastic[0] > 0.0


def test_nodes_out_of_contact_may_have_zero_area():
    sg = make(2)
    tau, slip = sg.step([-1e9, 0.0], [10.0, -5.0], [10.0, -5.0], 1e-9, 1e-9, 0.0, 1e-9)
    assert np.all(tau == 0.0) and list(slip) == [10.0, -5.0]
    with pytest.raises(SimulationError, match="node 1"):
        sg.step([-1e9, 1e9], 10.0, 10.0, 1e-9, 1e-9, [0.0, 0.0], 1e-9)


def test_bad_input_raises_a_simulation_error_naming_node_and_cycle():
    sg = make(3)
    with pytest.raises(SimulationError, match=r"cycle 7, t = 7\.0+e-09 s.*node 1"):
        sg.step([1e9, np.nan, 1e9], 10.0, 10.0, 1.0, 1.0, 1.0, 1e-9, cycle=7, time=7e-9)


def test_constructor_refuses_initial_temperature_at_melting():
    with pytest.raises(ValueError, match="below the melting"):
        make(T0=AL.melting_temperature)
