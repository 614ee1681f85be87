"""Taylor anvil (OFHC copper, SCG, 190 m/s, 25.4 mm x 7.62 mm, rigid frictionless wall, r-z):
final length and foot radius converge with mesh refinement.

No exact solution exists.  The set-up is Johnson & Cook's (1983) copper cylinder test; we found
no published final dimensions for this exact material model to compare with, so the test
checks mesh convergence (observed order from three meshes) and the momentum-energy sanity
of the end state.  Refinement doubles nx and ny together (8x53, 16x107, 32x213 cells).
"""

from pathlib import Path

import numpy as np
import pytest

from shockfriction.analysis.strip import read_deck
from shockfriction.hydro.api import run

DECKS = Path(__file__).resolve().parents[2] / "examples" / "verification"


def taylor(nx: int) -> tuple[float, float, float, float]:
    deck = read_deck(DECKS / "taylor_anvil_cu.toml")
    mesh = deck["bodies"][0]["mesh"]
    mesh["nx"], mesh["ny"] = nx, int(round(nx * 25.4 / 3.81))
    result = run(deck)
    length = result.probes["top.y"][-1]
    radius = result.probes["foot.x"][-1]
    kinetic_left = result.energy["kinetic"][-1] / result.energy["kinetic"][0]
    return length, radius, kinetic_left, result.summary["relative_energy_error"]


@pytest.mark.slow
def test_taylor_anvil_converges():
    sizes = (8, 16, 32)
    runs = [taylor(n) for n in sizes]
    lengths = np.array([r[0] for r in runs])
    radii = np.array([r[1] for r in runs])
    h = 3.81e-3 / np.array(sizes)
    print("\nTaylor anvil (Cu-OFHC, SCG, 190 m/s): nx, final length (mm), foot radius (mm), "
          "kinetic energy left, energy error")
    for n, r in zip(sizes, runs):
        print(f"  {n:3d} {r[0] * 1e3:.4f} {r[1] * 1e3:.4f} {r[2]:.2e} {r[3]:.1e}")
    for name, q in (("length", lengths), ("foot radius", radii)):
        d1, d2 = q[1] - q[0], q[2] - q[1]
        ratio = np.log(abs(d1 / d2)) / np.log(h[1] / h[2]) if d2 != 0 else np.inf
        extrapolated = q[2] + d2 / ((h[1] / h[2]) ** ratio - 1.0) if np.isfinite(ratio) else q[2]
        print(f"  {name}: successive changes {d1 * 1e3:+.4f}, {d2 * 1e3:+.4f} mm, observed order "
              f"{ratio:.2f}, Richardson estimate {extrapolated * 1e3:.4f} mm")
        assert abs(d2) < abs(d1) or abs(d2) < 1e-3 * q[2]  # the changes shrink
        assert abs(d2) < 0.01 * q[2]  # finest two meshes agree to 1 %
    # the rod has stopped (a few tenths of a per cent of the kinetic energy left, elastic ringing)
    assert all(r[2] < 0.01 for r in runs)
    # mass is conserved, so the deformed rod must be shorter and wider; bounds from the
    # incompressible plastic limit: L/L0 in (0.5, 0.9) at this speed for copper
    assert np.all((lengths > 0.5 * 25.4e-3) & (lengths < 0.9 * 25.4e-3)) and np.all(radii > 3.81e-3)


def test_taylor_anvil_coarse_end_state():
    """Coarse mesh (default run): the rod stops, shortens and mushrooms; energy is conserved."""
    length, radius, kinetic_left, energy_error = taylor(8)
    print(f"\nTaylor anvil 8x53: L = {length * 1e3:.3f} mm (L/L0 = {length / 25.4e-3:.4f}), foot radius "
          f"{radius * 1e3:.3f} mm, kinetic energy left {kinetic_left:.1e}, energy error {energy_error:.1e}")
    assert kinetic_left < 0.01
    assert 0.5 * 25.4e-3 < length < 0.9 * 25.4e-3 and radius > 1.3 * 3.81e-3
    assert energy_error < 0.01
