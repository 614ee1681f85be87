"""The viscoplastic sub-grid columns as slide-line friction (law 'subgrid-viscoplastic') in the coupled strip."""

import numpy as np
import pytest

from shockfriction.errors import DeckError
from shockfriction.friction.subgrid.viscoplastic import P_PICARD_TOL
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


def test_pressure_shear_ti6al4v_reduces_to_the_thermoelastic_model(tmp_path):
    """The Ti-6Al-4V pressure-shear example (steel flyer, 101 m/s at 33 deg, 1.4 GPa, ~38 m/s slip, f = 0.15) with
    the viscoplastic columns against the thermoelastic ones (thesis ch. 7, a separate code path).  The f branch
    governs and the titanium layer stays as strong as its body, so the excess layer (the default closure) adds no
    slip and the two models must give the same interface: from 0.2 us on, temperature rise measured within 2.0e-4
    and friction stress within 5.0e-5 of its peak (the `shear` closure of the first draft: 2.5e-3 and 3.0e-4, its
    elastic layer taking part of the first steps' slip)."""
    from pathlib import Path

    from shockfriction.hydro.api import run
    from shockfriction.io.interface import read_interface

    text = (Path(__file__).resolve().parents[2] / "examples" / "pressure_shear_ti6al4v.toml").read_text()
    assert 'law = "subgrid-thermoelastic"' in text
    out = {}
    for law in ("subgrid-thermoelastic", "subgrid-viscoplastic"):
        deck = tmp_path / f"{law}.toml"
        deck.write_text(text.replace('law = "subgrid-thermoelastic"', f'law = "{law}"'))
        run(deck, tmp_path / law)
        out[law] = read_interface(tmp_path / law / "interface.h5")["interface"]
    a, b = out["subgrid-thermoelastic"], out["subgrid-viscoplastic"]
    w = a["t_s"] >= 0.2e-6
    n = a["theta_interface_K"].shape[1]
    Tb = np.array([np.interp(a["t_s"][w], b["t_s"], b["theta_interface_K"][:, j]) for j in range(n)]).T
    taub = np.array([np.interp(a["t_s"][w], b["t_s"], b["tau_Pa"][:, j]) for j in range(n)]).T
    dT = np.max(np.abs(Tb - a["theta_interface_K"][w]) / (a["theta_interface_K"][w] - 300.0))
    dtau = np.max(np.abs(taub - a["tau_Pa"][w])) / np.max(np.abs(a["tau_Pa"]))
    print(f"\nTi pressure-shear, viscoplastic vs thermoelastic from 0.2 us: dT-rise {dT:.2e}, dtau {dtau:.2e}, "
          f"max Theta(0) {a['theta_interface_K'].max():.1f} / {b['theta_interface_K'].max():.1f} K", end="")
    assert a["theta_interface_K"].max() > 700.0  # the regime: the interface heats by ~480 K
    assert dT < 3e-4 and dtau < 1e-4


def test_slide_line_passes_the_tolerance_to_the_viscoplastic_columns(coupled_decks):
    deck = coupled_decks["strip"](target="Al5083-H111", model="viscoplastic", mu0=0.3, f=0.3, end="0.3 us",
                                   picard_tol="1e-3 K")
    fm = prepare(deck).interfaces[0].line.friction_model
    assert fm.columns.vp.par[P_PICARD_TOL] == 1e-3


def test_slide_line_refuses_the_tolerance_for_another_law(coupled_decks):
    deck = coupled_decks["strip"](target="Al5083-H111", model="thermoelastic", mu0=0.3, f=0.3, end="0.3 us",
                                   picard_tol="1e-3 K")
    with pytest.raises(DeckError, match=r"slide_lines\[0\].*picard_tol only with the subgrid-viscoplastic law"):
        prepare(deck)
