"""Sub-grid friction on a slide line: one column under every slave node, force coupling (thesis Part III).

Every hydro step, after the contact step of the slide line (normal impulses P_n known), the
friction step of Table 6.1 runs as follows for the slave nodes j:

1. column inputs (:func:`~shockfriction.coupled.kernels.column_inputs`): F_N = P_n/(S dt),
   free slip [V*]^{n+1/2}, previous slip [V]^{n-1/2} (same pairing), m_g, and the guide mass
   m_G under a uniform traction of the line (shared guide nodes counted);
2. the columns (:class:`~shockfriction.friction.subgrid.interface.SubgridInterface`, thesis
   Algorithms 1 and 2) solve the interface temperature and return the friction stress
   tau = min(mu0 F_N, tau_stick, f Ymax/sqrt(3) G(F_N, Theta(0))/G0) with the hydro step dt
   inside the friction step (force coupling, eq. 5.183 / 6.83);
3. the slide line applies the impulses, |P_t| <= tau S dt, by the projected Gauss-Seidel
   sweeps of its own tangential step (:func:`~shockfriction.coupled.kernels.capped_tangential_step`).

Nodes out of contact (P_n = 0) or without free slip (|[V*]| <= 1e-6 m/s, round-off of the contact
step) get tau = 0: their column receives no heat (it only keeps diffusing what it already holds).

Energy bookkeeping (per unit depth in plane strain, per radian in axisymmetry, like the slide
line's friction work): each step adds S_j^n times the per-area increments of node j,

* ``heat_columns``: heat put into the columns, beta_T tau [v] dt + the (lagged) plastic heat;
* ``heat_other``: the other body's share (1 - beta_T) tau [v] dt (counted, not deposited);
* ``cold_work``: (1 - beta_Q) of the plastic work (stored in the layer's defects);
* ``plastic_heat_pending``: beta_Q times the last step's plastic work, deposited next step;
* ``melt_energy``: lagged plastic heat that would have taken a column node past melting, clipped
  off (the energy melting would absorb; thermoelastoplastic only, the melt guard of
  :meth:`~shockfriction.friction.subgrid.interface.SubgridInterface.step` shared with the
  uncoupled driver);
* ``friction_work_columns``: tau |[V]^n| dt, the columns' view of the friction work.

The columns' balance friction_work_columns = heat_columns + heat_other + cold_work + pending + melt holds
to round-off; the hydrocode's friction work (impulse work, exact kinetic-energy loss) differs
from the columns' only where the actual corrected slip differs from the columns' prediction
(non-uniform stress along the line, nodes that stick in the Gauss-Seidel sweeps but not alone).
"""

from __future__ import annotations

import math

import numpy as np

from shockfriction.coupled.kernels import (capped_tangential_step, column_inputs, layer_shear_velocity, stash_sums,
                                          step_increments, tally_branches)
from shockfriction.errors import DeckError, SimulationError
from shockfriction.friction.subgrid.interface import SubgridInterface

IDLE_SLIP = 1e-6  # m/s: a free slip below this is contact round-off, the node's column stays idle
ENERGY_KEYS = ("friction_work_columns", "heat_columns", "heat_other", "cold_work", "plastic_heat_pending",
               "melt_energy", "columns_mechanical", "layer_work")
# which term of tau = min(mu0 F_N, tau_stick, sub-grid branch) governs a friction node-step (in contact, free slip)
BRANCHES = ("coulomb_cap", "sticking_cap", "subgrid")
# the viscoplastic column under a hydro node (docs/theory/viscoplastic.md, "Coupled closure"): by default
# ("excess") a quasi-static layer that slips only by its flow in excess of the unheated body's (the hydro carries the
# body, its shear waves and its homogeneous flow); the options "shear" and "held" hold its far end at the velocity
# the hydro's shear of the layer gives it at depth h, or at the node's (version 0.3): both depend on the thickness
COUPLED_VISCOPLASTIC = {"far_end": "held"}
# the "excess" closure's thermal far field: the column is continued below its resolved layer by geometric cells
# (ratio EXCESS_DEPTH_RATIO) down to EXCESS_DEPTH, so that its heat does not feel the far end (4 sqrt(alpha t) for
# an aluminium alloy is 0.28 mm at 100 us): the answer then does not depend on the thickness
EXCESS_DEPTH = 1e-3
EXCESS_DEPTH_RATIO = 1.1
#: the depth must reach THERMAL_REACH sqrt(alpha t_end): the rise there is at most erfc(2) = 0.5 % of the surface's
#: (0.17 % under a constant flux), and the insulated end's image adds < 1e-8 of the surface rise
#: (docs/theory/viscoplastic.md, "Thermal far field"; slide_lines[k].friction.depth)
THERMAL_REACH = 4.0
CLOSURES = ("excess", "shear", "held")


