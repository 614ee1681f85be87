"""Prescribed-velocity piston into an ideal gas (Rankine-Hugoniot), the interface hook's
energy bookkeeping, and the parallel kernels against the serial ones."""

import numpy as np
import pytest

from shockfriction.hydro.api import prepare, run_dict, run_simulation


def _piston(up=100.0, end="1.5 ms"):
    return {"time": {"end": end},
            "bodies": [{"name": "gas", "eos": "ideal-gas", "gamma": 1.4, "density": "1.2 kg/m^3",
                        "pressure": "1 bar", "heat_capacity": "718 J/(kg*K)",
                        "mesh": {"corners": [["0 m", "0 m"], ["0.01 m", "0 m"], ["0.01 m", "1 m"], ["0 m", "1 m"]],
                                 "nx": 1, "ny": 400},
                        "boundary": {"left": "symmetry", "right": "symmetry", "top": "fixed",
                                     "bottom": {"type": "velocity", "vy": f"{up} m/s"}}}],
            "probes": [{"name": "mid", "body": "gas", "cell": [0, 100], "quantities": ["p", "rho", "T"]}]}


def test_piston_driven_shock_in_an_ideal_gas():
    up, g, rho0, p0 = 100.0, 1.4, 1.2, 1e5
    c0 = np.sqrt(g * p0 / rho0)
    a = (g + 1) / 4 * up
    us = a + np.sqrt(a * a + c0 * c0)
    p1 = p0 + rho0 * us * up
    rho1 = rho0 * us / (us - up)
    res = run_dict(_piston(up))
    t = res.probes["t_s"]
    y_cell = 0.25 + 0.5 / 400
    t_arr = y_cell / us
    sel = t > t_arr + 0.15e-3
    p = res.probes["mid.p"][sel].mean()
    rho = res.probes["mid.rho"][sel].mean()
    print(f"Us = {us:.2f} m/s; P = {p:.1f} (exact {p1:.1f}), rho = {rho:.5f} (exact {rho1:.5f}); "
          f"relative energy error {res.summary['relative_energy_error']:.2e}")
    assert p == pytest.approx(p1, rel=5e-3)
    assert rho == pytest.approx(rho1, rel=5e-3)
    # shock arrival within two cells of the exact one
    k = np.argmax(res.probes["mid.p"] > 0.5 * (p0 + p1))
    assert t[k] == pytest.approx(t_arr, abs=2 * (1.0 / 400) / us)
    # the piston's work is the energy put into the gas: p1 * up * t per unit area (x the strip width)
    e = res.energy
    expected = p1 * up * e["t_s"][-1] * 0.01
    assert e["boundary_work"][-1] == pytest.approx(expected, rel=5e-3)
    assert res.summary["relative_energy_error"] < 1e-3
    assert res.probes["mid.T"][0] == pytest.approx(p0 / (0.4 * rho0) / 718.0, rel=1e-12)


class Brake:
    """A test interface: a drag impulse -rate dt v on every node; the lost kinetic energy goes
    into the first cell as heat (like friction with heating)."""

    def __init__(self, rate):
        self.rate = rate

    def apply(self, state, dt, t, cycle):
        v_old_x, v_old_y = state.vx.copy(), state.vy.copy()
        state.vx *= 1 - self.rate * dt
        state.vy *= 1 - self.rate * dt
        lost = 0.5 * np.sum(state.mass_own * (v_old_x**2 + v_old_y**2 - state.vx**2 - state.vy**2))
        state.e[0] += lost / state.cell_mass[0]
        state.energy.interface_heat += lost
        state.energy.friction_work += lost


def test_interface_hook_energy_bookkeeping():
    deck = {"time": {"end": "1 us"},
            "bodies": [{"name": "b", "material": "Al6061-T6", "strength": "elastic-perfectly-plastic",
                        "velocity": ["100 m/s", "50 m/s"],
                        "mesh": {"corners": [["0 mm", "0 mm"], ["2 mm", "0 mm"], ["2 mm", "2 mm"], ["0 mm", "2 mm"]],
                                 "nx": 4, "ny": 4}}]}
    sim = prepare(deck)
    sim.register_interface(Brake(1e5))  # 1/s
    res = run_simulation(sim)
    e = res.energy
    print(f"kinetic {e['kinetic'][0]:.4g} -> {e['kinetic'][-1]:.4g} J/m, interface work "
          f"{e['interface_work'][-1]:.4g}, heat {e['interface_heat'][-1]:.4g}, error {np.abs(e['error']).max():.2e}")
    assert e["kinetic"][-1] < 0.9 * e["kinetic"][0]
    # the velocity corrections' work is minus the heat they released (up to the leapfrog averaging)
    assert e["interface_work"][-1] == pytest.approx(-e["interface_heat"][-1], rel=2e-3)
    assert res.summary["relative_energy_error"] < 1e-3


def test_parallel_kernels_match_serial():
    deck = {"time": {"end": "0.6 us"},
            "bodies": [{"name": "b", "material": "Al6061-T6", "strength": "scg", "velocity": ["0 m/s", "-400 m/s"],
                        "mesh": {"corners": [["0 mm", "0 mm"], ["3 mm", "0 mm"], ["3 mm", "3 mm"], ["0 mm", "3.5 mm"]],
                                 "nx": 12, "ny": 12},
                        "boundary": {"bottom": "fixed", "left": "symmetry"}}],
            "geometry": "axisymmetric"}
    serial = run_dict(deck, threads=1)
    par = run_dict(deck, threads=2)
    a, b = serial.state, par.state
    assert a.cycle == b.cycle
    for name in ("x", "y", "vx", "vy", "pressure", "sxx", "sxy", "eps_p", "temperature"):
        u, v = getattr(a, name), getattr(b, name)
        scale = max(np.abs(u).max(), 1e-30)
        assert np.abs(u - v).max() <= 1e-9 * scale, name
    assert a.eps_p.max() > 0


class Recorder:
    """An interface with the optional hooks: counts after_step calls, is closed at the end."""

    def __init__(self):
        self.applied, self.after, self.closed, self.times = 0, 0, False, []

    def apply(self, state, dt, t, cycle):
        self.applied += 1

    def after_step(self, state, dt, t, cycle):
        self.after += 1
        self.times.append((t, cycle))

    def close(self):
        self.closed = True


def test_optional_interface_hooks(make_strip, tmp_path):
    rec = Recorder()
    sim = prepare(make_strip(ny_flyer=4, ny_target=10, end="0.3 us"), interfaces=[rec])
    res = run_simulation(sim, tmp_path)
    assert sim.out_dir == tmp_path
    assert rec.closed
    assert rec.after == res.state.cycle
    assert rec.applied == res.state.cycle + 1  # and the final record's velocity update
    assert rec.times[-1] == (res.state.t, res.state.cycle)
