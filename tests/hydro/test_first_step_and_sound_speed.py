"""The first step of a flow driven onto a wall (a cold gas, whose sound speed does not limit the
step), a fix found by the verification suite (the ideal-gas sound speed fix is tested in
tests/verification/test_hydro_acoustic_order.py)."""

import numpy as np

from shockfriction.hydro.api import prepare, run_dict


def _gas_strip(ny=100, energy="1e-6 J/kg", velocity="-1 m/s", end="0.05 s", pressure=None):
    body = {
        "name": "gas", "eos": "ideal-gas", "gamma": 5.0 / 3.0, "density": "1 kg/m^3",
        "velocity": ["0 m/s", velocity],
        "mesh": {"corners": [["0 m", "0 m"], ["0.01 m", "0 m"], ["0.01 m", "1 m"], ["0 m", "1 m"]],
                 "nx": 1, "ny": ny},
        "boundary": {"left": "symmetry", "right": "symmetry", "bottom": "symmetry"},
    }
    if pressure is None:
        body["specific_energy"] = energy
    else:
        body["pressure"] = pressure
    return {"title": "cold gas onto a wall", "time": {"end": end}, "bodies": [body]}


def test_first_step_sees_the_wall_that_stops_the_initial_flow():
    """The wall zeroes the bottom nodes' normal velocity: the first cell shrinks at |v|/dy, so the
    volume-change cap bounds the first step by max_volume_change dy/|v| = 0.1 x 0.01 m/(1 m/s)."""
    sim = prepare(_gas_strip())
    assert sim.state.dt <= 0.1 * 0.01 / 1.0 * (1 + 1e-12)
    res = run_dict(_gas_strip(end="0.3 s"), None)   # used to invert cell (0, 0) at cycle 0
    assert res.summary["completed"]
    # Noh, planar: density 4 behind the shock at y = t/3 = 0.1 m, i.e. in the first 40 of the
    # 100 cells (each compressed 4 times); the wall-heating cells (about 10) are left out.
    rho = res.state.rho
    assert np.all(np.abs(rho[10:35] - 4.0) < 0.01 * 4.0), rho[10:35]
    assert np.allclose(rho[45:], 1.0, rtol=2e-3)
