"""Least-squares calibration: recovery of known parameters, the Gauss-Newton covariance, bad fit files."""

from __future__ import annotations

import json
import os
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from shockfriction.cli import main
from shockfriction.sweep.fit import covariance, fit, write_outputs
from shockfriction.sweep.runners import run_deck

HERE = Path(__file__).resolve().parent
SRC = HERE.parents[1] / "src"

RAMP_FIT = """
kind = "python"
model = "sweep_test_models:ramp"
[set]
n = 301
t0 = "0 s"
[measured]
file = "measured.csv"
time_unit = "us"
value_unit = "m/s"
[computed]
record = "free_surface"
[[parameter]]
path = "a"
bounds = [1.0, 3.0]
initial = 1.5
[[parameter]]
path = "tau"
bounds = ["0.3 us", "2 us"]
initial = "1 us"
[time_shift]
bounds = ["-300 ns", "300 ns"]
"""


@pytest.fixture
def models_importable(monkeypatch):
    monkeypatch.syspath_prepend(str(HERE))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(HERE), str(SRC), os.environ.get("PYTHONPATH", "")]))


def synthetic(tmp_path: Path, truth: dict, noise: float, seed: int = 1) -> None:
    """A measured record made by running the model itself, plus Gaussian noise (time in us)."""
    rec = run_deck("python", {**truth, "n": 401}, tmp_path, "sweep_test_models:ramp").records["free_surface"]
    y = rec["velocity"] + np.random.default_rng(seed).normal(0.0, noise, rec["velocity"].size)
    np.savetxt(tmp_path / "measured.csv", np.c_[rec["time"] * 1e6, y], delimiter=",",
               header="time,velocity", comments="")


def test_fit_recovers_known_parameters_and_time_shift_from_a_noisy_synthetic_record(tmp_path, models_importable):
    synthetic(tmp_path, {"a": 2.0, "tau": "0.8 us", "t0": "150 ns"}, noise=0.02)
    (tmp_path / "fit.toml").write_text(RAMP_FIT)
    res = fit(tmp_path / "fit.toml", workers=2)
    truth = {"a": 2.0, "tau": 0.8, "time_shift": 150e-9}
    assert res.success
    for name, value, sigma in zip(res.names, res.values, res.sigma):
        err = abs(value - truth[name])
        print(f"{name}: {value:.6g} +- {sigma:.2g} (true {truth[name]:.6g}, {err / sigma:.2f} sigma)")
        assert err <= 3.0 * sigma, f"{name} off by more than 3 sigma"
        assert err <= 0.01 * abs(truth[name]), f"{name} off by more than 1 %"
    assert res.rms == pytest.approx(0.02, rel=0.15), "the residual is the noise level"
    paths = write_outputs(res, tmp_path / "out")
    report = json.loads(paths["report"].read_text())
    assert report["parameters"]["tau"]["unit"] == "us" and report["residual"]["dof"] == 401 - 3
    assert paths["plot"].stat().st_size > 10_000


def test_covariance_of_a_straight_line_is_the_ordinary_least_squares_one():
    # y = a + b t: Cov = s^2 (X^T X)^-1 exactly, with X = [1, t]
    t = np.linspace(0.0, 1.0, 11)
    X = np.c_[np.ones_like(t), t]
    r = np.random.default_rng(0).normal(0.0, 0.1, t.size)
    cov, ident, dof = covariance(X, r)
    exact = (r @ r) / (t.size - 2) * np.linalg.inv(X.T @ X)
    np.testing.assert_allclose(cov, exact, rtol=1e-12)
    assert ident == [True, True] and dof == 9


def test_reported_sigma_matches_the_scatter_of_repeated_fits(tmp_path, monkeypatch):
    """Monte Carlo: 40 noise draws; the spread of the fitted a, b equals the reported sigma (within 25 %)."""
    monkeypatch.syspath_prepend(str(HERE))
    (tmp_path / "fit.toml").write_text("""
kind = "python"
model = "sweep_test_models:line"
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
""")
    t = np.linspace(0.0, 1.0, 101)
    rng = np.random.default_rng(3)
    est, sig = [], []
    with ThreadPoolExecutor(2) as ex:
        for _ in range(40):
            y = 0.5 + 2.0 * t + rng.normal(0.0, 0.1, t.size)
            np.savetxt(tmp_path / "m.csv", np.c_[t, y], delimiter=",", header="time,value", comments="")
            res = fit(tmp_path / "fit.toml", executor=ex)
            est.append(res.values)
            sig.append(res.sigma)
    spread, reported = np.std(est, axis=0, ddof=1), np.mean(sig, axis=0)
    print("scatter", spread, "reported", reported)
    np.testing.assert_allclose(spread, reported, rtol=0.25)
    np.testing.assert_allclose(np.mean(est, axis=0), [0.5, 2.0], atol=3 * reported.max() / np.sqrt(40) * 2)


