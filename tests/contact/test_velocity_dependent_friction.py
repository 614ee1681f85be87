"""Velocity-dependent friction (modified Coulomb, eq. 2.90) evaluated at the corrected slip.

Kernel level: the per-node scalar equation tau = tau_max(|s*| - tau c) is solved (with and
without the relaxation of the law's slip), slip-independent laws give the same impulses for both
evaluations, and ``evaluation = "free"`` is the thesis's eq. 3.79.  Hydrocode level: the elastic
pressure-shear strip (steel on steel, 100 m/s at 30 degrees, mu0 = 0.3, mu_inf = 0.05,
gamma = 0.05 s/m) converges to the exact root s = V_t - mu(s) sigma_n (1/Z_1s + 1/Z_2s) with
30/60/120 cells per plate; the thesis's free-slip evaluation stays 5-8% low (docs/theory/slide-lines.md,
section 4)."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from shockfriction.analysis.interface_stability import unstable_modes
from shockfriction.analysis.pressure_shear import pressure_shear_velocity_dependent
from shockfriction.contact.impulses import normal_step, point_weights, tangential_step
from shockfriction.deck.base import validate
from shockfriction.contact.deck import SlideLineDeck
from shockfriction.errors import DeckError
from shockfriction.friction.laws import (COULOMB, COULOMB_TRESCA, MODIFIED_COULOMB, TRESCA, corrected_traction,
                                         law_parameters, traction_limit, velocity_dependent_mu)
from shockfriction.hydro.api import run_dict

MU0, MU_INF, GAMMA = 0.3, 0.05, 0.05
FRICTION = {"mu_inf": MU_INF, "gamma": f"{GAMMA} s/m"}


# ---------------------------------------------------------------- the per-node equation
def test_corrected_traction_is_the_law_at_the_corrected_slip():
    p = law_parameters(mu0=MU0, mu_inf=MU_INF, gamma=GAMMA, relaxation_steps=0)
    sigma, c = 2e9, 4.3e-8                    # Pa, m/s per Pa (the strip's step compliance)
    for s_free in (40.0, 80.0, -60.0):
        tau = corrected_traction(MODIFIED_COULOMB, p, sigma, abs(s_free), s_free, c, 1.0, np.inf, np.inf)
        s_corr = abs(s_free) - tau * c
        assert 0.0 < s_corr < abs(s_free)
        assert tau == pytest.approx(velocity_dependent_mu(s_corr, p) * sigma, rel=1e-13)
        # theta = 0 is the free slip of eq. 3.79
        free = corrected_traction(MODIFIED_COULOMB, p, sigma, abs(s_free), s_free, c, 0.0, np.inf, np.inf)
        assert free == traction_limit(MODIFIED_COULOMB, p, sigma, abs(s_free), np.inf, np.inf)
        assert free < tau                      # velocity weakening: the free slip under-estimates tau
    # a slow pair sticks: the law at zero slip (mu0) exceeds the sticking traction
    tau = corrected_traction(MODIFIED_COULOMB, p, sigma, 1.0, 1.0, c, 1.0, np.inf, np.inf)
    assert tau == pytest.approx(MU0 * sigma, rel=1e-15) and tau >= 1.0 / c
    # Coulomb-Tresca: the root also lands on the Tresca plateau
    q = law_parameters(mu0=MU0, mu_inf=MU_INF, gamma=GAMMA, mu_T=0.1, relaxation_steps=0)
    y = 1e9
    tau = corrected_traction(COULOMB_TRESCA, q, sigma, 80.0, 80.0, c, 1.0, y, y)
    assert tau == pytest.approx(traction_limit(COULOMB_TRESCA, q, sigma, 80.0 - tau * c, y, y), rel=1e-13)


def _pair(law, params, slip_law=None, vt=60.0, dt=1e-9):
    """One slave node (mass 2) on one guide node (mass 3) with normal closing speed 40 m/s."""
    mass = np.array([2.0, 3.0, 3.0])
    vx = np.array([vt, 0.0, 0.0])
    vy = np.array([-40.0, 0.0, 0.0])
    slave, guide = np.array([0]), np.array([1, 2])
    active = np.array([True])
    gnode, gw = np.zeros((1, 2), np.int64), np.zeros((1, 2))
    point_weights(guide, np.array([0]), np.array([0.0]), active, gnode, gw)
    lam_n, lam_t, s_free, s = (np.zeros(1) for _ in range(4))
    normal_step(vx, vy, mass, slave, gnode, gw, np.array([0.0]), np.array([1.0]), np.array([0.0]), active, dt,
                False, 50, 1e-12, lam_n)
    area = np.array([1e-3])
    tangential_step(vx, vy, mass, slave, gnode, gw, np.array([1.0]), np.array([0.0]), active, dt, area, law,
                    params, np.array([1e9]), np.array([1e9]), lam_n, 50, 1e-12, lam_t, s_free, s, slip_law)
    sigma = lam_n[0] / (dt * area[0])
    return sigma, abs(lam_t[0]) / (dt * area[0]), s_free[0], s[0]


def test_tangential_step_evaluations():
    corrected = law_parameters(mu0=MU0, mu_inf=MU_INF, gamma=GAMMA, relaxation_steps=0)
    sigma, tau, s_free, s = _pair(MODIFIED_COULOMB, corrected)
    print(f"corrected: sigma {sigma:.4g} Pa, tau {tau:.4g} Pa, free slip {s_free:.4g}, slip {s:.4g} m/s")
    assert 0.0 < s < s_free
    assert tau == pytest.approx(velocity_dependent_mu(s, corrected) * sigma, rel=1e-10)
    free = law_parameters(mu0=MU0, mu_inf=MU_INF, gamma=GAMMA, evaluation="free")
    sigma_f, tau_f, s_free_f, _ = _pair(MODIFIED_COULOMB, free)
    assert tau_f == pytest.approx(velocity_dependent_mu(s_free_f, free) * sigma_f, rel=1e-12)
    # relaxed: the law sees (s_law_old + |s|/n)/(1 + 1/n), and the state keeps that value
    n, s_old = 5.0, 10.0
    state = np.array([s_old])
    sigma, tau, _, s = _pair(MODIFIED_COULOMB, law_parameters(mu0=MU0, mu_inf=MU_INF, gamma=GAMMA,
                                                              relaxation_steps=n), slip_law=state)
    seen = (s_old + abs(s) / n) / (1.0 + 1.0 / n)
    assert state[0] == pytest.approx(seen, rel=1e-12)
    assert tau == pytest.approx(velocity_dependent_mu(seen, corrected) * sigma, rel=1e-10)


@pytest.mark.parametrize("law,kw", [(COULOMB, dict(mu0=0.2)), (TRESCA, dict(mu_T=0.3)),
                                    (MODIFIED_COULOMB, dict(mu0=0.2, mu_inf=0.2, gamma=GAMMA))])
def test_slip_independent_laws_ignore_the_evaluation(law, kw):
    out = [_pair(law, law_parameters(**kw, evaluation=ev)) for ev in ("corrected", "free")]
    assert out[0] == out[1]     # bit for bit


def test_deck_evaluation_option():
    base = {"guide": {"body": "a", "side": "top"}, "slave": {"body": "b", "side": "bottom"}}
    sl = validate(SlideLineDeck, {**base, "friction": {"law": "modified_coulomb", "mu0": 0.3, "mu_inf": 0.05}}, "t")
    assert sl.friction.evaluation == "corrected" and sl.friction.relaxation_steps == 5.0
    with pytest.raises(DeckError) as err:
        validate(SlideLineDeck, {**base, "friction": {"law": "coulomb", "mu0": 0.3, "evaluation": "mid"}}, "t")
    print(err.value)
    assert "evaluation" in str(err.value)


# ---------------------------------------------------------------- the pressure-shear strip
RHO, CL, CS = 7850.0, 5900.0, 3200.0
COMPLIANCE_S = 2.0 / (RHO * CS)


def _root(sigma_n):
    """Exact slip and shear of the 1D problem for a given normal stress."""
    def mu(s):
        return MU_INF + (MU0 - MU_INF) * math.exp(-GAMMA * s)
    s = brentq(lambda s: s - 50.0 + mu(s) * sigma_n * COMPLIANCE_S, 0.0, 50.0, xtol=1e-13)
    return s, mu(s) * sigma_n


def _strip(contact_decks, ny, evaluation="corrected", t0=0.4e-6, t1=0.85e-6, shear_viscosity="elastic"):
    deck = contact_decks["pressure_shear"](mu=MU0, law="modified_coulomb", end="0.9 us", ny=ny,
                                           friction_extra={**FRICTION, "evaluation": evaluation})
    deck["viscosity"] = {"shear": shear_viscosity}
    d = run_dict(deck).simulation.interfaces[0].record.arrays()
    sel = (d["t"] > t0) & (d["t"] < t1)
    return -d["tau"][sel].mean(), d["slip"][sel].mean(), d["sigma_n"][sel].mean()


def test_modified_coulomb_converges_to_the_exact_root(contact_decks):
    """Window [0.4, 0.85] us: after the start-up transient, before the release waves return (1.02 us).

    Two errors per mesh: against the exact solution (tau 186.87 MPa, slip 35.12 m/s), which
    keeps the hydrocode's mesh-independent +0.07% on sigma_n (finite strain against the acoustic
    solution, also seen with Coulomb), and the friction error: tau and slip against the exact
    root for the normal stress the run produced."""
    exact = pressure_shear_velocity_dependent(100.0, math.radians(30.0), MU0, MU_INF, GAMMA,
                                              RHO, CL, CS, RHO, CL, CS)
    assert exact.tau == pytest.approx(186.87e6, rel=1e-4) and exact.slip_rate == pytest.approx(35.12, rel=1e-3)
    meshes = (30, 60, 120)
    fric_err = []
    for ny in meshes:
        tau, slip, sigma = _strip(contact_decks, ny)
        s_ex, tau_ex = _root(sigma)
        e_tau, e_slip = (tau - tau_ex) / tau_ex, (slip - s_ex) / s_ex
        fric_err.append(max(abs(e_tau), abs(e_slip)))
        raw_tau, raw_slip = (tau - exact.tau) / exact.tau, (slip - exact.slip_rate) / exact.slip_rate
        print(f"{ny:4d} cells: tau {tau / 1e6:.3f} MPa ({raw_tau:+.3%} vs exact), slip {slip:.3f} m/s "
              f"({raw_slip:+.3%}), sigma_n {sigma / 1e9:.5f} GPa ({sigma / exact.sigma_n - 1:+.3%}); "
              f"friction error tau {e_tau:+.3%}, slip {e_slip:+.3%}")
        assert abs(raw_tau) < 0.03 and abs(raw_slip) < 0.03
    orders = [math.log2(a / b) for a, b in zip(fric_err, fric_err[1:])]
    print("friction error " + ", ".join(f"{e:.3%}" for e in fric_err) + "; observed orders "
          + ", ".join(f"{o:.2f}" for o in orders))
    assert all(b < a for a, b in zip(fric_err, fric_err[1:]))
    assert fric_err[-1] < 0.002


def test_free_slip_option_keeps_the_thesis_bias(contact_decks):
    """evaluation = "free" is the thesis's eq. 3.79: tau stays 4-9% below the exact value at every
    mesh (no convergence); regression pin of the 60-cell value (window [0.15, 0.85] us).  Pinned
    without the shear viscosity: with it (default) the bias is -6.4/-10.2/-13.3% at 30/60/120 cells,
    it grows as the damped lattice follows the biased law more closely."""
    exact_tau = pressure_shear_velocity_dependent(100.0, math.radians(30.0), MU0, MU_INF, GAMMA,
                                                  RHO, CL, CS, RHO, CL, CS).tau
    for ny in (30, 60, 120):
        tau, slip, _ = _strip(contact_decks, ny, "free", t0=0.15e-6, shear_viscosity="off")
        err = tau / exact_tau - 1.0
        print(f"free slip, {ny:4d} cells: tau {tau / 1e6:.3f} MPa ({err:+.2%}), slip {slip:.3f} m/s")
        assert -0.09 < err < -0.04
        if ny == 60:
            assert tau == pytest.approx(171.37e6, rel=2e-3)
            assert slip == pytest.approx(36.338, rel=2e-3)


def test_weakening_law_that_must_weld(contact_decks):
    """100 m/s at 45 degrees, mu0 = 0.6, mu_inf = 0.05, gamma = 0.02 s/m: mu(s) sigma_n > tau(s) for
    every slip s in [0, V_t], so the only solution is welded (tau = tau_s = 888.1 MPa).  The
    corrected evaluation welds; the free slip of eq. 3.79 starts at V_t = 70.7 m/s, sees a low mu and
    keeps sliding (about -50% in tau)."""
    mu0, mu_inf, gamma, angle = 0.6, 0.05, 0.02, math.radians(45.0)
    exact = pressure_shear_velocity_dependent(100.0, angle, mu0, mu_inf, gamma, RHO, CL, CS, RHO, CL, CS)
    vt = 100.0 * math.sin(angle)
    s = np.linspace(0.0, vt, 1001)
    mu = mu_inf + (mu0 - mu_inf) * np.exp(-gamma * s)
    assert exact.sticking and np.all(s - vt + mu * exact.sigma_n * COMPLIANCE_S > 0.0)   # no sliding root
    out = {}
    for evaluation in ("corrected", "free"):
        deck = contact_decks["pressure_shear"](mu=mu0, law="modified_coulomb", end="0.9 us", ny=60, angle_deg=45.0,
                                               friction_extra={"mu_inf": mu_inf, "gamma": f"{gamma} s/m",
                                                               "evaluation": evaluation})
        d = run_dict(deck).simulation.interfaces[0].record.arrays()
        sel = (d["t"] > 0.4e-6) & (d["t"] < 0.85e-6)
        out[evaluation] = (-d["tau"][sel].mean(), d["slip"][sel].mean())
        print(f"{evaluation}: tau {out[evaluation][0] / 1e6:.2f} MPa (welded exact {exact.tau / 1e6:.2f}), "
              f"slip {out[evaluation][1]:.3g} m/s")
    assert out["corrected"][0] == pytest.approx(exact.tau, rel=0.01)
    assert abs(out["corrected"][1]) < 1e-6 * vt
    assert out["free"][0] < 0.7 * exact.tau and out["free"][1] > 0.2 * vt


# ---------------------------------------------------------------- linear stability on the lattice
def test_lattice_stability_of_the_evaluations():
    """The strip's weakening slope b = |F_N| |dmu/ds| = 4.3e6 Pa s/m is 0.17 rho c_s.  Evaluations
    that see the slip without lag (free, midpoint, corrected) have a growing interface mode near the
    shear lattice's cutoff omega_c dt = 2 asin(lambda) (the flutter); with a lag (relaxed) or no
    phase (centred) there is none; without weakening nothing grows."""
    for lam in (0.15, 0.27):
        wc = 2.0 * math.asin(lam)
        for ev in ("free", "midpoint", "corrected", "centred", "relaxed"):
            assert unstable_modes(lam, 0.0, ev)[0] == 0
        for ev in ("free", "midpoint", "corrected"):
            count, z, w = unstable_modes(lam, 0.17, ev)
            print(f"lambda {lam}, {ev}: {count} growing modes, |z| - 1 = {z - 1:.2e} per step at {w / wc:.2f} omega_c")
            assert count == 2 and z - 1.0 > 1e-3 and 0.9 < w / wc < 1.0
        for ev, n in (("centred", 5), ("relaxed", 1), ("relaxed", 5), ("relaxed", 20)):
            assert unstable_modes(lam, 0.17, ev, n)[0] == 0
            assert unstable_modes(lam, 0.45, ev, n)[0] == 0


# ---------------------------------------------------------------- sliding block through all slip speeds
P_LOAD, RAMP, V0, H_MM = 100e6, 0.2e-6, 50.0, 0.2


class _TopPressure:
    """A uniform normal pressure p(t) on the block's top side (as in test_sliding_block.py)."""

    def __init__(self, sim, body, side, pressure):
        self.nodes = sim.mesh.side_nodes(body, side)
        self.pressure = pressure

    def apply(self, state, dt, t, cycle):
        x, y = state.x[self.nodes], state.y[self.nodes]
        seg = np.hypot(np.diff(x), np.diff(y))
        trib = np.zeros(self.nodes.size)
        trib[:-1] += 0.5 * seg
        trib[1:] += 0.5 * seg
        state.vy[self.nodes] -= self.pressure(t) * trib * dt / state.mass[self.nodes]


