"""The slide line's geometry over the slave nodes in parallel (``contact_geometry_parallel``,
``hat_weights_parallel``: the parallel hydro kernels' path, docs/theory/threads.md) gives the bytes of the serial
kernels: on open and periodic lines, plane and axisymmetric, with nodes off the guide (inactive), over moving
configurations that reseed the local search from the last cycle's segments.  And the position shifts' cell
volumes (``shifted_volumes``, over every cell or the listed ones) are ``cell_volumes``' bytes on the
cells touching a moved node, and ``shift_listed_nodes`` over the nodes that may carry a shift is ``shift_nodes``."""

import numpy as np
import pytest

from shockfriction.contact.pairing import (contact_geometry, contact_geometry_parallel, hat_weights,
                                           hat_weights_parallel)
from shockfriction.hydro import kernels as K


def _line(ns: int, ng: int, rng, periodic: bool):
    """A wavy guide and a slave side above it (some nodes beyond the search window: inactive)."""
    sg = np.linspace(0.0, 1.0, ng)
    ss = np.linspace(-0.05, 1.05, ns + (1 if periodic else 0)) if not periodic else np.linspace(0.0, 1.0, ns + 1)
    gx = sg + 0.3 / ng * rng.uniform(-1, 1, ng) * (np.arange(ng) % (ng - 1) != 0)
    gy = 0.02 * np.sin(7 * sg)
    sx = ss + 0.2 / ns * rng.uniform(-1, 1, ss.size)
    sy = 0.02 * np.sin(7 * ss) + rng.uniform(-0.004, 0.01, ss.size)
    if periodic:   # the slave's last node is its first's image, the guide's too
        sx[-1] = sx[0] + 1.0
        sy[-1] = sy[0]
        gx[-1] = gx[0] + 1.0
        gy[-1] = gy[0]
    x = np.concatenate((gx, sx)) + 1.5
    y = np.concatenate((gy, sy)) + 0.5
    guide = np.arange(ng, dtype=np.int64)
    side = np.arange(ng, ng + ss.size, dtype=np.int64)
    slave = side[:-1].copy() if periodic else side.copy()
    return x, y, guide, side, slave


