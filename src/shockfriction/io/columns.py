"""Sub-grid column profiles to ``columns.h5``: T(z) and eps_p(z) under chosen slide-line nodes.

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


def write_columns(path: str | Path, lines: list) -> Path:
    """Write the profiles of the slide lines ``lines`` (each with a ``friction_model``)."""
    path = Path(path)
    with h5py.File(path, "w") as h5:
        for line in lines:
            fm = line.friction_model
            grp = h5.create_group(line.name)
            nz = fm.columns.z.size
            nn = fm.profile_nodes.size
            grp.create_dataset("z_m", data=fm.columns.z)
            grp.create_dataset("node", data=fm.profile_nodes)
            grp.create_dataset("node_index", data=line.slave[fm.profile_nodes])
            grp.create_dataset("t_s", data=np.array(fm.profile_t, float))
            grp.create_dataset("theta_K", data=np.array(fm.profile_theta, float).reshape(-1, nn, nz))
            grp.create_dataset("eps_p", data=np.array(fm.profile_eps, float).reshape(-1, nn, nz))
            grp.attrs["model"] = fm.model
            grp.attrs["material"] = fm.columns.material.name
            grp.attrs["body"] = fm.modelled_body
            grp.attrs["beta_T"] = fm.columns.beta_T
            grp.attrs["melting_temperature_K"] = fm.columns.material.melting_temperature
    return path


def read_columns(path: str | Path) -> dict[str, dict[str, np.ndarray]]:
    """{slide line: {dataset: array, 'attrs': {...}}}."""
    out = {}
    with h5py.File(path, "r") as h5:
        for name, grp in h5.items():
            out[name] = {k: grp[k][()] for k in grp}
            out[name]["attrs"] = dict(grp.attrs)
    return out
