"""Slide-line records in ``interface.h5``: one HDF5 group per slide line (written during the run by
:class:`~shockfriction.io.records.RecordWriter`).

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


def read_interface(path: str | Path) -> dict[str, dict[str, np.ndarray]]:
    """Read ``interface.h5`` back: {line name: {dataset name: array}} (attributes under ``attrs``)."""
    out = {}
    with h5py.File(path, "r") as h5:
        for name, grp in h5.items():
            out[name] = {k: grp[k][()] for k in grp}
            out[name]["attrs"] = dict(grp.attrs)
    return out
