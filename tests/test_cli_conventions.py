"""Command-line conventions: --version, output-folder refusal and --force, option checks, exit
codes, logging levels, deck JSON schemas, and no matplotlib backend switching."""

import json
import logging
import subprocess
import sys
from pathlib import Path

import pytest

import shockfriction
from shockfriction.cli import main
from shockfriction.errors import UsageError
from shockfriction.io.outdir import OUTPUT_PATTERNS, prepare_out_dir

ROOT = Path(__file__).resolve().parents[1]

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


def cli(argv, capsys):
    """Exit status, stdout and stderr (newlines folded) of one command."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    cap = capsys.readouterr()
    code = exc.value.code
    return (0 if code is None else code), cap.out, cap.err.replace("\n", " ")


def test_version_prints_the_package_version(capsys):
    code, out, _ = cli(["--version"], capsys)
    assert code == 0 and out.strip() == f"shockfriction {shockfriction.__version__}"
    # one source: pyproject reads the version from the package (no tag needed in a fresh clone)
    import re
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" in project["project"]["dynamic"]
    assert project["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "shockfriction.__version__"}
    assert re.fullmatch(r"\d+\.\d+\.\d+", shockfriction.__version__) and shockfriction.__version__ != "0.1.0"


def test_help_documents_the_exit_codes(capsys):
    for argv in (["--help"], ["run", "--help"]):
        code, out, _ = cli(argv, capsys)
        text = " ".join(out.split())
        assert code == 0
        for part in ("0 done", "2 deck or usage error", "3 run failure", "130 interrupted"):
            assert part in text, (argv, part)


# --- output folders ----------------------------------------------------------------------------

def test_prepare_out_dir_creates_accepts_empty_and_refuses_non_empty(tmp_path):
    new = prepare_out_dir(tmp_path / "a" / "b")
    assert new.is_dir()
    assert prepare_out_dir(new) == new                      # empty: fine
    (new / "probes.csv").write_text("old")
    with pytest.raises(UsageError, match="not empty.*--force"):
        prepare_out_dir(new)
    assert prepare_out_dir(new, restart=True) == new        # a restart keeps everything
    assert (new / "probes.csv").exists()
    with pytest.raises(UsageError, match="exclude each other"):
        prepare_out_dir(new, force=True, restart=True)


def test_force_removes_previous_outputs_only(tmp_path):
    old = ["probes.csv", "energy.csv", "summary.json", "fields.h5", "fields.xmf", "interface.h5",
           "interface_top.png", "history_low.csv", "profiles.png", "columns_a.png"]
    for name in old + ["notes.txt", "deck.toml"]:
        (tmp_path / name).write_text("x")
    prepare_out_dir(tmp_path, force=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.toml", "notes.txt"]
    assert all(any(Path(n).match(p) for p in OUTPUT_PATTERNS) for n in old)


def test_out_naming_a_file_is_a_usage_error(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(UsageError, match="is a file"):
        prepare_out_dir(f)


@pytest.mark.parametrize("command", ["run", "subgrid", "sweep", "fit"])
def test_every_command_refuses_an_out_that_is_a_file(command, tmp_path, capsys):
    f = tmp_path / "taken"
    f.write_text("x")
    deck = tmp_path / "deck.toml"
    deck.write_text(RUN_DECK if command == "run" else SUBGRID_DECK)
    code, _, err = cli([command, deck, "--out", f], capsys)
    assert code == 2
    assert "usage error" in err and "is a file" in err and "Traceback" not in err


def test_run_refuses_a_non_empty_out_then_force_replaces_the_old_outputs(tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(RUN_DECK)
    out = tmp_path / "out"
    out.mkdir()
    (out / "interface.h5").write_text("a previous deck's slide-line record")
    (out / "interface_old.png").write_text("stale plot")
    code, _, err = cli(["run", deck, "--out", out, "-q"], capsys)
    assert code == 2 and "is not empty" in err and "--force" in err
    assert (out / "interface.h5").read_text().startswith("a previous")   # untouched
    code, stdout, _ = cli(["run", deck, "--out", out, "-q", "--force"], capsys)
    assert code == 0 and "cycles" in stdout
    names = {p.name for p in out.iterdir()}
    assert {"probes.csv", "energy.csv", "summary.json"} <= names
    assert "interface.h5" not in names and "interface_old.png" not in names


def test_subgrid_refuses_a_non_empty_out_then_force_runs(tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(SUBGRID_DECK)
    out = tmp_path / "o"
    out.mkdir()
    (out / "history_gone.csv").write_text("old")
    code, _, err = cli(["subgrid", deck, "--out", out, "--no-plots"], capsys)
    assert code == 2 and "is not empty" in err
    code, _, _ = cli(["subgrid", deck, "--out", out, "--no-plots", "--force"], capsys)
    assert code == 0
    assert (out / "history.csv").exists() and not (out / "history_gone.csv").exists()


def test_a_bad_deck_leaves_a_non_empty_out_alone(tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(RUN_DECK.replace('"20 ns"', '"20"'))
    out = tmp_path / "out"
    out.mkdir()
    (out / "probes.csv").write_text("keep me")
    code, _, err = cli(["run", deck, "--out", out, "--force"], capsys)
    assert code == 2 and "time.end" in err
    assert (out / "probes.csv").read_text() == "keep me"


# --- option checks -------------------------------------------------------------------------------

@pytest.mark.parametrize("argv, option", [(["run", "{deck}", "--threads", "-5"], "--threads"),
                                          (["subgrid", "{deck}", "--threads", "-1"], "--threads"),
                                          (["sweep", "{deck}", "--out", "{out}", "--workers", "0"], "--workers"),
                                          (["fit", "{deck}", "--workers", "-1"], "--workers")])
def test_counts_are_checked(argv, option, tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(RUN_DECK)
    argv = [a.format(deck=deck, out=tmp_path / "o") for a in argv]
    code, _, err = cli(argv, capsys)
    assert code == 2 and option in err and "usage error" in err


def test_subgrid_columns_give_the_same_bytes_on_one_and_two_threads(tmp_path, capsys):
    """``subgrid --threads``: 8 viscoplastic columns (1600 cells in all: parallel blocks on two threads) write the
    same history on one and on two threads."""
    import numba

    loading = "".join(f'[[loading]]\ntimes = ["0 ns"]\nslip_velocity = ["{v} m/s"]\nnormal_stress = ["10 GPa"]\n'
                      for v in range(150, 230, 10))
    deck = tmp_path / "deck.toml"
    deck.write_text(SUBGRID_DECK.replace('duration = "5 ns"', 'duration = "10 ns"\nmodel = "viscoplastic"')
                    .replace("cells = 20", "cells = 200").split("[[loading]]")[0] + loading)
    try:
        for n in (1, 2):
            code, _, err = cli(["subgrid", deck, "--out", tmp_path / f"t{n}", "--threads", n, "--no-plots"], capsys)
            assert code == 0, err
            assert numba.get_num_threads() == min(n, numba.config.NUMBA_NUM_THREADS)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    a, b = (sorted(p.name for p in (tmp_path / f"t{n}").glob("history*.csv")) for n in (1, 2))
    assert a == b and len(a) == 8
    for name in a:
        assert (tmp_path / "t1" / name).read_bytes() == (tmp_path / "t2" / name).read_bytes(), name


def test_schema_of_unknown_kind_is_a_usage_error(capsys):
    code, _, err = cli(["schema", "nope"], capsys)
    assert code == 2 and "run, subgrid, sweep, fit" in err


# --- logging -------------------------------------------------------------------------------------

@pytest.mark.parametrize("flags, level", [([], logging.WARNING), (["-v"], logging.INFO), (["-vv"], logging.DEBUG),
                                          (["-q"], logging.ERROR)])
def test_verbosity_sets_the_package_log_level(flags, level, tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(SUBGRID_DECK)
    code, _, _ = cli(["subgrid", deck, "--out", tmp_path / "o", "--no-plots", *flags], capsys)
    assert code == 0
    assert logging.getLogger("shockfriction").level == level


def test_verbose_run_logs_through_the_rich_handler(tmp_path, capsys):
    deck = tmp_path / "deck.toml"
    deck.write_text(RUN_DECK)
    code, _, err = cli(["run", deck, "--out", tmp_path / "o", "-v"], capsys)
    assert code == 0
    assert "4 zones, 9 nodes" in err
    code, _, err = cli(["run", deck, "--out", tmp_path / "o2", "-q"], capsys)
    assert code == 0 and "zones" not in err


def test_library_modules_do_not_print():
    offenders = [str(p.relative_to(ROOT)) for p in (ROOT / "src" / "shockfriction").rglob("*.py")
                 if "commands" not in p.parts and p.name not in ("cli.py",)
                 and any(line.lstrip().startswith("print(") for line in p.read_text().splitlines())]
    assert offenders == []


# --- JSON schema ---------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["run", "subgrid", "sweep", "fit"])
def test_schema_command_prints_json(kind, capsys):
    code, out, _ = cli(["schema", kind], capsys)
    assert code == 0
    schema = json.loads(out)
    assert schema["type"] == "object" and schema["properties"]


def test_unit_fields_are_strings_with_their_dimension(capsys):
    _, out, _ = cli(["schema", "run"], capsys)
    schema = json.loads(out)
    end = schema["$defs"]["TimeSpec"]["properties"]["end"]
    assert end["type"] == "string" and end["x-dimension"] == "[time]" and end["x-si-unit"] == "s"
    assert end["x-bound"] == "> 0 s" and "with its unit" in end["description"]
    temp = schema["$defs"]["Body"]["properties"]["temperature"]
    assert temp["type"] == "string" and temp["default"] == "300 K"   # SI default shown with its unit
    vel = schema["$defs"]["Body"]["properties"]["velocity"]
    assert [s["x-dimension"] for s in vel["prefixItems"]] == ["[length] / [time]"] * 2
    assert vel["default"] == ["0 m/s", "0 m/s"]
    # no unit field is left typed as a bare number (dimensionless ones accept both)
    text = json.dumps(schema)
    assert '"x-dimension": "[time]", "x-si-unit": "s"' in text.replace('"x-quantity": "time", ', "")


def test_subgrid_schema_validates_an_example_deck_shape(capsys):
    """Every key of an example deck is a property of the schema (a drift check, not a validator)."""
    import tomllib

    _, out, _ = cli(["schema", "subgrid"], capsys)
    schema = json.loads(out)
    deck = tomllib.loads((ROOT / "examples" / "subgrid" / "ball_al_200ms.toml").read_text())
    assert set(deck) <= set(schema["properties"])
    assert schema["properties"]["duration"]["type"] == "string"


def test_markdown_reference_has_a_table_per_section():
    from shockfriction.deck.schema import markdown_reference

    md = markdown_reference("run")
    assert "## TimeSpec" in md and "| `end` | time `[time]`" in md and "**required**" in md


# --- matplotlib ----------------------------------------------------------------------------------

def test_no_backend_switching_in_library_code():
    offenders = [str(p.relative_to(ROOT)) for p in (ROOT / "src").rglob("*.py")
                 if "matplotlib.use(" in p.read_text()]
    assert offenders == []


def test_plotting_keeps_the_users_backend(tmp_path):
    code = f"""
