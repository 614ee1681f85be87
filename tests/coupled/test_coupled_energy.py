"""Energy audit of the coupled friction: the hydrocode's friction work (the kinetic energy the
friction impulses remove) equals the heat put into the columns plus the other body's share
(plus, for the thermoelastoplastic model, the cold work and the plastic heat not yet deposited),
within 1%; the heat stored in the columns, rho c int (T - T0) dz S, equals the heat put in; and
kinetic + internal + heat in the columns + other share stays equal to the initial
energy within 1e-4 (measured 1.7e-5 and 7.5e-7; the contact's inelastic loss is heat in the cells)."""

import numpy as np
import pytest

from shockfriction.hydro.api import prepare, run_simulation
from shockfriction.io.interface import read_interface

CASES = {
    # Ti-6Al-4V target under a tool-steel flyer (the Prakash example), thermoelastic columns
    "thermoelastic": dict(model="thermoelastic"),
    # Al target under a stainless flyer: the layer yields (f Ymax > Y0), plastic slip and cold work
    "thermoelastoplastic": dict(model="thermoelastoplastic", flyer="AISI321", target="Al5083-H111", vt=100.0,
                                vn=100.0, mu0=0.3, f=0.7, end="0.8 us"),
    # the same with viscoplastic columns (the default excess layer): two-sided heat (the other body conducts its
    # share); the `shear` closure's books (kinetic and elastic energy, layer_work) are checked on the cone below
    "viscoplastic": dict(model="viscoplastic", flyer="AISI321", target="Al5083-H111", vt=100.0, vn=100.0, mu0=0.3,
                         f=0.7, end="0.3 us"),
}


def _heat(parts):
    """What the friction left in the columns and the other body (J per unit depth)."""
    return (parts["heat_columns"] + parts["heat_other"] + parts["cold_work"] + parts["plastic_heat_pending"]
            + parts["melt_energy"] + parts["columns_mechanical"] - parts["layer_work"])


@pytest.fixture(scope="module", params=list(CASES))
def audited(request, coupled_decks, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param)
    sim = prepare(coupled_decks["strip"](**CASES[request.param]))
    res = run_simulation(sim, out)
    return request.param, res, sim.interfaces[0].line, read_interface(out / "interface.h5")["interface"]


def test_friction_work_equals_the_heat_within_one_percent(audited):
    name, res, line, d = audited
    fm = line.friction_model
    w_hydro = line.total_friction_work
    parts = fm.energy_balance()
    heat = _heat(parts)
    rel = abs(heat - w_hydro) / w_hydro
    print(f"{name}: hydro friction work {w_hydro:.6e} J/m, columns {parts['heat_columns']:.6e} + other body "
          f"{parts['heat_other']:.6e} + cold work {parts['cold_work']:.3e} + pending {parts['plastic_heat_pending']:.3e}"
          f" = {heat:.6e} J/m: relative difference {rel:.2e}")
    assert w_hydro > 0.0
    assert rel < 0.01
    # the columns' own balance is exact, and the records carry it
    assert parts["friction_work_columns"] == pytest.approx(heat, rel=1e-10)
    assert d["subgrid_friction_work_hydro_J"][-1] == pytest.approx(w_hydro, rel=1e-12)
    # the heat stored in the columns (planar strip: constant areas) is the heat put in
    stored = float(line.area @ fm.columns.heat_stored)
    assert stored == pytest.approx(parts["heat_columns"], rel=1e-9)
    if name == "thermoelastoplastic":
        assert parts["cold_work"] > 0.0 and np.max(fm.columns.eps_p) > 0.0


def test_total_energy_with_the_column_heat(audited):
    name, res, line, _ = audited
    e = res.energy
    parts = line.friction_model.energy_balance()
    heat = _heat(parts)
    # the initial energy (the first row's kinetic energy is the leapfrog product across the impact's first step,
    # which carries that step's whole contact loss while its heat counts half: not the initial energy); the
    # contact's inelastic loss is in the cells (contact_heat), so kinetic + internal keeps it
    e0 = res.state.energy.initial * res.state.geometry_factor
    assert e["column_heat"][-1] == pytest.approx(parts["heat_columns"] - parts["layer_work"], rel=1e-9)
    final = e["total"][-1] + heat - e["boundary_work"][-1]
    rel = abs(final - e0) / e0
    # what is left is the hydrocode's own error (time integration), not the friction bookkeeping
    left = abs(final - e0 - e["error"][-1])
    print(f"{name}: kinetic + internal {e['total'][-1]:.6e} + heat {heat:.4e} = {final:.6e} J/m against "
          f"initial {e0:.6e}: {rel:.2e}")
    print(f"{name}: left after the hydrocode's own error {e['error'][-1]:.3e}: {left:.3e} J/m "
          f"({left / e0:.2e} of the initial energy)")
    assert heat > 0.001 * e0
    assert rel < 1e-4              # measured 1.7e-5 / 7.5e-7 (6.5e-5 / 7.5e-5 before the contact heat)
    assert left < 5e-5 * e0


@pytest.mark.slow  # 1-2 min each
@pytest.mark.parametrize("closure", ["excess", "shear"])
def test_viscoplastic_cone_books_close(closure, tmp_path):
    """Issue 25 item 6 on the cone shot (coarse 400 um mesh, viscoplastic columns, mu0 = 0.3, f = 0.7, 10 um / 250
    cells, to 1.5 us: the layer sticks, flows and reaches ~1000 K): friction work of the columns = heat in them + the
    other body's heat + cold work + their kinetic and elastic energy - layer work, to round-off (measured ~1e-15 of
    the friction work; the issue asks 1e-6); and the hydrocode's friction work agrees with the columns' to the
    slide line's own difference (corrected against predicted slip, measured 1.5e-4)."""
    from cone_shot import cone_deck

    deck = cone_deck("subgrid-viscoplastic", 0.3, 0.7, cell_um=400.0, end_us=1.5, cells=250)
    deck["slide_lines"][0]["friction"]["thickness"] = "10 um"
    deck["slide_lines"][0]["friction"]["closure"] = closure
    sim = prepare(deck)
    run_simulation(sim, tmp_path)
    line = sim.interfaces[0].line
    parts = line.friction_model.energy_balance()
    w = parts["friction_work_columns"]
    resid = abs(w - _heat(parts)) / w
    hydro = abs(line.total_friction_work - w) / w
    theta = line.friction_model.columns.theta_interface.max()
    print(f"\ncone books: friction work {w:.4e} J/rad, residual {resid:.1e}, hydro vs columns {hydro:.1e}, "
          f"layer work {parts['layer_work']:.3e}, columns' mechanical {parts['columns_mechanical']:.3e}, "
          f"max Theta(0) {theta:.0f} K")
    assert w > 0.0
    if closure == "excess":  # a quasi-static layer with no far end: no kinetic or elastic energy, no layer work
        assert parts["layer_work"] == 0.0 and parts["columns_mechanical"] == 0.0
    else:
        assert parts["layer_work"] != 0.0 and parts["columns_mechanical"] != 0.0
    assert resid < 1e-14  # measured 3.8e-16
    assert hydro < 3e-4  # measured 1.3e-4