def _geometry(func, x, y, slave, side, guide, periodic, axi, seg):
    ns, ng = slave.size, guide.size
    chunk = max(4, int(round(np.sqrt(ng - 1))))
    box = np.zeros((-(-(ng - 1) // chunk), 4))
    out = dict(gx=np.zeros(ng), gy=np.zeros(ng), xs=np.zeros(ns), ys=np.zeros(ns), seg=seg.copy(),
               coef=np.zeros(ns), nx=np.zeros(ns), ny=np.zeros(ns), tx=np.zeros(ns), ty=np.zeros(ns),
               gap=np.zeros(ns), gap_point=np.zeros(ns), active=np.zeros(ns, np.bool_), area=np.zeros(ns),
               xi_prev=np.zeros(ns), xi_node=np.zeros(ns), xi_next=np.zeros(ns))
    width = func(x, y, slave, side, guide, periodic, axi, 1, 1.0, 0.01, 0.01, True, chunk, box, out["gx"],
                 out["gy"], out["xs"], out["ys"], out["seg"], out["coef"], out["nx"], out["ny"], out["tx"],
                 out["ty"], out["gap"], out["gap_point"], out["active"], out["area"], out["xi_prev"],
                 out["xi_node"], out["xi_next"])
    return width, out


def _weights(func, g, guide, periodic, width):
    ns = g["seg"].size
    gnode = np.zeros((ns, width), np.int64)
    gw = np.zeros((ns, width))
    xbar = np.zeros(ns)
    ybar = np.zeros(ns)
    func(g["xi_prev"], g["xi_node"], g["xi_next"], g["seg"], g["coef"], g["active"], g["gx"], g["gy"], g["gy"],
         guide, periodic, gnode, gw, xbar, ybar)
    return gnode, gw, xbar, ybar


@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("axi", [False, True])
def test_parallel_geometry_gives_the_serial_bytes(periodic, axi):
    rng = np.random.default_rng(27 + periodic + 2 * axi)
    x, y, guide, side, slave = _line(300, 211, rng, periodic)
    seg = np.full(slave.size, -1, np.int64)
    for step in range(4):   # moving nodes: each cycle seeded by the last one's segments
        ws, serial = _geometry(contact_geometry, x, y, slave, side, guide, periodic, axi, seg)
        wp, parallel = _geometry(contact_geometry_parallel, x, y, slave, side, guide, periodic, axi, seg)
        assert ws == wp
        assert 0 < serial["active"].sum() <= slave.size
        if not periodic:
            assert not serial["active"].all()   # the ends hang past the guide
        for k in serial:
            np.testing.assert_array_equal(serial[k], parallel[k], err_msg=k)
        for a, b in zip(_weights(hat_weights, serial, guide, periodic, ws),
                        _weights(hat_weights_parallel, serial, guide, periodic, ws)):
            np.testing.assert_array_equal(a, b)
        seg = serial["seg"]
        x[side] += 0.3 / slave.size * rng.uniform(-1, 1, side.size)
        if periodic:
            x[side[-1]] = x[side[0]] + 1.0


@pytest.mark.parametrize("axi", [False, True])
def test_shifted_volumes_are_cell_volumes_of_the_moved_cells(axi):
    n = 40
    ii, jj = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="xy")
    x = (ii * 0.1 + 0.01 * np.sin(jj)).ravel() + 0.5
    y = (jj * 0.1).ravel().astype(float)
    c = np.arange(n * n)
    i, j = c % n, c // n
    n0 = j * (n + 1) + i
    conn = np.stack((n0, n0 + 1, n0 + n + 2, n0 + n + 1), axis=1).astype(np.int64)
    moved = np.zeros(x.size, np.bool_)
    moved[[0, 5, 200, 201, 777, x.size - 1]] = True
    ref = np.empty(conn.shape[0])
    K.cell_volumes(conn, x, y, axi, ref)
    every = np.arange(conn.shape[0])
    listed = np.flatnonzero((moved[conn].any(axis=1)) | (every % 7 == 0))  # the moved cells and others
    for func, cells in ((K.shifted_volumes, every), (K.shifted_volumes_parallel, every), (K.shifted_volumes, listed)):
        out = np.full(conn.shape[0], -1.0)
        func(conn, moved, x, y, axi, out, cells)
        touched = moved[conn].any(axis=1)
        np.testing.assert_array_equal(out[touched], ref[touched])
        assert (out[~touched] == -1.0).all()


def test_shifting_the_listed_nodes_is_shifting_every_node():
    """``shift_listed_nodes`` over the nodes that may carry a shift (some of them with none) gives
    ``shift_nodes``' bytes: positions, zeroed shifts, moved flags and the sum of (m_own/m) F . dx, per chunk of 64
    nodes then the chunks in order (terms of both signs over eight decades, so that another order differs)."""
    rng = np.random.default_rng(7)
    nn = 1000
    x0, y0 = rng.uniform(0, 1, nn), rng.uniform(0, 1, nn)
    fx, fy = rng.standard_normal(nn) * 10.0 ** rng.uniform(-4, 4, nn), rng.standard_normal(nn)
    mass = rng.uniform(1.0, 2.0, nn)
    mass_own = mass * rng.choice([1.0, 0.5], nn)
    listed = np.sort(rng.choice(nn, 150, replace=False)).astype(np.int64)
    sx0, sy0 = np.zeros(nn), np.zeros(nn)
    shifted = listed[rng.uniform(size=listed.size) < 0.7]
    sx0[shifted] = rng.standard_normal(shifted.size) * 1e-6
    sy0[shifted] = rng.standard_normal(shifted.size) * 1e-6
    runs = []
    for kind in ("serial", "parallel", "listed"):
        x, y, sx, sy, moved = x0.copy(), y0.copy(), sx0.copy(), sy0.copy(), np.zeros(nn, np.bool_)
        if kind == "listed":
            w = K.shift_listed_nodes(x, y, sx, sy, fx, fy, mass_own, mass, listed, moved)
        else:
            func = K.shift_nodes if kind == "serial" else K.shift_nodes_parallel
            w = func(x, y, sx, sy, fx, fy, mass_own, mass, np.zeros((nn + 63) // 64), moved)
        runs.append((w, x, y, sx, sy, moved))
    for other in runs[1:]:
        assert other[0] == runs[0][0]
        for a, b in zip(other[1:], runs[0][1:]):
            np.testing.assert_array_equal(a, b)
    assert runs[0][5].sum() == shifted.size and not runs[0][3].any()
    terms = (mass_own / mass * (fx * sx0 + fy * sy0))[listed]
    plain = 0.0
    for v in terms:
        plain += v
    assert plain != runs[0][0]   # the listed terms summed without the chunks differ: the order is tested