import matplotlib
matplotlib.use("svg")
from shockfriction.materials.library import get_material
from shockfriction.plot.stability import plot_stability_limit
import shockfriction.plot.subgrid, shockfriction.plot.coupled, shockfriction.plot.interface
import shockfriction.sweep.fitplot, shockfriction.cli
p = plot_stability_limit([get_material("Al6061-T6")], r"{tmp_path / 'st.png'}", samples=20)
import sys
assert matplotlib.get_backend() == "svg", matplotlib.get_backend()
assert "matplotlib.pyplot" not in sys.modules
assert open(p, "rb").read(8) == b"\\x89PNG\\r\\n\\x1a\\n"
print("ok")
"""
    env = {"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr


def test_a_viscoplastic_run_out_of_contact_plots_without_a_warning(tmp_path):
    """A viscoplastic sub-grid run in tension (no friction stress: tau = 0 throughout) keeps a linear stress axis: the
    log axis of the film panel printed matplotlib's "Data has no positive values" warning to the user."""
    import warnings

    import numpy as np

    from shockfriction.plot.subgrid import plot_interface

    t = np.linspace(0.0, 2e-8, 5)
    zeros = np.zeros((5, 1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        path = plot_interface(t, zeros + 300.0, zeros, ["ylp"], 1120.0, tmp_path / "i.png", film=zeros)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_ctrl_c_exits_130(tmp_path, capsys, monkeypatch):
    import shockfriction.hydro.api as api

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(api, "run_simulation", interrupted)
    deck = tmp_path / "deck.toml"
    deck.write_text(RUN_DECK)
    code, _, err = cli(["run", deck, "--out", tmp_path / "o"], capsys)
    assert code == 130 and "Traceback" not in err
