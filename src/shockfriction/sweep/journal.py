"""The sweep's journal: one small HDF5 file per finished run, written atomically.

``DIR/runs/<key>.h5`` is written under a temporary name and renamed
(``os.replace``, atomic on POSIX), so a sweep killed at any instant leaves
either a complete result file or none.  A resumed sweep skips every run whose
file exists: finished runs are neither lost nor recomputed.  The key is the
run's content hash (see :mod:`shockfriction.sweep.design`), so a result is
found again even when the sweep file is edited and the run moves.

File layout: attributes ``key, status, error, seconds, deck_json``; group
``scalars`` (attributes); group ``records/<name>/<column>`` (datasets).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import h5py
import numpy as np


def result_path(out_dir: Path, key: str) -> Path:
    return Path(out_dir) / "runs" / f"{key}.h5"


def write_result(out_dir: Path, result: dict, deck: dict) -> Path:
    """Write one run's result atomically; returns its path."""
    final = result_path(out_dir, result["key"])
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = final.with_name(f".{final.name}.{os.getpid()}.tmp")
    with h5py.File(tmp, "w") as h5:
        h5.attrs["key"] = result["key"]
        h5.attrs["status"] = result["status"]
        h5.attrs["error"] = result["error"]
        h5.attrs["seconds"] = float(result.get("seconds", 0.0))
        h5.attrs["deck_json"] = json.dumps(deck, sort_keys=True, default=repr)
        sc = h5.create_group("scalars")
        for name, value in result["scalars"].items():
            sc.attrs[name] = float(value)
        recs = h5.create_group("records")
        for name, cols in result["records"].items():
            g = recs.create_group(name)
            for col, arr in cols.items():
                g.create_dataset(col, data=np.asarray(arr, dtype=np.float64))
    with open(tmp, "rb") as fh:
        os.fsync(fh.fileno())
    os.replace(tmp, final)
    return final


def read_result(path: Path) -> dict:
    """One run's result as written by :func:`write_result`."""
    with h5py.File(path, "r") as h5:
        out = {k: h5.attrs[k] for k in ("key", "status", "error", "seconds")}
        out = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in out.items()}
        out["seconds"] = float(out["seconds"])
        out["scalars"] = {k: float(v) for k, v in h5["scalars"].attrs.items()}
        out["records"] = {name: {col: g[col][()] for col in g} for name, g in h5["records"].items()}
    return out


def read_summary(path: Path) -> dict:
    """One run's status, error, time and scalars, without its records (for the table)."""
    with h5py.File(path, "r") as h5:
        out = {k: h5.attrs[k] for k in ("key", "status", "error", "seconds")}
        out = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in out.items()}
        out["seconds"] = float(out["seconds"])
        out["scalars"] = {k: float(v) for k, v in h5["scalars"].attrs.items()}
    out["records"] = {}
    return out


def finished(out_dir: Path, retry_failed: bool = False) -> dict[str, str]:
    """``{key: status}`` of the runs already in the journal (failed ones left out if ``retry_failed``)."""
    runs = Path(out_dir) / "runs"
    done: dict[str, str] = {}
    if not runs.is_dir():
        return done
    for path in runs.glob("*.h5"):
        try:
            with h5py.File(path, "r") as h5:
                status = h5.attrs["status"]
        except OSError:  # not a complete file: treat as not finished (cannot happen after os.replace)
            continue
        status = status.decode() if isinstance(status, bytes) else str(status)
        if status == "failed" and retry_failed:
            continue
        done[path.stem] = status
    return done
