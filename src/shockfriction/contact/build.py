"""Build slide lines from the run deck's ``slide_lines`` entries and hook them into the cycle.

:func:`build_interfaces` validates each entry (:class:`~shockfriction.contact.deck.SlideLineDeck`),
finds the node paths and adjacent cells of the two sides on the mesh, the guide's outward
normal, the node-group representatives and the heat share, and returns one
:class:`SlideLineInterface` per entry.  The hydrocode calls their
``apply(state, dt, t, cycle)`` after the free velocities are known.
"""

from __future__ import annotations

import math

import numpy as np

from shockfriction.contact.deck import SlideLineDeck
from shockfriction.contact.pairing import guide_normal_sign
from shockfriction.contact.slideline import SlideLine
from shockfriction.deck.base import validate
from shockfriction.errors import DeckError, SimulationError
from shockfriction.friction.laws import LAW_IDS, law_parameters


class SlideLineInterface:
    """Adapter between the hydrocode state and a :class:`SlideLine` (no physics here)."""

    def __init__(self, line: SlideLine, heat: bool, simulation=None):
        self.line = line
        self.heat = heat
        self.name = line.name
        # velocities at t^{n-1/2}: the cycle keeps them while the interfaces run
        self._v_old = None
        self._column_heat = 0.0    # the sub-grid columns' heat at the last step (energy.csv column_heat)
        self._step = None          # (v^{n-1/2} x and y, dt, dt_pos) between apply and after_interfaces: scratch
        if simulation is not None and hasattr(simulation, "_vx_old"):
            self._v_old = (simulation._vx_old, simulation._vy_old)
        # the simulation, for its kernels' choice (parallel or serial) at each step (no checkpoint keeps it)
        self._sim = simulation
        # the simulation calls after_interfaces once every interface has corrected the velocities
        self._deferred = bool(getattr(simulation, "calls_after_interfaces", False))

    @property
    def shifted_nodes(self) -> np.ndarray:
        """The nodes whose position shift the line's penetration projection may make non-zero: its slave and guide
        nodes (their node groups' representatives), ascending."""
        return np.union1d(self.line.slave_imp, self.line.guide_imp).astype(np.int64)

    def apply(self, state, dt: float, t: float, cycle: int) -> None:
        """Correct the free velocities of the slide-line nodes by contact and friction impulses.

        ``dt`` is the velocity step dt^n (forces -> impulses); the gap is closed over the
        position step ``state.dt`` = dt^{n+1/2} when the state provides it.  Inside a
        :class:`~shockfriction.hydro.cycle.Simulation` the works, heats and records wait for
        :meth:`after_interfaces` (every slide line has corrected the velocities by then).
        """
        line = self.line
        dt_pos = float(getattr(state, "dt", 0.0) or dt)
        if self._v_old is not None:
            vx_old, vy_old = self._v_old
        else:    # v^{n-1/2} = v* - dt F/m (exact for nodes without a boundary constraint)
            vx_old = state.vx - dt * state.fx / state.mass
            vy_old = state.vy - dt * state.fy / state.mass
        self._step = (vx_old, vy_old, dt, dt_pos)
        line.apply(state.x, state.y, state.vx, state.vy, state.mass, dt, t, dt_position=dt_pos,
                   vx_old=vx_old, vy_old=vy_old, cell_yield=state.yield_stress, cell_mass=state.cell_mass,
                   cell_energy=state.e, shift_x=getattr(state, "shift_x", None),
                   shift_y=getattr(state, "shift_y", None), deferred=True,
                   parallel=bool(getattr(self._sim, "passes_parallel", False)))
        if not self._deferred:
            self.after_interfaces(state, dt, t, cycle)

    def after_interfaces(self, state, dt: float, t: float, cycle: int) -> None:
        """Once every interface has corrected the velocities (the cycle calls it before the node groups'
        position shifts): the impulses' works on the final v^{n+1/2}, the heats into the cells, the
        energy books and the record window."""
        line = self.line
        vx_old, vy_old, dt, dt_pos = self._step
        work = line.finish_step(state.x, state.y, state.vx, state.vy, vx_old, vy_old, state.mass, dt, dt_pos,
                                state.cell_mass, state.e)
        if not (math.isfinite(work) and math.isfinite(line.step_contact_loss)):
            raise SimulationError(f"slide line {line.name!r}: non-finite friction or contact work at cycle {cycle}, "
                                  f"t = {t:.6e} s")
        en = state.energy
        en.friction_work += work
        en.contact_work -= line.step_contact_loss     # the normal impulses' work on the bodies (<= 0)
        en.contact_heat += line.step_contact_heat     # ... their inelastic loss, put into the cells
        en.interface_heat += line.step_contact_heat
        if self.heat:
            en.friction_heat += work
            en.interface_heat += work
        fm = line.friction_model
        if fm is not None:    # sub-grid columns: the friction heat they took (out of the hydro's cells)
            # (viscoplastic columns: less the work the hydro's own shear did on them through z = h, layer_work)
            q = float(getattr(fm, "heat_columns", 0.0)) - float(getattr(fm, "layer_work", 0.0))
            en.column_heat += q - self._column_heat
            self._column_heat = q
        if line.record_due(t + dt_pos):    # the new positions only when a record is taken
            line.maybe_record(t + dt_pos, state.x + dt_pos * state.vx, state.y + dt_pos * state.vy)

    def finish(self, state) -> None:
        """Close the last (partial) record window."""
        self.line.maybe_record(state.t, state.x, state.y, force=True)

    @property
    def record(self):
        return self.line.record

    @property
    def total_friction_work(self) -> float:
        return self.line.total_friction_work

    @property
    def total_contact_loss(self) -> float:
        return self.line.total_contact_loss


