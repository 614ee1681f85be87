"""Sub-grid column profiles in ``columns.h5``: T(z) and eps_p(z) under chosen slide-line nodes
(written during the run by :class:`~shockfriction.io.records.RecordWriter`).

One HDF5 group per slide line with sub-grid friction:

================  ==================================================================
``z_m``           depth below the interface of the column nodes (n_z,); z = 0 is the interface
``node``          positions of the chosen nodes along the slave side (n_nodes,)
``node_index``    their global node indices (n_nodes,)
``t_s``           profile times (n_times,)
``theta_K``       temperature, shape (n_times, n_nodes, n_z)
``eps_p``         cumulated equivalent plastic strain, same shape (0 for the thermoelastic model)
================  ==================================================================

Attributes: ``model``, ``material``, ``body`` (the modelled side), ``beta_T``, ``melting_temperature_K``.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np


def read_columns(path: str | Path) -> dict[str, dict[str, np.ndarray]]:
    """{slide line: {dataset: array, 'attrs': {...}}}."""
    out = {}
    with h5py.File(path, "r") as h5:
        for name, grp in h5.items():
            out[name] = {k: grp[k][()] for k in grp}
            out[name]["attrs"] = dict(grp.attrs)
    return out
