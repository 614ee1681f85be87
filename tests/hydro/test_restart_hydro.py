"""Checkpoint/restart of a run without slide lines (tied strip, SCG strength, two threads): the
restarted run ends with the same histories and fields as an uninterrupted one, bit for bit."""

import filecmp
import json

import h5py
import numpy as np
import pytest

from shockfriction.hydro.api import prepare, run_dict, run_simulation


@pytest.mark.parametrize("serial_at_checkpoint", [False, True])
def test_hydro_restart_is_bit_for_bit(make_strip, tmp_path, serial_at_checkpoint):
    """``serial_at_checkpoint``: the thread governor had the serial kernels when the checkpoints were
    written (their scratch is not the parallel one's: a restart on two threads must not take it)."""
    deck = make_strip(ny_flyer=8, ny_target=20, end="1.0 us", strength="scg", material="Cu-OFHC")
    deck["threads"] = 2
    deck["output"] = {"field_interval": "0.25 us", "checkpoint_interval": "0.3 us", "probe_every": 2}
    ref = run_dict(deck, tmp_path / "ref")
    sim = prepare(deck)
    if serial_at_checkpoint:  # after the governor, before the outputs' hooks
        sim.between_cycles.append(lambda s: s.use_parallel(False))

    def crash(s):
        if s.state.t > 0.7e-6:
            raise RuntimeError("crash")

    sim.between_cycles.append(crash)
    with pytest.raises(RuntimeError):
        run_simulation(sim, tmp_path / "out")
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["completed"] is False
    res = run_dict(deck, tmp_path / "out", restart=True)
    assert res.summary["completed"] and res.state.cycle == ref.state.cycle
    for name in ("energy.csv", "probes.csv", "fields.xmf"):
        assert filecmp.cmp(tmp_path / "ref" / name, tmp_path / "out" / name, shallow=False), name
    with h5py.File(tmp_path / "ref" / "fields.h5") as a, h5py.File(tmp_path / "out" / "fields.h5") as b:
        assert sorted(a) == sorted(b)
        for step in (k for k in a if k.startswith("step_")):
            for name in a[step]:
                assert np.array_equal(a[step][name][()], b[step][name][()]), (step, name)
    for key in ref.probes:
        assert np.array_equal(ref.probes[key], res.probes[key])


def test_restart_keeps_spall_damage(tmp_path):
    """Tuler-Butcher damage accumulates across the checkpoint (State.damage is saved like every
    state array): the restarted run fails the same cells at the same times.  The checkpoint is given
    the scratch array that earlier builds saved, which a restart ignores."""
    def body(name, y0, y1, v):
        return {"name": name, "material": "Cu-OFHC", "velocity": ["0 m/s", v], "spall": "tuler-butcher",
                "mesh": {"corners": [["0 mm", f"{y0} mm"], ["0.01 mm", f"{y0} mm"], ["0.01 mm", f"{y1} mm"],
                                     ["0 mm", f"{y1} mm"]], "nx": 1, "ny": round((y1 - y0) / 0.02)},
                "boundary": {"left": "symmetry", "right": "symmetry"}}

    deck = {"time": {"end": "0.8 us"}, "bodies": [body("flyer", -0.5, 0.0, "300 m/s"), body("target", 0.0, 1.0, "0 m/s")],
            "ties": [{"sides": ["flyer.top", "target.bottom"]}],
            "output": {"checkpoint_interval": "0.3 us"},
            "probes": [{"name": "fs", "body": "target", "node": [0, -1], "quantities": ["vy"]}]}
    ref = run_dict(deck, tmp_path / "ref")
    assert (ref.state.damage > 0.0).any()
    sim = prepare(deck)

    def crash(s):
        if s.state.t > 0.35e-6:
            raise RuntimeError("crash")

    sim.between_cycles.append(crash)
    with pytest.raises(RuntimeError):
        run_simulation(sim, tmp_path / "out")
    # a checkpoint of an earlier build also holds the force pass's scratch as (cells, 8): ignored on load
    with h5py.File(tmp_path / "out" / "checkpoint.h5", "a") as h5:
        h5["simulation"].create_dataset("_corner", data=np.zeros((sim.state.n_cells, 8)))
    res = run_dict(deck, tmp_path / "out", restart=True)
    assert np.array_equal(res.state.damage, ref.state.damage)
    assert np.array_equal(res.probes["fs.vy"], ref.probes["fs.vy"])
    assert filecmp.cmp(tmp_path / "ref" / "energy.csv", tmp_path / "out" / "energy.csv", shallow=False)
