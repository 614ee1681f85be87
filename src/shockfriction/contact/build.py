"""Build slide lines from the run deck's ``slide_lines`` entries and hook them into the cycle.

:func:`build_slide_lines` validates each entry (:class:`~shockfriction.contact.deck.SlideLineDeck`),
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

    def __init__(self, line: SlideLine, heat: bool):
        self.line = line
        self.heat = heat
        self.name = line.name

    def apply(self, state, dt: float, t: float, cycle: int) -> None:
        """Correct the free velocities of the slide-line nodes by contact and friction impulses.

        ``dt`` is the velocity step dt^n (forces -> impulses); the gap is closed over the
        position step ``state.dt`` = dt^{n+1/2} when the state provides it.
        """
        line = self.line
        dt_pos = float(getattr(state, "dt", 0.0) or dt)
        work = line.apply(state.x, state.y, state.vx, state.vy, state.mass, dt, t, dt_position=dt_pos,
                          cell_yield=state.yield_stress,
                          cell_mass=state.cell_mass if self.heat else None,
                          cell_energy=state.e if self.heat else None)
        if not math.isfinite(work):
            raise SimulationError(f"slide line {line.name!r}: non-finite friction work at cycle {cycle}, "
                                  f"t = {t:.6e} s")
        state.energy.friction_work += work
        if self.heat:
            state.energy.interface_heat += work
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
        raise DeckError(f"{where}.body = {ref.body!r}: {exc.args[0]}") from None
    n = nodes.size
    first = ref.first % n if -n <= ref.first < n else None
    last = ref.last % n if -n <= ref.last < n else None
    if first is None or last is None or last - first < 1:
        raise DeckError(f"{where} = first {ref.first}, last {ref.last}: expected a range of at least two "
                        f"nodes among the {n} nodes of {ref.body}.{ref.side}")
    return nodes[first:last + 1].copy(), cells[first:last].copy(), mesh.body_index(ref.body)


def _representatives(n_nodes: int, groups) -> np.ndarray:
    rep = np.arange(n_nodes, dtype=np.int64)
    for g in groups or ():
        g = np.asarray(g, dtype=np.int64)
        rep[g] = g.min()
    return rep


def build_slide_lines(entries: list[dict], mesh, state, bodies, *, node_groups=None, periodic_bodies=(),
                      default_record_interval: float = math.inf, source: str = "deck") -> list[SlideLineInterface]:
    """One :class:`SlideLineInterface` per ``slide_lines`` entry.

    ``mesh`` provides ``side_nodes(body, side)``, ``side_cells(body, side)``, ``body_index``;
    ``state`` the initial ``x, y, conn``; ``bodies`` the deck bodies (for the heat share);
    ``node_groups`` the node groups the cycle moves as one node; ``periodic_bodies`` the names
    of bodies whose sides along the slide line are periodic (then both sides must span one period).
    """
    from shockfriction.materials.library import get_material, heat_share

    out = []
    names = set()
    rep = _representatives(state.x.size, node_groups)
    for k, raw in enumerate(entries):
        where = f"slide_lines[{k}]"
        deck = validate(SlideLineDeck, raw, f"{source}: {where}")
        if deck.name in names:
            raise DeckError(f"{source}: {where}.name = {deck.name!r}: expected a name not used by another slide line")
        names.add(deck.name)
        guide, guide_cells, gb = _path(mesh, deck.guide, f"{source}: {where}.guide")
        slave, slave_cells, sb = _path(mesh, deck.slave, f"{source}: {where}.slave")
        if gb == sb:
            raise DeckError(f"{source}: {where}: guide and slave are on the same body {deck.guide.body!r}; "
                            "expected two bodies")
        # guide outward normal from the centroid of the guide cell next to its first segment
        c = state.conn[guide_cells[0]]
        sign = guide_normal_sign(state.x, state.y, guide, float(state.x[c].mean()), float(state.y[c].mean()))
        fr = deck.friction
        params = law_parameters(mu0=fr.mu0 or 0.0, mu_inf=fr.mu_inf, gamma=fr.gamma, mu_T=fr.mu_T)
        share = None
        if deck.heat == "effusivity":
            mats = {b.name: b.material for b in bodies}
            ms, mg = mats.get(deck.slave.body), mats.get(deck.guide.body)
            if ms is None or mg is None:
                raise DeckError(f"{source}: {where}.heat = 'effusivity': expected both bodies to name a library "
                                "material (their conductivity and diffusivity give the share)")
            share = heat_share(get_material(ms), get_material(mg))
        periodic = deck.guide.body in periodic_bodies and deck.slave.body in periodic_bodies
        line = SlideLine(deck.name, slave, guide, slave_cells, guide_cells, sign, law=LAW_IDS[fr.law],
                         law_params=params, bilateral=deck.contact == "bilateral", heat_share_slave=share,
                         axisymmetric=bool(state.axisymmetric), radius_axis=0, periodic=periodic,
                         max_sweeps=deck.max_sweeps,
                         record_interval=deck.record_interval or default_record_interval,
                         x0=state.x, y0=state.y, node_representative=rep)
        out.append(SlideLineInterface(line, share is not None))
    return out