def _path(mesh, ref, where: str):
    """Node path, its segment cells and body index of a side reference."""
    try:
        nodes = mesh.side_nodes(ref.body, ref.side)
        cells = mesh.side_cells(ref.body, ref.side)
    except KeyError as exc:
        if ref.body in mesh.names:  # a file-meshed body without that physical curve
            raise DeckError(f"{where}.side = {ref.side!r}: {exc.args[0]}") from None
        raise DeckError(f"{where}.body = {ref.body!r}: expected one of the bodies ({exc.args[0]})") from None
    n = nodes.size
    first = ref.first % n if -n <= ref.first < n else None
    last = ref.last % n if -n <= ref.last < n else None
    if first is None or last is None or last - first < 1:
        raise DeckError(f"{where} = first {ref.first}, last {ref.last}: expected a range of at least two "
                        f"nodes among the {n} nodes of {ref.body}.{ref.side}")
    return nodes[first:last + 1].copy(), cells[first:last].copy(), mesh.body_index(ref.body)


def _representatives(n_nodes: int, ptr: np.ndarray, members: np.ndarray) -> np.ndarray:
    """Node -> the smallest node of its group (ties, periodic images), itself otherwise."""
    rep = np.arange(n_nodes, dtype=np.int64)
    for g in range(len(ptr) - 1):
        grp = members[ptr[g]:ptr[g + 1]]
        rep[grp] = grp.min()
    return rep


_ACROSS = {"bottom": ("left", "right"), "top": ("left", "right"), "left": ("bottom", "top"),
           "right": ("bottom", "top")}


def _periodic_along(body, side: str) -> bool:
    """True when the body is periodic along its side ``side`` (the two sides across it are periodic)."""
    if side not in _ACROSS:  # a physical curve of a file-meshed body: never periodic
        return False
    a, b = _ACROSS[side]
    return getattr(body.boundary, a) == "periodic" and getattr(body.boundary, b) == "periodic"