def test_a_parameter_the_record_does_not_determine_is_flagged(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(HERE))
    t = np.linspace(0.0, 1.0, 101)
    np.savetxt(tmp_path / "m.csv", np.c_[t, 1.0 + t], delimiter=",", header="time,value", comments="")
    (tmp_path / "fit.toml").write_text("""
kind = "python"
model = "sweep_test_models:line"
[set]
b = 1.0
[measured]
file = "m.csv"
value = "value"
[computed]
record = "r"
value = "value"
[[parameter]]
path = "a"
bounds = [0.0, 2.0]
[[parameter]]
path = "c"
bounds = [0.0, 1.0]
""")
    with ThreadPoolExecutor(1) as ex:
        res = fit(tmp_path / "fit.toml", executor=ex)
    assert res.identifiable == [True, False]
    assert res.values[0] == pytest.approx(1.0, abs=1e-9) and np.isinf(res.sigma[1])


@pytest.mark.parametrize("edit, fragments", [
    (("bounds = [1.0, 3.0]", "bounds = [3.0, 1.0]"), ["parameter[0]", "expected bounds (low, high) with high > low"]),
    (("initial = 1.5", "initial = 4.0"), ["parameter[0]", "expected an initial value inside the bounds"]),
    (('bounds = ["-300 ns", "300 ns"]', 'bounds = [-3, 3]'), ["time_shift", "expected times with their unit"]),
    (('file = "measured.csv"', 'file = "nothere.csv"'), ["measured.file = 'nothere.csv'", "expected a file"]),
    (('time_unit = "us"', 'time_unit = "parsec/s"'), ["measured", "time_unit"]),
    (('record = "free_surface"', 'record = "back"'), ["computed.record = 'back'", "expected a record the run produces"]),
])
def test_bad_fit_files_exit_2_with_field_and_expectation(tmp_path, capsys, models_importable, edit, fragments):
    synthetic(tmp_path, {"a": 2.0, "tau": "0.8 us"}, noise=0.0)
    (tmp_path / "fit.toml").write_text(RAMP_FIT.replace(*edit))
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(tmp_path / "fit.toml"), "--workers", "1", "--allow-python"])
    assert exc.value.code == 2
    err = " ".join(capsys.readouterr().err.split())
    for frag in fragments:
        assert frag in err


def test_measured_samples_beyond_the_run_exit_2(tmp_path, capsys, models_importable):
    """A measured record whose times lie beyond what the run computes (here 100 us later than the model's 10 us)
    exits 2 before the fit starts: np.interp would have held the record's end value there and the fit compared the
    samples with a constant the run never computed (it reported a residual and a best fit)."""
    synthetic(tmp_path, {"a": 2.0, "tau": "0.8 us"}, noise=0.0)
    data = np.loadtxt(tmp_path / "measured.csv", delimiter=",", skiprows=1)
    np.savetxt(tmp_path / "measured.csv", np.c_[data[:, 0] + 100.0, data[:, 1]], delimiter=",",
               header="time,velocity", comments="")
    (tmp_path / "fit.toml").write_text(RAMP_FIT)
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(tmp_path / "fit.toml"), "--out", str(tmp_path / "out"), "--workers", "1", "--allow-python"])
    assert exc.value.code == 2
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
    err = " ".join(capsys.readouterr().err.split())
    assert "401 of 401 measured samples (at the initial time shift) fall beyond the computed record" in err


