"""Outputs of sub-grid friction: extra datasets in ``interface.h5``, ``columns.h5`` and the maps
(written during the run by :class:`~shockfriction.io.records.RecordWriter`).

Datasets added to the slide line's group of ``interface.h5`` (record times of the slide line):

=============================  =====================================================================
``theta_interface_K``          column temperature at z = 0 at the record time (n_times, n_nodes)
``slip_local_mps``             true interface slip [v]^n, window-averaged (thermoelastic: = macro)
``slip_plastic_mps``           slip taken by the layer's plastic shear, sqrt(3) int d_eps dz/dt
``slip_macro_subgrid_mps``     the columns' |[V]^n| = |[V]^{n+1/2} + [V]^{n-1/2}|/2, window-averaged
``subgrid_<energy>_J``         cumulated energies (n_times,): friction_work_columns, heat_columns,
                               heat_other, cold_work, plastic_heat_pending, friction_work_hydro
=============================  =====================================================================

Energies are per unit depth (plane strain) or per radian (axisymmetric), like ``friction_work_J``.
"""


# record of the sub-grid friction model -> dataset of the slide line's group in interface.h5
SUBGRID_DATASETS = {"theta_interface": "theta_interface_K", "slip_local": "slip_local_mps",
                    "slip_plastic": "slip_plastic_mps", "slip_macro": "slip_macro_subgrid_mps"}
