"""The one-thread cycle's fused passes do exactly what the separate kernels do (docs/theory/fused-cycle.md,
"Node pass and update blocks", "Wavefront"): the node pass (velocities, constraints, kinetic energy, positions),
the cell update over blocks of ``UPDATE_BLOCK`` cells and the wavefront over the mesh, byte for byte, failures
included."""

import numpy as np
import pytest

from shockfriction.hydro import kernels as K
from shockfriction.hydro.api import prepare
from shockfriction.hydro.cycle import _wavefront
from shockfriction.hydro.partition import cell_bounds, make_partition, partition_count

N = 60  # 3600 cells: two blocks of the update, the second one partial
assert K.UPDATE_BLOCK < N * N < 2 * K.UPDATE_BLOCK


def block_deck(probes: bool, n: int = N) -> dict:
    deck = {"title": "blocks", "time": {"end": "1 ms"},
            "bodies": [{"name": "b", "material": "Al6061-T6", "strength": "scg", "velocity": ["0 m/s", "-500 m/s"],
                        "mesh": {"corners": [["0 mm", "0 mm"], ["6 mm", "0 mm"], ["6 mm", "6 mm"], ["0 mm", "6 mm"]],
                                 "nx": n, "ny": n},
                        # the corner node (0, 0) carries two constraints, applied in list order
                        "boundary": {"bottom": "symmetry", "left": "symmetry"}}]}
    if probes:
        deck["probes"] = [{"name": "c", "body": "b", "cell": [3, 3], "quantities": ["p"]}]
    return deck