def build_interfaces(entries, simulation) -> list[SlideLineInterface]:
    """One :class:`SlideLineInterface` per ``slide_lines`` entry of the run deck.

    ``entries`` are :class:`~shockfriction.contact.deck.SlideLineDeck` models (or dicts);
    ``simulation`` provides ``problem.deck``, ``mesh``, ``state`` and ``problem.groups``.
    A slide line is periodic when both bodies are periodic along their sides (a periodic strip);
    both sides must then span the same period.
    """
    from shockfriction.materials.library import get_material, heat_share

    problem = simulation.problem
    deck = problem.deck
    mesh = simulation.mesh
    state = simulation.state
    bodies = {b.name: b for b in deck.bodies}
    rep = _representatives(state.x.size, problem.groups.ptr, problem.groups.nodes)
    field_dt = deck.output.field_interval
    out = []
    for k, entry in enumerate(entries):
        where = f"slide_lines[{k}]"
        sl = entry if isinstance(entry, SlideLineDeck) else validate(SlideLineDeck, entry, f"deck: {where}")
        guide, guide_cells, gb = _path(mesh, sl.guide, where + ".guide")
        slave, slave_cells, sb = _path(mesh, sl.slave, where + ".slave")
        if gb == sb:
            raise DeckError(f"{where}.guide.body = {sl.guide.body!r}: expected a body other than the slave's")
        # the guide's outward normal: away from the centroid of the guide cell on its first segment
        c = state.conn[guide_cells[0]]
        sign = guide_normal_sign(state.x, state.y, guide, float(state.x[c].mean()), float(state.y[c].mean()))
        fr = sl.friction
        params = law_parameters(mu0=fr.mu0 or 0.0, mu_inf=fr.mu_inf, gamma=fr.gamma, mu_T=fr.mu_T,
                                evaluation=fr.evaluation, relaxation_steps=fr.relaxation_steps)
        share = None
        if sl.heat == "effusivity":
            ms, mg = bodies[sl.slave.body].material, bodies[sl.guide.body].material
            if ms is None or mg is None:
                raise DeckError(f"{where}.heat = 'effusivity': expected both bodies to name a library material "
                                "(their effusivities give the heat share)")
            share = heat_share(get_material(ms), get_material(mg))
        full_sides = (sl.guide.first == 0 and sl.guide.last == -1 and sl.slave.first == 0 and sl.slave.last == -1)
        periodic = (full_sides and _periodic_along(bodies[sl.guide.body], sl.guide.side)
                    and _periodic_along(bodies[sl.slave.body], sl.slave.side))
        if periodic:
            dg = np.array([state.x[guide[-1]] - state.x[guide[0]], state.y[guide[-1]] - state.y[guide[0]]])
            ds = np.array([state.x[slave[0]] - state.x[slave[-1]], state.y[slave[0]] - state.y[slave[-1]]])
            if np.abs(dg - ds).max() > 1e-9 * np.hypot(*dg):
                raise DeckError(f"{where}: the periodic sides {sl.guide.body}.{sl.guide.side} and "
                                f"{sl.slave.body}.{sl.slave.side} must span the same period")
        interval = sl.record_interval or field_dt
        if interval is None:
            interval = deck.time.end / 200.0
        line = SlideLine(sl.name, slave, guide, slave_cells, guide_cells, sign, law=LAW_IDS.get(fr.law, 0),
                         law_params=params, bilateral=sl.contact == "bilateral", heat_share_slave=share,
                         axisymmetric=bool(state.axisymmetric), radius_axis=0, periodic=periodic,
                         max_sweeps=sl.max_sweeps, record_interval=interval, guide_share=sl.guide_share,
                         x0=state.x, y0=state.y, node_representative=rep)
        if fr.subgrid_model is not None:  # sub-grid columns take over the friction step (shockfriction.coupled)
            from shockfriction.coupled.friction import build_subgrid_friction

            line.friction_model = build_subgrid_friction(sl, line, bodies, where, state=state,
                                                         t_end=float(deck.time.end))
        out.append(SlideLineInterface(line, share is not None, simulation))
    return out


def interface_lines(simulation) -> list:
    """The simulation's slide lines (the :class:`SlideLine` of each registered adapter)."""
    return [obj.line for obj in simulation.interfaces if isinstance(obj, SlideLineInterface)]


def write_interface_outputs(simulation, out_dir, writer=None) -> list:
    """Close the slide lines' last record windows; finish ``interface.h5`` (and ``columns.h5``), then make the
    maps, profiles and CSV tables in ``out_dir`` (:func:`shockfriction.io.products.make_products`: in up to the
    run's thread count of worker processes).  ``writer``: the run's :class:`~shockfriction.io.records.RecordWriter`
    (one is made when None).  Does nothing when the simulation has no slide line.  Returns the paths written.
    """
    from shockfriction.io.products import make_products
    from shockfriction.io.records import RecordWriter

    lines = interface_lines(simulation)
    if not lines:
        return []
    for obj in simulation.interfaces:
        if isinstance(obj, SlideLineInterface):
            obj.finish(simulation.state)
    if writer is None:
        writer = RecordWriter(out_dir, lines, simulation.state.geometry_factor)
    writer.close()
    written = [writer.interface_path] + ([writer.columns_path] if writer.columns_path is not None else [])
    return written + make_products(out_dir, simulation.threads)  # the cores the run was given
