"""Sweeps on the package's own decks: the sub-grid ball case and the 1D plate-impact strip."""

from __future__ import annotations

import csv
from pathlib import Path

import h5py
import numpy as np
import pytest

from shockfriction.deck.base import read_toml
from shockfriction.materials.library import get_material
from shockfriction.sweep.engine import run_sweep
from shockfriction.sweep.paths import set_paths

ROOT = Path(__file__).resolve().parents[2]
BALL = ROOT / "examples" / "subgrid" / "ball_al_200ms.toml"
PLATE = ROOT / "examples" / "plate_impact_al_250ms.toml"

SHORT_BALL = f"""
base = "{BALL}"
[set]
duration = "0.1 us"
output_times = []
"column.cells" = 100
"""


def rows(path: Path) -> list[dict]:
    with open(path) as fh:
        return [{k: v for k, v in r.items() if k != "seconds"} for r in csv.DictReader(fh)]


def test_subgrid_sweep_same_on_local_pool_and_dask_and_mu0_f_reach_the_model(tmp_path):
    from dask.distributed import LocalCluster

    (tmp_path / "sweep.toml").write_text(SHORT_BALL + """
[[parameter]]
path = "friction.mu0"
values = [0.02, 0.3]
[[parameter]]
path = "friction.f"
values = [0.3, 0.9]
[[keep.derived]]
name = "tau_peak"
record = "ball"
column = "tau"
op = "max"
""")
    local = run_sweep(tmp_path / "sweep.toml", tmp_path / "local", workers=2, progress=False)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0") as cluster:
        dask = run_sweep(tmp_path / "sweep.toml", tmp_path / "dask", scheduler=cluster.scheduler_address,
                         progress=False)
    assert local.ok == dask.ok == 4
    table = rows(local.table)
    assert table == rows(dask.table)
    with h5py.File(local.records) as a, h5py.File(dask.records) as b:
        for run in a:
            for col in ("time", "tau", "theta_interface"):
                np.testing.assert_array_equal(a[run]["ball"][col][()], b[run]["ball"][col][()])
    peak = {(float(r["friction.mu0"]), float(r["friction.f"])): float(r["tau_peak"]) for r in table}
    # tau = min(mu0 F_N, f Ymax/sqrt3 G/G0) under F_N = 10 GPa: with f = 0.9 the Coulomb cap of
    # mu0 = 0.02 (200 MPa) binds exactly; with f = 0.3 the SCG branch (< 200 MPa) governs for both mu0
    assert peak[(0.02, 0.9)] == pytest.approx(0.02 * 10e9, rel=1e-12)
    assert peak[(0.3, 0.9)] > 2.5 * peak[(0.02, 0.9)]
    assert peak[(0.02, 0.3)] == peak[(0.3, 0.3)] < 0.02 * 10e9


def test_a_run_that_melts_is_recorded_failed_and_the_sweep_goes_on(tmp_path):
    (tmp_path / "flux.toml").write_text("""
model = "thermoelastic"
material = "Al5083-H111"
other_material = "AISI321"
duration = "0.1 us"
dt = "1 ns"
[column]
cells = 100
[[loading]]
name = "flux"
times = ["0 us"]
heat_flux = ["1e9 W/m^2"]
""")
    (tmp_path / "sweep.toml").write_text("""
base = "flux.toml"
[[parameter]]
path = "loading[0].heat_flux[0]"
values = ["1e9 W/m^2", "1e13 W/m^2", "2e9 W/m^2"]
""")
    res = run_sweep(tmp_path / "sweep.toml", tmp_path / "out", workers=1, progress=False)
    table = rows(res.table)
    assert [r["status"] for r in table] == ["ok", "failed", "ok"]
    assert "SimulationError" in table[1]["error"] and "melting" in table[1]["error"]
    assert float(table[2]["flux.theta_interface_max"]) > float(table[0]["flux.theta_interface_max"])


def test_plate_impact_sweep_against_rankine_hugoniot(tmp_path):
    """Symmetric Al/Al impact at v: u_p = v/2, P = rho0 (c0 + s u_p) u_p, free surface at 2 u_p."""
    (tmp_path / "sweep.toml").write_text(f"""
base = "{PLATE}"
[set]
"output.field_interval" = "10 us"
[[parameter]]
path = "bodies[0].velocity[1]"
name = "v"
values = ["100 m/s", "0.3 km/s"]
[keep]
records = []
scalars = []
[[keep.derived]]
name = "p_peak"
record = "mid"
column = "p"
op = "max"
[[keep.derived]]
name = "fs_final"
record = "fs"
column = "vy"
op = "final"
""")
    res = run_sweep(tmp_path / "sweep.toml", tmp_path / "out", workers=2, progress=False)
    al = get_material("Al6061-T6")
    for r in rows(res.table):
        v = float(r["v [m/s]"])
        up = v / 2
        p_exact = al.rho0 * (al.eos_c0 + al.eos_s * up) * up
        print(f"v = {v}: P = {float(r['p_peak']):.6g} (exact {p_exact:.6g}), u_fs = {float(r['fs_final']):.6g}")
        assert float(r["p_peak"]) == pytest.approx(p_exact, rel=0.01)
        assert float(r["fs_final"]) == pytest.approx(2 * up, rel=0.01)
    assert [r["v [m/s]"] for r in rows(res.table)] == ["100.0", "300.0"]


def test_a_generated_deck_the_deck_model_refuses_exits_2_before_any_run(tmp_path, capsys):
    from shockfriction.cli import main

    (tmp_path / "sweep.toml").write_text(SHORT_BALL + """
[[parameter]]
path = "friction.mu0"
values = [0.1, -0.1]
""")
    with pytest.raises(SystemExit) as exc:
        main(["sweep", str(tmp_path / "sweep.toml"), "--out", str(tmp_path / "out"), "--allow-outside"])
    assert exc.value.code == 2
    err = " ".join(capsys.readouterr().err.split())
    assert "run r00001" in err and "friction.mu0 = -0.1: expected" in err and "greater than or equal to 0" in err
    assert not (tmp_path / "out" / "runs").exists()


def test_hydro_scalars_are_deterministic_and_carry_no_timings(tmp_path):
    from shockfriction.sweep.runners import run_deck

    deck = set_paths(read_toml(PLATE), {"time.end": "0.5 us", "output.field_interval": "10 us"})
    a, b = run_deck("run", deck, tmp_path), run_deck("run", deck, tmp_path)
    assert a.summary == b.summary and "cycles" in a.summary and "wall_time_s" not in a.summary
    assert set(a.records) == {"fs", "mid", "energy"} and set(a.records["fs"]) == {"time", "vy"}
    for name in a.records:
        for col in a.records[name]:
            np.testing.assert_array_equal(a.records[name][col], b.records[name][col])
