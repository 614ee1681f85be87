"""Cheap python-kind models for the sweep tests (imported by name in worker processes)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np


def ramp(deck: dict, workdir: Path) -> dict:
    """A free-surface-like record v(t) = a * (1 - exp(-t / tau)) for t > t0, with scalars.

    deck: {"a": float, "tau": "<time>", "t0": "<time>", "n": int, "fail_above": float?,
           "die_at": float?, "sleep": float?, "marker_dir": str?}
    """
    from shockfriction.units import to_si

    if deck.get("marker_dir"):  # count executions: one file per call
        Path(deck["marker_dir"]).mkdir(parents=True, exist_ok=True)
        (Path(deck["marker_dir"]) / f"{deck['a']!r}-{os.getpid()}-{time.time_ns()}").touch()
    if deck.get("sleep"):
        time.sleep(float(deck["sleep"]))
    a = float(deck["a"])
    if "die_at" in deck and a == float(deck["die_at"]):
        os._exit(1)  # the worker process dies (as a segfault or an OOM kill would)
    if "fail_above" in deck and a > float(deck["fail_above"]):
        raise RuntimeError(f"a = {a} above {deck['fail_above']}: the model refuses")
    tau = to_si(deck["tau"], "time")
    t0 = to_si(deck.get("t0", "0 s"), "time")
    t = np.linspace(0.0, 10 * tau, int(deck.get("n", 201)))
    v = np.where(t > t0, a * (1.0 - np.exp(-(t - t0) / tau)), 0.0)
    (workdir / "scratch.txt").write_text("a run writes here")
    return {"records": {"free_surface": {"time": t, "velocity": v}, "rear": {"time": t, "velocity": 0.5 * v}},
            "summary": {"a_times_tau": a * tau}}


def line(deck: dict, workdir: Path) -> dict:
    """y = a + b t on t in [0, 1] s (101 samples); ``c`` is read and ignored (an unidentifiable parameter)."""
    t = np.linspace(0.0, 1.0, 101)
    float(deck.get("c", 0.0))
    return {"records": {"r": {"time": t, "value": float(deck["a"]) + float(deck["b"]) * t}}}


def two_wells(deck: dict, workdir: Path) -> dict:
    """y(t) = sin(p t) on t in [0, 10]: the misfit in p has many local minima."""
    t = np.linspace(0.0, 10.0, 201)
    return {"records": {"r": {"time": t, "value": np.sin(float(deck["p"]) * t)}}}
