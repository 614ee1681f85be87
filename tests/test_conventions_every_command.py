"""Issue 29: one set of conventions across every command and output (docs/cli.md).

Output folders (refused when non-empty, --force replaces; the Python API alike), the exit codes of
the code, of --help and of docs/cli.md agree, --dry-run runs and writes nothing, -v is verbose in
every command, decks whose pairings are degenerate exit 2, a sweep whose base deck names a relative
mesh runs from another folder, booleans are refused where numbers are expected, and every output of a
run shares one CSV header style and one file mode."""

from __future__ import annotations

import csv
import os
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from shockfriction.cli import app, main
from shockfriction.errors import EXIT_STATUS, UsageError

ROOT = Path(__file__).resolve().parents[1]

MODELS = """
import numpy as np
def line(deck, workdir):
    t = np.linspace(0.0, 1.0, 101)
    if float(deck.get("a", 0.0)) > 2.5:
        raise RuntimeError("refused")
    return {"records": {"r": {"time": t, "value": float(deck["a"]) + float(deck["b"]) * t}},
            "summary": {"peak": float(deck["a"]) + float(deck["b"])}}
"""

RUN_DECK = """
[time]
end = "20 ns"
[[bodies]]
name = "plate"
material = "Al6061-T6"
velocity = ["0 m/s", "100 m/s"]
[bodies.mesh]
corners = [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]]
nx = 2
ny = 2
[[probes]]
name = "c"
body = "plate"
cell = [0, 0]
quantities = ["p", "eps_p", "rho"]
[[probes]]
name = "n"
body = "plate"
node = [0, 0]
quantities = ["vy"]
"""

SUBGRID_DECK = """
material = "Al5083-H111"
heat_share = 0.5
duration = "5 ns"
dt = "1 ns"
[column]
thickness = "20 um"
cells = 20
[friction]
mu0 = 0.3
f = 0.3
[[loading]]
times = ["0 ns"]
slip_velocity = ["50 m/s"]
normal_stress = ["1 GPa"]
"""

LINE_FIT = """
kind = "python"
model = "sf_conv_models:line"
[measured]
file = "m.csv"
value = "value"
[computed]
record = "r"
value = "value"
[[parameter]]
path = "a"
bounds = [-5.0, 5.0]
[[parameter]]
path = "b"
bounds = [-5.0, 5.0]
"""

LINE_SWEEP = """
model = "sf_conv_models:line"
[set]
b = 1.0
[[parameter]]
path = "a"
values = [1.0, 2.0]
"""


