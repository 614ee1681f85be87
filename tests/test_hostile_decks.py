"""Issue 28, safe decks: hostile decks end fast with exit status 2 and a one-line message, small, and
write nothing outside the output folder; pool workers of a sweep die with it (SIGKILL included).

Each deck runs the command line in a fresh interpreter (``python -m shockfriction``) under a small
wrapper that reports the wall time and the peak memory of the command (``RUSAGE_CHILDREN``
``ru_maxrss`` of the wrapper: the largest resident set of the command and of its children, gmsh
included)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

WRAPPER = r"""
import json, resource, subprocess, sys, time
t0 = time.monotonic()
res = subprocess.run([sys.executable, "-m", "shockfriction", *sys.argv[1:]], capture_output=True, text=True,
                     timeout=60, stdin=subprocess.DEVNULL)
print(json.dumps({"rc": res.returncode, "seconds": time.monotonic() - t0, "stderr": res.stderr,
                  "stdout": res.stdout, "maxrss_kib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss}))
"""

RUN_BLOCK = """
[time]
end = "20 ns"
[[bodies]]
name = "plate"
material = "Al6061-T6"
[bodies.mesh]
corners = [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]]
nx = {nx}
ny = {ny}
"""

RUN_GEO = """
[time]
end = "20 ns"
[[bodies]]
name = "plate"
material = "Al6061-T6"
mesh = { file = "evil.geo", group = "plate", scale = "1 mm" }
"""

SQUARE = """
Point(1) = {0, 0, 0, %(h)s}; Point(2) = {1, 0, 0, %(h)s}; Point(3) = {1, 1, 0, %(h)s}; Point(4) = {0, 1, 0, %(h)s};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1}; Recombine Surface{1};
Physical Surface("plate") = {1};
"""


def _hostile(tmp_path: Path, case: str) -> tuple[list[str], Path]:
    """(command line arguments, folder the deck lives in) of one hostile case."""
    deck_dir = tmp_path / "decks"
    deck_dir.mkdir()
    out = tmp_path / "out"
    marker = tmp_path / "PWNED"
    if case in ("geo-systemcall", "geo-printf", "geo-save"):
        body = {"geo-systemcall": f'SystemCall "touch {marker}";',
                "geo-printf": f'Printf("pwned") > "{marker}";',
                "geo-save": f'Save "{marker}.msh";'}[case]
        (deck_dir / "evil.geo").write_text(body + SQUARE % {"h": "0.5"})
        (deck_dir / "deck.toml").write_text(RUN_GEO)
        return ["run", str(deck_dir / "deck.toml"), "--out", str(out)], deck_dir
    if case == "geo-1e8-elements":
        (deck_dir / "evil.geo").write_text(SQUARE % {"h": "1e-4"})
        (deck_dir / "deck.toml").write_text(RUN_GEO)
        return ["run", str(deck_dir / "deck.toml"), "--out", str(out), "--allow-geo"], deck_dir
    if case == "body-19M-cells":
        (deck_dir / "deck.toml").write_text(RUN_BLOCK.format(nx=4360, ny=4360))
        return ["run", str(deck_dir / "deck.toml"), "--out", str(out)], deck_dir
    if case in ("sweep-lhs-1e12", "sweep-grid-product", "sweep-range-n-1e12"):
        (deck_dir / "deck.toml").write_text(RUN_BLOCK.format(nx=2, ny=2))
        text = {"sweep-lhs-1e12": '[sample]\nmethod = "lhs"\nn = 1000000000000\n[[parameter]]\n'
                                  'path = "time.end"\nrange = ["1 ns", "2 ns"]\n',
                "sweep-range-n-1e12": '[[parameter]]\npath = "time.end"\nrange = ["1 ns", "2 ns"]\n'
                                      'n = 1000000000000\n',
                "sweep-grid-product": "".join(f'[[parameter]]\npath = "bodies[0].temperature"\nname = "t{k}"\n'
                                              f'range = ["300 K", "400 K"]\nn = 10000\n' for k in range(4))}[case]
        (deck_dir / "sweep.toml").write_text('base = "deck.toml"\n' + text)
        return ["sweep", str(deck_dir / "sweep.toml"), "--out", str(out), "--workers", "1"], deck_dir
    if case == "dev-zero":
        return ["run", "/dev/zero", "--out", str(out)], deck_dir
    if case == "fifo":
        os.mkfifo(deck_dir / "deck.toml")
        return ["run", str(deck_dir / "deck.toml"), "--out", str(out)], deck_dir
    if case == "nesting-1000":
        (deck_dir / "deck.toml").write_text("title = " + "[" * 1000 + "]" * 1000 + "\n" + RUN_BLOCK.format(nx=2, ny=2))
        return ["run", str(deck_dir / "deck.toml"), "--out", str(out)], deck_dir
    if case == "inline-table-nesting-1000":
        (deck_dir / "deck.toml").write_text("x = " + "{a = " * 1000 + "1" + "}" * 1000 + "\n")
        return ["sweep", str(deck_dir / "deck.toml"), "--out", str(out)], deck_dir
    if case == "huge-deck":
        (deck_dir / "deck.toml").write_text("# " + "x" * (2 << 20) + "\n" + RUN_BLOCK.format(nx=2, ny=2))
        return ["run", str(deck_dir / "deck.toml"), "--out", str(out)], deck_dir
    raise AssertionError(case)


def _snapshot(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


CASES = ["geo-systemcall", "geo-printf", "geo-save", "geo-1e8-elements", "body-19M-cells", "sweep-lhs-1e12",
         "sweep-range-n-1e12", "sweep-grid-product", "dev-zero", "fifo", "nesting-1000",
         "inline-table-nesting-1000", "huge-deck"]
FAST = {"geo-systemcall", "sweep-lhs-1e12", "fifo", "nesting-1000", "geo-1e8-elements"}


@pytest.mark.parametrize("case", [c if c in FAST else pytest.param(c, marks=pytest.mark.slow) for c in CASES])
def test_a_hostile_deck_exits_2_fast_small_and_writes_nothing(case, tmp_path):
    argv, deck_dir = _hostile(tmp_path, case)
    work = tmp_path / "cwd"
    work.mkdir()
    before = _snapshot(tmp_path)
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch), PYTHONPATH=str(ROOT / "src"))
    res = subprocess.run([sys.executable, "-c", WRAPPER, *argv], cwd=work, capture_output=True, text=True,
                         timeout=120, env=env)
    report = json.loads(res.stdout.strip().splitlines()[-1])
    err = report["stderr"].strip()
    print(f"\n{case}: exit {report['rc']} in {report['seconds']:.2f} s, peak {report['maxrss_kib'] / 1024:.0f} MB: "
          f"{err}")
    assert report["rc"] == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err and "internal error" not in err, err
    assert report["seconds"] < 10.0
    assert report["maxrss_kib"] < 500 * 1024
    assert _snapshot(tmp_path) - before == {"tmp"}, _snapshot(tmp_path) - before   # nothing written, no output
    assert list(scratch.iterdir()) == []                                             # no scratch left
    assert not (tmp_path / "out").exists()


def test_a_geo_script_runs_nothing_without_allow_geo_and_a_msh_needs_no_flag(tmp_path):
    from shockfriction.errors import DeckError
    from shockfriction.hydro.api import load
    from shockfriction.safety import Trust

    argv, deck_dir = _hostile(tmp_path, "geo-systemcall")
    with pytest.raises(DeckError, match="--allow-geo"):
        load(deck_dir / "deck.toml", trust=Trust())
    assert not (tmp_path / "PWNED").exists()
    (deck_dir / "evil.msh").write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
    (deck_dir / "msh.toml").write_text(RUN_GEO.replace("evil.geo", "evil.msh"))
    assert load(deck_dir / "msh.toml", trust=Trust()).bodies[0].mesh.file.endswith("evil.msh")


def test_a_subgrid_history_that_goes_non_finite_exits_3_naming_where(tmp_path, capsys, monkeypatch):
    import numpy as np

    from shockfriction.cli import main
    from shockfriction.friction.subgrid import driver

    real = driver.ThermalColumns.surface

    def poisoned(self):
        theta = real(self)
        return np.full_like(theta, np.nan) if self.theta.sum() > 300.0 * self.theta.size + 1.0 else theta

    monkeypatch.setattr(driver.ThermalColumns, "surface", poisoned)
    deck = tmp_path / "flux.toml"
    deck.write_text('material = "Al5083-H111"\nheat_share = 0.5\nduration = "5 ns"\ndt = "1 ns"\n'
                    '[column]\nthickness = "20 um"\ncells = 20\n'
                    '[[loading]]\nname = "hot"\ntimes = ["0 ns"]\nheat_flux = ["1e9 W/m^2"]\n')
    with pytest.raises(SystemExit) as exc:
        main(["subgrid", str(deck), "--out", str(tmp_path / "o"), "--no-plots"])
    err = " ".join(capsys.readouterr().err.split())
    assert exc.value.code == 3
    assert "column 'hot': theta_interface became non-finite (nan) at step" in err and ", t = " in err
    rows = (tmp_path / "o" / "history.csv").read_text().splitlines()
    assert rows[0].startswith("t [s],") and "nan" not in " ".join(r.split(",")[1] for r in rows[1:])


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_a_killed_sweep_leaves_no_process_and_no_scratch_folder_behind(tmp_path, sig):
    psutil = pytest.importorskip("psutil")
    mods = tmp_path / "mods"
    mods.mkdir()
    (mods / "sf_sleepy.py").write_text(
        "import time\n"
        "def model(deck, workdir):\n"
        "    (workdir / 'busy').write_text('x')\n"
        "    time.sleep(60)\n"
        "    return {'records': {}, 'summary': {}}\n")
    (tmp_path / "sweep.toml").write_text('model = "sf_sleepy:model"\n[[parameter]]\npath = "a"\n'
                                         'values = [1.0, 2.0, 3.0, 4.0]\n')
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch),
               PYTHONPATH=os.pathsep.join([str(mods), str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    proc = subprocess.Popen([sys.executable, "-m", "shockfriction", "sweep", str(tmp_path / "sweep.toml"),
                             "--out", str(tmp_path / "o"), "--workers", "2", "--quiet", "--allow-python"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    parent = psutil.Process(proc.pid)
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline and len(list(scratch.rglob("busy"))) < 2:
        time.sleep(0.2)
    kids = parent.children(recursive=True)
    assert len(list(scratch.rglob("busy"))) == 2, "the workers did not start their runs"
    assert len(kids) >= 2
    os.kill(proc.pid, sig)
    proc.wait(timeout=30)
    assert proc.returncode == (-signal.SIGKILL if sig == signal.SIGKILL else 130)
    time.sleep(5.0)
    alive = [p for p in kids if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
    for p in alive:  # clean up before failing
        p.kill()
    assert not alive, [p.cmdline()[:3] for p in alive]
    out, err = proc.communicate(timeout=5)   # nobody holds the pipes open: this returns at once
    assert list(scratch.iterdir()) == [], list(scratch.iterdir())


def test_a_worker_that_dies_leaves_no_scratch_folder(tmp_path):
    mods = tmp_path / "mods"
    mods.mkdir()
    (mods / "sf_crashy.py").write_text(
        "import os\n"
        "def model(deck, workdir):\n"
        "    (workdir / 'busy').write_text('x')\n"
        "    if float(deck['a']) > 1.5:\n"
        "        os._exit(1)  # as a segfault or an OOM kill would\n"
        "    return {'records': {}, 'summary': {}}\n")
    (tmp_path / "sweep.toml").write_text('model = "sf_crashy:model"\n[[parameter]]\npath = "a"\nvalues = [1.0, 2.0]\n')
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch),
               PYTHONPATH=os.pathsep.join([str(mods), str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    res = subprocess.run([sys.executable, "-m", "shockfriction", "sweep", str(tmp_path / "sweep.toml"),
                          "--out", str(tmp_path / "o"), "--workers", "1", "--quiet", "--allow-python"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert res.returncode == 1, res.stderr          # runs left pending with the dead worker
    assert "pending" in res.stdout
    assert list(scratch.iterdir()) == [], list(scratch.rglob("*"))
