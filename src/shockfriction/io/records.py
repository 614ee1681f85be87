"""Slide-line and sub-grid records written as the run goes: ``interface.h5`` and ``columns.h5``.

The layouts are those of :mod:`shockfriction.io.interface`, :mod:`shockfriction.coupled.outputs`
and :mod:`shockfriction.io.columns`; every time-indexed dataset is resizable along its first
axis (chunked, ``maxshape = (None, ...)``).  :meth:`RecordWriter.append` writes the records the
slide lines (and their sub-grid columns) have taken since the last call, updates the running
totals held as attributes, and flushes both files, so that a run killed at any time leaves files
that open and hold every record up to the last output.  ``t_s`` is grown last: its length is the
number of complete records.  On a restart the files are rebuilt from the records the checkpoint
holds (the writer starts from an empty file and appends them all).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from shockfriction.coupled.outputs import SUBGRID_DATASETS
from shockfriction.io.interface import DATASETS


def _grow(grp, name: str, tail: tuple, dtype=np.float64, chunk: int = 64):
    return grp.create_dataset(name, shape=(0,) + tail, maxshape=(None,) + tail, dtype=dtype,
                              chunks=(chunk,) + tail if tail else (max(chunk, 256),))


def _put(ds, rows) -> None:
    """Append ``rows`` (a list of arrays or floats, one per record) to ``ds``."""
    n0 = ds.shape[0]
    data = np.asarray(rows, dtype=ds.dtype).reshape((len(rows),) + ds.shape[1:])
    ds.resize(n0 + len(rows), axis=0)
    ds[n0:] = data


class RecordWriter:
    """``interface.h5`` (and ``columns.h5`` with sub-grid friction) for the slide lines ``lines``."""

    def __init__(self, out_dir: str | Path, lines: list, geometry_factor: float = 1.0):
        self.out_dir = Path(out_dir)
        self.lines = list(lines)
        self.geometry_factor = float(geometry_factor)
        self.coupled = [ln for ln in self.lines if ln.friction_model is not None]
        self.interface_path = self.out_dir / "interface.h5"
        self.columns_path = self.out_dir / "columns.h5" if self.coupled else None
        self._n = {ln.name: 0 for ln in self.lines}
        self._n_profiles = {ln.name: 0 for ln in self.coupled}
        self._h5 = h5py.File(self.interface_path, "w")
        for ln in self.lines:
            grp = self._h5.create_group(ln.name)
            ns = ln.record.slave_nodes.size
            grp.create_dataset("node_index", data=ln.record.slave_nodes)
            for key, name in DATASETS.items():
                tail = () if key == "t" else (ns,)
                _grow(grp, name, tail, np.int8 if key == "active" else np.float64)
            grp.attrs["law"] = ln.law
            grp.attrs["bilateral"] = int(ln.bilateral)
            grp.attrs["heat_share_slave"] = -1.0 if ln.heat_share_slave is None else ln.heat_share_slave
            grp.attrs["axisymmetric"] = int(ln.axisymmetric)
            fm = ln.friction_model
            if fm is not None:
                self._create_subgrid(grp, fm, ns)
        self._col = None
        if self.coupled:
            self._col = h5py.File(self.columns_path, "w")
            for ln in self.coupled:
                fm = ln.friction_model
                grp = self._col.create_group(ln.name)
                nz, nn = fm.columns.z.size, fm.profile_nodes.size
                grp.create_dataset("z_m", data=fm.columns.z)
                grp.create_dataset("node", data=fm.profile_nodes)
                grp.create_dataset("node_index", data=ln.slave[fm.profile_nodes])
                _grow(grp, "theta_K", (nn, nz), chunk=1)
                _grow(grp, "eps_p", (nn, nz), chunk=1)
                _grow(grp, "t_s", ())
                grp.attrs["model"] = fm.model
                grp.attrs["material"] = fm.columns.material.name
                grp.attrs["body"] = fm.modelled_body
                grp.attrs["beta_T"] = fm.columns.beta_T
                grp.attrs["melting_temperature_K"] = fm.columns.material.melting_temperature
        self.append()

    def _create_subgrid(self, grp, fm, ns: int) -> None:
        from shockfriction.coupled.friction import ENERGY_KEYS

        for name in SUBGRID_DATASETS.values():
            _grow(grp, name, (ns,))
        for key in ENERGY_KEYS + ("friction_work_hydro",):
            _grow(grp, f"subgrid_{key}_J", ())
        sg = fm.columns
        attrs = {"subgrid_model": fm.model, "subgrid_material": sg.material.name, "subgrid_body": fm.modelled_body,
                 "beta_T": sg.beta_T, "beta_Q": sg.beta_Q, "mu0": sg.mu0, "f": sg.f,
                 "column_thickness_m": float(sg.z[-1]), "column_cells": sg.z.size - 1,
                 "melting_temperature_K": sg.material.melting_temperature, "geometry_factor": self.geometry_factor}
        for key, value in attrs.items():
            grp.attrs[key] = value

    def append(self) -> bool:
        """Write the records taken since the last call and flush; True if there were any."""
        from shockfriction.coupled.friction import ENERGY_KEYS

        wrote = False
        for ln in self.lines:
            rec, grp, n0 = ln.record, self._h5[ln.name], self._n[ln.name]
            n1 = len(rec.t)
            if n1 > n0:
                for key, name in DATASETS.items():
                    if key != "t":
                        _put(grp[name], getattr(rec, key)[n0:n1])
                fm = ln.friction_model
                if fm is not None:
                    for key, name in SUBGRID_DATASETS.items():
                        _put(grp[name], fm.record[key][n0:n1])
                    for key in ENERGY_KEYS + ("friction_work_hydro",):
                        _put(grp[f"subgrid_{key}_J"], fm.record[key][n0:n1])
                _put(grp["t_s"], rec.t[n0:n1])  # last: its length counts the complete records
                self._n[ln.name] = n1
                wrote = True
            grp.attrs["total_friction_work_J"] = float(ln.total_friction_work)
            grp.attrs["total_contact_loss_J"] = float(ln.total_contact_loss)
            if ln.friction_model is not None:
                for key, value in ln.friction_model.energy_balance().items():
                    grp.attrs[f"total_{key}_J"] = value
                for key, value in ln.friction_model.branch_counts.items():  # node-steps governed by each branch
                    grp.attrs[f"branch_{key}_node_steps"] = value
        for ln in self.coupled:
            fm, grp, n0 = ln.friction_model, self._col[ln.name], self._n_profiles[ln.name]
            n1 = len(fm.profile_t)
            if n1 > n0:
                _put(grp["theta_K"], fm.profile_theta[n0:n1])
                _put(grp["eps_p"], fm.profile_eps[n0:n1])
                _put(grp["t_s"], fm.profile_t[n0:n1])
                self._n_profiles[ln.name] = n1
                wrote = True
        self._h5.flush()
        if self._col is not None:
            self._col.flush()
        return wrote

    def close(self) -> None:
        """Write what is left and close the files."""
        if self._h5.id.valid:
            self.append()
            self._h5.close()
        if self._col is not None and self._col.id.valid:
            self._col.close()
