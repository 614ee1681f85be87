"""Safety of decks from elsewhere (docs/theory/reliability.md): file references stay in the deck's
folder, Python models need --allow-python and are never imported by --dry-run, names that become
file names are checked, errors never quote a file's contents; sweeps report failed runs, tear their
pool down on SIGTERM, and key runs by the package's code."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from shockfriction.cli import main
from shockfriction.deck.base import read_toml

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
EXAMPLES = ROOT / "examples"

MODEL = '''
import os, time
from pathlib import Path
MARK = os.environ.get("SF_TEST_MARK")
if MARK:
    Path(MARK).write_text("imported")
def model(deck, workdir):
    if deck.get("sleep"):
        time.sleep(float(deck["sleep"]))
    if float(deck["a"]) > 1.5:
        raise RuntimeError("refused")
    return {"records": {"r": {"time": [0.0, 1.0], "value": [0.0, float(deck["a"])]}}, "summary": {}}
'''


@pytest.fixture
def model_module(tmp_path, monkeypatch):
    """A Python model that leaves a marker file when it is imported."""
    mods = tmp_path / "mods"
    mods.mkdir()
    (mods / "sf_marker_model.py").write_text(MODEL)
    mark = tmp_path / "imported.txt"
    monkeypatch.syspath_prepend(str(mods))
    monkeypatch.setenv("SF_TEST_MARK", str(mark))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(mods), str(SRC), os.environ.get("PYTHONPATH", "")]))
    sys.modules.pop("sf_marker_model", None)
    return mark


def _cli(capsys, *argv) -> tuple[int, str]:
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    return exc.value.code, " ".join(capsys.readouterr().err.split())


def _sweep(folder: Path, base: str) -> Path:
    path = folder / "sweep.toml"
    path.write_text(f'base = "{base}"\n[[parameter]]\npath = "friction.mu0"\nvalues = [0.1, 0.2]\n')
    return path


@pytest.mark.parametrize("how", ["dotdot", "absolute"])
def test_sweep_base_outside_the_folder_is_refused_unless_allowed(tmp_path, capsys, how):
    deck = EXAMPLES / "subgrid" / "ball_al_200ms.toml"
    inner = tmp_path / "a" / "b"
    inner.mkdir(parents=True)
    (tmp_path / "a" / "deck.toml").write_text(deck.read_text())
    base = "../deck.toml" if how == "dotdot" else str(deck)
    sweep = _sweep(inner, base)
    code, err = _cli(capsys, "sweep", str(sweep), "--out", str(tmp_path / "out"), "--dry-run")
    assert code == 2 and f"base = '{base}'" in err and "--allow-outside" in err
    code, err = _cli(capsys, "sweep", str(sweep), "--out", str(tmp_path / "out"), "--dry-run", "--allow-outside")
    assert code == 0


def test_fit_measured_file_outside_is_refused_and_a_non_csv_is_never_quoted(tmp_path, capsys):
    secret = tmp_path / "secret.txt"
    secret.write_text("root:x:0:0:TOPSECRET-LINE:/root:/bin/bash\nmore:secret\n")
    here = tmp_path / "fit"
    here.mkdir()
    (here / "deck.toml").write_text((EXAMPLES / "subgrid" / "ball_al_200ms.toml").read_text())
    fit = here / "fit.toml"
    fit.write_text('base = "deck.toml"\n[measured]\nfile = "../secret.txt"\nvalue = "tau"\n'
                   '[computed]\nrecord = "ball"\nvalue = "tau"\n'
                   '[[parameter]]\npath = "friction.f"\nbounds = [0.2, 1.2]\n')
    code, err = _cli(capsys, "fit", str(fit), "--out", str(tmp_path / "o"), "--workers", "1")
    assert code == 2 and "measured.file = '../secret.txt'" in err and "--allow-outside" in err
    code, err = _cli(capsys, "fit", str(fit), "--out", str(tmp_path / "o"), "--workers", "1", "--allow-outside")
    assert code == 2 and "measured.time = 'time'" in err
    assert "TOPSECRET" not in err and "root:x" not in err and "more:secret" not in err


def test_python_model_needs_allow_python_and_dry_run_never_imports_it(tmp_path, capsys, model_module):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('model = "sf_marker_model:model"\n[[parameter]]\npath = "a"\nvalues = [1.0, 2.0]\n')
    code, err = _cli(capsys, "sweep", str(sweep), "--out", str(tmp_path / "out"), "--dry-run")
    assert code == 2 and "model = 'sf_marker_model:model'" in err and "--allow-python" in err
    code, err = _cli(capsys, "sweep", str(sweep), "--out", str(tmp_path / "out"), "--dry-run", "--allow-python")
    assert code == 0
    assert not model_module.exists(), "--dry-run imported the model"
    assert "sf_marker_model" not in sys.modules


def test_a_sweep_with_failed_runs_exits_3_with_the_count(tmp_path, capsys, model_module):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('model = "sf_marker_model:model"\n[[parameter]]\npath = "a"\nvalues = [1.0, 2.0, 3.0]\n')
    code, err = _cli(capsys, "sweep", str(sweep), "--out", str(tmp_path / "out"), "--workers", "1", "--quiet",
                     "--allow-python")
    assert code == 3 and "2 of 3 runs failed" in err


def test_sigterm_to_a_sweep_terminates_its_pool_workers(tmp_path, model_module):
    psutil = pytest.importorskip("psutil")
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('model = "sf_marker_model:model"\n[set]\nsleep = 30.0\n'
                     '[[parameter]]\npath = "a"\nvalues = [0.1, 0.2, 0.3, 0.4]\n')
    proc = subprocess.Popen([sys.executable, "-m", "shockfriction", "sweep", str(sweep), "--out", str(tmp_path / "o"),
                             "--workers", "2", "--quiet", "--allow-python"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    parent = psutil.Process(proc.pid)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(parent.children(recursive=True)) < 3 and not model_module.exists():
        time.sleep(0.1)
    time.sleep(1.0)
    kids = parent.children(recursive=True)
    assert kids, "the sweep started no worker"
    os.kill(proc.pid, signal.SIGTERM)
    proc.wait(timeout=30)
    _, alive = psutil.wait_procs(kids, timeout=15)
    for p in alive:  # clean up before failing
        p.kill()
    assert not alive, f"{len(alive)} pool processes outlived the sweep"
    assert proc.returncode == 130


def test_fit_dataset_and_subgrid_loading_names_cannot_leave_the_output_folder(tmp_path, capsys):
    deck = read_toml(EXAMPLES / "subgrid" / "ball_al_200ms.toml")
    text = (EXAMPLES / "subgrid" / "ball_al_200ms.toml").read_text().replace('name = "ball"', 'name = "../escape"')
    (tmp_path / "sg.toml").write_text(text)
    code, err = _cli(capsys, "subgrid", str(tmp_path / "sg.toml"), "--out", str(tmp_path / "o"))
    assert code == 2 and "loading[0].name = '../escape'" in err
    assert deck["loading"][0]["name"] == "ball"
    fit = (EXAMPLES / "calibration" / "ball_two_loadings_fit.toml").read_text().replace('name = "low"', 'name = "a/b"')
    (tmp_path / "decks").mkdir()
    (tmp_path / "decks" / "ball_al_200ms.toml").write_text((EXAMPLES / "subgrid" / "ball_al_200ms.toml").read_text())
    for f in ("ball_low_synthetic.csv", "ball_high_synthetic.csv"):
        (tmp_path / f).write_bytes((EXAMPLES / "calibration" / f).read_bytes())
    (tmp_path / "fit.toml").write_text(fit)
    code, err = _cli(capsys, "fit", str(tmp_path / "fit.toml"), "--out", str(tmp_path / "o"), "--workers", "1")
    assert code == 2 and "dataset[0].name = 'a/b'" in err
    assert not (tmp_path.parent / "escape").exists() and not (tmp_path / "escape").exists()


def test_calibration_base_decks_are_copies_of_the_examples():
    pairs = [("calibration/decks/ball_al_200ms.toml", "subgrid/ball_al_200ms.toml"),
             ("calibration/decks/plate_impact_al_250ms.toml", "plate_impact_al_250ms.toml")]
    for copy, original in pairs:
        assert read_toml(EXAMPLES / copy) == read_toml(EXAMPLES / original), copy


def test_run_keys_change_with_the_package_code(monkeypatch):
    from shockfriction.sweep import design

    before = design.run_key("run", None, {"a": 1}, {})
    assert before == design.run_key("run", None, {"a": 1}, {})
    monkeypatch.setattr(design, "code_hash", lambda: "edited-source")
    assert design.run_key("run", None, {"a": 1}, {}) != before
