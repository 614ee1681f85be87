"""The viscoplastic sub-grid columns as slide-line friction (law 'subgrid-viscoplastic') in the coupled strip."""

import numpy as np

from shockfriction.hydro.api import prepare, run_simulation


def test_viscoplastic_law_runs_in_the_coupled_strip(coupled_decks, tmp_path):
    deck = coupled_decks["strip"](target="Al5083-H111", model="viscoplastic", mu0=0.3, f=0.3, end="0.3 us")
    sim = prepare(deck)
    fm = sim.interfaces[0].line.friction_model
    fm.trace = []
    run_simulation(sim, tmp_path)
    sg = fm.columns
    tau = np.array([r["tau"] for r in fm.trace])
    print(f"\nsteps {len(fm.trace)}, max tau {tau.max()/1e6:.1f} MPa, max Theta(0) {sg.theta_interface.max():.1f} K, "
          f"column friction work {fm.friction_work_columns:.3e} J")
    assert sg.model == "viscoplastic"
    assert np.all(np.isfinite(tau)) and tau.max() > 0.0
    assert np.all(np.isfinite(sg.theta)) and sg.theta_interface.max() > 300.0
    assert np.all(np.abs(sg.vp.energy_residual()) < 1e-9)
