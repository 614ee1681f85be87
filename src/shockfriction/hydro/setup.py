"""From a validated :class:`~shockfriction.deck.run.RunDeck` to mesh, state arrays,
boundary constraints, node groups and probes (no physics here beyond t = 0)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from shockfriction.deck.run import NODE_QUANTITIES, RunDeck
from shockfriction.errors import DeckError
from shockfriction.hydro import matprops as mp
from shockfriction.hydro.eos import isentrope_table
from shockfriction.hydro.kernels import cell_volumes, initial_cell_state, nodal_masses
from shockfriction.hydro.state import State
from shockfriction.materials.library import SCG_ORDER, get_material
from shockfriction.mesh.assembly import Mesh
from shockfriction.mesh.block import SIDES, Block
from shockfriction.units import UnitError, pressure_power_time_to_si

IDEAL_GAS_DEFAULT_CV = 718.0  # J/(kg K), air; only used for the reported temperature
ELASTIC_NO_YIELD = 1e300  # Pa: the flow stress of strength = "elastic" (never reached)


@dataclass
class Constraints:
    """Velocity constraints v.n = value, applied in list order (symmetry, velocity, fixed)."""

    node: np.ndarray
    nx: np.ndarray
    ny: np.ndarray
    value: np.ndarray


@dataclass
class Groups:
    """Node groups (ties, periodic pairs) in CSR form: members of group g are
    ``nodes[ptr[g]:ptr[g+1]]``."""

    ptr: np.ndarray
    nodes: np.ndarray


@dataclass
class ProbeSpec:
    name: str
    kind: str  # "node" or "cell"
    index: int
    quantities: list[str]


@dataclass
class Problem:
    """Everything the cycle needs, built from a deck."""

    deck: RunDeck
    mesh: Mesh
    state: State
    constraints: Constraints
    groups: Groups
    probes: list[ProbeSpec]


def _from_body_or_material(body, mat, field: str, key: str, source: str) -> float:
    """The body's inline value of ``field``, else the library material's ``key``."""
    value = getattr(body, field)
    if value is not None:
        return value
    if mat is not None and mat.has(key):
        return getattr(mat, key)
    where = f"material {mat.name!r} has no {key}" if mat is not None else "no material is given"
    raise DeckError(f"{source}: body {body.name!r}: {field} is needed ({where}); give it in the body")


def material_row(body, source: str) -> tuple[np.ndarray, np.ndarray]:
    """Kernel parameter row and isentrope table of one body (a library material, overridden by the
    body's inline values; without a material every property is inline)."""
    row = mp.empty_props(1)[0]
    table = np.zeros(mp.N_TABLE)
    mat = get_material(body.material) if body.material else None
    row[mp.P_T0] = body.temperature
    if body.pressure_floor is not None:
        row[mp.P_PMIN] = body.pressure_floor
    if body.eos == "ideal-gas":
        row[mp.P_EOS] = mp.EOS_IDEAL_GAS
        row[mp.P_RHO0] = body.density
        row[mp.P_GAMMA] = body.gamma
        row[mp.P_CV] = body.heat_capacity or IDEAL_GAS_DEFAULT_CV
    else:
        row[mp.P_EOS] = mp.EOS_MG_CUBIC if body.eos_tension == "cubic" else mp.EOS_MIE_GRUNEISEN
        for col, key, field in ((mp.P_C0, "eos_c0", "c0"), (mp.P_S, "eos_s", "s"),
                                (mp.P_GAMMA0, "eos_gamma0", "gamma0"), (mp.P_RHO0, "rho0", "density")):
            row[col] = _from_body_or_material(body, mat, field, key, source)
        row[mp.P_CV] = body.heat_capacity or mat.heat_capacity
        row[mp.P_MU_LO], row[mp.P_MU_HI], table = isentrope_table(row)
    if body.strength in ("elastic", "elastic-perfectly-plastic"):
        row[mp.P_STRENGTH] = mp.STRENGTH_EPP
        row[mp.P_G0] = _from_body_or_material(body, mat, "shear_modulus", "G0", source)
        # elastic: no yield (a finite stand-in for infinity, so that Y d_eps = 0 stays 0 in the kernels)
        row[mp.P_Y0] = ELASTIC_NO_YIELD if body.strength == "elastic" else \
            _from_body_or_material(body, mat, "yield_stress", "Y0", source)
    elif body.strength == "scg":
        row[mp.P_STRENGTH] = mp.STRENGTH_SCG
        params = mat.scg_params()
        if body.shear_modulus is not None:
            params[SCG_ORDER.index("G0")] = body.shear_modulus
        if body.yield_stress is not None:
            params[SCG_ORDER.index("Y0")] = body.yield_stress
        row[mp.P_SCG:mp.P_SCG + 9] = params
        row[mp.P_G0] = params[SCG_ORDER.index("G0")]
        row[mp.P_G_CONST] = 1.0 if body.elastic_modulus == "constant" else 0.0
    if body.spall == "cutoff":
        row[mp.P_SPALL] = mp.SPALL_CUTOFF
        row[mp.P_PSPALL] = _from_body_or_material(body, mat, "spall_strength", "spall_strength", source)
    elif body.spall == "tuler-butcher":
        row[mp.P_SPALL] = mp.SPALL_TULER_BUTCHER
        row[mp.P_TB_SIGMA0] = _from_body_or_material(body, mat, "tb_sigma0", "tb_sigma0", source)
        lam = _from_body_or_material(body, mat, "tb_lambda", "tb_lambda", source)
        row[mp.P_TB_LAMBDA] = lam
        if body.tb_K is not None:
            try:
                row[mp.P_TB_K] = pressure_power_time_to_si(body.tb_K, lam)
            except UnitError as exc:
                raise DeckError(f"{source}: bodies.{body.name}.tb_K = {body.tb_K!r}: {exc}") from None
        else:
            row[mp.P_TB_K] = _from_body_or_material(body, mat, "tb_K", "tb_K", source)
        if not row[mp.P_TB_K] > 0.0:
            raise DeckError(f"{source}: bodies.{body.name}.tb_K: must be positive")
    return row, table


def _side_normal(mesh: Mesh, body: str, side: str, source: str) -> tuple[float, float]:
    nodes = mesh.side_nodes(body, side)
    px, py = mesh.x[nodes], mesh.y[nodes]
    tx, ty = px[-1] - px[0], py[-1] - py[0]
    length = np.hypot(tx, ty)
    tx, ty = tx / length, ty / length
    off = np.abs((px - px[0]) * ty - (py - py[0]) * tx)
    if off.max() > 1e-9 * length:
        raise DeckError(f"{source}: bodies.{body}.boundary.{side} = 'symmetry' needs a straight side")
    return ty, -tx  # outward normal of a counter-clockwise side


def _union_find_groups(n: int, pairs: list[tuple[int, int]]) -> Groups:
    parent = np.arange(n)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in pairs:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    members: dict[int, list[int]] = {}
    for a in {x for p in pairs for x in p}:
        members.setdefault(find(a), []).append(a)
    groups = [sorted(v) for v in members.values() if len(v) > 1]
    ptr = np.concatenate([[0], np.cumsum([len(g) for g in groups])]).astype(np.int64)
    nodes = np.array([x for g in groups for x in g], dtype=np.int64)
    return Groups(ptr, nodes)


def _match_tie(mesh: Mesh, ref_a: str, ref_b: str, source: str) -> list[tuple[int, int]]:
    ba, _, sa = ref_a.partition(".")
    bb, _, sb = ref_b.partition(".")
    na = _side_nodes(mesh, ba, sa, f"{source}: tie {ref_a}")
    nb = _side_nodes(mesh, bb, sb, f"{source}: tie {ref_b}")
    if len(na) != len(nb):
        raise DeckError(f"{source}: tie {ref_a} / {ref_b}: the sides have {len(na)} and {len(nb)} nodes; "
                        "a tie needs matching nodes")
    pa = np.column_stack([mesh.x[na], mesh.y[na]])
    seg = np.hypot(*np.diff(pa, axis=0).T).min()
    for order in (nb[::-1], nb):
        pb = np.column_stack([mesh.x[order], mesh.y[order]])
        if np.abs(pa - pb).max() <= 1e-6 * seg:
            return list(zip(na.tolist(), order.tolist()))
    raise DeckError(f"{source}: tie {ref_a} / {ref_b}: the node positions do not coincide "
                    "(a tie needs matching, coincident nodes; use a slide line otherwise)")


def _probe(deck: RunDeck, mesh: Mesh, k: int, source: str) -> list[ProbeSpec]:
    p = deck.probes[k]
    b = mesh.body_index(p.body)
    blk = mesh.blocks[b]
    if p.point is not None:
        try:
            at = blk.point(p.point)
        except KeyError as exc:
            raise DeckError(f"{source}: probes[{k}].point = {p.point!r}: {exc.args[0]}") from None
    else:
        at = p.at
    node_q = [q for q in p.quantities if q in NODE_QUANTITIES]
    cell_q = [q for q in p.quantities if q not in NODE_QUANTITIES]
    out = []
    if p.node is not None:
        i, j = p.node
        if not (-(blk.nx + 1) <= i <= blk.nx and -(blk.ny + 1) <= j <= blk.ny):
            raise DeckError(f"{source}: probes[{k}].node = {list(p.node)}: outside the {blk.nx + 1} x "
                            f"{blk.ny + 1} nodes of body {p.body!r}")
        out.append(ProbeSpec(p.name, "node", mesh.node_index(b, i, j), node_q))
    elif p.cell is not None:
        i, j = p.cell
        if not (-blk.nx <= i < blk.nx and -blk.ny <= j < blk.ny):
            raise DeckError(f"{source}: probes[{k}].cell = {list(p.cell)}: outside the {blk.nx} x {blk.ny} "
                            f"cells of body {p.body!r}")
        out.append(ProbeSpec(p.name, "cell", mesh.cell_index(b, i, j), cell_q))
    else:
        px, py = at
        s0, s1 = mesh.node_start[b], mesh.node_start[b + 1]
        if node_q:
            d = np.hypot(mesh.x[s0:s1] - px, mesh.y[s0:s1] - py)
            out.append(ProbeSpec(p.name, "node", int(s0 + np.argmin(d)), node_q))
        if cell_q:
            c0, c1 = mesh.cell_start[b], mesh.cell_start[b + 1]
            conn = mesh.conn[c0:c1]
            cx = mesh.x[conn].mean(axis=1)
            cy = mesh.y[conn].mean(axis=1)
            out.append(ProbeSpec(p.name, "cell", int(c0 + np.argmin(np.hypot(cx - px, cy - py))), cell_q))
    return out


def _block(body, source: str, max_cells: int | None = None):
    """The mesh block of a body: a mapped quad, or a physical surface of a gmsh file."""
    m = body.mesh
    if not body.from_file:
        return Block.from_outline(m.corners, m.nx, m.ny, m.sides, m.ratio_x, m.ratio_y)
    from shockfriction.mesh.gmsh import MeshFileError, load_block

    try:
        return load_block(m.file, m.group, m.scale, m.parameters, max_cells)
    except MeshFileError as exc:
        raise DeckError(f"{source}: bodies.{body.name}.mesh: {exc}") from None


def _side_nodes(mesh: Mesh, body: str, side: str, where: str) -> np.ndarray:
    try:
        return mesh.side_nodes(body, side)
    except KeyError as exc:
        raise DeckError(f"{where}: {exc.args[0]}") from None
    except ValueError as exc:  # MeshFileError: a side that is not one boundary path
        raise DeckError(f"{where}: {exc}") from None
def _check_overlap(mesh: Mesh, source: str) -> None:
    """DeckError if a cell centre of one body lies inside another body's outline (overlapping matter)."""
    if len(mesh.names) < 2:
        return
    from matplotlib.path import Path as Outline

    cx = mesh.x[mesh.conn].mean(axis=1)
    cy = mesh.y[mesh.conn].mean(axis=1)
    for b, name in enumerate(mesh.names):
        try:  # a mapped block's outline; a gmsh body has its own side names (gmsh meshes one geometry)
            ring = np.concatenate([mesh.side_nodes(b, side)[:-1] for side in SIDES])
        except (KeyError, ValueError):
            continue
        px, py = mesh.x[ring], mesh.y[ring]
        others = mesh.cell_body != b
        box = (others & (cx > px.min()) & (cx < px.max()) & (cy > py.min()) & (cy < py.max()))
        cand = np.flatnonzero(box)
        if cand.size == 0:
            continue
        inside = Outline(np.column_stack([px, py])).contains_points(np.column_stack([cx[cand], cy[cand]]))
        if inside.any():
            other, i, j = mesh.cell_ij(int(cand[np.argmax(inside)]))
            raise DeckError(f"{source}: bodies {other!r} and {name!r} overlap: the centre of cell ({i}, {j}) of "
                            f"{other!r} lies inside {name!r} (expected bodies that touch at most; check the corners)")


def build_problem(deck: RunDeck, source: str = "deck") -> Problem:
    """Mesh every body, number globally, set initial state, constraints, groups, probes."""
    blocks = [_block(b, source, deck.max_cells) for b in deck.bodies]
    names = [b.name for b in deck.bodies]
    mesh = Mesh(names, blocks)
    if deck.geometry == "axisymmetric":
        for k, b in enumerate(deck.bodies):
            s0, s1 = mesh.node_start[k], mesh.node_start[k + 1]
            if b.from_file and mesh.x[s0:s1].min() < -1e-12 * max(np.abs(mesh.x).max(), 1e-300):
                raise DeckError(f"{source}: bodies.{b.name}.mesh: axisymmetric meshes need x = r >= 0 "
                                f"(min x = {mesh.x[s0:s1].min():.6g} m)")
    axi = deck.geometry == "axisymmetric"
    nb = len(deck.bodies)
    props = mp.empty_props(nb)
    tables = np.zeros((nb, mp.N_TABLE))
    for k, body in enumerate(deck.bodies):
        props[k], tables[k] = material_row(body, source)
    mat = mesh.cell_body.copy()
    vol = np.zeros(mesh.n_cells)
    cell_volumes(mesh.conn, mesh.x, mesh.y, axi, vol)
    if np.any(vol <= 0.0):
        c = int(np.argmin(vol))
        name, i, j = mesh.cell_ij(c)
        where = f"cell ({i}, {j})" if j >= 0 else f"file cell {i}"
        raise DeckError(f"{source}: body {name!r}: {where} has a non-positive volume at t = 0 "
                        "(check the corners' order and the side polylines)")
    _check_overlap(mesh, source)
    rho = props[mat, mp.P_RHO0].copy()
    cmass = rho * vol
    mass_own = np.zeros(mesh.n_nodes)
    nodal_masses(mesh.conn, mesh.x, mesh.y, rho, axi, mass_own)
    e = np.zeros(mesh.n_cells)
    for k, body in enumerate(deck.bodies):
        if body.eos == "ideal-gas":
            sel = mat == k
            e[sel] = body.specific_energy if body.specific_energy is not None else \
                body.pressure / ((body.gamma - 1.0) * body.density)
    vx = np.zeros(mesh.n_nodes)
    vy = np.zeros(mesh.n_nodes)
    for k, body in enumerate(deck.bodies):
        s0, s1 = mesh.node_start[k], mesh.node_start[k + 1]
        vx[s0:s1], vy[s0:s1] = body.velocity
        if body.radial_velocity is not None:  # v = v_r (x, y)/|(x, y)| added (Noh-type problems)
            rr = np.hypot(mesh.x[s0:s1], mesh.y[s0:s1])
            safe = np.where(rr > 0.0, rr, 1.0)
            vx[s0:s1] += np.where(rr > 0.0, body.radial_velocity * mesh.x[s0:s1] / safe, 0.0)
            vy[s0:s1] += np.where(rr > 0.0, body.radial_velocity * mesh.y[s0:s1] / safe, 0.0)

    # ---- node groups: periodic sides and ties
    pairs: list[tuple[int, int]] = []
    for k, body in enumerate(deck.bodies):
        bnd = body.boundary
        if bnd.left == "periodic":
            left = mesh.side_nodes(k, "left")[::-1]
            right = mesh.side_nodes(k, "right")
            shift = np.column_stack([mesh.x[right] - mesh.x[left], mesh.y[right] - mesh.y[left]])
            if np.abs(shift - shift[0]).max() > 1e-9 * np.hypot(*shift[0]):
                raise DeckError(f"{source}: body {body.name!r}: periodic left/right sides must be translates")
            pairs += list(zip(left.tolist(), right.tolist()))
        if bnd.bottom == "periodic":
            bottom = mesh.side_nodes(k, "bottom")
            top = mesh.side_nodes(k, "top")[::-1]
            shift = np.column_stack([mesh.x[top] - mesh.x[bottom], mesh.y[top] - mesh.y[bottom]])
            if np.abs(shift - shift[0]).max() > 1e-9 * np.hypot(*shift[0]):
                raise DeckError(f"{source}: body {body.name!r}: periodic bottom/top sides must be translates")
            pairs += list(zip(bottom.tolist(), top.tolist()))
    for tie in deck.ties:
        pairs += _match_tie(mesh, tie.sides[0], tie.sides[1], source)
    groups = _union_find_groups(mesh.n_nodes, pairs)
    mass = mass_own.copy()
    for g in range(len(groups.ptr) - 1):
        members = groups.nodes[groups.ptr[g]:groups.ptr[g + 1]]
        mg = mass_own[members].sum()
        mass[members] = mg
        vx[members] = (mass_own[members] * vx[members]).sum() / mg
        vy[members] = (mass_own[members] * vy[members]).sum() / mg

    # ---- boundary constraints (symmetry first, then prescribed velocity, then fixed)
    rows: dict[int, list] = {0: [], 1: [], 2: []}
    for k, body in enumerate(deck.bodies):
        for side, kind in body.boundary.given(body.from_file):
            if kind == "free" or kind == "periodic":
                continue
            nodes = _side_nodes(mesh, body.name, side, f"{source}: bodies.{body.name}.boundary.{side}")
            if kind == "symmetry":
                nxn, nyn = _side_normal(mesh, body.name, side, source)
                rows[0] += [(n, nxn, nyn, 0.0) for n in nodes]
            elif kind == "fixed":
                rows[2] += [(n, 1.0, 0.0, 0.0) for n in nodes] + [(n, 0.0, 1.0, 0.0) for n in nodes]
            elif not isinstance(kind, str):
                if kind.vx is not None:
                    rows[1] += [(n, 1.0, 0.0, kind.vx) for n in nodes]
                    vx[nodes] = kind.vx
                if kind.vy is not None:
                    rows[1] += [(n, 0.0, 1.0, kind.vy) for n in nodes]
                    vy[nodes] = kind.vy
    if axi:  # nodes on the axis r = 0 always have v_r = 0 (whatever the deck says of that side)
        scale = max(np.abs(mesh.x).max(), np.abs(mesh.y).max(), 1e-300)
        rows[0] += [(int(n), 1.0, 0.0, 0.0) for n in np.flatnonzero(np.abs(mesh.x) <= 1e-12 * scale)]
    member_of = {}
    for g in range(len(groups.ptr) - 1):
        members = groups.nodes[groups.ptr[g]:groups.ptr[g + 1]].tolist()
        for n in members:
            member_of[n] = members
    table = []
    seen = set()
    for pri in (0, 1, 2):
        for n, a, b, v in rows[pri]:
            for m in member_of.get(int(n), [int(n)]):
                key = (m, round(a, 12), round(b, 12), round(v, 9), pri)
                if key not in seen:
                    seen.add(key)
                    table.append((m, a, b, v))
    if table:
        arr = np.array(table, dtype=float)
        constraints = Constraints(arr[:, 0].astype(np.int64), arr[:, 1].copy(), arr[:, 2].copy(), arr[:, 3].copy())
    else:
        constraints = Constraints(np.zeros(0, np.int64), np.zeros(0), np.zeros(0), np.zeros(0))

    state = State(axisymmetric=axi, conn=mesh.conn.copy(), x=mesh.x.copy(), y=mesh.y.copy(), vx=vx, vy=vy,
                  mass=mass, mass_own=mass_own, cell_mass=cmass, volume=vol, rho=rho, e=e, mat=mat,
                  props=props, isentrope=tables)
    initial_cell_state(state.mat, state.props, state.isentrope, state.rho, state.e, state.pressure,
                       state.temperature, state.shear_modulus, state.yield_stress, state.sound_speed, state.eps_p)
    probes = [s for k in range(len(deck.probes)) for s in _probe(deck, mesh, k, source)]
    return Problem(deck, mesh, state, constraints, groups, probes)


def build_slide_lines(problem: Problem, simulation) -> list:
    """Interface objects for the deck's ``slide_lines`` (built by the contact module).

    The contact module provides ``shockfriction.contact.build.build_interfaces(
    entries, simulation) -> list`` of objects with ``apply(state, dt, t, cycle)``.
    """
    entries = problem.deck.slide_lines
    if not entries:
        return []
    try:
        from shockfriction.contact.build import build_interfaces
    except ImportError:
        raise DeckError("slide_lines are given but this installation has no contact module "
                        "(shockfriction.contact.build)") from None
    return list(build_interfaces(entries, simulation))
