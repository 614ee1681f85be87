"""Smooth flow: an acoustic standing wave converges at second order in space and time
(the Wilkins / von Neumann-Richtmyer scheme's claim, thesis section 3.2.1).

Ideal gas between two walls 1 m apart, v(y, 0) = A sin(pi y), A = 1e-6 c (linear regime), square
cells, no linear viscosity (first order by design; the quadratic term is O(A^2)).  Exact:
p' = -rho0 c A cos(pi y) sin(omega t), compared at a quarter period where |p'| is largest.
"""

from pathlib import Path

import numpy as np
import pytest

from shockfriction.analysis.convergence import l1_error, observed_order
from shockfriction.analysis.strip import read_deck, strip_profile
from shockfriction.hydro.api import prepare, run_simulation

DECKS = Path(__file__).resolve().parents[2] / "examples" / "verification"
GAMMA, RHO0, P0 = 1.4, 1.0, 1.0
C = np.sqrt(GAMMA * P0 / RHO0)
AMPLITUDE = 1e-6 * C
K = np.pi
OMEGA = C * K


def _prepared(cells, width=None, t_end=None):
    deck = read_deck(DECKS / "acoustic_standing_wave.toml")
    mesh = deck["bodies"][0]["mesh"]
    mesh["ny"] = cells
    w = 1.0 / cells if width is None else width
    mesh["corners"][1][0] = mesh["corners"][2][0] = f"{w} m"
    deck["time"]["end"] = f"{t_end if t_end is not None else 0.5 * np.pi / OMEGA} s"
    sim = prepare(deck)
    sim.state.vy[:] = AMPLITUDE * np.sin(K * sim.state.y)
    sim.reinitialize()  # first step and initial energy from the edited velocities
    return sim


def pressure_error(cells, width=None):
    result = run_simulation(_prepared(cells, width))
    prof = strip_profile(result.state, "y")
    exact = -RHO0 * C * AMPLITUDE * np.cos(K * prof["coord"]) * np.sin(OMEGA * result.state.t)
    return l1_error(prof["p"] - P0, exact, prof["size"]) / (RHO0 * C * AMPLITUDE)


def test_acoustic_wave_second_order():
    cells = (25, 50, 100)
    errors = [pressure_error(n) for n in cells]
    order = observed_order([1.0 / n for n in cells], errors)
    print(f"\nacoustic standing wave: relative L1(p') = {errors} at {cells} cells, observed order {order:.3f}")
    assert order > 1.9
    assert errors[-1] < 1e-4


@pytest.mark.slow
def test_acoustic_wave_second_order_fine():
    cells = (50, 100, 200, 400)
    errors = [pressure_error(n) for n in cells]
    order = observed_order([1.0 / n for n in cells], errors)
    print(f"\nacoustic standing wave: relative L1(p') = {errors} at {cells} cells, observed order {order:.3f}")
    assert order > 1.9


def test_ideal_gas_sound_speed_is_gamma_p_over_rho():
    sim = _prepared(50)
    assert np.allclose(sim.state.sound_speed, C, rtol=1e-12)