def test_samples_the_fitted_shift_moves_beyond_the_run_are_reported(tmp_path, models_importable):
    """A fitted time shift of 280 ns moves the first measured samples (0-0.24 us, every 20 ns) before the run's
    record starts (0, every 26.7 ns): the fit still runs, and its message says how many samples were compared with
    the record's end values: 13, counted by hand."""
    synthetic(tmp_path, {"a": 2.0, "tau": "0.8 us", "t0": "280 ns"}, noise=0.0)
    (tmp_path / "fit.toml").write_text(RAMP_FIT)
    with ThreadPoolExecutor(1) as ex:
        res = fit(tmp_path / "fit.toml", executor=ex)
    assert res.values[2] == pytest.approx(280e-9, rel=1e-3)
    assert "(13 measured samples fall beyond the computed record at the fitted time shift" in res.message


def test_fit_through_a_dask_cluster_equals_the_local_fit(tmp_path, monkeypatch):
    from dask.distributed import LocalCluster

    monkeypatch.syspath_prepend(str(HERE))
    t = np.linspace(0.0, 1.0, 101)
    y = 0.5 + 2.0 * t + np.random.default_rng(5).normal(0.0, 0.1, t.size)
    np.savetxt(tmp_path / "m.csv", np.c_[t, y], delimiter=",", header="time,value", comments="")
    (tmp_path / "fit.toml").write_text("""
kind = "python"
model = "sweep_test_models:line"
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
""")
    with ThreadPoolExecutor(2) as ex:
        local = fit(tmp_path / "fit.toml", executor=ex)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0") as cluster:
        remote = fit(tmp_path / "fit.toml", scheduler=cluster.scheduler_address)
    np.testing.assert_array_equal(local.values, remote.values)
    np.testing.assert_array_equal(local.sigma, remote.sigma)
    # and the straight line is the ordinary least-squares one
    X = np.c_[np.ones_like(t), t]
    np.testing.assert_allclose(local.values, np.linalg.lstsq(X, y, rcond=None)[0], rtol=1e-6)


def test_an_unreachable_scheduler_is_a_clear_error():
    from shockfriction.errors import DeckError
    from shockfriction.sweep.executors import open_executor

    with pytest.raises(DeckError, match="--scheduler = 'tcp://127.0.0.1:9': expected the address of a running Dask"):
        with open_executor("tcp://127.0.0.1:9", connect_timeout=1.0):
            pass


def test_top_level_record_and_dataset_tables_together_exit_2(tmp_path, capsys, models_importable):
    synthetic(tmp_path, {"a": 2.0, "tau": "0.8 us"}, noise=0.0)
    extra = '[[dataset]]\n[dataset.measured]\nfile = "measured.csv"\n[dataset.computed]\nrecord = "free_surface"\n'
    (tmp_path / "fit.toml").write_text(RAMP_FIT.replace("[solver]", "") + extra)
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(tmp_path / "fit.toml"), "--workers", "1", "--allow-python"])
    assert exc.value.code == 2
    err = " ".join(capsys.readouterr().err.split())
    assert "kind, model, measured, computed, time_shift, set at the top level with dataset tables" in err


def test_two_records_of_one_deck_share_its_runs_and_both_constrain_the_fit(tmp_path, models_importable):
    from shockfriction.sweep.fit import FitProblem
    from shockfriction.sweep.fitspec import load_fit

    rec = run_deck("python", {"a": 2.0, "tau": "0.8 us", "n": 401}, tmp_path, "sweep_test_models:ramp").records
    for name in ("free_surface", "rear"):
        np.savetxt(tmp_path / f"{name}.csv", np.c_[rec[name]["time"] * 1e6, rec[name]["velocity"]],
                   delimiter=",", header="time,velocity", comments="")
    block = """
[[dataset]]
name = "{name}"
kind = "python"
model = "sweep_test_models:ramp"
[dataset.set]
n = 401
[dataset.measured]
file = "{name}.csv"
time_unit = "us"
[dataset.computed]
record = "{name}"
"""
    params = '[[parameter]]\npath = "a"\nbounds = [1.0, 3.0]\n[[parameter]]\npath = "tau"\nbounds = ["0.3 us", "2 us"]\n'
    (tmp_path / "fit.toml").write_text(block.format(name="free_surface") + block.format(name="rear") + params)
    spec, here = load_fit(tmp_path / "fit.toml")
    with ThreadPoolExecutor(2) as ex:
        prob = FitProblem(spec, here, ex)
        both = prob.records([prob.x0])[0]
        assert prob.runs == 1, "one deck, one run, two records"
        np.testing.assert_array_equal(both[1][1], 0.5 * both[0][1])
        res = fit(tmp_path / "fit.toml", executor=ex)
    np.testing.assert_allclose(res.values, [2.0, 0.8], rtol=1e-6)
    assert res.samples == 2 * 401 and [c.name for c in res.curves] == ["free_surface", "rear"]


