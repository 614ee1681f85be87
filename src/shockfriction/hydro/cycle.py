"""The explicit Lagrangian cycle (thesis Fig. 3.7) and its interface hook.

One call of :meth:`Simulation.step` advances t^n -> t^{n+1}:

1. nodal forces F^n from sigma^n at x^n (+ hourglass, edge and shear viscosity on v^{n-1/2}),
   one pass over the cells (:func:`~shockfriction.hydro.kernels.cell_forces_serial`);
2. node groups (ties, periodic sides) share their summed force;
3. free velocities v* = v^{n-1/2} + dt^n F/m, boundary constraints applied;
4. **interface hook**: every registered interface object's
   ``apply(state, dt, t, cycle)`` is called in registration order, with
   ``dt = state.dt_velocity`` (dt^n, the step of the impulses) and ``t = t^n``;
   ``state.dt`` is the coming position step dt^{n+1/2}.  It corrects
   ``state.vx, state.vy`` by impulses (a node of a group: change it by J/mass,
   ``state.mass`` is the group mass), may add heat to cells' ``state.e`` (and then
   adds the same amount, J per unit depth or per radian, to
   ``state.energy.interface_heat``) and may report its terms (``friction_work``,
   ``friction_heat``, ``contact_work``, ``contact_heat``, ``column_heat`` of
   ``state.energy``).  The cycle measures the work of the
   corrections (``state.energy.interface_work``), re-synchronises node groups
   and re-applies the boundary constraints.  An interface may also add position
   shifts to ``state.shift_x, shift_y`` (penetration projections, mass-weighted so
   that sum m dx = 0); the cycle syncs them over node groups, removes their
   constrained components and moves x^n by them, energy-neutrally: the cells they
   touch take their volume at the shifted x^n as V^n (the shift does no p dV work;
   e is kept), and -sum F.dx, what it would have made, is booked as
   ``state.energy.projection_work`` for the record (not in the balance).  An interface that names the nodes
   it may shift (``shifted_nodes``, an array of node indices) lets the cycle pass over those nodes and their
   cells only;
5. positions x^{n+1} = x^n + dt^{n+1/2} v^{n+1/2};
6. cells: the viscous forces' heat of step 3-4, density, strain rate, stress, viscosity,
   energy, EOS, temperature and the next stable time step, one call
   (:func:`~shockfriction.hydro.kernels.update_cells_serial`).  On a cycle whose history row
   has probes of a cell or observers the viscous heat goes into the cells before the row instead
   (they see it at t^n; probes of nodes are read before the update); the state is the same either
   way.  The energy sums are taken only for a row (docs/theory/fused-cycle.md).

On one thread, without interfaces and when the row (if any) has no probes or observers, steps 1-6
are one call (:func:`~shockfriction.hydro.kernels.cycle_serial`: the same operations in the same order, steps
3 and 5 in one pass over the nodes; on a mesh of ``WAVE_MIN_CELLS`` cells or more, a wavefront: the forces of a
few hundred cells, the nodes they complete, the update blocks whose nodes have moved, and again).

Histories are taken at t^n with node velocities (v^{n-1/2} + v^{n+1/2})/2 and the
leapfrog kinetic energy sum m v^{n-1/2}.v^{n+1/2}/2 (docs/theory/hydrocode.md, sec. 5).
"""

from __future__ import annotations

import math
import time as _time
from typing import Callable, Protocol

import numpy as np

from shockfriction import threading_policy
from shockfriction.errors import SimulationError
from shockfriction.hydro import kernels as K
from shockfriction.hydro.guards import RunGuards
from shockfriction.hydro.partition import make_partition, partition_count
from shockfriction.hydro.setup import Problem


class Interface(Protocol):
    """What the cycle calls between the free velocities and the position update."""

    def apply(self, state, dt: float, t: float, cycle: int) -> None: ...


# the staged cycle's node passes run in parallel from this many nodes (Simulation.passes_parallel).  0: always, on
# the parallel path.  On the 16-core device machine the cone shot (32 k nodes) ran 1.44 s with its passes serial
# (from 131 072 nodes) and 0.89 s with them parallel on 16 threads, 1.28 / 0.86 s on 8 (docs/theory/threads.md)
STAGED_PARALLEL_NODES = 0
# ... and from this many threads (with the slide lines' geometry, contact/build.py).  With passive waiting 4: on the
# 2-core machine waking the worker for each pass of 32 k nodes cost more than the pass; with the short spin
# (threading_policy.SPIN_ROUNDS) the passes pay from 2 threads: the 1 us cone shot x1.46-1.49 (Coulomb) and x1.38
# (thermoelastoplastic) on 2 threads with them parallel, x1.33-1.36 and x1.22 serial (docs/theory/threads.md,
# "A short spin")
STAGED_PARALLEL_THREADS = 2

ENERGY_COLUMNS = ("t_s", "kinetic", "internal", "total", "boundary_work", "interface_work", "interface_heat",
                  "friction_work", "friction_heat", "column_heat", "contact_work", "contact_heat", "projection_work",
                  "error")


