"""Sweep files: design (grid, Latin hypercube), dotted paths, derived scalars, bad files exit 2."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from shockfriction.cli import main
from shockfriction.deck.base import validate
from shockfriction.errors import DeckError
from shockfriction.sweep.design import build_runs
from shockfriction.sweep.keep import derive
from shockfriction.sweep.paths import parse_path, set_paths
from shockfriction.sweep.spec import SweepSpec

BASE = {"friction": {"mu0": 0.3, "f": 0.7}, "bodies": [{"velocity": "100 m/s"}, {"velocity": "0 m/s"}]}


def spec(**kw) -> SweepSpec:
    data = {"base": "deck.toml", **kw}
    s = validate(SweepSpec, data, "sweep.toml")
    s.check("sweep.toml")
    return s


def test_grid_is_the_full_product_first_parameter_slowest():
    s = spec(parameter=[{"path": "friction.mu0", "values": [0.1, 0.2]},
                        {"path": "bodies[0].velocity", "range": ["100 m/s", "0.3 km/s"], "n": 3}])
    runs = build_runs(s, BASE, "subgrid")
    assert [r.values["friction.mu0"] for r in runs] == [0.1, 0.1, 0.1, 0.2, 0.2, 0.2]
    assert [r.numbers["bodies[0].velocity"] for r in runs] == [100.0, 200.0, 300.0] * 2
    assert runs[4].deck["bodies"][0]["velocity"] == "200.0 m/s" and runs[4].deck["friction"]["mu0"] == 0.2
    assert BASE["friction"]["mu0"] == 0.3, "the base deck is never changed"
    assert len({r.key for r in runs}) == 6


def test_latin_hypercube_puts_one_point_in_each_stratum_and_is_reproducible():
    n = 16
    s = spec(sample={"method": "lhs", "n": n, "seed": 7},
             parameter=[{"path": "friction.mu0", "range": [0.0, 0.4]},
                        {"path": "friction.f", "range": [0.01, 1.0], "scale": "log"}])
    runs = build_runs(s, BASE, "subgrid")
    mu = np.array([r.numbers["friction.mu0"] for r in runs])
    f = np.array([r.numbers["friction.f"] for r in runs])
    assert sorted(np.floor(mu / 0.4 * n).astype(int)) == list(range(n))
    u = (np.log(f) - np.log(0.01)) / (np.log(1.0) - np.log(0.01))
    assert sorted(np.floor(u * n).astype(int)) == list(range(n))
    assert [r.key for r in build_runs(s, BASE, "subgrid")] == [r.key for r in runs]


def test_dotted_paths():
    assert parse_path("bodies[1].velocity") == ["bodies", 1, "velocity"] == parse_path("bodies.1.velocity")
    d = set_paths(BASE, {"friction.new_field": 1, "bodies[1].velocity": "5 m/s"})
    assert d["friction"]["new_field"] == 1 and d["bodies"][1]["velocity"] == "5 m/s"
    with pytest.raises(DeckError, match=r"'frction' is not there \(keys there: friction, bodies\)"):
        set_paths(BASE, {"frction.mu0": 0.1})
    with pytest.raises(DeckError, match="a list of 2 items"):
        set_paths(BASE, {"bodies[2].velocity": "1 m/s"})


@pytest.mark.parametrize("op, exact", [
    ("max", 1.0), ("min", 0.0), ("initial", 0.0), ("final", 1.0),
    ("integral", 0.5), ("mean", 0.5), ("time_of_max", 1.0), ("time_of_min", 0.0), ("arrival", 0.25)])
def test_derived_scalars_of_a_linear_ramp_are_exact(op, exact):
    t = np.linspace(0.0, 1.0, 11)
    assert derive(op, t, t.copy(), threshold=0.25) == pytest.approx(exact, abs=1e-14)


def test_arrival_never_reached_is_nan():
    assert np.isnan(derive("arrival", np.arange(3.0), np.zeros(3), threshold=1.0))


BAD = [
    ('base = "deck.toml"\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1, "3 furlongz"]\n',
     ["parameter[0].values", "'3 furlongz'", "expected a number or a quantity such as '250 m/s'"]),
    ('base = "deck.toml"\n[[parameter]]\npath = "friction.mu0"\nrange = [0.1, "2 m/s"]\nn = 2\n',
     ["parameter[0].range", "expected values in one dimension"]),
    ('base = "deck.toml"\n[[parameter]]\npath = "frction.mu0"\nvalues = [0.1]\n',
     ["path = 'frction.mu0'", "expected an existing table", "keys there: friction"]),
    ('base = "deck.toml"\n[sample]\nmethod = "lhs"\nn = 4\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1]\n',
     ["parameter[0] (friction.mu0)", "expected a range (low and high values) with sample.method = 'lhs'"]),
    ('base = "nothere.toml"\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1]\n',
     ["base = 'nothere.toml'", "expected a deck file relative to the sweep file"]),
    ('base = "deck.toml"\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1]\nstep = 3\n',
     ["parameter[0].step", "expected no such key"]),
    ('base = "deck.toml"\n[[parameter]]\npath = "friction.mu0"\nrange = [0.1, 0.3]\n',
     ["parameter[0] (friction.mu0)", "expected n (the number of grid values) with its range"]),
    ('base = "deck.toml"\nkind = "hydro"\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1]\n',
     ["kind = 'hydro'", "expected"]),
    ('kind = "python"\nmodel = "no_such_module:fn"\n[[parameter]]\npath = "a"\nvalues = [0.1]\n',
     ["model = 'no_such_module:fn'", "expected an importable function"]),
    ('base = "deck.toml"\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1]\n[keep]\nrecords = 3\n',
     ["keep.records", "= 3"]),
]


@pytest.mark.parametrize("text, fragments", BAD)
def test_bad_sweep_files_exit_2_naming_field_value_and_expectation(tmp_path, capsys, monkeypatch, text, fragments):
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parent))
    if "kind" not in text:
        text = 'kind = "python"\nmodel = "sweep_test_models:ramp"\n' + text
    (tmp_path / "deck.toml").write_text("[friction]\nmu0 = 0.3\nf = 0.7\n")
    (tmp_path / "sweep.toml").write_text(text)
    with pytest.raises(SystemExit) as exc:
        main(["sweep", str(tmp_path / "sweep.toml"), "--out", str(tmp_path / "out"), "--allow-python"])
    assert exc.value.code == 2
    err = " ".join(capsys.readouterr().err.split())
    for frag in fragments:
        assert frag in err
    assert not (tmp_path / "out" / "runs").exists(), "nothing runs when the sweep file is bad"
