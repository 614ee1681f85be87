"""Outputs of sub-grid friction: extra datasets in ``interface.h5``, ``columns.h5`` and the maps.

Datasets added to the slide line's group of ``interface.h5`` (record times of the slide line):

=============================  =====================================================================
``theta_interface_K``          column temperature at z = 0 at the record time (n_times, n_nodes)
``slip_local_mps``             true interface slip [v]^n, window-averaged (thermoelastic: = macro)
``slip_plastic_mps``           slip taken by the layer's plastic shear, sqrt(3) int d_eps dz/dt
``slip_macro_subgrid_mps``     the columns' |[V]^n| = |[V]^{n+1/2} + [V]^{n-1/2}|/2, window-averaged
``subgrid_<energy>_J``         cumulated energies (n_times,): friction_work_columns, heat_columns,
                               heat_other, cold_work, plastic_heat_pending, melt_energy,
                               friction_work_hydro
=============================  =====================================================================

Group attributes ``branch_<coulomb_cap|sticking_cap|subgrid>_node_steps``: how many friction
node-steps (in contact, with free slip) each term of tau = min(mu0 F_N, tau_stick, sub-grid) governed.

Energies are per unit depth (plane strain) or per radian (axisymmetric), like ``friction_work_J``.
"""

from __future__ import annotations

from pathlib import Path

import h5py

from shockfriction.coupled.friction import ENERGY_KEYS
from shockfriction.io.columns import write_columns


def write_subgrid_outputs(lines: list, interface_h5: str | Path, out_dir: str | Path,
                          geometry_factor: float = 1.0) -> list[Path]:
    """Append the sub-grid records to ``interface_h5``; write ``columns.h5`` and the PNG maps."""
    from shockfriction.plot.coupled import plot_columns, plot_subgrid_interface

    out_dir = Path(out_dir)
    with h5py.File(interface_h5, "a") as h5:
        for line in lines:
            fm = line.friction_model
            rec = fm.records()
            grp = h5[line.name]
            grp.create_dataset("theta_interface_K", data=rec["theta_interface"])
            grp.create_dataset("slip_local_mps", data=rec["slip_local"])
            grp.create_dataset("slip_plastic_mps", data=rec["slip_plastic"])
            grp.create_dataset("slip_macro_subgrid_mps", data=rec["slip_macro"])
            for key in ENERGY_KEYS + ("friction_work_hydro",):
                grp.create_dataset(f"subgrid_{key}_J", data=rec[key])
            sg = fm.columns
            attrs = {"subgrid_model": fm.model, "subgrid_material": sg.material.name, "subgrid_body": fm.modelled_body,
                     "beta_T": sg.beta_T, "beta_Q": sg.beta_Q, "mu0": sg.mu0, "f": sg.f,
                     "column_thickness_m": float(sg.z[-1]), "column_cells": sg.z.size - 1,
                     "melting_temperature_K": sg.material.melting_temperature, "geometry_factor": geometry_factor}
            for key, value in attrs.items():
                grp.attrs[key] = value
            for key, value in fm.energy_balance().items():
                grp.attrs[f"total_{key}_J"] = value
            for key, value in fm.branch_counts.items():  # friction node-steps governed by each branch
                grp.attrs[f"branch_{key}_node_steps"] = value
    columns = write_columns(out_dir / "columns.h5", lines)
    written = [columns]
    written += plot_subgrid_interface(interface_h5, out_dir)
    written += plot_columns(columns, out_dir)
    return written
