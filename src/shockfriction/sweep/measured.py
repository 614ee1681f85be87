"""Read a measured record: a CSV of time and value columns, or an HDF5 group of SI columns."""

from __future__ import annotations

import csv
from pathlib import Path

import h5py
import numpy as np

from shockfriction.errors import DeckError
from shockfriction.sweep.fitspec import Measured
from shockfriction.sweep.quantities import in_unit, si_factor


def read_measured(m: Measured, here: Path, source: str = "fit") -> tuple[np.ndarray, np.ndarray]:
    """(t, y) in SI, sorted by time, restricted to the window, NaN rows dropped."""
    path = here / m.file
    if m.group is not None:
        t, y = _read_h5(path, m, source)
    else:
        t, y = _read_csv(path, m, source)
        t, y = t * si_factor(m.time_unit), y * si_factor(m.value_unit)
    ok = np.isfinite(t) & np.isfinite(y)
    t, y = t[ok], y[ok]
    if m.window is not None:
        lo, hi = in_unit(m.window[0], "s"), in_unit(m.window[1], "s")
        inside = (t >= lo) & (t <= hi)
        t, y = t[inside], y[inside]
    order = np.argsort(t, kind="stable")
    if len(t) < 2:
        raise DeckError(f"{source}: measured: {len(t)} usable samples in {path} (window {m.window}): "
                        "expected at least 2")
    return t[order], y[order]


def _read_csv(path: Path, m: Measured, source: str) -> tuple[np.ndarray, np.ndarray]:
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected a CSV with a header row, found nothing")
    header = [h.strip() for h in rows[0]]
    cols = []
    for field in ("time", "value"):
        name = getattr(m, field)
        if name not in header:
            raise DeckError(f"{source}: measured.{field} = {name!r}: expected one of the CSV columns {header}")
        cols.append(header.index(name))
    try:
        data = np.array([[float(r[c]) for c in cols] for r in rows[1:]], dtype=np.float64).reshape(-1, 2)
    except (ValueError, IndexError) as exc:
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected numbers in columns "
                        f"{m.time!r} and {m.value!r} ({exc})") from None
    return data[:, 0], data[:, 1]


def _read_h5(path: Path, m: Measured, source: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        with h5py.File(path, "r") as h5:
            if m.group not in h5:
                raise DeckError(f"{source}: measured.group = {m.group!r}: expected a group of {path}")
            g = h5[m.group]
            for field in ("time", "value"):
                name = getattr(m, field)
                if name not in g:
                    raise DeckError(f"{source}: measured.{field} = {name!r}: expected one of {sorted(g)}")
            return g[m.time][()].astype(np.float64), g[m.value][()].astype(np.float64)
    except OSError as exc:
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected an HDF5 file ({exc})") from None
