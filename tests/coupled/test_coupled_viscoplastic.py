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


def test_excess_closure_continues_the_column_to_the_deck_depth(coupled_decks):
    """The 'excess' closure's thermal continuation ends at friction.depth (default EXCESS_DEPTH, 1 mm); the other
    body's thermal column scales with it (sqrt(alpha2/alpha1) of the depth)."""
    from shockfriction.coupled.friction import EXCESS_DEPTH

    kw = dict(target="Al5083-H111", model="viscoplastic", mu0=0.3, f=0.3, end="0.3 us", cells=50)
    default = prepare(coupled_decks["strip"](**kw)).interfaces[0].line.friction_model.columns.vp
    deep = prepare(coupled_decks["strip"](depth="3 mm", **kw)).interfaces[0].line.friction_model.columns.vp
    assert default.z[-1] == pytest.approx(EXCESS_DEPTH, rel=1e-12)
    assert deep.z[-1] == pytest.approx(3e-3, rel=1e-12)
    assert deep.z_other[-1] / default.z_other[-1] == pytest.approx(3.0, rel=0.05)


def test_a_run_longer_than_the_thermal_depth_is_a_deck_error(coupled_decks):
    """Heat diffuses 4 sqrt(alpha t) in time.end: beyond the continuation's insulated end the run would trap it.
    Al 5083-H111 (alpha = kappa/(rho c)) over 5 ms reaches 4 sqrt(alpha 5e-3) > 1 mm: refused, naming the key and
    the depth it needs; the same run with that depth is accepted."""
    import math

    from shockfriction.materials.library import get_material

    al = get_material("Al5083-H111")
    reach = 4.0 * math.sqrt(al.conductivity / (al.rho0 * al.heat_capacity) * 5e-3)
    assert 1.5e-3 < reach < 3e-3  # the regime (1.98 mm): the default 1 mm and 1.5 mm are too short, 3 mm is not
    kw = dict(target="Al5083-H111", model="viscoplastic", mu0=0.3, f=0.3, end="5 ms", cells=50)
    with pytest.raises(DeckError) as err:
        prepare(coupled_decks["strip"](**kw))
    print(err.value)
    assert "slide_lines[0].friction.depth (omitted: 0.001 m)" in str(err.value)
    assert f"4 sqrt(alpha t_end) = {reach:.3g} m" in str(err.value)
    with pytest.raises(DeckError, match=r"slide_lines\[0\]\.friction\.depth = 0\.0015 m: expected at least"):
        prepare(coupled_decks["strip"](depth="1.5 mm", **kw))
    fm = prepare(coupled_decks["strip"](depth="3 mm", **kw)).interfaces[0].line.friction_model
    assert fm.columns.vp.z[-1] == pytest.approx(3e-3, rel=1e-12)


@pytest.mark.parametrize("extra, message", [
    ({"closure": "shear", "depth": "1 mm"}, "depth only with closure = 'excess'"),
    ({"depth": "10 um"}, "expected more than thickness"),
    ({"depth": "-1 mm"}, "friction.depth"),
])
def test_bad_depth_is_a_deck_error(coupled_decks, extra, message):
    deck = coupled_decks["strip"](target="Al5083-H111", model="viscoplastic", mu0=0.3, f=0.3, end="0.3 us", **extra)
    with pytest.raises(DeckError) as err:
        prepare(deck)
    print(err.value)
    assert message in str(err.value) and "slide_lines[0]" in str(err.value)


def test_depth_is_refused_for_another_law(coupled_decks):
    deck = coupled_decks["strip"](target="Al5083-H111", model="thermoelastoplastic", mu0=0.3, f=0.3, end="0.3 us",
                                   depth="2 mm")
    with pytest.raises(DeckError, match=r"slide_lines\[0\].*depth only with the subgrid-viscoplastic law"):
        prepare(deck)


def test_the_thermal_reach_leaves_the_surface_within_round_off_of_a_semi_infinite_body():
    """Why THERMAL_REACH = 4: under a constant flux the insulated end at L = 4 sqrt(alpha t) adds, by the method of
    images, 2 sum_k ierfc(k L/sqrt(alpha t))/ierfc(0) to the surface rise (Carslaw-Jaeger): below 1e-8; at
    L = sqrt(alpha t) the same sum is 18 % (Carslaw and Jaeger, section 3.8)."""
    from shockfriction.coupled.friction import THERMAL_REACH
    from shockfriction.friction.subgrid.analytic import ierfc

    def excess(reach):
        return 2.0 * sum(float(ierfc(k * reach)) for k in range(1, 20)) / float(ierfc(0.0))

    print(f"surface excess at 4: {excess(THERMAL_REACH):.2e}, at 1: {excess(1.0):.3f}")
    assert excess(THERMAL_REACH) < 1e-8
    assert excess(1.0) == pytest.approx(0.1816, abs=1e-4)
