"""Histories and records as pandas DataFrames with units in the column names, and as CSV files.

* probes and energy: one row per recorded cycle, ``t [s]`` first (``cone_fs.vy [m/s]``,
  ``kinetic [J]``; energies are per radian in axisymmetric runs, per metre of depth in plane
  strain: ``[J/m]``);
* slide-line records (``interface.h5``): long format, one row per (slide line, record time,
  slave node): ``line, t [s], node, node_index, x [m], y [m], sigma_n [Pa], tau [Pa],
  slip [m/s], cum_slip [m], friction_work [J], active`` and, with sub-grid friction,
  ``theta_interface [K], slip_local [m/s], slip_plastic [m/s], slip_macro_subgrid [m/s]``;
  written to ``interface.csv``;
* sub-grid column profiles (``columns.h5``): long format, one row per (slide line, profile
  time, profiled node, column depth): ``line, t [s], node, node_index, z [m], theta [K], eps_p [-]``;
  written to ``columns.csv``.

The HDF5 files stay the full record (attributes, energies); the CSV files are what
``pandas.read_csv`` (or a spreadsheet, or ParaView's CSV reader) opens directly.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

# interface.h5 dataset -> column name (per (time, node) arrays)
INTERFACE_COLUMNS = {
    "node_x_m": "x [m]", "node_y_m": "y [m]", "sigma_n_Pa": "sigma_n [Pa]", "tau_Pa": "tau [Pa]",
    "slip_mps": "slip [m/s]", "cum_slip_m": "cum_slip [m]", "friction_work_J": "friction_work [J]",
    "active": "active", "theta_interface_K": "theta_interface [K]", "slip_local_mps": "slip_local [m/s]",
    "slip_plastic_mps": "slip_plastic [m/s]", "slip_macro_subgrid_mps": "slip_macro_subgrid [m/s]",
}


def unit_column(name: str) -> str:
    """``cone_fs.vy_m/s`` -> ``cone_fs.vy [m/s]``; ``t_s`` -> ``t [s]``; ``eps_p_1`` -> ``eps_p [-]``;
    a name already in the ``name [unit]`` style is returned as it is."""
    if name.endswith("]"):
        return name
    m = re.fullmatch(r"(.+?)_(m/s|m|s|Pa|K|J|J/m|J/kg|kg/m3|kg|1)", name)
    if not m:
        return name
    unit = {"1": "-", "kg/m3": "kg/m^3"}.get(m.group(2), m.group(2))
    return f"{m.group(1)} [{unit}]"


def history_frame(columns: dict[str, np.ndarray], header: list[str]) -> pd.DataFrame:
    """A history (dict of equal-length arrays, keys in the order of ``header``'s unit-suffixed
    names) as a DataFrame with ``name [unit]`` columns."""
    keys = list(columns)
    return pd.DataFrame({unit_column(h): np.asarray(columns[k]) for k, h in zip(keys, header)})


def interface_frame(records: dict[str, dict[str, np.ndarray]]) -> pd.DataFrame:
    """Slide-line records ({line: {dataset: array}}, as :func:`shockfriction.io.interface.read_interface`)
    in long format (one row per line, record time, slave node)."""
    frames = []
    for name, rec in records.items():
        t = np.asarray(rec["t_s"], float)
        idx = np.asarray(rec["node_index"])
        nt, nn = t.size, idx.size
        cols = {"line": np.full(nt * nn, name, dtype=object), "t [s]": np.repeat(t, nn),
                "node": np.tile(np.arange(nn), nt), "node_index": np.tile(idx, nt)}
        for key, col in INTERFACE_COLUMNS.items():
            if key in rec and np.shape(rec[key]) == (nt, nn):
                cols[col] = np.asarray(rec[key]).reshape(-1)
        frames.append(pd.DataFrame(cols))
    if not frames:
        return pd.DataFrame(columns=["line", "t [s]", "node", "node_index"] + list(INTERFACE_COLUMNS)[:8])
    return pd.concat(frames, ignore_index=True)


def columns_frame(profiles: dict[str, dict[str, np.ndarray]]) -> pd.DataFrame:
    """Sub-grid column profiles ({line: {dataset: array}}, as :func:`shockfriction.io.columns.read_columns`)
    in long format (one row per line, profile time, profiled node, depth)."""
    frames = []
    for name, rec in profiles.items():
        t, z = np.asarray(rec["t_s"], float), np.asarray(rec["z_m"], float)
        node, idx = np.asarray(rec["node"]), np.asarray(rec["node_index"])
        nt, nn, nz = t.size, node.size, z.size
        frames.append(pd.DataFrame({
            "line": np.full(nt * nn * nz, name, dtype=object), "t [s]": np.repeat(t, nn * nz),
            "node": np.tile(np.repeat(node, nz), nt), "node_index": np.tile(np.repeat(idx, nz), nt),
            "z [m]": np.tile(z, nt * nn), "theta [K]": np.asarray(rec["theta_K"], float).reshape(-1),
            "eps_p [-]": np.asarray(rec["eps_p"], float).reshape(-1)}))
    if not frames:
        return pd.DataFrame(columns=["line", "t [s]", "node", "node_index", "z [m]", "theta [K]", "eps_p [-]"])
    return pd.concat(frames, ignore_index=True)


def write_record_tables(out_dir: str | Path, only: str | None = None) -> list[Path]:
    """``interface.csv`` from ``interface.h5`` and ``columns.csv`` from ``columns.h5`` when present
    (``only`` = "interface" or "columns": that one alone)."""
    from shockfriction.io.columns import read_columns
    from shockfriction.io.interface import read_interface

    out_dir = Path(out_dir)
    written = []
    for h5, csv, reader, frame in (("interface.h5", "interface.csv", read_interface, interface_frame),
                                   ("columns.h5", "columns.csv", read_columns, columns_frame)):
        if only is not None and not h5.startswith(only):
            continue
        if (out_dir / h5).is_file():
            frame(reader(out_dir / h5)).to_csv(out_dir / csv, index=False, float_format="%.10e")
            written.append(out_dir / csv)
    return written
