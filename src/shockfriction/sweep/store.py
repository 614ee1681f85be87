"""The sweep's two result files, rebuilt from the journal (each written atomically).

* ``sweep.csv``: one row per run in sweep order: ``run``, the parameters (header
  ``name [unit]``, numbers in that unit), ``status`` (ok / failed / pending),
  ``error``, ``seconds`` and the kept scalars (SI).
* ``records.h5``: one group per finished run (``r00012``) with attributes
  (key, status, error, parameter values, scalars) and one subgroup per kept
  record holding its columns.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path

import h5py
import numpy as np

from shockfriction.sweep.design import RunPoint
from shockfriction.sweep.journal import read_result, result_path


def _replace_atomically(tmp: Path, final: Path) -> None:
    with open(tmp, "rb") as fh:
        os.fsync(fh.fileno())
    os.replace(tmp, final)


def gather(out_dir: Path, runs: list[RunPoint]) -> dict[str, dict]:
    """``{run_id: result}`` of the runs whose result is in the journal."""
    found = {}
    for run in runs:
        path = result_path(out_dir, run.key)
        if path.is_file():
            found[run.run_id] = read_result(path)
    return found


def write_table(out_dir: Path, runs: list[RunPoint], units: dict[str, str], results: dict[str, dict]) -> Path:
    """Write ``sweep.csv`` (one row per run)."""
    scalar_names: list[str] = []
    for res in results.values():
        scalar_names += [s for s in res["scalars"] if s not in scalar_names]
    params = list(units)
    header = ["run", *(f"{p} [{units[p]}]" if units[p] else p for p in params),
              "status", "error", "seconds", *scalar_names]
    final = Path(out_dir) / "sweep.csv"
    tmp = final.with_name(".sweep.csv.tmp")
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for run in runs:
            res = results.get(run.run_id)
            row = [run.run_id, *(repr(run.numbers[p]) for p in params)]
            if res is None:
                row += ["pending", "", "", *([""] * len(scalar_names))]
            else:
                row += [res["status"], res["error"], f"{res['seconds']:.3f}",
                        *(repr(res["scalars"][s]) if s in res["scalars"] else "" for s in scalar_names)]
            w.writerow(row)
    _replace_atomically(tmp, final)
    return final


def write_records(out_dir: Path, runs: list[RunPoint], units: dict[str, str], results: dict[str, dict]) -> Path:
    """Write ``records.h5`` (one group per finished run)."""
    final = Path(out_dir) / "records.h5"
    tmp = final.with_name(".records.h5.tmp")
    with h5py.File(tmp, "w") as h5:
        h5.attrs["parameters"] = json.dumps(units)
        for run in runs:
            res = results.get(run.run_id)
            if res is None:
                continue
            g = h5.create_group(run.run_id)
            g.attrs["key"] = run.key
            g.attrs["status"] = res["status"]
            g.attrs["error"] = res["error"]
            g.attrs["deck_values"] = json.dumps(run.values)
            for p, x in run.numbers.items():
                g.attrs[f"param:{p}"] = x
            for s, x in res["scalars"].items():
                g.attrs[f"scalar:{s}"] = x
            for name, cols in res["records"].items():
                rg = g.create_group(name)
                for col, arr in cols.items():
                    rg.create_dataset(col, data=np.asarray(arr))
    _replace_atomically(tmp, final)
    return final