def _wavefront(conn: np.ndarray, n_nodes: int, grouped: bool,
               wave: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """For the one-thread cycle's wavefront (:func:`~shockfriction.hydro.kernels.cycle_serial`, steps of
    ``wave`` cells): node_wait[n], the last cell touching any of nodes 0 .. n (-1 for none); cell_wait[c], the
    last node of any of cells 0 .. c; zero_wait[n], the first cell touching any of nodes n, n + 1 ... (the number
    of cells for none); and the rows of the ring that holds the viscous corner forces from the force pass to the
    update: the most cells between an update block's first cell and the force front when that block is updated,
    in whole update blocks (one row per cell when that is as many, or with node groups, whose nodes wait for
    every force)."""
    nc = conn.shape[0]
    nodes = conn.reshape(-1)
    cells = np.repeat(np.arange(nc, dtype=np.int64), conn.shape[1])
    last_cell = np.full(n_nodes, -1, dtype=np.int64)
    np.maximum.at(last_cell, nodes, cells)
    node_wait = np.maximum.accumulate(last_cell)
    first_cell = np.full(n_nodes, nc, dtype=np.int64)
    np.minimum.at(first_cell, nodes, cells)
    zero_wait = np.minimum.accumulate(first_cell[::-1])[::-1].copy()
    cell_wait = np.maximum.accumulate(conn.max(axis=1)).astype(np.int64)
    ub = K.UPDATE_BLOCK
    rows = nc
    if nc and not grouped:
        first = np.arange(0, nc, ub)
        last_node = cell_wait[np.minimum(first + ub, nc) - 1]
        front = np.minimum(nc, (node_wait[last_node] // wave + 1) * wave)  # forces done when the block goes
        rows = int(-(-int(np.max(front - first)) // ub) * ub)
        if rows >= nc:
            rows = nc
    return node_wait, cell_wait, zero_wait, rows


class Simulation:
    """A problem in time: state, numerics, interfaces and histories."""

    def __init__(self, problem: Problem, interfaces=None, threads: int | None = None):
        self.problem = problem
        self.mesh = problem.mesh
        self.state = problem.state
        self.interfaces: list[Interface] = []
        self._after_step: list = []
        self._after_interfaces: list = []
        # interfaces built for this simulation may leave their works and heats to after_interfaces
        self.calls_after_interfaces = True
        self.out_dir = None
        deck = problem.deck
        self.t_end = deck.time.end
        self.cfl = deck.time.cfl
        self.dvmax = deck.time.max_volume_change
        self.dt_growth = deck.time.dt_growth
        self.dt_max = deck.time.dt_max or math.inf
        self.max_cycles = deck.time.max_cycles
        self.cq = deck.viscosity.quadratic
        self.cl = deck.viscosity.linear
        self.hg = deck.viscosity.hourglass
        self.qedge = deck.viscosity.kind == "edge"
        visc = deck.viscosity
        self.shear_visc = (visc.shear != "off" and (visc.shear_linear > 0.0 or visc.shear_quadratic > 0.0))
        self.shear_visc_args = (visc.shear_linear, visc.shear_quadratic, visc.shear == "elastic")
        threads = deck.threads if threads is None else threads
        self.threads = threading_policy.effective_threads(threads, self.state.n_cells)
        self.parallel = self.threads > 1
        s = self.state
        nn, nc = s.n_nodes, s.n_cells
        self._x_half = np.empty(nn)
        self._y_half = np.empty(nn)
        self._vx_old = np.empty(nn)
        self._vy_old = np.empty(nn)
        self._vx_free = np.empty(nn)
        self._vy_free = np.empty(nn)
        self._vx_pre = np.empty(nn)
        self._vy_pre = np.empty(nn)
        # velocity jumps of constraints and interfaces in the previous step (energy budget)
        self._jx_bc_prev, self._jy_bc_prev = np.zeros(nn), np.zeros(nn)
        self._jx_int_prev, self._jy_int_prev = np.zeros(nn), np.zeros(nn)
        self._int_active = False
        self._heat_in_update = False  # the viscous heat of this step still to be put in by the cell update
        self._pending_row = None  # (ke, ie, heat, budget, probe values) of a history row waiting for that heat
        self._all_nodes = np.arange(nn, dtype=np.int64)
        self._bc_nodes = np.unique(problem.constraints.node).astype(np.int64)
        self._finished = False
        self._vcorner = np.zeros((nc, 8))
        self._dtcell = np.empty(nc)
        # the chunk sums of the history sums (internal energy, kinetic energy, viscous heat; kernels.SUM_CHUNK)
        self._sums = np.zeros((3, (max(nc, nn) + K.SUM_CHUNK - 1) // K.SUM_CHUNK + 1))
        # per-cell values handed between the cell update's loops (in a tuple: scratch that no checkpoint keeps;
        # the serial update goes over blocks of K.UPDATE_BLOCK cells: one block's worth), the per-material
        # reciprocals that the update computes first and the chunk sums of its viscous heat
        width = max(1, min(nc, K.UPDATE_BLOCK))
        self._scratch = (np.empty((11, width)), np.empty((s.props.shape[0], K.N_MREC)), self._sums[2])
        self._errcell = np.zeros(nc, dtype=np.int64)
        # the force pass's scratch (in a tuple: no checkpoint keeps it): the serial kernel's block scratch, and the
        # parallel kernels' partition of the mesh (hydro/partition.py, up to 4 partitions per thread) with a
        # scratch per partition: force blocks, update blocks and reciprocals, the border nodes' corner forces, each
        # partition's step and bad cell (a parallel run also keeps the serial scratch: its governor runs the serial
        # kernels when one thread is faster)
        self._force_scratch = (np.zeros(K.FORCE_SCRATCH), None)
        # numba's thread count also sets the sub-grid columns' (their kernels choose by it): one thread means one
        threading_policy.use_threads(self.threads if self.parallel else 1)
        if self.parallel:
            part = make_partition(s.conn, nn, partition_count(self.threads, nc))
            npart = part.parts
            self.partition = part
            self._force_scratch = (self._force_scratch[0], (
                np.zeros((npart, K.FORCE_SCRATCH)), part.arrays(), np.zeros((nc, 8)), (part.bnodes, part.bptr,
                                                                                       part.bcorn)))
            self._par_update = (np.empty((npart, 11 * K.UPDATE_BLOCK)), np.empty((npart, s.props.shape[0], K.N_MREC)),
                                self._sums[2], part.cbounds, np.empty(npart), np.empty((npart, 2), dtype=np.int64))
        c = problem.constraints
        self._cons = (c.node, c.nx, c.ny, c.value)
        # the constraints of each constrained node (bc_nodes ascending), in list order: for the node pass
        order = np.argsort(c.node, kind="stable").astype(np.int64)
        self._bc_ptr = np.searchsorted(c.node[order], np.append(self._bc_nodes, nn)).astype(np.int64)
        self._bc_cons = order
        self._cons_fixed = (c.node, c.nx, c.ny, np.zeros_like(c.value))   # for position shifts
        # position shifts' scratch (a tuple: no checkpoint keeps it): the nodes they move, zeros (never written)
        self._shift_scratch = (np.zeros(nn, np.bool_), np.zeros(nn))
        self._shift_lists = None   # _shifted_lists' answer, once built
        # kernels.jump_works' chunk sums (interface work, boundary work); a tuple: no checkpoint keeps it
        self._jump_parts = (np.zeros((2, (nn + K.SUM_CHUNK - 1) // K.SUM_CHUNK)),)
        self._grp = (problem.groups.ptr, problem.groups.nodes)
        # the one-thread cycle's wavefront (steps of `wave` cells; one step of all cells on a smaller mesh):
        # (node_wait, cell_wait, zero_wait, wave) and its ring of viscous corner forces (in tuples: scratch that
        # no checkpoint keeps)
        wave = K.WAVE_CELLS if nc >= K.WAVE_MIN_CELLS else max(nc, 1)
        node_wait, cell_wait, zero_wait, rows = _wavefront(s.conn, nn, problem.groups.ptr.shape[0] > 1, wave)
        self._waits = (node_wait, cell_wait, zero_wait, wave)
        self._vring = (self._vcorner if rows == nc else np.zeros((rows, 8)),)
        s.dt = self._first_time_step()
        self._dt_prev = 0.0  # leapfrog start: v^{-1/2} = v^0 and a half velocity step
        s.energy.initial = K.kinetic_energy(s.vx, s.vy, s.mass_own) + K.internal_energy(s.e, s.e_el, s.cell_mass)
        self.energy_rows: list[tuple] = []
        self.probe_rows: list[tuple] = []
        self.probe_columns = [f"{p.name}.{q}" for p in problem.probes for q in p.quantities]
        self.probe_every = deck.output.probe_every
        self._getters = [self._probe_getter(q, p.index) for p in problem.probes for q in p.quantities]
        # every probe a node's (velocity, position): read at t^n before the cell update, which does not touch them
        self._probes_on_nodes = all(p.kind == "node" for p in problem.probes)
        self.observers: list[Callable[["Simulation"], None]] = []
        # called by run() between cycles (state at t^n, nothing half-updated): output writers, checkpoints
        self.between_cycles: list[Callable[["Simulation"], None]] = []
        if self.parallel:  # the parallel kernels or the serial ones, whichever runs faster under the machine's load
            self.between_cycles.append(threading_policy.ThreadGovernor(self.threads))
        self.wall_time = 0.0
        self.guards = RunGuards(self)
        for obj in interfaces or []:
            self.register_interface(obj)

    def use_parallel(self, parallel: bool) -> None:
        """Between cycles: the parallel kernels (a run set up with threads > 1 only) or the serial
        ones.  Both give the same bytes (sums in cell and node order), so only the speed changes."""
        if parallel and self._force_scratch[1] is None:
            raise RuntimeError("this simulation was set up for one thread")
        self.parallel = bool(parallel)

    @property
    def _corner(self) -> np.ndarray:
        """The serial force pass's block scratch."""
        return self._force_scratch[0]

    def _partition_args(self) -> tuple:
        """The parallel force pass's arguments after the internal-energy flag: the partition and its scratch."""
        blocks, (cb, pptr, pnodes, border), bcorner, (bnodes, bptr, bcorn) = self._force_scratch[1]
        return cb, pptr, pnodes, border, bcorner, bnodes, bptr, bcorn, self._sums[0]

    def reinitialize(self) -> None:
        """After editing the initial state by hand at t = 0 (``state.e``, ``vx``, ``vy``, the
        deviators ...): recompute pressure, temperature, moduli, flow stress and sound speed from
        (rho, e), the first time step and the initial energy."""
        s = self.state
        if s.cycle != 0:
            raise RuntimeError("reinitialize() is for the initial state (cycle 0)")
        K.initial_cell_state(s.mat, s.props, s.isentrope, s.rho, s.e, s.pressure, s.temperature, s.shear_modulus,
                             s.yield_stress, s.sound_speed, s.eps_p)
        s.dt = self._first_time_step()
        s.energy.initial = K.kinetic_energy(s.vx, s.vy, s.mass_own) + K.internal_energy(s.e, s.e_el, s.cell_mass)

    def _first_time_step(self) -> float:
        """First step from the sound speed and from the volume change that the initial velocities
        make once the boundary constraints act on them (a cold gas driven onto a wall, Noh)."""
        s, deck = self.state, self.problem.deck
        vx, vy = s.vx.copy(), s.vy.copy()
        K.apply_constraints(vx, vy, s.vx, s.vy, s.mass_own, *self._cons, 0.0)
        dt0 = K.initial_time_step(s.conn, s.x, s.y, vx, vy, s.sound_speed, self.cfl, self.dvmax, s.axisymmetric)
        if deck.time.dt_initial is not None:
            dt0 = min(dt0, deck.time.dt_initial)
        return min(dt0, self.dt_max, self.t_end)

    # ------------------------------------------------------------------ hooks
    def register_interface(self, obj: Interface) -> None:
        """Add an interface (slide line, driver) called every cycle after the free velocities.

        Optional methods of the object: ``after_interfaces(state, dt, t, cycle)`` is called once every
        interface of the step has corrected the velocities (node groups synced, before the position
        shifts: the works of the impulses on the final v^{n+1/2}); ``after_step(state, dt, t, cycle)``
        is called at the end of each cycle (positions and cells at t^{n+1} = t, dt the step just done), ``close()``
        when the run ends (also on failure); ``simulation.out_dir`` is the output folder of the
        run (None without one), for interface histories.  Optional attribute ``shifted_nodes``: every node
        whose position shift (``state.shift_x, shift_y``) the object may make non-zero (the cycle then moves
        those nodes only: :meth:`_shifted_lists`)."""
        self.interfaces.append(obj)
        self._shift_lists = None  # the nodes that position shifts may move: built again on first use
        if hasattr(obj, "after_step"):
            self._after_step.append(obj)
        if hasattr(obj, "after_interfaces"):
            self._after_interfaces.append(obj)

    def _fail(self, cell: int, code: int) -> None:
        s = self.state
        name, i, j = self.mesh.cell_ij(cell)
        where = f"cell ({i}, {j})" if j >= 0 else f"file cell {i}"
        raise SimulationError(
            f"body {name!r}, {where} [global cell {cell}]: {K.ERR_MESSAGES.get(code, 'error')} "
            f"at cycle {s.cycle}, t = {s.t:.6e} s (dt = {s.dt:.3e} s)")

    def _forces(self, want_ie: bool, sum_border: bool = True) -> float:
        """Nodal forces F^n into state.fx, fy (viscous corner forces kept for their heat) in one
        pass over the cells (+ a gather over the nodes when parallel); returns the internal
        energy at t^n if ``want_ie`` (else 0).  ``sum_border`` False (parallel kernels): the border nodes' forces
        are left to :func:`~shockfriction.hydro.kernels.border_velocities_parallel`."""
        s = self.state
        args = (s.conn, s.x, s.y, s.vx, s.vy, s.sxx, s.syy, s.sxy, s.pressure, s.q, s.rho, s.sound_speed,
                s.shear_modulus, s.yield_stress, s.axisymmetric, self.hg, self.qedge, self.cq, self.cl,
                self.shear_visc, *self.shear_visc_args)
        if self.parallel:  # the same sums as the serial pass, whatever the thread count (kernels, "Sums")
            return K.forces_parallel(*args, self._force_scratch[1][0], self._vcorner, s.fx, s.fy, s.e, s.e_el,
                                     s.cell_mass, want_ie, *self._partition_args(), sum_border)
        return K.cell_forces_serial(*args, self._corner, self._vcorner, s.fx, s.fy, s.e, s.e_el, s.cell_mass,
                                    want_ie)

    # ------------------------------------------------------------------ one cycle
    def step(self) -> None:
        """Advance t^n -> t^{n+1} (steps 1-6 of the module docstring)."""
        if self._finished:
            raise RuntimeError("this simulation has finished (its velocities are at the final time)")
        dt = self.state.dt
        if not dt > 0.0:  # t = t_end: the last step set dt to what remained, 0 (a slide line would divide by it)
            raise RuntimeError(f"this simulation is at its end time t = {self.state.t:.6g} s (deck time.end): "
                               "nothing left to step")
        if self.interfaces or self._int_active or (
                (self._getters or self.observers) and self.state.cycle % self.probe_every == 0):
            self._velocity_stage(final=False)
            self._advance_stage()
        else:
            self._fused_step()
        for obj in self._after_step:
            obj.after_step(self.state, dt, self.state.t, self.state.cycle)

    @property
    def passes_parallel(self) -> bool:
        """The staged cycle's (interfaces, probes) node passes between the force pass and the cell update (free
        velocities, the jumps' works, position shifts, kinetic energy, viscous heat, positions) and the slide lines'
        geometry in parallel: with the parallel kernels on :data:`STAGED_PARALLEL_THREADS` threads or more and a
        mesh of :data:`STAGED_PARALLEL_NODES` nodes or more (0: any).  The serial and parallel passes give the same
        bytes."""
        return (self.parallel and self.threads >= STAGED_PARALLEL_THREADS
                and self.state.n_nodes >= STAGED_PARALLEL_NODES)

    @property
    def _plain_serial(self) -> bool:
        """One thread and no interfaces this step or the last: steps 1-3 run as one call."""
        return not (self.parallel or self.interfaces or self._int_active)

    def _velocity_stage(self, final: bool) -> None:
        """Steps 1-4 and the histories at t^n.  ``final``: the row at the end time, with a virtual
        next step as long as the last one (the velocities end half a step past t_end)."""
        s = self.state
        if final:
            s.dt = self._dt_prev
        dt = s.dt
        dtv = 0.5 * (self._dt_prev + dt)
        s.dt_velocity = dtv
        record = final or s.cycle % self.probe_every == 0
        en = s.energy
        ke = None
        heats_before = (en.friction_heat, en.contact_heat)
        if self._plain_serial:
            # 1-3 in one call (one thread, no interfaces this step or the last)
            q_before = en.interface_heat
            ie, wbc, ke = K.velocities_serial(
                s.conn, s.x, s.y, s.vx, s.vy, s.sxx, s.syy, s.sxy, s.pressure, s.q, s.rho, s.sound_speed,
                s.shear_modulus, s.yield_stress, s.axisymmetric, self.hg, self.qedge, self.cq, self.cl,
                self.shear_visc, *self.shear_visc_args, self._corner, self._vcorner, s.fx, s.fy, s.e, s.e_el,
                s.cell_mass, record, *self._grp, s.mass, dtv, self._vx_old, self._vy_old, self._vx_pre, self._vy_pre,
                s.mass_own, *self._cons, self._bc_nodes, self._jx_bc_prev, self._jy_bc_prev)
            if self._cons[0].shape[0]:
                en.boundary_work += wbc
        else:
            # 1-2 forces (and the internal energy at t^n for the history row); 3 free velocities (v^{n-1/2} kept
            # in _vx_old, v* in _vx_pre): on the parallel path without node groups the border nodes' force sums
            # and the velocities in one parallel region (the same bytes)
            grouped = self._grp[0].shape[0] > 1
            fused = self.passes_parallel and not grouped
            ie = self._forces(record, not fused)
            if grouped:
                K.sum_groups(s.fx, s.fy, *self._grp)
            q_before = en.interface_heat
            if fused:
                _, _, bcorner, (bnodes, bptr, bcorn) = self._force_scratch[1]
                K.border_velocities_parallel(s.vx, s.vy, s.fx, s.fy, s.mass, dtv, self._vx_old, self._vy_old,
                                             self._vx_pre, self._vy_pre, True, bcorner, bnodes, bptr, bcorn,
                                             self._partition_args()[0].shape[0] - 1)
            else:
                advance = K.advance_velocities_parallel if self.passes_parallel else K.advance_velocities
                advance(s.vx, s.vy, s.fx, s.fy, s.mass, dtv, self._vx_old, self._vy_old, self._vx_pre,
                        self._vy_pre, True)
            # and the boundary constraints
            K.apply_constraints(s.vx, s.vy, self._vx_old, self._vy_old, s.mass_own, *self._cons, dtv)
            # 4 interfaces
            int_prev = self._int_active
            if self.interfaces:
                self._vx_free[:] = s.vx
                self._vy_free[:] = s.vy
                for obj in self.interfaces:
                    obj.apply(s, dtv, s.t, s.cycle)
                if self._grp[0].shape[0] > 1:
                    K.sync_groups(s.vx, s.vy, self._vx_free, self._vy_free, *self._grp)
                for obj in self._after_interfaces:
                    obj.after_interfaces(s, dtv, s.t, s.cycle)
                self._apply_position_shifts()
            joint = bool(self.interfaces) and self._cons[0].shape[0] > 0
            if joint:
                # the interfaces' jumps J = v - v_free, added to _vx_pre; the constraints; their jumps v - v_pre
                # over all nodes: the three steps below in one pass (jump_works: the same bytes)
                works = K.jump_works_parallel if self.passes_parallel else K.jump_works
                wi, wb = works(s.mass_own, self._vx_old, self._vy_old, s.vx, s.vy, self._vx_free, self._vy_free,
                               self._jx_int_prev, self._jy_int_prev, self._vx_pre, self._vy_pre, self._jx_bc_prev,
                               self._jy_bc_prev, *self._cons[1:], self._bc_nodes, self._bc_ptr, self._bc_cons,
                               self._jump_parts[0])
                en.interface_work += wi
                en.boundary_work += wb
            elif self.interfaces:
                # the interfaces' jumps J = v - v_free; added to _vx_pre (constraint impulses = what the
                # constraints changed)
                en.interface_work += self._impulse_work(
                    self._all_nodes, s.mass_own, self._vx_old, self._vy_old, s.vx, s.vy, self._vx_free,
                    self._vy_free, self._jx_int_prev, self._jy_int_prev, True, self._vx_pre, self._vy_pre)
                K.apply_constraints(s.vx, s.vy, self._vx_old, self._vy_old, s.mass_own, *self._cons, dtv)
            elif self._int_active:  # no jumps this step, the last step's still count
                en.interface_work += self._impulse_work(
                    self._all_nodes, s.mass_own, self._vx_old, self._vy_old, s.vx, s.vy, s.vx, s.vy,
                    self._jx_int_prev, self._jy_int_prev, False, self._vx_pre, self._vy_pre)
            self._int_active = bool(self.interfaces)
            if self._cons[0].shape[0] and not joint:
                # without interfaces (this step and the last) the jumps live on the constrained nodes only
                nodes = self._all_nodes if (self._int_active or int_prev) else self._bc_nodes
                en.boundary_work += self._impulse_work(
                    nodes, s.mass_own, self._vx_old, self._vy_old, s.vx, s.vy, self._vx_pre, self._vy_pre,
                    self._jx_bc_prev, self._jy_bc_prev, False, self._vx_pre, self._vy_pre)
        # heat of the hourglass / edge / shear viscosity forces over this velocity step: in the cell
        # update, unless the history row of this cycle has probes of a cell or observers, which must see it
        # in the cells at t^n: then here, before the row (a row without them, or whose probes are all of
        # nodes, read now, is completed after the update, which returns the heat)
        in_update = not record or not (final or self.observers or (self._getters and not self._probes_on_nodes))
        self._heat_in_update = in_update
        if not record:
            return
        # heat put into cells during this step counts half at t^n (it is centred there)
        q_int = 0.5 * (q_before + en.interface_heat)
        if ke is None:
            if self.passes_parallel:
                ke = K.kinetic_energy_product_parallel(self._vx_old, self._vy_old, s.vx, s.vy, s.mass_own,
                                                       self._sums[1])
            else:
                ke = K.kinetic_energy_product(self._vx_old, self._vy_old, s.vx, s.vy, s.mass_own)
        budget = (en.boundary_work, en.interface_work, q_int, *self._books(heats_before))
        if in_update:  # node probes are read now (the node pass moves x to x^{n+1} before the update)
            self._pending_row = (ke, ie, q_int - q_before, budget, [float(g()) for g in self._getters])
            return
        if self.passes_parallel:
            qv = K.viscous_heat_parallel(s.conn, self._vcorner, self._vx_old, self._vy_old, s.vx, s.vy, dtv,
                                         s.cell_mass, s.e, self._sums[2])
        else:
            qv = K.viscous_heat_serial(s.conn, self._vcorner, self._vx_old, self._vy_old, s.vx, s.vy, dtv,
                                       s.cell_mass, s.e)
        self._record(ke, ie + 0.5 * qv + (q_int - q_before), budget)

    def _fused_step(self) -> None:
        """Steps 1-6 in one call (:func:`~shockfriction.hydro.kernels.cycle_serial`): one thread, no
        interfaces (this step or the last), the viscous heat in the cell update (no history row with
        probes or observers this cycle).  The same kernels, in the same order, as
        :meth:`_velocity_stage` + :meth:`_advance_stage`, and the same energy book-keeping."""
        s = self.state
        dt = s.dt
        dtv = 0.5 * (self._dt_prev + dt)
        s.dt_velocity = dtv
        record = s.cycle % self.probe_every == 0
        self._heat_in_update = True
        if self.parallel:
            ie, wbc, ke, dtn, bad, code, qv = K.cycle_parallel(
                s.conn, s.x, s.y, s.vx, s.vy, s.sxx, s.syy, s.sxy, s.pressure, s.q, s.rho, s.sound_speed,
                s.shear_modulus, s.yield_stress, s.axisymmetric, self.hg, self.qedge, self.cq, self.cl,
                self.shear_visc, *self.shear_visc_args, self._force_scratch[1][0], self._vcorner, s.fx, s.fy, s.e,
                s.e_el, s.cell_mass, record, *self._grp, s.mass, dtv, self._vx_old, self._vy_old, self._vx_pre,
                self._vy_pre, s.mass_own, *self._cons[1:], self._bc_nodes, self._bc_ptr, self._bc_cons,
                self._jx_bc_prev, self._jy_bc_prev, dt, self._x_half, self._y_half, s.mat, s.props, s.isentrope,
                s.volume, s.eps_p, s.temperature, self._dtcell, self._errcell, self.cfl, self.dvmax, s.damage,
                *self._par_update[:2], self._sums, *self._partition_args()[:-1], *self._par_update[4:])
            self._after_fused(record, dt, dtn, bad, code, qv, ie, wbc, ke)
            return
        ie, wbc, ke, dtn, bad, code, qv = K.cycle_serial(
            s.conn, s.x, s.y, s.vx, s.vy, s.sxx, s.syy, s.sxy, s.pressure, s.q, s.rho, s.sound_speed,
            s.shear_modulus, s.yield_stress, s.axisymmetric, self.hg, self.qedge, self.cq, self.cl, self.shear_visc,
            *self.shear_visc_args, self._corner, self._vring[0], s.fx, s.fy, s.e, s.e_el, s.cell_mass, record,
            *self._grp, s.mass, dtv, self._vx_old, self._vy_old, self._vx_pre, self._vy_pre, s.mass_own,
            *self._cons[1:], self._bc_nodes, self._bc_ptr, self._bc_cons, self._jx_bc_prev, self._jy_bc_prev, dt,
            self._x_half, self._y_half, s.mat, s.props, s.isentrope, s.volume, s.eps_p, s.temperature, self._dtcell,
            self._errcell, self.cfl, self.dvmax, s.damage, *self._scratch, *self._waits)
        self._after_fused(record, dt, dtn, bad, code, qv, ie, wbc, ke)

    def _after_fused(self, record, dt, dtn, bad, code, qv, ie, wbc, ke) -> None:
        s = self.state
        en = s.energy
        if self._cons[0].shape[0]:
            en.boundary_work += wbc
        if record:  # the row at t^n, as _velocity_stage books it (no interface heat this step: q_int = q_before)
            budget = (en.boundary_work, en.interface_work, en.interface_heat,
                      *self._books((en.friction_heat, en.contact_heat)))
            self._pending_row = (ke, ie, 0.0, budget, None)   # (no probes on a one-call cycle's row)
        self._end_step(dt, dtn, bad, code, qv)

    def _impulse_work(self, nodes, *args) -> float:
        """:func:`~shockfriction.hydro.kernels.impulse_work`, in parallel over many nodes (the same sum)."""
        if self.passes_parallel and nodes.shape[0] > 4 * K.SUM_CHUNK:
            return K.impulse_work_parallel(nodes, *args, self._sums[1])
        return K.impulse_work(nodes, *args)

    def _apply_position_shifts(self) -> None:
        """Move x^n by the interfaces' position shifts (penetration projections): node groups
        share them, constrained directions keep none; energy-neutral (the touched cells' V^n is
        their volume at the shifted x^n); -sum F.dx, what the shift would have made, is booked as
        projection work (a measure, not in the balance)."""
        s = self.state
        sx, sy = s.shift_x, s.shift_y
        nodes, cells = self._shifted_lists()
        if not K.any_shifted(sx, sy, self._all_nodes if nodes is None else nodes):
            return
        moved, zero = self._shift_scratch
        if self._grp[0].shape[0] > 1:
            K.sync_groups(sx, sy, zero, zero, *self._grp)
        # (the reactions' work, computed from the "old" values passed here, is not wanted: zeros will do)
        K.apply_constraints(sx, sy, zero, zero, s.mass_own, *self._cons_fixed, 0.0)
        # a group's force is the group sum, given to each member: weight by mass_own/mass.  Moves x^n, zeroes the
        # shifts and marks the nodes moved (after the groups and constraints) in ``moved``; then, energy-neutral,
        # the cells touching a shifted node take their volume at the shifted x^n as V^n, so the cell update's
        # -p dV sees only the motion over the step, not the shift (e is kept across the shift).  Where every
        # interface names the nodes it may shift, over those nodes and their cells only (the same bytes)
        if nodes is not None:
            w = -K.shift_listed_nodes(s.x, s.y, sx, sy, s.fx, s.fy, s.mass_own, s.mass, nodes, moved)
            K.shifted_volumes(s.conn, moved, s.x, s.y, s.axisymmetric, s.volume, cells)
        else:
            shift = K.shift_nodes_parallel if self.passes_parallel else K.shift_nodes
            w = -shift(s.x, s.y, sx, sy, s.fx, s.fy, s.mass_own, s.mass, self._sums[1], moved)
            volumes = K.shifted_volumes_parallel if self.passes_parallel else K.shifted_volumes
            volumes(s.conn, moved, s.x, s.y, s.axisymmetric, s.volume, cells)
        s.energy.projection_work += w

    def _shifted_lists(self) -> tuple:
        """(the nodes whose position shift may be non-zero, ascending; the cells touching them) when every
        interface names the nodes it may shift (its ``shifted_nodes``), with the other members of their node
        groups (which share a group's shift); (None, every cell) when one does not (the shifts then pass over
        every node and cell).  Built on first use after an interface is registered."""
        if self._shift_lists is None:
            named = [getattr(obj, "shifted_nodes", None) for obj in self.interfaces]
            if any(n is None for n in named):
                self._shift_lists = (None, np.arange(self.state.n_cells, dtype=np.int64))
            else:
                nn = self.state.n_nodes
                mark = np.zeros(nn, np.bool_)
                for n in named:
                    mark[np.asarray(n, np.int64)] = True
                ptr, members = self._grp
                for g in range(ptr.shape[0] - 1):
                    grp = members[ptr[g]:ptr[g + 1]]
                    if mark[grp].any():
                        mark[grp] = True
                nodes = np.flatnonzero(mark).astype(np.int64)
                cells = np.flatnonzero(mark[self.state.conn].any(axis=1)).astype(np.int64)
                self._shift_lists = (nodes, cells)
        return self._shift_lists

    def _advance_stage(self) -> None:
        """Steps 5-6: positions, cells, next time step."""
        s = self.state
        dt = s.dt
        # 5 positions
        if self.parallel:
            move = K.move_nodes_parallel if self.passes_parallel else K.move_nodes
            move(s.x, s.y, s.vx, s.vy, dt, self._x_half, self._y_half)
        # 6 cells (serial: 5 and 6 in one call)
        args = (s.conn, self._x_half, self._y_half, s.x, s.y, s.vx, s.vy, s.mat, s.props, s.isentrope, s.cell_mass,
                s.volume, s.rho, s.e, s.e_el, s.pressure, s.q, s.sxx, s.syy, s.sxy, s.eps_p, s.temperature,
                s.shear_modulus, s.yield_stress, s.sound_speed, s.axisymmetric, dt, self.cq, self.cl, self.cfl,
                self.dvmax, self._dtcell, self._errcell, self.qedge, s.damage, self._heat_in_update, self._vcorner,
                self._vx_old, self._vy_old, s.dt_velocity)
        if self.parallel:
            dtn, bad, code, qv = K.update_parallel(*args, *self._par_update)
        else:
            args = args + self._scratch
            dtn, bad, code, qv = K.advance_serial(*args)
        self._end_step(dt, dtn, bad, code, qv)

    def _end_step(self, dt: float, dtn: float, bad: int, code: int, qv: float) -> None:
        """After the cell update: the pending history row, a bad cell's error, t^{n+1}, the next step."""
        s = self.state
        if self._pending_row is not None:  # the history row at t^n, now that its viscous heat is known
            ke, ie, dq, budget, probes = self._pending_row
            self._pending_row = None
            self._record(ke, ie + 0.5 * qv + dq, budget, probes)
        if bad >= 0:
            self._fail(bad, code)
        s.t += dt
        s.cycle += 1
        self._dt_prev = dt
        self.guards.after_step(dtn, self._dtcell)
        dtn = min(dtn, self.dt_growth * dt, self.dt_max)
        remaining = self.t_end - s.t
        if dtn >= remaining * (1.0 - 1e-9):
            dtn = remaining
        elif remaining - dtn < 0.1 * dtn:  # avoid a sliver of a last step: two equal ones
            dtn = 0.5 * remaining
        s.dt = dtn

    # ------------------------------------------------------------------ histories
    def _books(self, heat_before: tuple[float, float]) -> tuple:
        """The interfaces' reported terms for a history row at t^n: friction work, friction heat, column heat,
        contact work, contact heat, projection work.  The heats put into cells during this step count half
        (centred at t^n like ``interface_heat``; ``heat_before``: friction and contact heat before this step's
        interfaces)."""
        en = self.state.energy
        return (en.friction_work, 0.5 * (heat_before[0] + en.friction_heat), en.column_heat, en.contact_work,
                0.5 * (heat_before[1] + en.contact_heat), en.projection_work)

    def _record(self, ke: float, ie: float, budget: tuple | None = None, probes: list | None = None) -> None:
        """One history row at t^n; ``budget`` = (boundary work, interface work, interface heat, friction work,
        friction heat, column heat, contact work, contact heat, projection work) at t^n (default: the running
        totals); ``probes``: the probes' values at t^n, read earlier (default: read now).

        error = total - (initial + boundary work + interface work + interface heat) + max(0, contact work):
        every exchange is booked (the projection is energy-neutral: its column is not in the balance), but
        energy that the contact created (contact work > 0) is error, not an exchange."""
        s = self.state
        f = s.geometry_factor
        en = s.energy
        if budget is None:
            budget = (en.boundary_work, en.interface_work, en.interface_heat, en.friction_work, en.friction_heat,
                      en.column_heat, en.contact_work, en.contact_heat, en.projection_work)
        wbc, wint, qint, fw, fh, colh, cw, ch, pw = budget
        total = ke + ie
        err = total - (en.initial + wbc + wint + qint) + max(0.0, cw)
        self.energy_rows.append((s.t, f * ke, f * ie, f * total, f * wbc, f * wint, f * qint, f * fw, f * fh,
                                 f * colh, f * cw, f * ch, f * pw, f * err))
        if self._getters:
            self.probe_rows.append((s.t, *(probes if probes is not None else [float(g()) for g in self._getters])))
        for obs in self.observers:
            obs(self)

    def _probe_getter(self, qn: str, i: int) -> Callable[[], float]:
        """A function returning probe quantity ``qn`` of node/cell ``i`` at t^n."""
        s = self.state
        node = {"vx": lambda: 0.5 * (self._vx_old[i] + s.vx[i]), "vy": lambda: 0.5 * (self._vy_old[i] + s.vy[i]),
                "x": lambda: s.x[i], "y": lambda: s.y[i]}
        if qn in node:
            return node[qn]
        cell = {
            "p": lambda: s.pressure[i], "q": lambda: s.q[i], "sxx": lambda: s.sxx[i], "syy": lambda: s.syy[i],
            "sxy": lambda: s.sxy[i], "szz": lambda: -(s.sxx[i] + s.syy[i]),
            "sigma_xx": lambda: s.sxx[i] - s.pressure[i] - s.q[i],
            "sigma_yy": lambda: s.syy[i] - s.pressure[i] - s.q[i],
            "sigma_xy": lambda: s.sxy[i],
            "sigma_zz": lambda: -(s.sxx[i] + s.syy[i]) - s.pressure[i] - s.q[i],
            "rho": lambda: s.rho[i], "e": lambda: s.e[i], "T": lambda: s.temperature[i], "eps_p": lambda: s.eps_p[i],
            "Y": lambda: s.yield_stress[i], "G": lambda: s.shear_modulus[i], "damage": lambda: s.damage[i],
        }
        return cell[qn]

    def record_final(self) -> None:
        """The state at the end time as the last history row: the forces at t^N and the velocity
        update of a virtual next step (interfaces and constraints included), so that the row is
        centred at t^N like every other.  The simulation is then finished."""
        if not self._finished:
            self._velocity_stage(final=True)
            self._finished = True

    # ------------------------------------------------------------------ loop
    def run(self, progress: Callable[[float], None] | None = None) -> None:
        """Cycle to the end time (or max_cycles); ``progress(t)`` is called every 50 cycles."""
        s = self.state
        start = _time.perf_counter()
        try:
            while s.t < self.t_end * (1.0 - 1e-12) and s.cycle < self.max_cycles:
                self.step()
                for hook in self.between_cycles:
                    hook(self)
                if progress is not None and s.cycle % 50 == 0:
                    progress(s.t)
            self.record_final()
            self.guards.model_range()
            self.guards.finished()
        finally:
            self.wall_time += _time.perf_counter() - start
            for obj in self.interfaces:
                if hasattr(obj, "close"):
                    obj.close()

    # ------------------------------------------------------------------ diagnostics
    def momentum(self) -> tuple[float, float]:
        """Total momentum (x, y) per unit depth / per radian, from v^{n+1/2}."""
        return K.momentum(self.state.vx, self.state.vy, self.state.mass_own)

    def energy_history(self) -> dict[str, np.ndarray]:
        arr = np.array(self.energy_rows, dtype=float).reshape(-1, len(ENERGY_COLUMNS))
        return {k: arr[:, i] for i, k in enumerate(ENERGY_COLUMNS)}

    def probe_history(self) -> dict[str, np.ndarray]:
        cols = ["t_s"] + self.probe_columns
        arr = np.array(self.probe_rows, dtype=float).reshape(-1, len(cols))
        return {k: arr[:, i] for i, k in enumerate(cols)}

    def relative_energy_error(self) -> float:
        """max |error| over the run divided by the largest of |initial|, max kinetic, max internal."""
        h = self.energy_history()
        if h["t_s"].size == 0:
            return 0.0
        scale = max(abs(self.state.energy.initial) * self.state.geometry_factor, np.abs(h["kinetic"]).max(),
                    np.abs(h["internal"]).max(), 1e-300)
        return float(np.abs(h["error"]).max() / scale)
