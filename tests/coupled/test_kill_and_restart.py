"""Kill-safe outputs and checkpoint/restart on a coupled run (pressure-shear strip, thermoelastoplastic
sub-grid friction): SIGKILL leaves every output readable up to the last output time; SIGTERM stops
cleanly (exit 143) with a checkpoint; a run stopped mid-way and restarted from its checkpoint ends
with the same fields, histories and records as an uninterrupted run, bit for bit."""

import csv
import filecmp
import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

from shockfriction.hydro.api import prepare, run, run_simulation

SRC = Path(__file__).resolve().parents[2] / "src"

DECK = """
title = "kill/restart strip"
[time]
end = "{end}"
cfl = 0.5
[output]
field_interval = "0.1 us"
checkpoint_interval = "0.2 us"
[[bodies]]
name = "flyer"
material = "Steel4340"
strength = "scg"
velocity = ["55 m/s", "85 m/s"]
mesh = {{ corners = [["0 mm", "-5 mm"], ["0.1 mm", "-5 mm"], ["0.1 mm", "0 mm"], ["0 mm", "0 mm"]], nx = 2, ny = 25 }}
boundary = {{ left = "periodic", right = "periodic" }}
[[bodies]]
name = "target"
material = "Ti-6Al-4V"
strength = "scg"
mesh = {{ corners = [["0 mm", "0 mm"], ["0.1 mm", "0 mm"], ["0.1 mm", "6 mm"], ["0 mm", "6 mm"]], nx = 3, ny = 30 }}
boundary = {{ left = "periodic", right = "periodic" }}
[[slide_lines]]
name = "interface"
guide = {{ body = "flyer", side = "top" }}
slave = {{ body = "target", side = "bottom" }}
record_interval = "20 ns"
friction = {{ law = "subgrid-thermoelastoplastic", mu0 = 0.15, f = 0.15, thickness = "20 um", cells = 100, profile_interval = "0.1 us" }}
[[probes]]
name = "rear"
body = "target"
node = [0, -1]
quantities = ["vx", "vy"]
"""
OUTPUTS = ("energy.csv", "probes.csv", "fields.xmf", "fields.h5", "interface.h5", "columns.h5", "summary.json")


def _deck(tmp_path, end="0.6 us") -> Path:
    path = tmp_path / "strip.toml"
    path.write_text(DECK.format(end=end))
    return path


def _h5_items(path) -> dict:
    out = {}
    with h5py.File(path, "r") as h5:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
            for k, v in obj.attrs.items():
                out[f"{name}@{k}"] = v
        h5.visititems(visit)
    return out


def assert_same_outputs(a: Path, b: Path) -> None:
    """Every history and record file identical (CSV bytes, every HDF5 dataset and attribute)."""
    for name in ("energy.csv", "probes.csv", "fields.xmf"):
        assert filecmp.cmp(a / name, b / name, shallow=False), name
    for name in ("fields.h5", "interface.h5", "columns.h5"):
        da, db = _h5_items(a / name), _h5_items(b / name)
        assert da.keys() == db.keys(), name
        for key in da:
            assert np.array_equal(da[key], db[key]), f"{name}:{key}"


def check_readable(out: Path) -> float:
    """Every output file opens; each holds its records up to the last output time; return that time."""
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is False
    t_out = summary["final_time_s"]
    with (out / "energy.csv").open() as fh:
        rows = list(csv.reader(fh))
    assert all(len(r) == len(rows[0]) for r in rows)
    assert float(rows[-1][0]) > t_out - 5e-9  # rows up to the summary's time (less the last step)
    with (out / "probes.csv").open() as fh:
        prow = list(csv.reader(fh))
    assert float(prow[-1][0]) > t_out - 5e-9
    root = ET.parse(out / "fields.xmf").getroot()
    grids = root.findall(".//Grid[@GridType='Uniform']")
    times = [float(g.find("Time").get("Value")) for g in grids]
    assert times and times[-1] <= t_out * (1 + 1e-12)  # the index never ahead of the summary
    # the last field output before the last output time, or (killed between the summary's write and the
    # index's) the one before it
    assert times[-1] > t_out - 2 * 0.1e-6 * (1 + 1e-6)
    with h5py.File(out / "fields.h5", "r") as h5:
        for item in root.iter("DataItem"):
            assert h5[item.text.split(":", 1)[1]].shape == tuple(int(d) for d in item.get("Dimensions").split())
    with h5py.File(out / "interface.h5", "r") as h5:
        g = h5["interface"]
        n = g["t_s"].shape[0]
        assert n > 0 and g["t_s"][-1] > t_out - 20e-9 * 1.01 and g["t_s"][-1] <= t_out * (1 + 1e-12)
        for name in ("sigma_n_Pa", "tau_Pa", "theta_interface_K", "slip_local_mps"):
            assert g[name].shape[0] >= n and np.isfinite(g[name][:n]).all()
    with h5py.File(out / "columns.h5", "r") as h5:
        g = h5["interface"]
        assert g["t_s"].shape[0] >= 2 and g["theta_K"].shape[0] >= g["t_s"].shape[0]
    return t_out