class SubgridFriction:
    """The friction model a :class:`~shockfriction.contact.slideline.SlideLine` delegates its tangential step to.

    ``material`` is the modelled body's library material, ``other`` the opposite body's material or
    directly the heat share beta_T.  ``profile_nodes`` (positions along the slave side) and
    ``profile_interval`` select the T(z), eps_p(z) profiles kept for ``columns.h5`` (sampled at
    the slide line's record times).  ``trace=True`` keeps every step's inputs and outputs (tests).
    """

    def __init__(self, name: str, n_nodes: int, model: str, material, other, *, mu0: float, f: float,
                 thickness: float = 20e-6, cells: int = 500, grading: float = 1.0, taylor_quinney: float = 0.9,
                 T0: float = 300.0, bilateral: bool = False, profile_nodes=None, profile_interval: float = 0.0,
                 modelled_body: str = "slave", trace: bool = False, picard_tol: float | None = None,
                 pressure_melting: bool = True, closure: str = "excess", state=None,
                 excess_depth: float = EXCESS_DEPTH):
        self.name = name
        self.model = model
        self.modelled_body = modelled_body
        if closure not in CLOSURES:
            raise ValueError(f"closure must be one of {CLOSURES}, got {closure!r}")
        self.closure = closure
        self._state = state  # the hydro state (positions, connectivity) that the "shear" closure reads
        self.columns = SubgridInterface(n_nodes, material, other, thickness=thickness, n_cells=cells,
                                        grading=grading, model=model, mu0=mu0, f=f, taylor_quinney=taylor_quinney,
                                        T0=T0, viscoplastic={**COUPLED_VISCOPLASTIC,
                                                             **({"far_end": "excess", "depth": float(excess_depth),
                                                                 "depth_ratio": EXCESS_DEPTH_RATIO}
                                                                if closure == "excess" else {}),
                                                             "picard_tol": picard_tol,
                                                             "pressure_melting": pressure_melting}
                                        if model == "viscoplastic" else None)
        self._vp_before = np.zeros((6, n_nodes))  # viscoplastic column energies before a step (see _vp_books)
        self.bilateral = bool(bilateral)
        n = n_nodes
        for key in ("sigma_n", "v_free", "v_prev", "m_slave", "m_guide", "cap"):
            setattr(self, key, np.zeros(n))
        for key in ENERGY_KEYS:
            setattr(self, key, 0.0)
        self._before = np.zeros((5, n))  # the column energies before a step (see step_increments)
        self._parts = np.zeros((5, n))  # their increments per unit area
        self._win_local = np.zeros(n)
        self._win_plastic = np.zeros(n)
        self._win_macro = np.zeros(n)
        self._win_time = 0.0
        self._branch_counts = np.zeros(len(BRANCHES), dtype=np.int64)  # an array: checkpoints keep it
        self.record = {k: [] for k in ("t", "theta_interface", "slip_local", "slip_plastic", "slip_macro")
                       + ENERGY_KEYS + ("friction_work_hydro",)}
        if profile_nodes is None:
            profile_nodes = np.unique(np.linspace(0, n - 1, min(n, 5)).round().astype(int))
        self.profile_nodes = np.asarray(profile_nodes, dtype=np.int64)
        self.profile_interval = float(profile_interval)
        self.profile_t: list[float] = []
        self.profile_theta: list[np.ndarray] = []
        self.profile_eps: list[np.ndarray] = []
        self._next_profile = 0.0
        self._profile(0.0)
        self.trace = [] if trace else None
        self.steps = 0

    # ------------------------------------------------------------------ the friction step

    @property
    def branch_counts(self) -> dict[str, int]:
        """Friction node-steps governed by each branch (Coulomb cap, sticking cap, sub-grid model)."""
        return {k: int(v) for k, v in zip(BRANCHES, self._branch_counts)}
    def tangential(self, line, vx, vy, vx_old, vy_old, mass, dt: float, t: float) -> int:
        """Friction step of ``line`` (after its contact step): correct ``vx, vy``; return the sweeps."""
        sg = self.columns
        column_inputs(vx, vy, vx_old, vy_old, mass, line.slave_imp, line.gnode, line.gw, line.tx, line.ty,
                      line.active, line.lam_n, line.area, dt, self.bilateral, self._guide_load(mass.size),
                      IDLE_SLIP, self.sigma_n, self.v_free,
                      self.v_prev, self.m_slave, self.m_guide)
        stash_sums(sg.friction_work, sg.heat_interface, sg.heat_plastic, sg.plastic_work, sg.melt_energy, self._before)
        vp = self.model == "viscoplastic"
        if vp:
            self._vp_sums(self._vp_before)
            if self.closure == "shear" and self._state is not None:
                st = self._state
                if self.modelled_body == "slave":
                    ca, cb = line.slave_cell_before, line.slave_cell_after
                else:  # the guide cell of each node's paired segment
                    ca = line.guide_cells[np.clip(line.seg, 0, line.guide_cells.size - 1)]
                    cb = np.full(ca.size, -1, np.int64)
                layer_shear_velocity(st.x, st.y, vx_old, vy_old, st.conn, ca, cb, line.tx, line.ty, line.nx, line.ny,
                                     line.active, float(sg.vp.z[-1]), sg.v_far)
        try:
            tau, _ = sg.step(self.sigma_n, self.v_free, self.v_prev, self.m_slave, self.m_guide, line.area, dt,
                             cycle=self.steps + 1, time=t)
        except SimulationError as exc:
            raise SimulationError(f"slide line {self.name!r}, sub-grid friction step {self.steps + 1}: {exc}") from None
        S = line.area
        parts = self._parts
        step_increments(sg.friction_work, sg.heat_interface, sg.heat_plastic, sg.plastic_work, sg.melt_energy,
                        self._before, tau, sg.slip_local, sg.slip_plastic, sg.slip_macro, S, dt, sg.beta_T, sg.beta_Q,
                        self.cap, parts, self._win_local, self._win_plastic, self._win_macro)
        sweeps = capped_tangential_step(vx, vy, mass, line.slave_imp, line.gnode, line.gw, line.tx, line.ty,
                                        line.active, self.cap, line.max_sweeps, line.rel_tol, line.lam_t, line.slip)
        line.slip_free[:] = self.v_free
        if vp:
            self._vp_books(S)
        else:
            self.friction_work_columns += float(S @ parts[0])
            self.heat_columns += float(S @ parts[1])
            self.heat_other += float(S @ parts[2])
            self.cold_work += float(S @ parts[3])
            self.plastic_heat_pending = float(S @ sg.plastic_heat_pending)
            self.melt_energy += float(S @ parts[4])
        self._tally(tau)
        self._win_time += dt
        self.steps += 1
        if self.trace is not None:
            self.trace.append({"t": t, "dt": dt, "sigma_n": self.sigma_n.copy(), "v_free": self.v_free.copy(),
                               "v_prev": self.v_prev.copy(), "slip_macro": sg.slip_macro.copy(),
                               "slip_local": sg.slip_local.copy(), "tau": tau.copy(),
                               "theta_interface": sg.theta_interface.copy(), "area": S.copy(),
                               "lam_t": line.lam_t.copy(), "slip": line.slip.copy(), "active": line.active.copy()})
        return sweeps

    def _vp_sums(self, out: np.ndarray) -> None:
        """The viscoplastic columns' running energies per unit area (rows: friction work, enthalpy (sensible + latent)
        + heat out, the other body's heat, cold work, kinetic + elastic, work through z = h)."""
        E = self.columns.vp.energies()
        out[0] = E["friction_work"]
        out[1] = E["heat_stored"] + E["heat_out"]
        out[2] = E["heat_other_body"]
        out[3] = E["cold_work"]
        out[4] = E["kinetic"] + E["elastic"]
        out[5] = E["radiated"]

    def _vp_books(self, S: np.ndarray) -> None:
        """Book a viscoplastic step: friction work = heat in the columns + the other body's heat + cold work + the
        columns' kinetic and elastic energy - the work the hydro's shear does on the layers through z = h
        (``layer_work``: energy the hydro's cells hold already, so it is not counted twice)."""
        after = np.empty_like(self._vp_before)
        self._vp_sums(after)
        d = after - self._vp_before
        self.friction_work_columns += float(S @ d[0])
        self.heat_columns += float(S @ d[1])
        self.heat_other += float(S @ d[2])
        self.cold_work += float(S @ d[3])
        self.columns_mechanical += float(S @ d[4])
        self.layer_work -= float(S @ d[5])

    def _tally(self, tau: np.ndarray) -> None:
        """Count which branch gave tau at each friction node-step (in contact with free slip): the Coulomb cap
        mu0 F_N, the sticking cap tau_stick, or the sub-grid model (tau below both caps)."""
        sg = self.columns
        tally_branches(self.sigma_n, self.v_free, tau, sg.tau_coulomb, sg.tau_stick, self._branch_counts)

    def _guide_load(self, n: int) -> np.ndarray:
        if getattr(self, "_load", None) is None or self._load.size != n:
            self._load = np.zeros(n)
        return self._load

    # ------------------------------------------------------------------ records
    def on_record(self, t_end: float, friction_work_hydro: float) -> None:
        """Close a record window at ``t_end`` (called by the slide line when it records)."""
        w = self._win_time if self._win_time > 0.0 else 1.0
        rec = self.record
        rec["t"].append(t_end)
        rec["theta_interface"].append(self.columns.theta_interface.copy())
        rec["slip_local"].append(self._win_local / w)
        rec["slip_plastic"].append(self._win_plastic / w)
        rec["slip_macro"].append(self._win_macro / w)
        for key in ENERGY_KEYS:
            rec[key].append(getattr(self, key))
        rec["friction_work_hydro"].append(float(friction_work_hydro))
        self._win_local[:] = 0.0
        self._win_plastic[:] = 0.0
        self._win_macro[:] = 0.0
        self._win_time = 0.0
        if t_end >= self._next_profile * (1 - 1e-12):
            self._profile(t_end)

    def _profile(self, t: float) -> None:
        self.profile_t.append(t)
        self.profile_theta.append(self.columns.theta[self.profile_nodes].copy())
        self.profile_eps.append(self.columns.eps_p[self.profile_nodes].copy())
        if self.profile_interval > 0.0:
            while self._next_profile <= t * (1 + 1e-12):
                self._next_profile += self.profile_interval
        else:
            self._next_profile = t

    def records(self) -> dict[str, np.ndarray]:
        """Record arrays: ``t`` (n_times,), per-node (n_times, n_nodes), energies (n_times,)."""
        n = self.columns.n_columns
        out = {"t": np.array(self.record["t"], float)}
        for key in ("theta_interface", "slip_local", "slip_plastic", "slip_macro"):
            out[key] = np.array(self.record[key], float).reshape(-1, n)
        for key in ENERGY_KEYS + ("friction_work_hydro",):
            out[key] = np.array(self.record[key], float)
        return out

    def energy_balance(self) -> dict[str, float]:
        """The totals now (J per unit depth or per radian)."""
        return {key: float(getattr(self, key)) for key in ENERGY_KEYS}


