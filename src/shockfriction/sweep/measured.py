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
        raise DeckError(f"{source}: measured: {len(t)} usable samples in {m.file!r} (window {m.window}): "
                        "expected at least 2")
    return t[order], y[order]


def _read_csv(path: Path, m: Measured, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Columns ``m.time`` and ``m.value`` of a CSV.  Errors never quote the file (it may not be a
    record at all: a deck must not be able to print a file of the machine through an error)."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    except (UnicodeDecodeError, csv.Error):
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected a UTF-8 CSV text file") from None
    except OSError as exc:
        raise DeckError(f"{source}: measured.file = {m.file!r}: cannot be read "
                        f"({exc.strerror or type(exc).__name__})") from None
    if not rows:
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected a CSV with a header row, found nothing")
    header = [h.strip() for h in rows[0]]
    cols = []
    for field in ("time", "value"):
        name = getattr(m, field)
        if name not in header:
            raise DeckError(f"{source}: measured.{field} = {name!r}: expected a column of the CSV's header row "
                            f"(the file's header has {len(header)} columns, none of that name)")
        cols.append(header.index(name))
    bad = 0
    data = []
    for k, r in enumerate(rows[1:], start=2):
        try:
            data.append([float(r[c]) for c in cols])
        except (ValueError, IndexError):
            bad = k
            break
    if bad:
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected numbers in columns {m.time!r} and "
                        f"{m.value!r} (row {bad} of the file is not)")
    arr = np.array(data, dtype=np.float64).reshape(-1, 2)
    return arr[:, 0], arr[:, 1]


def _read_h5(path: Path, m: Measured, source: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        with h5py.File(path, "r") as h5:
            if m.group not in h5:
                raise DeckError(f"{source}: measured.group = {m.group!r}: expected a group of {path}")
            g = h5[m.group]
            for field in ("time", "value"):
                name = getattr(m, field)
                if name not in g:
                    raise DeckError(f"{source}: measured.{field} = {name!r}: expected a dataset of group "
                                f"{m.group!r} ({len(g)} datasets there, none of that name)")
            return g[m.time][()].astype(np.float64), g[m.value][()].astype(np.float64)
    except OSError:
        raise DeckError(f"{source}: measured.file = {m.file!r}: expected an HDF5 file") from None
