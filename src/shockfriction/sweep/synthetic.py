"""Synthetic measured records made by the code itself: a run at known parameters plus noise.

Used to test a fit end to end (the fit must give the known values back within
its uncertainty) and to check before an experiment whether the planned record
determines the parameters at all.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from shockfriction.sweep.quantities import si_factor
from shockfriction.sweep.runners import run_deck


def synthetic_record(kind: str, deck: dict, record: str, time: str, value: str, noise: float,
                     seed: int = 0, model: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(t, y + N(0, noise^2)) of ``record`` of a run of ``deck`` (SI units, ``noise`` in SI)."""
    with tempfile.TemporaryDirectory(prefix="sf-synthetic-") as tmp:
        rec = run_deck(kind, deck, Path(tmp), model).records[record]
    y = rec[value] + np.random.default_rng(seed).normal(0.0, noise, rec[value].size)
    return rec[time].copy(), y


def write_csv(path: str | Path, t: np.ndarray, y: np.ndarray, time_unit: str = "s", value_unit: str = "",
              names: tuple[str, str] = ("time", "value"), comment: str = "") -> Path:
    """Write a two-column CSV (header row ``time,value``) in the given units."""
    path = Path(path)
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    rows = "".join(f"{a:.10g},{b:.10g}\n" for a, b in zip(t / si_factor(time_unit), y / si_factor(value_unit)))
    path.write_text(head + f"{names[0]},{names[1]}\n" + rows)
    return path