def _start(deck: Path, out: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(SRC))
    return subprocess.Popen([sys.executable, "-m", "shockfriction", "run", str(deck), "--out", str(out), "-q"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_checkpoint(proc, out: Path, n_fields: int = 3, timeout: float = 240.0) -> dict:
    """Wait until the run has a checkpoint and ``n_fields`` field outputs; return its summary."""
    start = time.monotonic()
    while time.monotonic() - start < timeout:
        assert proc.poll() is None, proc.communicate()
        try:
            s = json.loads((out / "summary.json").read_text())
        except (FileNotFoundError, json.JSONDecodeError):
            s = {}
        if s.get("checkpoint_time_s") is not None and s["final_time_s"] >= (n_fields - 1) * 0.1e-6:
            return s
        time.sleep(0.02)
    raise AssertionError("no checkpoint written in time")


@pytest.fixture(scope="module", autouse=True)
def no_plots():
    """The PNG maps take most of the time of these small runs; they are not under test here."""
    with pytest.MonkeyPatch.context() as mp:
        for mod, name in (("interface", "plot_interface"), ("coupled", "plot_subgrid_interface"),
                          ("coupled", "plot_columns")):
            mp.setattr(f"shockfriction.plot.{mod}.{name}", lambda *a, **k: [])
        yield


@pytest.fixture(scope="module")
def reference(tmp_path_factory, no_plots):
    tmp = tmp_path_factory.mktemp("reference")
    deck = _deck(tmp)
    res = run(deck, tmp / "out")
    assert res.summary["completed"]
    return deck, tmp / "out", res


def test_restart_after_a_crash_is_bit_for_bit(reference, tmp_path):
    """A run stopped by an error after its second checkpoint (its outputs finished as on failure,
    with a partial record window past the checkpoint) and restarted ends identical to the reference."""
    deck, ref, res_ref = reference
    out = tmp_path / "out"
    sim = prepare(deck)

    def crash(s):
        if s.state.t > 0.47e-6:
            raise RuntimeError("simulated crash")

    sim.between_cycles.append(crash)
    with pytest.raises(RuntimeError, match="simulated crash"):
        run_simulation(sim, out)
    with h5py.File(out / "checkpoint.h5", "r") as h5:
        assert h5.attrs["time_s"] == pytest.approx(0.4e-6, rel=0.02)
    res = run(deck, out, restart=True)
    assert res.summary["completed"] and res.state.cycle == res_ref.state.cycle
    assert_same_outputs(ref, out)
    for key in res_ref.energy:
        assert np.array_equal(res.energy[key], res_ref.energy[key])
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is True and summary["restarted_from_s"] == pytest.approx(0.4e-6, rel=0.02)


def test_restart_refuses_another_deck(reference, tmp_path):
    from shockfriction.errors import DeckError

    deck, _, _ = reference
    out = tmp_path / "out"
    sim = prepare(deck)
    sim.between_cycles.append(lambda s: (_ for _ in ()).throw(RuntimeError("stop"))
                              if s.state.t > 0.25e-6 else None)
    with pytest.raises(RuntimeError):
        run_simulation(sim, out)
    other = tmp_path / "other.toml"
    other.write_text(DECK.format(end="0.6 us").replace("mu0 = 0.15", "mu0 = 0.2"))
    with pytest.raises(DeckError, match="slide_lines"):
        run(other, out, restart=True)
    with pytest.raises(DeckError, match="no checkpoint"):
        run(deck, tmp_path / "empty", restart=True)
    import shutil

    shutil.copytree(out, tmp_path / "no_fields")
    (tmp_path / "no_fields" / "fields.h5").unlink()
    with pytest.raises(DeckError, match="fields.h5"):
        run(deck, tmp_path / "no_fields", restart=True)
    longer = tmp_path / "longer.toml"  # the end time may change
    longer.write_text(DECK.format(end="0.7 us"))
    res = run(longer, out, restart=True)
    assert res.summary["completed"] and res.state.t == pytest.approx(0.7e-6, rel=1e-12)
    assert json.loads((out / "summary.json").read_text())["restarted_from_s"] == pytest.approx(0.2e-6, rel=0.05)


def test_sigkill_leaves_readable_outputs_and_restarts_bit_for_bit(reference, tmp_path):
    deck, ref, _ = reference
    out = tmp_path / "out"
    proc = _start(deck, out)
    _wait_for_checkpoint(proc, out)
    proc.send_signal(signal.SIGKILL)
    proc.communicate()
    assert proc.returncode == -signal.SIGKILL
    for name in OUTPUTS:
        assert (out / name).stat().st_size > 0, name
    t_out = check_readable(out)
    assert 0.2e-6 <= t_out < 0.6e-6
    from shockfriction.cli import main

    with pytest.raises(SystemExit) as exc:  # the command line's --restart
        main(["run", str(deck), "--out", str(out), "--restart", "-q"])
    assert exc.value.code in (0, None)
    assert json.loads((out / "summary.json").read_text())["completed"] is True
    assert_same_outputs(ref, out)


@pytest.mark.slow
def test_sigterm_stops_cleanly_with_a_checkpoint(reference, tmp_path):
    deck, ref, _ = reference
    out = tmp_path / "out"
    proc = _start(deck, out)
    _wait_for_checkpoint(proc, out, n_fields=2)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "SIGTERM" in err and "--restart" in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] == "SIGTERM" and summary["completed"] is False
    assert summary["checkpoint_time_s"] == summary["final_time_s"]  # checkpoint at the stop
    check_readable(out)
    assert (out / "interface_interface.png").is_file()  # outputs finished as at the end of a run
    res = run(deck, out, restart=True)
    assert res.summary["completed"]
    assert_same_outputs(ref, out)


@pytest.mark.parametrize("closure", ["excess", "shear"])
def test_restart_with_viscoplastic_columns_is_bit_for_bit(tmp_path, no_plots, closure):
    """The checkpoint also carries the viscoplastic columns' state (velocity, elastic strain, enthalpy,
    energies; with the "shear" closure the columns with velocities, held at the hydro's shear, and their mechanics
    window): an Al target with 'subgrid-viscoplastic' friction, crashed after its first checkpoint and restarted,
    ends identical to an uninterrupted run."""
    text = (DECK.format(end="0.3 us").replace('material = "Ti-6Al-4V"', 'material = "Al5083-H111"')
            .replace('law = "subgrid-thermoelastoplastic", mu0 = 0.15, f = 0.15',
                     f'law = "subgrid-viscoplastic", mu0 = 0.3, f = 0.3, closure = "{closure}"')
            .replace('checkpoint_interval = "0.2 us"', 'checkpoint_interval = "0.1 us"'))
    assert 'law = "subgrid-viscoplastic"' in text and 'material = "Al5083-H111"' in text and '"0.1 us"' in text
    deck = tmp_path / "vp.toml"
    deck.write_text(text)
    ref = run(deck, tmp_path / "ref")
    assert ref.summary["completed"]
    out = tmp_path / "out"
    sim = prepare(deck)

    def crash(s):
        if s.state.t > 0.15e-6:
            raise RuntimeError("simulated crash")

    sim.between_cycles.append(crash)
    with pytest.raises(RuntimeError, match="simulated crash"):
        run_simulation(sim, out)
    res = run(deck, out, restart=True)
    assert res.summary["completed"] and res.state.cycle == ref.state.cycle
    assert_same_outputs(tmp_path / "ref", out)
