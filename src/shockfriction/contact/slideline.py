"""A slide line between two body sides: pairing, contact, friction, heat and its records.

The hydrocode calls :meth:`SlideLine.apply` once per cycle, after the free nodal
velocities v* = v^{n-1/2} + dt F/m are known and before the positions advance
(thesis eqs. 3.54-3.60).  The per-node work is done by the numba kernels of
:mod:`~shockfriction.contact.pairing` and :mod:`~shockfriction.contact.impulses`;
this class only gathers their arrays, keeps the running sums and the records.

Records (per slave node, averaged over each record window of length
``record_interval`` so that they are impulse-exact rather than one noisy cycle):

* ``sigma_n``: normal stress = sum of normal impulses / (S_g window), compression > 0
* ``tau``: shear stress on the slave along the guide tangent t = sum of tangential impulses / (S_g window)
* ``slip``: mean slip rate (v_g - v_G).t over the window
* ``cum_slip``: cumulated slip displacement, integral of the slip rate (signed)
* ``work``: cumulated friction work of the node (J, per radian when axisymmetric)
* ``x``, ``y``: node position at the end of the window; ``active``: paired at the last cycle
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from shockfriction.contact.impulses import (accumulate_step, deposit_contact_heat, deposit_friction_heat, impulse_work,
                                            normal_step,
                                            penetration_projection, point_weights, side_yield_stress,
                                            tangential_step)
from shockfriction.contact.pairing import (contact_geometry, contact_geometry_parallel, hat_weights,
                                           hat_weights_parallel, heat_weights_kernel, projection_gap,
                                           slave_nodal_areas)
from shockfriction.friction.laws import FRICTIONLESS


# a slide line's geometry (pairing, hat coordinates and weights) runs over its slave nodes in parallel when the
# hydro kernels are the parallel ones and it has this many slave nodes (the same bytes: each node is independent).
# 1: every line; on the 16-core device machine the cone shot (lines of 306 and 21 slave nodes) ran faster so, with
# the staged cycle's node passes parallel too, than with both serial (docs/theory/threads.md)
PARALLEL_MIN_NODES = 1


@dataclass
class InterfaceRecord:
    """Time series of one slide line: lists of per-node arrays, one entry per record time."""

    name: str
    slave_nodes: np.ndarray
    t: list = field(default_factory=list)
    x: list = field(default_factory=list)
    y: list = field(default_factory=list)
    sigma_n: list = field(default_factory=list)
    tau: list = field(default_factory=list)
    slip: list = field(default_factory=list)
    cum_slip: list = field(default_factory=list)
    work: list = field(default_factory=list)
    active: list = field(default_factory=list)

    def arrays(self) -> dict[str, np.ndarray]:
        """Stacked arrays, shape (n_times, n_slave_nodes) (``t`` has shape (n_times,))."""
        n = self.slave_nodes.size

        def stack(v, dtype=float):
            return np.array(v, dtype=dtype).reshape(len(v), n)

        return {
            "t": np.array(self.t, dtype=float),
            "x": stack(self.x), "y": stack(self.y),
            "sigma_n": stack(self.sigma_n), "tau": stack(self.tau), "slip": stack(self.slip),
            "cum_slip": stack(self.cum_slip), "work": stack(self.work),
            "active": stack(self.active, bool),
        }


class SlideLine:
    """Contact and friction between a guide (master) side and a sliding (slave) side.

    Parameters
    ----------
    slave, guide:
        Ordered node indices of the two sides (any order along each side; the guide
        order fixes the tangent t).  With ``periodic`` each side spans exactly one
        period, its last node being the periodic image of its first.
    slave_cells:
        Cell next to each slave segment (``slave[k]``-``slave[k+1]``), length ns - 1.
    guide_cells:
        Cell next to each guide segment, length ng - 1.
    normal_sign:
        +1 or -1 such that n = s (t_y, -t_x) points out of the guide body
        (:func:`~shockfriction.contact.pairing.guide_normal_sign`).
    law, law_params:
        Friction law id and parameter array (:mod:`shockfriction.friction.laws`).
    bilateral:
        Thesis's permanent contact (tension allowed) instead of unilateral contact.
    heat_share_slave:
        None: friction work is not deposited (thesis ch. 3 baseline).  Otherwise the
        share beta_T of the slave body (eq. 2.101); the rest goes to the guide cells.
    axisymmetric, radius_axis:
        Nodal surfaces per radian about the axis (0: x is the radius, 1: y is).
    max_gap, max_penetration:
        Search window of the pairing (m); default half the smallest initial guide segment.
    guide_share:
        ``"segment"`` (default): the projection's guide nodes and weights are the mortar-type
        integrals of the guide's hat functions against the slave node's hat function
        (:func:`~shockfriction.contact.pairing.hat_weights`: consistent nodal forces on the
        guide, the contact patch test passes with non-matching meshes);
        ``"point"``: the thesis's (1 - coef, coef) on the paired segment (eqs. 3.84-3.85).
    node_representative:
        For node groups that the hydrocode moves as one node (ties, periodic images): the
        member that receives the impulses of every node of its group (the others are synced
        by the hydrocode afterwards).  ``mass`` must then be the group mass.  Default:
        every node represents itself.
    """

    def __init__(self, name: str, slave, guide, slave_cells, guide_cells, normal_sign: float, *,
                 law: int = FRICTIONLESS, law_params=None, bilateral: bool = False,
                 heat_share_slave: float | None = None, axisymmetric: bool = False, radius_axis: int = 1,
                 periodic: bool = False, max_gap: float | None = None, max_penetration: float | None = None,
                 max_sweeps: int = 50, rel_tol: float = 1e-10, record_interval: float = math.inf,
                 guide_share: str = "segment",
                 x0: np.ndarray | None = None, y0: np.ndarray | None = None,
                 node_representative: np.ndarray | None = None):
        self.name = name
        slave = np.asarray(slave, dtype=np.int64)
        guide = np.asarray(guide, dtype=np.int64)
        slave_cells = np.asarray(slave_cells, dtype=np.int64)
        self.periodic = bool(periodic)
        self.slave_side = slave                      # full side, for the nodal surfaces
        self.slave = slave[:-1].copy() if periodic else slave.copy()
        self.guide = guide.copy()
        self.guide_cells = np.asarray(guide_cells, dtype=np.int64)
        rep = node_representative
        self.slave_imp = self.slave.copy() if rep is None else np.asarray(rep, np.int64)[self.slave]
        self.guide_imp = self.guide.copy() if rep is None else np.asarray(rep, np.int64)[self.guide]
        if periodic:    # the guide's last node is the periodic image of its first
            self.guide_imp[-1] = self.guide_imp[0]
        ns = self.slave.size
        before = np.full(ns, -1, np.int64)
        after = np.full(ns, -1, np.int64)
        before[1:] = slave_cells[:ns - 1]
        after[:] = slave_cells[:ns] if slave_cells.size >= ns else np.append(slave_cells, -1)
        if periodic:
            before[0] = slave_cells[-1]
        self.slave_cell_before = before
        self.slave_cell_after = after
        self.normal_sign = float(normal_sign)
        self.law = int(law)
        self.law_params = np.zeros(4) if law_params is None else np.asarray(law_params, dtype=np.float64)
        self.bilateral = bool(bilateral)
        self.heat_share_slave = heat_share_slave
        self.axisymmetric = bool(axisymmetric)
        self.radius_axis = int(radius_axis)
        if guide_share not in ("segment", "point"):
            raise ValueError(f"guide_share must be 'segment' or 'point', not {guide_share!r}")
        self.guide_share = guide_share
        self.max_sweeps = int(max_sweeps)
        self.rel_tol = float(rel_tol)
        self.record_interval = float(record_interval)
        if x0 is not None and y0 is not None:
            seg_len = np.hypot(np.diff(x0[guide]), np.diff(y0[guide]))
            h = 0.5 * float(seg_len.min())
        else:
            h = math.inf
        self.max_gap = h if max_gap is None else float(max_gap)
        self.max_penetration = h if max_penetration is None else float(max_penetration)
        # per-node work arrays
        self.seg = np.full(ns, -1, np.int64)
        self.coef = np.zeros(ns)
        self.nx = np.zeros(ns)
        self.ny = np.zeros(ns)
        self.tx = np.zeros(ns)
        self.ty = np.zeros(ns)
        self.gap = np.zeros(ns)
        self.gap_point = np.zeros(ns)
        self.active = np.zeros(ns, np.bool_)
        self.lam_n = np.zeros(ns)
        self.lam_t = np.zeros(ns)
        self.lam_p = np.zeros(ns)         # position "impulses" of the penetration projection (kg m)
        self.work_n = np.zeros(ns)
        self.work_t = np.zeros(ns)
        self.slip_free = np.zeros(ns)
        self.slip = np.zeros(ns)
        self.slip_law = np.zeros(ns)      # slip speed seen by a velocity-dependent law (its relaxed state)
        self.area = np.zeros(ns)
        self.xi_prev = np.zeros(ns)
        self.xi_node = np.zeros(ns)
        self.xi_next = np.zeros(ns)
        self.gnode = np.zeros((ns, 2), np.int64)
        self.gw = np.zeros((ns, 2))
        # running sums
        self.cum_slip = np.zeros(ns)
        self.cum_work = np.zeros(ns)
        self.total_friction_work = 0.0
        self.total_contact_loss = 0.0     # the normal impulses' work (J, >= 0 dissipated)
        self.total_contact_heat = 0.0     # what of it went into the cells (J)
        self.step_contact_loss = 0.0
        self.step_contact_heat = 0.0
        self._guide_local = None          # node -> its index along the guide (-1 off it), for the contact heat
        self._win_lam_n = np.zeros(ns)
        self._win_lam_t = np.zeros(ns)
        self._win_slip = np.zeros(ns)
        self._win_time = 0.0
        self._next_record = self.record_interval if math.isfinite(self.record_interval) else 0.0
        self.record = InterfaceRecord(name, self.slave.copy())
        self.sweeps_normal = 0
        self.sweeps_tangential = 0
        # optional friction model taking over the tangential step (sub-grid columns, shockfriction.coupled)
        self.friction_model = None
        # the guide's segments in runs of ~sqrt(N) for the local search (pairing.guide_chunk_boxes)
        nseg = max(self.guide.size - 1, 1)
        self.search_chunk = max(4, int(round(math.sqrt(nseg))))
        ng = self.guide.size
        # per-cycle scratch (a tuple: not part of a checkpoint): gx, gy, xs, ys, chunk boxes, xbar, ybar,
        # heat weights, slave and guide yield stresses
        self._scratch = (np.zeros(ng), np.zeros(ng), np.zeros(ns), np.zeros(ns),
                         np.zeros((-(-nseg // self.search_chunk), 4)), np.zeros(ns), np.zeros(ns), np.zeros(ns),
                         np.zeros(ns), np.zeros(ns))

    # ------------------------------------------------------------------ geometry
    def geometry(self, x, y, parallel: bool = False) -> None:
        """This cycle's pairing, nodal surfaces, gaps and projection weights (``seg``, ``coef``, normals,
        ``gap``, ``gap_point``, ``area``, ``gnode``, ``gw``) at the positions ``x, y``.  ``parallel``: over the
        slave nodes in parallel when there are :data:`PARALLEL_MIN_NODES` or more (the same bytes)."""
        gx, gy, xs, ys, box, xbar, ybar = self._scratch[:7]
        hat = self.guide_share == "segment"
        parallel = parallel and self.slave.size >= PARALLEL_MIN_NODES
        geometry = contact_geometry_parallel if parallel else contact_geometry
        width = geometry(x, y, self.slave, self.slave_side, self.guide, self.periodic, self.axisymmetric,
                                 self.radius_axis, self.normal_sign, self.max_gap, self.max_penetration, hat,
                                 self.search_chunk, box, gx, gy, xs, ys, self.seg, self.coef, self.nx, self.ny,
                                 self.tx, self.ty, self.gap, self.gap_point, self.active, self.area, self.xi_prev,
                                 self.xi_node, self.xi_next)
        ns = self.slave.size
        if self.gnode.shape[1] != width:
            self.gnode = np.zeros((ns, width), np.int64)
            self.gw = np.zeros((ns, width))
        if not hat:
            point_weights(self.guide_imp, self.seg, self.coef, self.active, self.gnode, self.gw)
            return
        gr = (gx if self.radius_axis == 0 else gy) if self.axisymmetric else np.ones_like(gx)
        weights = hat_weights_parallel if parallel else hat_weights
        weights(self.xi_prev, self.xi_node, self.xi_next, self.seg, self.coef, self.active, gx, gy, gr,
                self.guide_imp, self.periodic, self.gnode, self.gw, xbar, ybar)
        # the gap consistent with the averaged guide velocity (equal to the point gap on a flat guide); the
        # projection removes a penetration that both gaps see (the averaged gap of the velocity step differs
        # from the point gap at guide kinks: pushing either alone out pumps energy)
        projection_gap(xs, ys, xbar, ybar, self.nx, self.ny, self.active, self.gap, self.gap_point)

    def nodal_areas(self, x, y) -> np.ndarray:
        area = slave_nodal_areas(x, y, self.slave_side, self.axisymmetric, self.radius_axis)
        if self.periodic:
            area = area[:-1].copy()
            area[0] += slave_nodal_areas(x, y, self.slave_side, self.axisymmetric, self.radius_axis)[-1]
        return area

    # ------------------------------------------------------------------ one cycle
    def apply(self, x, y, vx, vy, mass, dt: float, t: float, *, dt_position: float | None = None,
              vx_old=None, vy_old=None, cell_yield=None, cell_mass=None, cell_energy=None,
              shift_x=None, shift_y=None, deferred: bool = False, parallel: bool = False) -> float:
        """Correct the free velocities ``vx, vy`` in place; return the friction work of this step (J).

        ``dt`` is the velocity step (impulse = force dt) and ``dt_position`` the step that takes
        the positions from t^n to t^{n+1} (default ``dt``; the gap closes over it).
        ``x, y`` are the positions at t^n, ``mass`` the nodal (group) masses; ``vx_old, vy_old``
        the velocities at t^{n-1/2}, for the friction work -P_t (s^{n-1/2} + s^{n+1/2})/2 (without
        them the free velocities stand in, and the work is the kinetic energy the correction
        removes from the free state); ``cell_yield`` (Pa) is
        needed by the Tresca laws; ``cell_mass`` and ``cell_energy`` (specific internal energy,
        J/kg, updated in place) by the heat deposits: the friction heat (with ``heat_share_slave``)
        and always the normal impulses' inelastic loss (``step_contact_heat``; without the cell
        arrays that loss leaves the books).  ``shift_x, shift_y`` (node arrays, m):
        the penetration projection adds its position shifts there (the caller moves x^n by
        them); without them a penetration is only held, not removed.  ``deferred``: stop after the
        corrections and return 0; the caller calls :meth:`finish_step` once every interface of the
        step has corrected the velocities (the works of the impulses are then those of the final
        v^{n+1/2}: a node that two slide lines share is counted right, and the lines' works sum to
        the kinetic energy the corrections took).  ``parallel``: the geometry over the slave nodes in parallel
        (:meth:`geometry`; the same bytes).
        """
        dt_pos = dt if dt_position is None else float(dt_position)
        if vx_old is None or vy_old is None:
            vx_old, vy_old = vx.copy(), vy.copy()
        self.geometry(x, y, parallel)
        self.sweeps_normal = normal_step(vx, vy, mass, self.slave_imp, self.gnode, self.gw, self.nx,
                                         self.ny, self.gap, self.active, dt_pos, self.bilateral, self.max_sweeps,
                                         self.rel_tol, self.lam_n)
        w_heat, y_slave, y_guide = self._scratch[7:]
        if self.friction_model is not None:
            self.sweeps_tangential = self.friction_model.tangential(self, vx, vy, vx_old, vy_old, mass, dt, t)
        elif cell_yield is not None:
            heat_weights_kernel(x, y, self.slave_side, self.periodic, w_heat)
            side_yield_stress(cell_yield, self.slave_cell_before, self.slave_cell_after, w_heat, self.seg,
                              self.guide_cells, y_slave, y_guide)
        else:
            y_slave[:] = np.inf
            y_guide[:] = np.inf
        if self.friction_model is None:
            self.sweeps_tangential = tangential_step(
                vx, vy, mass, self.slave_imp, self.gnode, self.gw, self.tx, self.ty, self.active, dt,
                self.area, self.law, self.law_params, y_slave, y_guide, self.lam_n, self.max_sweeps, self.rel_tol,
                self.lam_t, self.slip_free, self.slip, self.slip_law)
        if shift_x is not None and shift_y is not None:
            penetration_projection(vx, vy, mass, self.slave_imp, self.gnode, self.gw, self.nx, self.ny, self.gap_point,
                                   self.active, dt_pos, self.max_sweeps, self.rel_tol, shift_x, shift_y,
                                   self.lam_p)
        if deferred:
            return 0.0
        return self.finish_step(x, y, vx, vy, vx_old, vy_old, mass, dt, dt_pos, cell_mass, cell_energy)

    def finish_step(self, x, y, vx, vy, vx_old, vy_old, mass, dt: float, dt_position: float, cell_mass=None,
                    cell_energy=None) -> float:
        """The step's works, heats and running sums after the corrections (``vx, vy``: v^{n+1/2}, ``vx_old,
        vy_old``: v^{n-1/2}, ``x, y``: x^n): the impulses' work -P (w^{n-1/2} + w^{n+1/2})/2, the friction heat
        (with ``heat_share_slave``) and the normal impulses' inelastic loss into the cells (with the cell
        arrays), the records' window sums.  Returns the friction work of the step (J)."""
        impulse_work(vx, vy, vx_old, vy_old, self.slave_imp, self.gnode, self.gw, self.nx, self.ny,
                     self.active, self.lam_n, self.work_n)
        impulse_work(vx, vy, vx_old, vy_old, self.slave_imp, self.gnode, self.gw, self.tx, self.ty,
                     self.active, self.lam_t, self.work_t)
        w_heat = self._scratch[7]
        self.step_contact_heat = 0.0
        if cell_energy is not None and cell_mass is not None:
            heat_weights_kernel(x, y, self.slave_side, self.periodic, w_heat)
            if self.heat_share_slave is not None:
                deposit_friction_heat(self.work_t, self.active, self.seg, float(self.heat_share_slave),
                                      self.slave_cell_before, self.slave_cell_after, w_heat,
                                      self.guide_cells, cell_mass, cell_energy)
            # the contact's inelastic loss is heat in the contacting cells, whatever the friction heat does
            if self._guide_local is None or self._guide_local.size != mass.size:
                local = np.full(mass.size, -1, np.int64)
                local[self.guide_imp[::-1]] = np.arange(self.guide_imp.size)[::-1]   # the first index of a node
                self._guide_local = local
            self.step_contact_heat = deposit_contact_heat(
                self.work_n, self.active, self.slave_imp, self.gnode, self.gw, mass, self.slave_cell_before,
                self.slave_cell_after, w_heat, self._guide_local, self.guide_cells, self.periodic, cell_mass,
                cell_energy)
        step_work = float(self.work_t.sum())
        self.step_contact_loss = float(self.work_n.sum())
        self.total_friction_work += step_work
        self.total_contact_loss += self.step_contact_loss
        self.total_contact_heat += self.step_contact_heat
        accumulate_step(self.work_t, self.slip, self.lam_n, self.lam_t, dt_position, self.cum_work, self.cum_slip,
                        self._win_lam_n, self._win_lam_t, self._win_slip)
        self._win_time += dt
        return step_work

    def record_due(self, t_end: float, force: bool = False) -> bool:
        """True when :meth:`maybe_record` would close the window at ``t_end``."""
        return self._win_time > 0.0 and (force or t_end >= self._next_record * (1 - 1e-12))

    def maybe_record(self, t_end: float, x_new, y_new, force: bool = False) -> bool:
        """Close the record window if ``t_end`` reached the next record time (or ``force``)."""
        if not self.record_due(t_end, force):
            return False
        rec = self.record
        denom = self.area * self._win_time
        safe = np.where(denom > 0.0, denom, 1.0)
        rec.t.append(t_end)
        rec.x.append(x_new[self.slave].copy())
        rec.y.append(y_new[self.slave].copy())
        rec.sigma_n.append(np.where(denom > 0.0, self._win_lam_n / safe, 0.0))
        rec.tau.append(np.where(denom > 0.0, self._win_lam_t / safe, 0.0))
        rec.slip.append(self._win_slip / self._win_time)
        rec.cum_slip.append(self.cum_slip.copy())
        rec.work.append(self.cum_work.copy())
        rec.active.append(self.active.copy())
        if self.friction_model is not None:
            self.friction_model.on_record(t_end, self.total_friction_work)
        self._win_lam_n[:] = 0.0
        self._win_lam_t[:] = 0.0
        self._win_slip[:] = 0.0
        self._win_time = 0.0
        while self._next_record <= t_end * (1 + 1e-12):
            self._next_record += self.record_interval if math.isfinite(self.record_interval) else math.inf
            if not math.isfinite(self._next_record):
                break
        return True
