"""No traceback and no runaway run: each failure the fuzzing of 675 example decks found on main
(issue 13) exits 2 (deck) or 3 (run) with one message; run guards stop collapsing or endless runs
and warn once when a state leaves the models' range (docs/theory/reliability.md)."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pytest

from shockfriction.cli import main
from shockfriction.deck.base import read_toml
from shockfriction.errors import SimulationError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PLATE = (EXAMPLES / "plate_impact_al_250ms.toml").read_text()
BALL = (EXAMPLES / "subgrid" / "ball_al_200ms.toml").read_text()


def _cli(tmp_path, capsys, text: str | bytes, cmd: str = "run", *extra) -> tuple[int, str]:
    deck = tmp_path / "deck.toml"
    deck.write_bytes(text if isinstance(text, bytes) else text.encode())
    with pytest.raises(SystemExit) as exc:
        main([*extra, cmd, str(deck), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return exc.value.code, " ".join(err.split())


@pytest.mark.parametrize("edit, fragments", [
    (('title = "Al/Al', 'title = "\xff'), ["not valid TOML: expected UTF-8 text"]),
    (('material = "Al6061-T6"', 'material = ""'), ["bodies[0].material = ''"]),
    (('velocity = ["0 m/s", "250 m/s"]', 'velocity = ["0 m/s", "1e30 m/s"]'),
     ["bodies[0].velocity[1] = '1e30 m/s'", "magnitude at most"]),
    (('end = "2.6 us"', 'end = "1e300 s"'), ["time.end = '1e300 s'", "magnitude at most 1000 s"]),
    (('end = "2.6 us"', 'end = "100 s"'), ["2e+08 field outputs planned", "output.max_fields = 10000"]),
    (('["0.1 mm", "10 mm"]', '["0.1 mm", "1e300 mm"]'), ["'1e300 mm' is 1e+297 m"]),
    (('["0.1 mm", "10 mm"]', '["0.1 mm", "nan mm"]'), ["'nan mm' is not a finite number"]),
    (('[["0 mm", "0 mm"], ["0.1 mm", "0 mm"]', '[["0 mm", "-1 mm"], ["0.1 mm", "-1 mm"]'),
     ["bodies 'target' and 'flyer' overlap"]),
    (("cfl = 0.6", "cfl = nan"), ["time.cfl"]),
])
def test_deck_errors_found_by_fuzzing_exit_2_with_one_message(tmp_path, capsys, edit, fragments):
    assert edit[0] in PLATE
    text = PLATE.replace(*edit)
    code, err = _cli(tmp_path, capsys, text.encode("latin-1") if "\xff" in text else text)
    assert code == 2
    for frag in fragments:
        assert frag in err
    assert "np.float64(" not in err


def test_a_folder_given_as_deck_exits_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", str(tmp_path)])
    assert exc.value.code == 2 and "is a folder" in capsys.readouterr().err


@pytest.mark.parametrize("edit, fragments", [
    (('duration = "2.5 us"', 'duration = "1e300 s"'), ["duration = '1e300 s'"]),
    (('duration = "2.5 us"', 'duration = "1 s"'), ["duration / dt = 1e+09 steps", "max_steps"]),
    (("f = 0.3 ", "f = -1.5 "), ["friction.f = -1.5"]),
    (('thickness = "20 um"', 'thickness = "1e300 um"'), ["column.thickness = '1e300 um'"]),
])
def test_subgrid_deck_errors_exit_2_naming_the_field(tmp_path, capsys, edit, fragments):
    assert edit[0] in BALL
    text = BALL.replace(*edit)
    if "1 s" in edit[1]:
        text = text.replace('output_times = ["10 ns", "0.1 us", "0.25 us", "0.5 us", "1 us", "2.5 us"]', "")
    code, err = _cli(tmp_path, capsys, text, "subgrid")
    assert code == 2
    for frag in fragments:
        assert frag in err
    assert "loading" not in err, "the friction table's error is blamed on the loading"


def test_projected_cycle_count_above_max_cycles_exits_3_at_once(tmp_path, capsys):
    text = PLATE.replace('end = "2.6 us"', 'end = "900 us"').replace('field_interval = "0.5 us"',
                                                                     'field_interval = "100 us"')
    text = text.replace("cfl = 0.6", "cfl = 0.6\nmax_cycles = 5000")
    code, err = _cli(tmp_path, capsys, text)
    assert code == 3 and "more than time.max_cycles = 5000" in err and "at cycle 1," in err


def test_time_step_collapse_stops_the_run_naming_the_cell():
    from shockfriction.hydro.api import prepare

    sim = prepare(EXAMPLES / "plate_impact_al_250ms.toml")
    for _ in range(3):
        sim.step()
    g = sim.guards
    assert g.dt_ref > 0.0
    with pytest.raises(SimulationError, match=r"body '(flyer|target)', cell \(0, \d+\) at cycle 3.*time step collapsed"):
        g.after_step(g.dt_ref * 0.5 * g.min_fraction, sim._dtcell)
    with pytest.raises(SimulationError, match="no valid step"):
        g.after_step(float("nan"), sim._dtcell)


def test_leaving_the_models_range_warns_once_per_body_and_lands_in_the_summary(tmp_path, caplog):
    from shockfriction.hydro.api import run_dict

    deck = read_toml(EXAMPLES / "plate_impact_al_250ms.toml")
    deck["bodies"][0]["velocity"] = ["0 m/s", "50 km/s"]
    deck["time"]["end"] = "0.2 us"
    with caplog.at_level(logging.WARNING, logger="shockfriction"):
        res = run_dict(deck, tmp_path)
    msgs = [r.getMessage() for r in caplog.records if r.name == "shockfriction"]
    assert any("pressure" in m and "fit range" in m for m in msgs)
    assert any("temperature" in m and "20000 K" in m for m in msgs)
    assert len(msgs) == len(set(msgs)) <= 4, "one warning per kind and body, not one per cycle"
    assert res.summary["warnings"] == msgs
    ordinary = run_dict(read_toml(EXAMPLES / "plate_impact_al_250ms.toml") | {"time": {"end": "0.2 us"}}, None)
    assert ordinary.summary["warnings"] == []


def test_an_unexpected_exception_is_one_line_exit_3_and_debug_shows_the_traceback(tmp_path, capsys, monkeypatch):
    from shockfriction.hydro import api

    def boom(*a, **k):
        raise RuntimeError("boom")

    monkeypatch.setattr(api, "prepare", boom)
    code, err = _cli(tmp_path, capsys, PLATE)
    assert code == 3 and "internal error RuntimeError: boom" in err and "--debug" in err
    (tmp_path / "deck.toml").write_text(PLATE)
    with pytest.raises(RuntimeError, match="boom"):
        main(["--debug", "run", str(tmp_path / "deck.toml"), "--out", str(tmp_path / "o")])


def test_a_normal_run_keeps_its_time_steps_far_from_the_collapse_limit():
    """dt_min_fraction = 1e-5 is far below what a strong shock does to dt (plate impact: > 0.3)."""
    from shockfriction.hydro.api import prepare

    sim = prepare(EXAMPLES / "plate_impact_al_250ms.toml")
    dts = []
    while sim.state.t < 1.0e-6:
        sim.step()
        dts.append(sim.state.dt)
    assert np.min(dts[5:]) / sim.guards.dt_ref > 0.3


def test_stepping_past_the_end_time_is_a_clear_error_not_a_division_by_zero():
    """Simulation.step() at t = time.end (the last step left dt = 0): a RuntimeError that says so; before, a deck
    with slide lines died in the contact step's division by dt (a ZeroDivisionError from a numba kernel)."""
    from cone_shot import cone_deck

    from shockfriction.hydro.api import prepare

    sim = prepare(cone_deck(law="coulomb", cell_um=400, end_us=0.1))
    while sim.state.t < sim.t_end * (1.0 - 1e-12):
        sim.step()
    assert sim.state.t == pytest.approx(1e-7, rel=1e-12) and sim.state.dt == 0.0
    with pytest.raises(RuntimeError, match="at its end time"):
        sim.step()