def cli(argv, capsys):
    """Exit status, stdout and stderr (newlines folded) of one command."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    cap = capsys.readouterr()
    code = exc.value.code
    return (0 if code is None else code), cap.out, " ".join(cap.err.split())


@pytest.fixture
def models(tmp_path_factory, monkeypatch):
    """A Python model module importable here and in spawned workers."""
    folder = tmp_path_factory.mktemp("models")
    (folder / "sf_conv_models.py").write_text(MODELS)
    monkeypatch.syspath_prepend(str(folder))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(folder), str(ROOT / "src"),
                                                       os.environ.get("PYTHONPATH", "")]))
    sys.modules.pop("sf_conv_models", None)


def _fit_folder(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "fit.toml").write_text(LINE_FIT)
    t = np.linspace(0.0, 1.0, 101)
    np.savetxt(folder / "m.csv", np.c_[t, 0.5 + 2.0 * t], delimiter=",", header="time,value", comments="")
    return folder / "fit.toml"


# --- output folders: every command and the API ----------------------------------------------------

def _stale(out: Path, name: str) -> None:
    out.mkdir(parents=True, exist_ok=True)
    (out / name).write_text("a previous run's output")


@pytest.mark.parametrize("command", ["run", "subgrid", "fit", "sweep"])
def test_every_command_refuses_a_non_empty_out_and_force_replaces_it(command, tmp_path, capsys, models):
    if command == "fit":
        deck = _fit_folder(tmp_path)
        stale, new, extra = "evaluations.csv", "fit.json", ["--workers", "1", "--allow-python"]
    elif command == "sweep":
        deck = tmp_path / "sweep.toml"
        deck.write_text(LINE_SWEEP)
        stale, new, extra = "sweep.csv", "plan.json", ["--workers", "1", "--allow-python", "-q"]
    else:
        deck = tmp_path / "deck.toml"
        deck.write_text(RUN_DECK if command == "run" else SUBGRID_DECK)
        stale, new, extra = "probes.csv" if command == "run" else "history.csv", "energy.csv" if command == "run" \
            else "profiles.csv", ["-q"] + (["--no-plots"] if command == "subgrid" else [])
    out = tmp_path / "out"
    _stale(out, stale)
    (out / "notes.txt").write_text("the user's own file")
    code, stdout, err = cli([command, deck, "--out", out, *extra], capsys)
    assert code == 2 and "is not empty" in err and "--force" in err, err
    assert sorted(p.name for p in out.iterdir()) == sorted([stale, "notes.txt"])   # untouched
    assert (out / stale).read_text() == "a previous run's output"
    code, stdout, err = cli([command, deck, "--out", out, "--force", *extra], capsys)
    assert code == 0, err
    assert (out / new).is_file() and (out / "notes.txt").read_text() == "the user's own file"
    if (out / stale).exists():
        assert (out / stale).read_text() != "a previous run's output"


def test_a_sweep_folder_is_resumed_without_force(tmp_path, capsys, models):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(LINE_SWEEP)
    argv = ["sweep", sweep, "--out", tmp_path / "o", "--workers", "1", "--allow-python", "-q"]
    assert cli(argv, capsys)[0] == 0
    code, out, _ = cli(argv, capsys)
    assert code == 0 and "2 already finished" in " ".join(out.split())


def test_the_python_api_follows_the_same_rule(tmp_path, models):
    import tomllib

    from shockfriction.deck.subgrid import SubgridDeck
    from shockfriction.friction.subgrid.driver import run_subgrid
    from shockfriction.hydro.api import run_dict
    from shockfriction.sweep.engine import run_sweep
    from shockfriction.sweep.fit import fit, write_outputs

    deck = tomllib.loads(RUN_DECK)
    out = tmp_path / "run"
    _stale(out, "probes.csv")
    with pytest.raises(UsageError, match="not empty"):
        run_dict(deck, out)
    assert (out / "probes.csv").read_text() == "a previous run's output"
    assert run_dict(deck, out, force=True).summary["completed"]
    assert (out / "probes.csv").read_text().startswith("t [s],")

    sg = SubgridDeck.model_validate(tomllib.loads(SUBGRID_DECK))
    out = tmp_path / "sg"
    _stale(out, "history.csv")
    with pytest.raises(UsageError, match="not empty"):
        run_subgrid(sg, out)
    run_subgrid(sg, out, force=True)
    assert (out / "history.csv").read_text().startswith("t [s],")

    res = fit(_fit_folder(tmp_path / "f"), workers=1)
    out = tmp_path / "fit_out"
    _stale(out, "fit.json")
    with pytest.raises(UsageError, match="not empty"):
        write_outputs(res, out)
    assert write_outputs(res, out, force=True)["report"].read_text().startswith("{")

    (tmp_path / "sw").mkdir()
    sweep = tmp_path / "sw" / "sweep.toml"
    sweep.write_text(LINE_SWEEP)
    out = tmp_path / "sweep_out"
    _stale(out, "notes.txt")
    with pytest.raises(UsageError, match="not empty"):
        run_sweep(sweep, out, workers=1, progress=False)
    assert run_sweep(sweep, out, workers=1, progress=False, force=True).ok == 2


def test_analyze_writes_its_figure_only_where_plot_says(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    base = ["analyze", "--pair", "Al5083-H111:AISI321", "--velocity", "200 m/s", "--pressure", "10 GPa",
            "--time", "1 us", "--json"]
    target = tmp_path / "figs" / "stability.png"
    code, out, err = cli([*base, "--plot", target], capsys)
    assert code == 0 and target.is_file() and str(target) in err
    assert out.lstrip().startswith("{")                       # stdout stays pure JSON
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figs"]
    code, _, err = cli([*base, "--plot", target], capsys)
    assert code == 2 and "--force" in err
    assert cli([*base, "--plot", target, "--force"], capsys)[0] == 0


# --- exit codes: code, --help and docs/cli.md -------------------------------------------------------

def _doc_exit_table() -> dict[int, str]:
    text = (ROOT / "docs" / "cli.md").read_text()
    section = text.split("## Exit status", 1)[1].split("\n## ", 1)[0]
    rows = re.findall(r"^\| (\d+) \| (.+?) \|$", section, flags=re.M)
    return {int(code): meaning for code, meaning in rows}


def test_exit_codes_agree_between_the_code_help_and_docs(capsys):
    import typer.main

    docs = _doc_exit_table()
    assert set(docs) == set(EXIT_STATUS), (sorted(docs), sorted(EXIT_STATUS))
    for code, meaning in EXIT_STATUS.items():   # the docs row says what the code's table says
        head = meaning.split(" (")[0]
        assert docs[code].startswith(head), (code, docs[code], head)
    commands = [c.name for c in typer.main.get_command(app).commands.values()]
    assert {"run", "subgrid", "sweep", "fit", "analyze", "impact", "materials", "schema"} <= set(commands)
    for argv in [["--help"]] + [[c, "--help"] for c in commands]:
        code, out, _ = cli(argv, capsys)
        text = " ".join(out.replace("│", " ").split())
        assert code == 0
        for status, meaning in EXIT_STATUS.items():
            assert f"{status} {' '.join(meaning.split()[:3])}" in text, (argv, status)


def test_a_sweep_with_failed_runs_exits_with_the_documented_status(tmp_path, capsys, models):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(LINE_SWEEP.replace("values = [1.0, 2.0]", "values = [1.0, 3.0]"))
    code, out, err = cli(["sweep", sweep, "--out", tmp_path / "o", "--workers", "1", "--allow-python", "-q"],
                         capsys)
    assert code == 3 == [c for c, m in EXIT_STATUS.items() if "sweep with failed runs" in m][0]
    assert "1 of 2 runs failed" in err
    assert "2 runs: 1 ok, 1 failed" in " ".join(out.split())   # the result on stdout, even with -q


# --- options ------------------------------------------------------------------------------------------

def test_v_is_verbose_in_every_command_and_impact_keeps_velocity(capsys):
    import typer.main

    for cmd in typer.main.get_command(app).commands.values():
        opts = {o for p in cmd.params for o in p.opts}
        assert "-v" in opts and "--verbose" in opts, cmd.name
        v = [p for p in cmd.params if "-v" in p.opts][0]
        assert v.name == "verbose", cmd.name
    code, out, _ = cli(["impact", "Al6061-T6", "Al6061-T6", "--velocity", "250 m/s", "--strength", "none", "-v"],
                       capsys)
    assert code == 0 and "interface pressure" in out


@pytest.mark.parametrize("command", ["run", "subgrid", "fit", "sweep"])
def test_dry_run_validates_prints_and_writes_nothing(command, tmp_path, capsys, models):
    if command == "fit":
        deck = _fit_folder(tmp_path)
    elif command == "sweep":
        deck = tmp_path / "sweep.toml"
        deck.write_text(LINE_SWEEP)
    else:
        deck = tmp_path / "deck.toml"
        deck.write_text(RUN_DECK if command == "run" else SUBGRID_DECK)
    before = sorted(p.name for p in tmp_path.iterdir())
    extra = ["--allow-python"] if command in ("sweep", "fit") else []
    code, out, err = cli([command, deck, "--out", tmp_path / "o", "--dry-run", *extra], capsys)
    assert code == 0, err
    assert "valid" in out or "every deck valid" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == before        # no output folder made
    deck.write_text(deck.read_text() + "\nunknown_key = 1\n")
    code, _, err = cli([command, deck, "--out", tmp_path / "o", "--dry-run", *extra], capsys)
    assert code == 2 and "unknown_key" in err


# --- deck semantics -----------------------------------------------------------------------------------

TWO_BLOCKS = RUN_DECK.split("[[probes]]")[0] + """
[[bodies]]
name = "top"
material = "Al6061-T6"
[bodies.mesh]
corners = [["0 mm", "1 mm"], ["1 mm", "1 mm"], ["1 mm", "2 mm"], ["0 mm", "2 mm"]]
nx = 2
ny = 2
"""


@pytest.mark.parametrize("extra, fragments", [
    ('[[ties]]\nsides = ["plate.top", "plate.top"]\n', ["ties[0].sides", "'plate.top' twice"]),
    ('[[slide_lines]]\nname = "s"\nguide = { body = "plate", side = "top" }\nslave = { body = "plate", side = "top" }\n',
     ["slide_lines[0]", "different sides"]),
    ('[[ties]]\nsides = ["plate.top", "top.bottom"]\n[[ties]]\nsides = ["top.bottom", "plate.top"]\n',
     ["ties[1].sides", "already joined by ties[0].sides"]),
    ('[[ties]]\nsides = ["plate.top", "top.bottom"]\n[[slide_lines]]\nname = "s"\n'
     'guide = { body = "plate", side = "top" }\nslave = { body = "top", side = "bottom" }\n',
     ["slide_lines[0]", "already joined by ties[0].sides"]),
])
def test_a_side_joined_to_itself_or_twice_exits_2(extra, fragments, tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(TWO_BLOCKS + extra)
    code, _, err = cli(["run", deck, "--out", tmp_path / "o", "--dry-run"], capsys)
    assert code == 2 and "Traceback" not in err, err
    for f in fragments:
        assert f in err, (f, err)


@pytest.mark.parametrize("deck, edit, field", [
    (RUN_DECK, ('end = "20 ns"', 'end = "20 ns"\ncfl = true'), "time.cfl = True"),
    (RUN_DECK, ("nx = 2", "nx = true"), "nx = True"),
    (SUBGRID_DECK, ("mu0 = 0.3", "mu0 = false"), "friction.mu0 = False"),
])
def test_numbers_refuse_booleans(deck, edit, field, tmp_path, capsys):
    path = tmp_path / "deck.toml"
    path.write_text(deck.replace(*edit))
    command = "run" if "bodies" in deck else "subgrid"
    code, _, err = cli([command, path, "--out", tmp_path / "o", "--dry-run"], capsys)
    assert code == 2 and field in err and "boolean" in err, err


def test_fit_bounds_refuse_a_boolean(tmp_path, capsys, models):
    fit = _fit_folder(tmp_path)
    fit.write_text(LINE_FIT.replace("bounds = [-5.0, 5.0]\n[[parameter]]\npath = \"b\"\nbounds = [-5.0, 5.0]",
                                    "bounds = [-5.0, 5.0]\n[[parameter]]\npath = \"b\"\nbounds = [-5.0, true]"))
    code, _, err = cli(["fit", fit, "--out", tmp_path / "o", "--dry-run", "--allow-python"], capsys)
    assert code == 2 and "parameter[1].bounds" in err and "boolean" in err, err


# --- paths --------------------------------------------------------------------------------------------

GEO = """
SetFactory("Built-in");
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 3; Transfinite Surface{1}; Recombine Surface{1};
Physical Surface("plate") = {1};
Physical Curve("bottom") = {1};
"""


@pytest.fixture
def mesh_folder(tmp_path):
    """A folder with a .msh (made by gmsh from GEO) and a run deck naming it relatively."""
    gmsh = pytest.importorskip("gmsh")
    folder = tmp_path / "decks"
    folder.mkdir()
    (folder / "plate.geo").write_text(GEO)
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(folder / "plate.geo"))
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(folder / "plate.msh"))
    finally:
        gmsh.finalize()
    deck = RUN_DECK.split("[[probes]]")[0].replace(
        '[bodies.mesh]\ncorners = [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]]\nnx = 2\nny = 2\n',
        '[bodies.mesh]\nfile = "plate.msh"\ngroup = "plate"\nscale = "1 mm"\n')
    assert 'file = "plate.msh"' in deck
    (folder / "deck.toml").write_text(deck)
    return folder


def test_a_sweep_whose_base_names_a_relative_mesh_runs_from_another_folder(mesh_folder, tmp_path, capsys,
                                                                            monkeypatch):
    (mesh_folder / "sweep.toml").write_text('base = "deck.toml"\n[[parameter]]\npath = "time.end"\n'
                                            'values = ["5 ns"]\n')
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    code, out, err = cli(["sweep", mesh_folder / "sweep.toml", "--out", tmp_path / "o", "--workers", "1", "-q"],
                         capsys)
    assert code == 0, err
    assert "1 ok" in out
    assert list(elsewhere.iterdir()) == []


def test_run_mesh_files_stay_inside_the_decks_folder_unless_allowed(mesh_folder, tmp_path, capsys):
    inner = mesh_folder / "inner"
    inner.mkdir()
    text = (mesh_folder / "deck.toml").read_text().replace('file = "plate.msh"', 'file = "../plate.msh"')
    (inner / "deck.toml").write_text(text)
    code, _, err = cli(["run", inner / "deck.toml", "--out", tmp_path / "o", "--dry-run"], capsys)
    assert code == 2 and "bodies[0].mesh.file = '../plate.msh'" in err and "--allow-outside" in err
    code, out, err = cli(["run", inner / "deck.toml", "--out", tmp_path / "o", "--dry-run", "--allow-outside"],
                         capsys)
    assert code == 0 and "4 cells" in out, err
    geo = (mesh_folder / "deck.toml").read_text().replace('file = "plate.msh"', 'file = "plate.geo"')
    (mesh_folder / "geo.toml").write_text(geo)
    code, _, err = cli(["run", mesh_folder / "geo.toml", "--out", tmp_path / "o", "--dry-run"], capsys)
    assert code == 2 and "--allow-geo" in err
    code, out, err = cli(["run", mesh_folder / "geo.toml", "--out", tmp_path / "o", "--dry-run", "--allow-geo"],
                         capsys)
    assert code == 0 and "4 cells" in out, err


# --- outputs: one header style, one file mode ------------------------------------------------------------

HEADER = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*( \[[^\[\]]+\])?$")
BARE_OK = {"line", "node", "node_index", "active", "iterations", "substeps", "run", "status", "error", "seconds",
           "rms"}


def _check_folder(out: Path, bare: set[str] = frozenset()) -> list[str]:
    mask = os.umask(0)
    os.umask(mask)
    mode = 0o666 & ~mask
    names = []
    for path in sorted(out.rglob("*")):
        if path.is_file():
            assert path.stat().st_mode & 0o777 == mode, (path.name, oct(path.stat().st_mode & 0o777))
            names.append(path.name)
        if path.suffix == ".csv":
            with path.open() as fh:
                header = next(csv.reader(fh))
            for col in header:
                assert HEADER.match(col), (path.name, col)
                assert "[" in col or col in BARE_OK | bare or col.split(".")[-1] in BARE_OK, (path.name, col)
                assert not re.search(r"_(s|m|K|Pa|mps|Wm2|J)$", col), (path.name, col)   # the old style
    return names


def test_every_output_of_a_run_shares_one_header_style_and_mode(tmp_path, capsys):
    from shockfriction.hydro.api import run_dict

    strip = {
        "title": "strip", "time": {"end": "60 ns", "cfl": 0.5}, "output": {"field_interval": "30 ns"},
        "bodies": [
            {"name": "flyer", "material": "Steel4340", "strength": "scg", "velocity": ["55 m/s", "85 m/s"],
             "mesh": {"corners": [["0 mm", "-1 mm"], ["0.1 mm", "-1 mm"], ["0.1 mm", "0 mm"], ["0 mm", "0 mm"]],
                      "nx": 1, "ny": 10}, "boundary": {"left": "periodic", "right": "periodic"}},
            {"name": "target", "material": "Ti-6Al-4V", "strength": "scg",
             "mesh": {"corners": [["0 mm", "0 mm"], ["0.1 mm", "0 mm"], ["0.1 mm", "1 mm"], ["0 mm", "1 mm"]],
                      "nx": 1, "ny": 10}, "boundary": {"left": "periodic", "right": "periodic"}}],
        "slide_lines": [{"name": "interface", "guide": {"body": "flyer", "side": "top"},
                         "slave": {"body": "target", "side": "bottom"}, "record_interval": "10 ns",
                         "friction": {"law": "subgrid-thermoelastic", "mu0": 0.15, "f": 0.15, "thickness": "20 um",
                                      "cells": 20, "profile_nodes": [0], "profile_interval": "20 ns"}}],
        "probes": [{"name": "rear", "body": "target", "node": [0, -1], "quantities": ["vx", "vy"]},
                   {"name": "near", "body": "target", "cell": [0, 2], "quantities": ["sigma_xy", "T", "eps_p"]}],
    }
    out = tmp_path / "run"
    run_dict(strip, out)
    names = _check_folder(out)
    assert {"probes.csv", "energy.csv", "interface.csv", "columns.csv", "summary.json", "fields.xmf",
            "fields.h5"} <= set(names)
    deck = tmp_path / "sg.toml"
    deck.write_text(SUBGRID_DECK)
    assert cli(["subgrid", deck, "--out", tmp_path / "sg", "-q"], capsys)[0] == 0
    assert {"history.csv", "profiles.csv", "interface.png"} <= set(_check_folder(tmp_path / "sg"))


def test_the_sweep_and_fit_tables_share_the_header_style(tmp_path, capsys, models):
    fit = _fit_folder(tmp_path / "f")
    assert cli(["fit", fit, "--out", tmp_path / "fo", "--workers", "1", "-q", "--allow-python"], capsys)[0] == 0
    _check_folder(tmp_path / "fo", bare={"a", "b"})   # parameters given without a unit keep their names
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(LINE_SWEEP)
    assert cli(["sweep", sweep, "--out", tmp_path / "so", "--workers", "1", "--allow-python", "-q"], capsys)[0] == 0
    header = (tmp_path / "so" / "sweep.csv").read_text().splitlines()[0].split(",")
    assert all(HEADER.match(c) for c in header), header


def test_no_scratch_folder_is_left_by_a_subgrid_sweep(tmp_path, capsys, monkeypatch):
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.setenv("TMPDIR", str(scratch))
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", None)
    (tmp_path / "deck.toml").write_text(SUBGRID_DECK)
    (tmp_path / "sweep.toml").write_text('base = "deck.toml"\n[[parameter]]\npath = "friction.mu0"\n'
                                         'values = [0.2, 0.3]\n')
    code, _, err = cli(["sweep", tmp_path / "sweep.toml", "--out", tmp_path / "o", "--workers", "1", "-q"], capsys)
    assert code == 0, err
    assert list(scratch.iterdir()) == []