def test_measured_record_read_from_a_sweeps_records_file(tmp_path, models_importable):
    """Any record a run produces can be the measurement: here one kept by a sweep in records.h5."""
    from shockfriction.sweep.engine import run_sweep

    (tmp_path / "sweep.toml").write_text("""
kind = "python"
model = "sweep_test_models:ramp"
[set]
n = 301
t0 = "0 s"
[[parameter]]
path = "tau"
values = ["0.5 us", "0.8 us"]
[[parameter]]
path = "a"
values = [2.0]
""")
    with ThreadPoolExecutor(2) as ex:
        run_sweep(tmp_path / "sweep.toml", tmp_path / "sw", executor=ex, progress=False)
        (tmp_path / "fit.toml").write_text("""
kind = "python"
model = "sweep_test_models:ramp"
[set]
n = 301
t0 = "0 s"
[measured]
file = "sw/records.h5"
group = "r00001/free_surface"
[computed]
record = "free_surface"
[[parameter]]
path = "a"
bounds = [1.0, 3.0]
[[parameter]]
path = "tau"
bounds = ["0.3 us", "2 us"]
""")
        res = fit(tmp_path / "fit.toml", executor=ex)
    np.testing.assert_allclose(res.values, [2.0, 0.8], rtol=1e-6)
    assert res.rms < 1e-9


def test_fit_command_prints_the_table_and_writes_report_plot_and_records(tmp_path, models_importable, capsys):
    synthetic(tmp_path, {"a": 2.0, "tau": "0.8 us", "t0": "150 ns"}, noise=0.02)
    (tmp_path / "fit.toml").write_text(RAMP_FIT)
    with pytest.raises(SystemExit) as exc:
        main(["fit", str(tmp_path / "fit.toml"), "--out", str(tmp_path / "out"), "--workers", "2", "--allow-python"])
    assert exc.value.code == 0
    out = capsys.readouterr()
    assert "time_shift" in out.out and "residual rms" in out.out and "evaluation 1:" in out.err
    for name in ("fit.json", "fit.png", "computed.csv", "evaluations.csv"):
        assert (tmp_path / "out" / name).stat().st_size > 0
    report = json.loads((tmp_path / "out" / "fit.json").read_text())
    assert report["success"] and report["parameters"]["a"]["value"] == pytest.approx(2.0, rel=0.01)


def test_several_starts_escape_a_local_minimum(tmp_path, monkeypatch):
    """sin(p t) against sin(2.3 t): from p = 0.6 a local search stalls in a side minimum;
    the best of 16 Latin-hypercube starts leads to the true p."""
    from shockfriction.sweep.fit import FitProblem, best_start
    from shockfriction.sweep.fitspec import load_fit

    monkeypatch.syspath_prepend(str(HERE))
    t = np.linspace(0.0, 10.0, 201)
    np.savetxt(tmp_path / "m.csv", np.c_[t, np.sin(2.3 * t)], delimiter=",", header="time,value", comments="")
    text = """
kind = "python"
model = "sweep_test_models:two_wells"
[measured]
file = "m.csv"
value = "value"
[computed]
record = "r"
value = "value"
[[parameter]]
path = "p"
bounds = [0.1, 4.0]
initial = 0.6
[solver]
starts = {starts}
"""
    with ThreadPoolExecutor(2) as ex:
        (tmp_path / "one.toml").write_text(text.format(starts=1))
        single = fit(tmp_path / "one.toml", executor=ex)
        (tmp_path / "many.toml").write_text(text.format(starts=16))
        many = fit(tmp_path / "many.toml", executor=ex)
        spec, here = load_fit(tmp_path / "many.toml")
        prob = FitProblem(spec, here, ex)
        _, costs = best_start(prob, np.array([(0.6 - 0.1) / 3.9]), 16, 0)
    assert abs(single.values[0] - 2.3) > 0.1, "the single start must be stuck for the test to mean anything"
    assert many.values[0] == pytest.approx(2.3, abs=1e-6) and many.rms < 1e-6
    assert len(costs) == 16