def test_node_pass_matches_the_separate_kernels():
    """Without probes every cycle is the fused one (one pass over the nodes); a probe row every cycle
    takes the staged path (advance_velocities, apply_constraints, kinetic_energy_product, move_nodes)."""
    fused, staged = prepare(block_deck(False), threads=1), prepare(block_deck(True), threads=1)
    for _ in range(40):
        fused.step()
        staged.step()
    a, b = fused.state, staged.state
    for name in ("x", "y", "vx", "vy", "e", "e_el", "pressure", "sxx", "eps_p", "temperature", "fx"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.dt == b.dt
    ea, eb = np.array(fused.energy_rows), np.array(staged.energy_rows)
    assert np.array_equal(ea, eb)
    assert a.eps_p.max() > 0 and a.energy.boundary_work != 0.0


def use_wave(sim, wave: int) -> int:
    """Run ``sim``'s fused cycle as a wavefront of ``wave`` cells (the mesh here is below WAVE_MIN_CELLS, whose
    cycle is one step of all cells); returns the rows of its ring of viscous corner forces."""
    s = sim.state
    node_wait, cell_wait, zero_wait, rows = _wavefront(s.conn, s.n_nodes, sim._grp[0].shape[0] > 1, wave)
    sim._waits = (node_wait, cell_wait, zero_wait, wave)
    sim._vring = (sim._vcorner if rows == s.n_cells else np.zeros((rows, 8)),)
    return rows


def local_shuffle(n: int, window: int, rng) -> np.ndarray:
    """A numbering shuffled within windows of ``window`` (an unstructured mesh's: local, not monotone)."""
    perm = np.arange(n)
    for a in range(0, n, window):
        rng.shuffle(perm[a:a + window])
    return perm


def renumber(sim, rng) -> None:
    """Renumber ``sim``'s cells and nodes (shuffled within windows), state and cycle arrays alike."""
    s = sim.state
    nc, nn = s.n_cells, s.n_nodes
    assert nc != nn
    pc, pn = local_shuffle(nc, 97, rng), local_shuffle(nn, 89, rng)  # new cell i is old cell pc[i]
    new_node = np.empty(nn, dtype=np.int64)
    new_node[pn] = np.arange(nn)
    for obj in (s, sim):
        for name, a in list(vars(obj).items()):
            if not isinstance(a, np.ndarray) or a.ndim == 0 or name.startswith("_bc") or name == "_all_nodes":
                continue
            if name == "conn":
                setattr(obj, name, new_node[a[pc]].astype(a.dtype))
            elif a.shape[0] == nc:
                setattr(obj, name, a[pc].copy())
            elif a.shape[0] == nn:
                setattr(obj, name, a[pn].copy())
    node = new_node[sim._cons[0]]
    sim._cons = (node, *sim._cons[1:])
    sim._bc_nodes = np.unique(node).astype(np.int64)
    order = np.argsort(node, kind="stable").astype(np.int64)
    sim._bc_ptr = np.searchsorted(node[order], np.append(sim._bc_nodes, nn)).astype(np.int64)
    sim._bc_cons = order


@pytest.mark.parametrize("wave", [64, 256])
@pytest.mark.parametrize("shuffled", [False, True])
def test_wavefront_matches_the_three_passes(wave, shuffled):
    """The fused cycle as a wavefront (forces of ``wave`` cells, then the nodes and update blocks they complete,
    the viscous corner forces in a ring smaller than the mesh) against the same cycle in one step of all cells
    (the three passes one after the other, pinned to the separate kernels above): the state and every energy row
    byte for byte over 40 cycles, on the block's numbering and on one shuffled within windows (cells and nodes
    out of order, as in an unstructured mesh)."""
    sims = [prepare(block_deck(False, 100), threads=1) for _ in range(2)]  # 10 000 cells: 5 update blocks
    if shuffled:
        for sim in sims:
            renumber(sim, np.random.default_rng(3))
    rows = use_wave(sims[0], wave)
    assert use_wave(sims[1], sims[1].state.n_cells) == sims[1].state.n_cells
    assert rows < sims[0].state.n_cells and rows % K.UPDATE_BLOCK == 0  # the ring wraps
    for _ in range(40):
        for sim in sims:
            sim.step()
    a, b = sims[0].state, sims[1].state
    for name in ("x", "y", "vx", "vy", "e", "e_el", "pressure", "q", "sxx", "sxy", "eps_p", "temperature", "fx",
                 "sound_speed", "yield_stress"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.dt == b.dt
    assert np.array_equal(np.array(sims[0].energy_rows), np.array(sims[1].energy_rows))
    assert a.eps_p.max() > 0 and a.energy.boundary_work != 0.0


def test_wavefront_waits_on_a_hand_mesh():
    """node_wait, cell_wait, zero_wait and the ring's rows of a 2 x 1 strip numbered out of order."""
    conn = np.array([[1, 0, 4, 5], [0, 2, 3, 4]])  # cell 0 on nodes 0, 1, 4, 5; cell 1 on nodes 0, 2, 3, 4
    node_wait, cell_wait, zero_wait, rows = _wavefront(conn, 6, False, 1)
    assert node_wait.tolist() == [1, 1, 1, 1, 1, 1]  # node 0 waits for cell 1, so do the nodes after it
    assert cell_wait.tolist() == [5, 5]
    assert zero_wait.tolist() == [0, 0, 0, 0, 0, 0]
    assert rows == 2
    assert _wavefront(conn, 7, False, 1)[2].tolist() == [0, 0, 0, 0, 0, 0, 2]  # node 6 in no cell: at the end


def update_args(sim) -> list:
    s = sim.state
    return [s.conn, sim._x_half, sim._y_half, s.x, s.y, s.vx, s.vy, s.mat, s.props, s.isentrope, s.cell_mass,
            s.volume, s.rho, s.e, s.e_el, s.pressure, s.q, s.sxx, s.syy, s.sxy, s.eps_p, s.temperature,
            s.shear_modulus, s.yield_stress, s.sound_speed, s.axisymmetric, s.dt, sim.cq, sim.cl, sim.cfl,
            sim.dvmax, sim._dtcell, sim._errcell, sim.qedge, s.damage, True, sim._vcorner, sim._vx_old,
            sim._vy_old, s.dt_velocity]


@pytest.mark.parametrize("broken", [None, "inverted", "nan"])
def test_update_blocks_match_one_call(broken):
    """update_serial (blocks) against update_cells_serial over all cells at once: the same state, step,
    viscous heat and, with a bad cell in the second block, the same cell, code and heat."""
    sim = prepare(block_deck(False), threads=1)
    for _ in range(10):
        sim.step()
    s = sim.state
    K.move_nodes(s.x, s.y, s.vx, s.vy, s.dt, sim._x_half, sim._y_half)
    bad_cell = K.UPDATE_BLOCK + 100
    if broken == "inverted":  # a node of that cell thrown across the cell
        n = s.conn[bad_cell, 2]
        s.x[n] -= 1e-3
        sim._x_half[n] -= 1e-3
    elif broken == "nan":
        s.e[bad_cell] = np.nan
    one = [a.copy() if isinstance(a, np.ndarray) else a for a in update_args(sim)]
    blocks = [a.copy() if isinstance(a, np.ndarray) else a for a in update_args(sim)]
    chunks = s.n_cells // K.SUM_CHUNK + 1
    r_one = K.update_cells_serial(*one, np.empty((11, s.n_cells)), np.empty((s.props.shape[0], K.N_MREC)), 0.0,
                                  np.empty(chunks))
    r_blocks = K.update_serial(*blocks, np.empty((11, K.UPDATE_BLOCK)), np.empty((s.props.shape[0], K.N_MREC)),
                               np.empty(chunks))
    assert r_one == r_blocks
    if broken is None:
        assert r_one[1] == -1 and r_one[3] > 0.0
        for u, v in zip(one, blocks):
            if isinstance(u, np.ndarray):
                assert np.array_equal(u, v, equal_nan=True)
    else:
        assert r_one[1] == bad_cell
        assert r_one[2] == (K.ERR_INVERTED if broken == "inverted" else K.ERR_NAN)


@pytest.mark.parametrize("axi, qedge", [(False, False), (True, False), (False, True), (True, True)])
@pytest.mark.parametrize("parts", [1, 2, 3, 7])
def test_partitioned_force_pass_matches_the_serial_pass(axi, qedge, parts):
    """The parallel force pass (partitions of whole SUM_CHUNKs, each one's own nodes summed in place, the border
    nodes from their stored corners in cell order) against the serial one (blocks in order, scattered in cell
    order): the same nodal forces, viscous corner forces and internal energy, byte for byte, with a partial last
    block, uneven partitions and each flag case."""
    sim = prepare(block_deck(False), threads=1)
    for _ in range(10):
        sim.step()
    s = sim.state
    nc, nn = s.n_cells, s.x.size
    assert nc % K.FORCE_BLOCK != 0
    rng = np.random.default_rng(5)
    vx, vy = s.vx + rng.normal(0.0, 5.0, nn), s.vy + rng.normal(0.0, 5.0, nn)  # hourglass and edge terms at work
    args = [s.conn, s.x, s.y, vx, vy, s.sxx, s.syy, s.sxy, s.pressure, s.q, s.rho, s.sound_speed, s.shear_modulus,
            s.yield_stress, axi, sim.hg, qedge, sim.cq, sim.cl, sim.shear_visc, *sim.shear_visc_args]
    fx, fy, vc_serial = np.empty(nn), np.empty(nn), np.empty((nc, 8))
    ie = K.cell_forces_serial(*args, np.zeros(K.FORCE_SCRATCH), vc_serial, fx, fy, s.e, s.e_el, s.cell_mass, True)
    part = make_partition(s.conn, nn, parts)
    gx, gy, vc_parallel = np.full(nn, np.nan), np.full(nn, np.nan), np.empty((nc, 8))
    ie_p = K.forces_parallel(*args, np.zeros((parts, K.FORCE_SCRATCH)), vc_parallel, gx, gy, s.e, s.e_el,
                             s.cell_mass, True, *part.arrays(), np.zeros((nc, 8)), part.bnodes, part.bptr, part.bcorn,
                             np.zeros(nc // K.SUM_CHUNK + 1), True)
    assert np.array_equal(vc_parallel, vc_serial)
    assert np.array_equal(gx, fx) and np.array_equal(gy, fy)
    assert ie_p == ie
    assert np.abs(vc_serial).max() > 0.0


def test_partition_of_a_hand_mesh():
    """Two rows of three cells, numbered by hand, cut in two: the border nodes are those of both rows, summed from
    their corners in cell order; a node of no cell is a border node (force 0)."""
    #  8   9  10  11
    #  4   5   6   7      12 (no cell)
    #  0   1   2   3
    conn = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [4, 5, 9, 8], [5, 6, 10, 9], [6, 7, 11, 10]])
    part = make_partition(conn, 13, 2)
    assert part.cbounds.tolist() == [0, 0, 6]  # whole chunks of SUM_CHUNK cells: the first partition is empty
    bounds = cell_bounds(10 * K.SUM_CHUNK + 5, 4)
    assert bounds.tolist() == [0, 2 * K.SUM_CHUNK, 5 * K.SUM_CHUNK, 8 * K.SUM_CHUNK, 10 * K.SUM_CHUNK + 5]
    # cut the six cells after the third
    part = make_partition(conn, 13, 2, cbounds=np.array([0, 3, 6]))
    assert part.bnodes.tolist() == [4, 5, 6, 7, 12]
    assert part.border.tolist() == [0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1]
    assert part.pnodes[part.pnode_ptr[0]:part.pnode_ptr[1]].tolist() == [0, 1, 2, 3]
    assert part.pnodes[part.pnode_ptr[1]:part.pnode_ptr[2]].tolist() == [8, 9, 10, 11]
    # node 5: corner 2 of cell 0, 3 of cell 1, 1 of cell 3, 0 of cell 4, in that (cell) order
    j = part.bnodes.tolist().index(5)
    assert part.bcorn[part.bptr[j]:part.bptr[j + 1]].tolist() == [2, 7, 13, 16]
    assert part.bptr[-1] == part.bptr[-2]  # node 12: no corner


def test_partition_count_is_a_whole_number_per_thread():
    assert partition_count(1, 10) == 1 and partition_count(2, 10) == 2  # small meshes: one per thread
    assert partition_count(2, 40_000) == 8 and partition_count(16, 640_000) == 64  # four per thread
    assert partition_count(16, 40_000) == 64 and partition_count(16, 31_921) == 48  # the 200 x 200 block, the cone
    assert partition_count(16, 20_000) == 32  # 39 would leave seven threads a further round
    for threads in range(1, 20):
        for cells in (100, 5_000, 40_000, 70_000, 640_000):
            assert partition_count(threads, cells) % threads == 0


@pytest.mark.parametrize("parallel", [False, True])
def test_jump_works_match_the_three_calls(parallel):
    """kernels.jump_works (one pass: the interfaces' jumps' work carried into v_pre, the constraints, the
    constraints' jumps' work) gives the bytes of impulse_work + apply_constraints + impulse_work, on a mesh with a
    node of two constraints (the corner), nodes past a whole chunk (a partial last chunk) and jumps from the last
    step."""
    sim = prepare(block_deck(False, 24))  # 625 nodes: 9 chunks of 64 and one of 49
    s = sim.state
    nn = s.n_nodes
    assert nn % K.SUM_CHUNK and nn > 4 * K.SUM_CHUNK
    rng = np.random.default_rng(7)
    vx_old, vy_old = rng.normal(size=nn), rng.normal(size=nn)
    vx, vy = rng.normal(size=nn), rng.normal(size=nn)
    vx_free, vy_free = vx + 0.1 * rng.normal(size=nn), vy + 0.1 * rng.normal(size=nn)
    vx_pre, vy_pre = rng.normal(size=nn), rng.normal(size=nn)
    jint = rng.normal(size=(2, nn))
    jbc = rng.normal(size=(2, nn))
    mass_own = s.mass_own
    cnode, cnx, cny, cval = sim._cons
    assert np.bincount(cnode).max() == 2
    # the three calls
    a = [x.copy() for x in (vx, vy, vx_pre, vy_pre, *jint, *jbc)]
    allnodes = np.arange(nn, dtype=np.int64)
    wi = K.impulse_work(allnodes, mass_own, vx_old, vy_old, a[0], a[1], vx_free, vy_free, a[4], a[5], True, a[2],
                        a[3])
    K.apply_constraints(a[0], a[1], vx_old, vy_old, mass_own, cnode, cnx, cny, cval, 1e-9)
    wb = K.impulse_work(allnodes, mass_own, vx_old, vy_old, a[0], a[1], a[2], a[3], a[6], a[7], False, a[2], a[3])
    # one pass
    b = [x.copy() for x in (vx, vy, vx_pre, vy_pre, *jint, *jbc)]
    works = K.jump_works_parallel if parallel else K.jump_works
    wi2, wb2 = works(mass_own, vx_old, vy_old, b[0], b[1], vx_free, vy_free, b[4], b[5], b[2], b[3], b[6], b[7], cnx,
                     cny, cval, sim._bc_nodes, sim._bc_ptr, sim._bc_cons, np.zeros((2, nn // K.SUM_CHUNK + 1)))
    assert wi2 == wi and wb2 == wb
    assert wb != 0.0 and wi != 0.0
    for x, y in zip(a, b):
        assert x.tobytes() == y.tobytes()
