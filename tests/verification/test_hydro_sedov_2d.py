"""Sedov blast on a genuinely 2D Cartesian mesh (plane strain, quarter plane): the cylindrical
similarity solution, read along the x axis and along the diagonal (mesh isotropy).

Known to fail (a limitation documented in docs/theory/hydrocode.md and docs/theory/exact-solutions.md: the diagonal cell at the edge of the
energy deposit inverts within ~70 cycles), hence xfail; when it runs, the shock radius along
both directions must be within 3 % of R(t) and within 2 % of each other.
"""

from pathlib import Path

import numpy as np
import pytest

from shockfriction.analysis import sedov
from shockfriction.analysis.convergence import front_position
from shockfriction.analysis.strip import cell_centres, read_deck
from shockfriction.hydro.api import prepare, run_simulation

DECKS = Path(__file__).resolve().parents[2] / "examples" / "verification"


@pytest.mark.xfail(reason="a limitation documented in docs/theory/hydrocode.md: the diagonal cell inverts early in Cartesian Sedov",
                   strict=False)
def test_sedov_cartesian_quarter_plane():
    cells, deposit_radius = 50, 3.0
    deck = read_deck(DECKS / "sedov_quarter_plane.toml")
    deck["bodies"][0]["mesh"]["nx"] = deck["bodies"][0]["mesh"]["ny"] = cells
    sim = prepare(deck)
    xc, yc = cell_centres(sim.state)
    hot = np.hypot(xc, yc) < deposit_radius / cells
    energy_quarter = 0.25  # E = 1 J/m for the whole line blast, rho0 = 1
    sim.state.e[hot] = energy_quarter / sim.state.volume[hot].sum()
    sim.reinitialize()
    result = run_simulation(sim)
    radius = sedov.solve(2, 1.4).shock_radius(1.0, result.state.t)
    xc, yc = cell_centres(result.state)
    r = np.hypot(xc, yc)
    fronts = {}
    for name, cells_ij in (("axis", [(i, 0) for i in range(cells)]), ("diagonal", [(i, i) for i in range(cells)])):
        idx = np.array([sim.mesh.cell_index("gas", i, j) for i, j in cells_ij])
        order = np.argsort(r[idx])
        rho = result.state.rho[idx][order]
        fronts[name] = front_position(r[idx][order], rho, 0.5 * (1.0 + rho.max()))
    print(f"\nSedov quarter plane ({cells}^2): R = {radius:.4f}, fronts {fronts}")
    for front in fronts.values():
        assert front == pytest.approx(radius, rel=0.03)
    assert fronts["axis"] == pytest.approx(fronts["diagonal"], rel=0.02)
