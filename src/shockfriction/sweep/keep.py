"""What a sweep keeps of each run: chosen records, summary scalars and derived scalars.

Derived scalars of a record column y(t) (t the record's time column):
max, min, initial, final; ``mean`` = (1/(t_end - t_0)) * int y dt and ``integral``
= int y dt (trapezoidal rule); ``time_of_max`` / ``time_of_min``; ``arrival`` =
first time at which |y| >= threshold, linearly interpolated between samples
(NaN if never reached).
"""

from __future__ import annotations

import numpy as np

from shockfriction.sweep.runners import RunResult


class KeepError(ValueError):
    """The keep section asks for something this run did not produce."""


def _trapezoid(y: np.ndarray, t: np.ndarray) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)))


def derive(op: str, t: np.ndarray, y: np.ndarray, threshold: float | None = None) -> float:
    """One derived scalar of y(t) (see the module docstring)."""
    if len(y) == 0:
        return float("nan")
    if op == "max":
        return float(np.max(y))
    if op == "min":
        return float(np.min(y))
    if op == "initial":
        return float(y[0])
    if op == "final":
        return float(y[-1])
    if op == "integral":
        return _trapezoid(y, t)
    if op == "mean":
        span = t[-1] - t[0]
        return _trapezoid(y, t) / span if span > 0 else float(y[0])
    if op == "time_of_max":
        return float(t[np.argmax(y)])
    if op == "time_of_min":
        return float(t[np.argmin(y)])
    if op == "arrival":
        above = np.flatnonzero(np.abs(y) >= threshold)
        if len(above) == 0:
            return float("nan")
        j = above[0]
        if j == 0:
            return float(t[0])
        a, b = abs(y[j - 1]), abs(y[j])
        return float(t[j - 1] + (threshold - a) / (b - a) * (t[j] - t[j - 1]))
    raise KeepError(f"unknown op {op!r}")


def select(result: RunResult, keep: dict) -> RunResult:
    """The records and scalars ``keep`` (a :class:`~shockfriction.sweep.spec.Keep` as a dict) asks for."""
    def pick(available: dict, wanted, what: str) -> dict:
        if wanted == "all":
            return dict(available)
        missing = [w for w in wanted if w not in available]
        if missing:
            raise KeepError(f"keep.{what}: {missing} not produced by this run; it has {sorted(available)}")
        return {w: available[w] for w in wanted}

    records = pick(result.records, keep["records"], "records")
    scalars = pick(result.summary, keep["scalars"], "scalars")
    for d in keep["derived"]:
        rec = result.records.get(d["record"])
        if rec is None:
            raise KeepError(f"keep.derived {d['name']!r}: record {d['record']!r} not produced; "
                            f"this run has {sorted(result.records)}")
        for col in (d["column"], d["time"]):
            if col not in rec:
                raise KeepError(f"keep.derived {d['name']!r}: record {d['record']!r} has no column {col!r}; "
                                f"its columns are {sorted(rec)}")
        scalars[d["name"]] = derive(d["op"], rec[d["time"]], rec[d["column"]], d.get("threshold"))
    return RunResult(records, scalars)