def build_subgrid_friction(sl, line, bodies: dict, where: str, trace: bool = False, state=None,
                           t_end: float | None = None) -> SubgridFriction:
    """The :class:`SubgridFriction` of a validated slide-line deck entry ``sl`` on ``line``.

    ``bodies`` maps body names to their deck entries (material, initial temperature); ``state`` the hydro state
    (the viscoplastic columns' "shear" closure reads its positions and cells); ``t_end`` the run's end time (s),
    against which the "excess" closure's depth is checked (:data:`THERMAL_REACH`).
    """
    from shockfriction.materials.library import get_material

    fr = sl.friction
    if sl.heat != "none":
        raise DeckError(f"{where}.heat = {sl.heat!r}: expected 'none' with friction law {fr.law!r} "
                        "(the sub-grid columns take the frictional heat; the other body's share is counted)")
    modelled = sl.slave.body if fr.body == "slave" else sl.guide.body
    opposite = sl.guide.body if fr.body == "slave" else sl.slave.body
    mat_name = bodies[modelled].material
    if mat_name is None:
        raise DeckError(f"{where}.friction.body = {fr.body!r}: expected the modelled body {modelled!r} to name a "
                        "library material (its conductivity, heat capacity and SCG data feed the columns)")
    material = get_material(mat_name)
    missing = [k for k in ("latent_heat", "liquid_viscosity") if not material.has(k)]
    if fr.subgrid_model == "viscoplastic" and missing:
        raise DeckError(f"{where}.friction.body = {fr.body!r}: the subgrid-viscoplastic law needs the modelled body's "
                        f"material with {' and '.join(missing)} ({modelled!r} is {mat_name}, which has none; model "
                        "the other body, or another law)")
    if fr.heat_share is not None:
        other = float(fr.heat_share)
    else:
        other_name = bodies[opposite].material
        if other_name is None:
            raise DeckError(f"{where}.friction.heat_share is missing: expected a value, since body {opposite!r} "
                            "names no library material (its effusivity would give beta_T)")
        other = get_material(other_name)
    T0 = float(bodies[modelled].temperature)
    if not T0 < material.melting_temperature:
        raise DeckError(f"bodies.{modelled}.temperature = {T0}: expected below the melting temperature "
                        f"{material.melting_temperature} K of {mat_name}")
    depth = EXCESS_DEPTH if fr.depth is None else float(fr.depth)
    if fr.subgrid_model == "viscoplastic" and fr.closure == "excess" and t_end is not None:
        reach = THERMAL_REACH * math.sqrt(material.diffusivity * float(t_end))
        if depth < reach:
            given = f"{where}.friction.depth = {depth:g} m" if fr.depth is not None else \
                f"{where}.friction.depth (omitted: {depth:g} m)"
            raise DeckError(f"{given}: expected at least {THERMAL_REACH:g} sqrt(alpha t_end) = {reach:.3g} m for "
                            f"{mat_name} (alpha = {material.diffusivity:.3g} m^2/s) over time.end = "
                            f"{float(t_end):g} s, or the frictional heat reaches the column's insulated end and stays "
                            "there; set a larger depth")
    n = line.slave.size
    nodes = fr.profile_nodes
    if nodes is not None:
        bad = [k for k in nodes if not -n <= k < n]
        if bad:
            raise DeckError(f"{where}.friction.profile_nodes = {list(nodes)!r}: expected slave node positions in "
                            f"[-{n}, {n - 1}] ({n} slave nodes)")
        nodes = [k % n for k in nodes]
    # default: every 10th record of the slide line
    interval = fr.profile_interval if fr.profile_interval is not None else 10.0 * line.record_interval
    return SubgridFriction(sl.name, n, fr.subgrid_model, material, other, mu0=float(fr.mu0), f=float(fr.f),
                           thickness=fr.thickness, cells=fr.cells, grading=fr.grading,
                           taylor_quinney=fr.taylor_quinney, T0=T0, bilateral=sl.contact == "bilateral",
                           profile_nodes=nodes, profile_interval=interval, modelled_body=fr.body, trace=trace,
                           picard_tol=fr.picard_tol, pressure_melting=fr.pressure_melting, closure=fr.closure,
                           state=state, excess_depth=depth)