def _ramp(t):
    return P_LOAD * min(max(t / RAMP, 0.0), 1.0)


def test_sliding_block_decelerates_along_the_velocity_dependent_law(contact_decks):
    """Block (0.2 mm, 5 cells across) sliding at 50 m/s on a fixed base (3 cells across), pressed
    by a ramped 100 MPa: the rigid-block law dV/dt = -mu(V) p(t - H/c_L)/(rho H), with
    mu0 = 0.3, mu_inf = 0.1, gamma = 0.05 s/m, integrated to the stop; then it sticks (mu0).
    The slip speed sweeps the whole law, and the stick exercises the relaxed slip at rest."""
    from scipy.integrate import solve_ivp

    from shockfriction.hydro.api import prepare, run_simulation

    mu0, mu_inf = 0.3, 0.1
    block = contact_decks["block"]
    per = {"left": "periodic", "right": "periodic"}
    base = block("base", 0, 0.2, -H_MM, 0, 3, 4, dict(per, bottom="fixed"))
    top = block("block", 0, 0.2, 0, H_MM, 5, 4, per, (f"{V0} m/s", "0 m/s"))
    deck = {"title": "sliding block", "time": {"end": "6 us", "cfl": 0.5}, "bodies": [base, top],
            "slide_lines": [{"name": "slide", "guide": {"body": "base", "side": "top"},
                             "slave": {"body": "block", "side": "bottom"}, "record_interval": "20 ns",
                             "friction": {"law": "modified_coulomb", "mu0": mu0, **FRICTION, "mu_inf": mu_inf}}]}
    sim = prepare(deck)
    sim.register_interface(_TopPressure(sim, "block", "top", _ramp))
    blk = sim.mesh.node_body == 1
    history = []
    sim.observers.append(lambda s: history.append(
        (s.state.t, float(np.sum(s.state.mass_own[blk] * (s._vx_old[blk] + s.state.vx[blk])) / 2))))
    res = run_simulation(sim)
    mass = float(res.state.cell_mass[res.mesh.cell_body == 1].sum())
    h = np.array(history)
    t, v = h[:, 0], h[:, 1] / mass
    h_m = H_MM * 1e-3
    t_arrive = h_m / CL

    def rhs(time, y):
        mu = mu_inf + (mu0 - mu_inf) * math.exp(-GAMMA * max(y[0], 0.0))
        return [-mu * _ramp(time - t_arrive) / (RHO * h_m)]

    stop = lambda time, y: y[0]     # noqa: E731
    stop.terminal = True
    sol = solve_ivp(rhs, (0.0, t[-1]), [V0], events=stop, dense_output=True, rtol=1e-10, atol=1e-10)
    t_stop = sol.t_events[0][0]
    v_pred = np.where(t < t_stop, sol.sol(np.minimum(t, t_stop))[0], 0.0)
    err = np.abs(v - v_pred).max() / V0
    t_stop_sim = t[np.argmax(v < 0.01 * V0)]
    print(f"stop at {t_stop * 1e6:.3f} us (simulated {t_stop_sim * 1e6:.3f} us, {t_stop_sim / t_stop - 1:+.2%}); "
          f"max |V - V_law|/V0 = {err:.2%}; after the stop max |V| {np.abs(v[t > t_stop + 0.1e-6]).max() / V0:.2%}")
    assert err < 0.03
    assert t_stop_sim == pytest.approx(t_stop, rel=0.03)
    assert np.abs(v[t > t_stop + 0.1e-6]).max() < 0.03 * V0
