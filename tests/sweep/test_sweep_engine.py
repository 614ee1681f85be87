"""The sweep engine on a cheap python-kind model: pool vs Dask, failures, resume after SIGKILL."""

from __future__ import annotations

import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from shockfriction.sweep.engine import run_sweep

HERE = Path(__file__).resolve().parent
SRC = HERE.parents[1] / "src"

SWEEP = """
kind = "python"
model = "sweep_test_models:ramp"
[set]
tau = "1 us"
{extra}
[[parameter]]
path = "a"
values = {values}
[[parameter]]
path = "t0"
range = ["0 ns", "200 ns"]
n = 2
[[keep.derived]]
name = "peak"
record = "free_surface"
column = "velocity"
op = "max"
"""


@pytest.fixture
def models_importable(monkeypatch):
    """Make the test model importable here and in spawned workers."""
    monkeypatch.syspath_prepend(str(HERE))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(HERE), str(SRC), os.environ.get("PYTHONPATH", "")]))


def write_sweep(tmp_path: Path, values="[1.0, 2.0, 3.0]", extra="") -> Path:
    path = tmp_path / "sweep.toml"
    path.write_text(SWEEP.format(values=values, extra=extra))
    return path


def read_table(path: Path) -> list[dict]:
    with open(path) as fh:
        return list(csv.DictReader(fh))


def records_of(path: Path) -> dict:
    out = {}
    with h5py.File(path) as h5:
        for run, g in h5.items():
            out[run] = {f"{name}/{col}": g[name][col][()] for name in g for col in g[name]}
    return out


def test_local_pool_and_dask_cluster_give_identical_results(tmp_path, models_importable):
    from dask.distributed import LocalCluster

    sweep = write_sweep(tmp_path)
    local = run_sweep(sweep, tmp_path / "local", workers=2, progress=False)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0") as cluster:
        remote = run_sweep(sweep, tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    assert (local.ok, remote.ok) == (6, 6)
    ta, tb = read_table(local.table), read_table(remote.table)
    drop = {"seconds"}
    assert [{k: v for k, v in r.items() if k not in drop} for r in ta] == \
           [{k: v for k, v in r.items() if k not in drop} for r in tb]
    ra, rb = records_of(local.records), records_of(remote.records)
    assert ra.keys() == rb.keys() and len(ra) == 6
    for run in ra:
        for name in ra[run]:
            np.testing.assert_array_equal(ra[run][name], rb[run][name])
    # the kept scalar is the exact model value: peak of a(1 - exp(-(t - t0)/tau)) on the sampled times
    row = ta[5]
    t = np.linspace(0.0, 10e-6, 201)
    assert float(row["peak"]) == pytest.approx(3.0 * (1 - np.exp(-(t[-1] - 200e-9) / 1e-6)), rel=1e-14)
    assert row["t0 [ns]"] == "200.0" and row["a"] == "3.0"


def test_a_failed_run_is_recorded_and_the_sweep_goes_on(tmp_path, models_importable):
    sweep = write_sweep(tmp_path, extra="fail_above = 2.5")
    res = run_sweep(sweep, tmp_path / "out", workers=1, progress=False)
    rows = read_table(res.table)
    assert (res.ok, res.failed, res.pending) == (4, 2, 0)
    for row in rows:
        if float(row["a"]) > 2.5:
            assert row["status"] == "failed"
            assert "RuntimeError: a = 3.0 above 2.5: the model refuses" in row["error"]
            assert row["peak"] == ""
        else:
            assert row["status"] == "ok" and row["error"] == ""
    # a failed run is finished: a rerun neither loses nor recomputes it, unless asked
    again = run_sweep(sweep, tmp_path / "out", workers=1, progress=False)
    assert (again.computed, again.reused, again.failed) == (0, 6, 2)
    retried = run_sweep(sweep, tmp_path / "out", workers=1, progress=False, retry_failed=True)
    assert (retried.computed, retried.failed) == (2, 2)


def test_killed_sweep_resumes_without_losing_or_recomputing_finished_runs(tmp_path, models_importable):
    markers = tmp_path / "markers"
    values = "[" + ", ".join(f"{a:.1f}" for a in range(1, 13)) + "]"
    sweep = write_sweep(tmp_path, values=values, extra=f'sleep = 0.15\nmarker_dir = "{markers}"')
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "shockfriction", "sweep", str(sweep), "--out", str(out), "--workers", "1", "--quiet",
           "--allow-python"]
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    runs_dir = out / "runs"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(list(runs_dir.glob("*.h5"))) < 5:
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGKILL)  # the sweep and its worker, mid-sweep
    proc.wait()
    finished_before = {p.name for p in runs_dir.glob("*.h5")}
    assert 5 <= len(finished_before) < 24, "the kill must land mid-sweep"
    calls_before = len(list(markers.iterdir()))

    res = run_sweep(sweep, out, workers=1, progress=False)
    assert (res.ok, res.pending) == (24, 0)
    assert res.reused == len(finished_before)
    assert res.computed == 24 - len(finished_before)
    # no finished run ran again: the new calls are exactly the runs that were not finished
    assert len(list(markers.iterdir())) - calls_before == 24 - len(finished_before)
    # and the resumed results equal those of an uninterrupted sweep
    clean = run_sweep(sweep, tmp_path / "clean", workers=2, progress=False)
    strip = lambda rows: [{k: v for k, v in r.items() if k != "seconds"} for r in rows]  # noqa: E731
    assert strip(read_table(res.table)) == strip(read_table(clean.table))


def test_the_table_is_refreshed_while_the_sweep_runs(tmp_path, models_importable, monkeypatch):
    import shockfriction.sweep.engine as engine

    monkeypatch.setattr(engine, "TABLE_REFRESH_S", 0.0)
    seen = []
    real = engine.write_table

    def spy(out_dir, runs, units, results):
        seen.append(sum(1 for r in results.values() if r["status"] == "ok"))
        return real(out_dir, runs, units, results)

    monkeypatch.setattr(engine, "write_table", spy)
    sweep = write_sweep(tmp_path)
    res = run_sweep(sweep, tmp_path / "out", workers=1, progress=False)
    assert res.ok == 6
    assert seen == [1, 2, 3, 4, 5, 6, 6], "one refresh per finished run, then the final table"


def test_dry_run_validates_and_lists_the_runs_and_runs_nothing(tmp_path, models_importable, capsys):
    from shockfriction.cli import main

    sweep = write_sweep(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(["sweep", str(sweep), "--out", str(tmp_path / "out"), "--dry-run", "--allow-python"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "6 runs of kind 'python'" in out and "0 finished, 6 to run" in out and "200.0 ns" in out
    assert not (tmp_path / "out").exists()


def test_a_run_whose_worker_dies_stays_pending_and_the_command_exits_1(tmp_path, models_importable, capsys):
    from shockfriction.cli import main

    sweep = write_sweep(tmp_path, values="[1.0, 2.0]", extra="die_at = 2.0")
    with pytest.raises(SystemExit) as exc:
        main(["sweep", str(sweep), "--out", str(tmp_path / "out"), "--workers", "1", "--quiet", "--allow-python"])
    assert exc.value.code == 1
    err = " ".join(capsys.readouterr().err.split())
    assert "lost with its worker, left pending" in err and "BrokenProcessPool" in err
    table = read_table(tmp_path / "out" / "sweep.csv")
    assert [r["status"] for r in table if r["a"] == "1.0"] == ["ok", "ok"], "runs before the death are kept"
    assert [r["status"] for r in table if r["a"] == "2.0"] == ["pending", "pending"]
