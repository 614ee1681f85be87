"""Issue 25, item 1: the viscoplastic columns under a slide line must not depend on their thickness.

The cone shot (100 um cells, mu0 = 0.3, f = 0.7, viscoplastic columns, 3 us), h = 20 um / 500 cells against
40 um / 1000 cells (the same dz): friction work, the columns' plastic work and the mean |slip| must change by
less than 2 % (the issue's bound).  With the default ``excess`` closure (docs/theory/viscoplastic.md, "Coupled
closure: the excess layer") measured +8.1e-8 (friction work), +8.0e-6 (plastic work), +1.7e-7 (mean slip); the
tolerances below sit near these (the ``shear`` closure of version 0.4's first draft: +25 % / +99 % / +13 %).  About 3-4 minutes on one core (two runs of ~70 and ~120 s
idle)."""

import numpy as np
import pytest

from cone_shot import cone_deck
from shockfriction.hydro.api import prepare, run_simulation
from shockfriction.io.interface import read_interface

TOL = 0.02  # the bound on the relative change from h = 20 to 40 um
# near the measured changes (a regression of the closure or of its thermal far field trips them)
NEAR = {"friction_work": 5e-7, "plastic_work": 5e-5, "mean_slip": 1e-6}


def _cone(h_um: float, tmp_path):
    deck = cone_deck("subgrid-viscoplastic", 0.3, 0.7, end_us=3.0, cells=int(25 * h_um), cell_um=100.0)
    deck["slide_lines"][0]["friction"]["thickness"] = f"{h_um} um"
    out = tmp_path / f"h{h_um:g}"
    sim = prepare(deck)
    run_simulation(sim, out)
    line = sim.interfaces[0].line
    fm = line.friction_model
    plastic = float(line.area @ fm.columns.vp.energies()["plastic_work"])
    slip = np.abs(read_interface(out / "interface.h5")["cone_wall"]["slip_mps"]).mean()
    return {"friction_work": line.total_friction_work, "plastic_work": plastic, "mean_slip": float(slip)}


@pytest.mark.slow
def test_coupled_viscoplastic_columns_do_not_depend_on_their_thickness(tmp_path):
    thin, thick = _cone(20.0, tmp_path), _cone(40.0, tmp_path)
    change = {k: thick[k] / thin[k] - 1.0 for k in thin}
    print(f"h = 20 um: {thin}\nh = 40 um: {thick}\nchange: {change}")
    for key, rel in change.items():
        assert abs(rel) < min(TOL, NEAR[key]), f"{key}: {thin[key]:.6g} -> {thick[key]:.6g} ({100 * rel:+.2e} %)"
