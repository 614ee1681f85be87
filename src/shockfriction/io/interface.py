"""Slide-line records to ``interface.h5``: one HDF5 group per slide line.

Datasets of group ``/<slide line name>`` (SI, shape (n_times, n_slave_nodes) unless noted):

=================  ==============================================================
``t_s``            record times (n_times,)
``node_index``     global index of each slave node (n_slave_nodes,)
``node_x_m``       slave node x at each record time
``node_y_m``       slave node y at each record time
``sigma_n_Pa``     normal stress, compression positive, window-averaged
``tau_Pa``         shear stress on the slave along the guide tangent, window-averaged
``slip_mps``       slip rate (v_slave - v_guide).t, window-averaged
``cum_slip_m``     cumulated slip displacement (signed)
``friction_work_J`` cumulated friction work of the node (J; per radian if axisymmetric)
``active``         1 where the node was paired with the guide at the record time
=================  ==============================================================

Attributes of the group: ``guide``, ``slave``, ``law``, ``total_friction_work_J``.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

DATASETS = {
    "t": "t_s", "x": "node_x_m", "y": "node_y_m", "sigma_n": "sigma_n_Pa", "tau": "tau_Pa",
    "slip": "slip_mps", "cum_slip": "cum_slip_m", "work": "friction_work_J", "active": "active",
}


def write_interface(path: str | Path, lines: list, attrs: dict[str, dict] | None = None) -> Path:
    """Write the records of ``lines`` (objects with ``.name``, ``.record``, ``.total_friction_work``)."""
    path = Path(path)
    with h5py.File(path, "w") as h5:
        for line in lines:
            grp = h5.create_group(line.name)
            data = line.record.arrays()
            for key, name in DATASETS.items():
                arr = data[key].astype(np.int8) if key == "active" else data[key]
                grp.create_dataset(name, data=arr)
            grp.create_dataset("node_index", data=line.record.slave_nodes)
            grp.attrs["total_friction_work_J"] = float(line.total_friction_work)
            grp.attrs["total_contact_loss_J"] = float(line.total_contact_loss)
            for k, v in (attrs or {}).get(line.name, {}).items():
                grp.attrs[k] = v
    return path


def read_interface(path: str | Path) -> dict[str, dict[str, np.ndarray]]:
    """Read ``interface.h5`` back: {line name: {dataset name: array}} (attributes under ``attrs``)."""
    out = {}
    with h5py.File(path, "r") as h5:
        for name, grp in h5.items():
            out[name] = {k: grp[k][()] for k in grp}
            out[name]["attrs"] = dict(grp.attrs)
    return out
