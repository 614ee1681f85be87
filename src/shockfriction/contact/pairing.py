"""Node-to-segment pairing: each slave (sliding) node onto the guide (master) polyline.

Guide nodes ``guide[0..Ng-1]`` form segments ``k = [guide[k], guide[k+1]]`` with unit
tangent t_k = (X_1 - X_0)/|X_1 - X_0| and the guide's outward normal
n_k = s (t_y, -t_x), s = ``normal_sign`` (+1 or -1, fixed at set-up so that n points
out of the guide body, towards the slave body).

For a slave node X_g (thesis section 3.3.1, eqs. 3.61-3.63, the gap of eq. 2.74):

    coef = (X_g - X_0).(X_1 - X_0)/|X_1 - X_0|^2,   g = (X_g - X_0).n_k

A segment is a candidate when -tol <= coef <= 1 + tol (coef then clipped to [0, 1])
and -max_penetration <= g <= max_gap.  A slave node in the wedge outside a *convex*
guide corner (beyond the end of the segment before the corner and before the start of
the one after it) is paired with the corner node itself: coef = 1 on the segment before,
normal n = (X_g - X_corner)/|X_g - X_corner| and g = |X_g - X_corner|.  Among all
candidates the one with the smallest |g| wins (ties: the lowest segment); a node with no
candidate (past a free end of the guide, or far from it) is inactive for this cycle.  The
search is redone every cycle, so a node that slides past a segment end is re-associated with
the next segment.  It starts from the node's segment of the previous cycle
(:func:`pair_slave_nodes_local`): the segments next to it give a bound on |g|, and only the
runs of segments whose bounding boxes lie within that bound are searched, which returns the
pairs of the all-segment search (:func:`pair_slave_nodes`, kept as the reference) at a cost
O(N_slave sqrt(N_guide)) instead of O(N_slave N_guide) (docs/theory/slideline-search.md).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from shockfriction.hydro.kernels import _twin

COEF_TOL = 1e-9


@njit(cache=True, inline="always")
def _segment_test(xs, ys, gx, gy, k, normal_sign, max_gap, max_penetration):
    """Segment k as a candidate for the point (xs, ys): (ok, clipped coef, nx, ny, tx, ty, g)."""
    x0 = gx[k]
    y0 = gy[k]
    dx = gx[k + 1] - x0
    dy = gy[k + 1] - y0
    l2 = dx * dx + dy * dy
    if l2 <= 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    c = ((xs - x0) * dx + (ys - y0) * dy) / l2
    if c < -COEF_TOL or c > 1.0 + COEF_TOL:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    inv_l = 1.0 / math.sqrt(l2)
    t_x = dx * inv_l
    t_y = dy * inv_l
    n_x = normal_sign * t_y
    n_y = -normal_sign * t_x
    g = (xs - x0) * n_x + (ys - y0) * n_y
    if g > max_gap or g < -max_penetration:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, min(max(c, 0.0), 1.0), n_x, n_y, t_x, t_y, g


@njit(cache=True, inline="always")
def _corner_test(xs, ys, gx, gy, k, normal_sign, max_gap):
    """Convex corner at guide point k (1 <= k <= Ng - 2) as a candidate: (ok, d, nx, ny, tx, ty).

    The point must lie beyond the end of segment k-1 and before the start of segment k, on the
    outer side of segment k-1, within ``max_gap`` of the corner."""
    xc = gx[k]
    yc = gy[k]
    ax = xc - gx[k - 1]
    ay = yc - gy[k - 1]
    bx = gx[k + 1] - xc
    by = gy[k + 1] - yc
    rx = xs - xc
    ry = ys - yc
    if rx * ax + ry * ay <= 0.0 or rx * bx + ry * by >= 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    # convex when the guide turns away from its outward normal: n_prev . b < 0
    la = math.sqrt(ax * ax + ay * ay)
    npx = normal_sign * ay / la
    npy = -normal_sign * ax / la
    if npx * bx + npy * by >= 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    d = math.sqrt(rx * rx + ry * ry)
    if d > max_gap:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    if rx * npx + ry * npy <= 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    if d > 0.0:
        bnx = rx / d
        bny = ry / d
    else:
        bnx = npx
        bny = npy
    return True, d, bnx, bny, -normal_sign * bny, normal_sign * bnx


@njit(cache=True)
def pair_slave_nodes(x, y, slave, gx, gy, normal_sign, max_gap, max_penetration,
                     seg, coef, nx, ny, tx, ty, gap, active):
    """Associate every slave node with its guide segment (or convex corner); fill the output arrays.

    The global search (every segment and corner for every node), the reference of
    :func:`pair_slave_nodes_local`.  ``x, y`` are the nodal coordinates, ``slave`` the slave
    node indices and ``gx, gy`` the coordinates of the guide polyline's points
    (``x[guide], y[guide]``).

    Outputs per slave node j: ``seg[j]`` (segment index, -1 if inactive), ``coef[j]`` in [0, 1],
    contact normal ``(nx, ny)`` (out of the guide) and tangent ``(tx, ty)`` (along the guide order),
    signed gap ``gap[j]`` (> 0 open, < 0 penetration) and ``active[j]``.
    """
    ng = gx.size
    for j in range(slave.size):
        xs = x[slave[j]]
        ys = y[slave[j]]
        best = -1
        best_abs = math.inf
        bc = 0.0
        bnx = 0.0
        bny = 0.0
        btx = 0.0
        bty = 0.0
        bg = 0.0
        for k in range(ng - 1):
            ok, c, n_x, n_y, t_x, t_y, g = _segment_test(xs, ys, gx, gy, k, normal_sign, max_gap, max_penetration)
            if ok and abs(g) < best_abs:
                best_abs = abs(g)
                best = k
                bc = c
                bnx = n_x
                bny = n_y
                btx = t_x
                bty = t_y
                bg = g
        # convex corners: slave node beyond the end of segment k-1 and before the start of segment k
        for k in range(1, ng - 1):
            ok, d, n_x, n_y, t_x, t_y = _corner_test(xs, ys, gx, gy, k, normal_sign, max_gap)
            if ok and d < best_abs:
                best_abs = d
                best = k - 1
                bc = 1.0
                bnx = n_x
                bny = n_y
                btx = t_x
                bty = t_y
                bg = d
        seg[j] = best
        active[j] = best >= 0
        coef[j] = bc
        nx[j] = bnx
        ny[j] = bny
        tx[j] = btx
        ty[j] = bty
        gap[j] = bg if best >= 0 else 0.0


WALK = 2    # segments tested on each side of the seed before the chunk boxes are searched


@njit(cache=True)
def guide_chunk_boxes(gx, gy, chunk, box):
    """Bounding boxes of runs of ``chunk`` guide segments; returns the search pad (m).

    ``box[c] = (xmin, xmax, ymin, ymax)`` of the guide points ``c chunk .. (c + 1) chunk``
    (segments ``c chunk .. (c + 1) chunk - 1`` and the corners at their first points).  The pad
    covers the pairing's coef tolerance (a candidate projects up to COEF_TOL |segment| past its
    ends) and the round-off of the distances, with a wide margin: a box farther than
    ``bound + pad`` from a point holds no segment or corner within ``bound`` of it.
    """
    nseg = gx.size - 1
    lmax = 0.0
    scale = 0.0
    for k in range(gx.size):
        scale = max(scale, abs(gx[k]), abs(gy[k]))
        if k < nseg:
            lmax = max(lmax, math.sqrt((gx[k + 1] - gx[k]) ** 2 + (gy[k + 1] - gy[k]) ** 2))
    for c in range(box.shape[0]):
        a = c * chunk
        b = min((c + 1) * chunk, nseg)
        box[c, 0] = gx[a]
        box[c, 1] = gx[a]
        box[c, 2] = gy[a]
        box[c, 3] = gy[a]
        for k in range(a + 1, b + 1):
            box[c, 0] = min(box[c, 0], gx[k])
            box[c, 1] = max(box[c, 1], gx[k])
            box[c, 2] = min(box[c, 2], gy[k])
            box[c, 3] = max(box[c, 3], gy[k])
    return 1e-7 * lmax + 1e-12 * scale


@njit(cache=True, inline="always")
def _box_far(px, py, xmin, xmax, ymin, ymax, bound):
    """True when the box is farther than ``bound`` from (px, py) (squared distances: no square root per box)."""
    ex = max(xmin - px, 0.0, px - xmax)
    ey = max(ymin - py, 0.0, py - ymax)
    return ex * ex + ey * ey > bound * bound


@njit(cache=True, inline="always")
def _segment_far(px, py, gx, gy, k, bound):
    """True when segment k's bounding box is farther than ``bound`` from (px, py)."""
    return _box_far(px, py, min(gx[k], gx[k + 1]), max(gx[k], gx[k + 1]), min(gy[k], gy[k + 1]),
                    max(gy[k], gy[k + 1]), bound)


@njit(cache=True, inline="always")
def _pair_node(j, xs, ys, gx, gy, normal_sign, max_gap, max_penetration, chunk, box, pad, seg, coef, nx, ny,
               tx, ty, gap, active):
    """Slave node j, at (xs, ys), of :func:`pair_slave_nodes_local` (it reads and writes only entry j)."""
    nseg = gx.size - 1
    hmax = max(max_gap, max_penetration)
    sbest = math.inf     # best segment: |g|, index
    sk = -1
    sc = 0.0
    snx = 0.0
    sny = 0.0
    stx = 0.0
    sty = 0.0
    sg = 0.0
    cbest = math.inf     # best convex corner: distance, point index
    ck = -1
    cnx = 0.0
    cny = 0.0
    ctx = 0.0
    cty = 0.0
    s0 = seg[j]
    lo = 0
    hi = -1
    if 0 <= s0 < nseg:
        lo = max(s0 - WALK, 0)
        hi = min(s0 + WALK, nseg - 1)
    for sweep in range(2):
        # sweep 0: the walk around the seed; sweep 1: the other segments of the chunks within the bound
        nch = 1 if sweep == 0 else box.shape[0]
        for c in range(nch):
            if sweep == 0:
                a = lo
                b = hi + 1
            else:
                bound = min(min(sbest, cbest), hmax) + pad
                if _box_far(xs, ys, box[c, 0], box[c, 1], box[c, 2], box[c, 3], bound):
                    continue
                a = c * chunk
                b = min((c + 1) * chunk, nseg)
            for k in range(a, b):
                if sweep == 1 and lo <= k <= hi:
                    continue
                bound = min(min(sbest, cbest), hmax) + pad
                if _segment_far(xs, ys, gx, gy, k, bound):
                    continue
                ok, cf, n_x, n_y, t_x, t_y, g = _segment_test(xs, ys, gx, gy, k, normal_sign, max_gap,
                                                              max_penetration)
                if ok and (abs(g) < sbest or (abs(g) == sbest and k < sk)):
                    sbest = abs(g)
                    sk = k
                    sc = cf
                    snx = n_x
                    sny = n_y
                    stx = t_x
                    sty = t_y
                    sg = g
                if 1 <= k <= nseg - 1:
                    ok, d, n_x, n_y, t_x, t_y = _corner_test(xs, ys, gx, gy, k, normal_sign, max_gap)
                    if ok and (d < cbest or (d == cbest and k < ck)):
                        cbest = d
                        ck = k
                        cnx = n_x
                        cny = n_y
                        ctx = t_x
                        cty = t_y
    if ck >= 0 and cbest < sbest:
        seg[j] = ck - 1
        coef[j] = 1.0
        nx[j] = cnx
        ny[j] = cny
        tx[j] = ctx
        ty[j] = cty
        gap[j] = cbest
        active[j] = True
    else:
        seg[j] = sk
        active[j] = sk >= 0
        coef[j] = sc
        nx[j] = snx
        ny[j] = sny
        tx[j] = stx
        ty[j] = sty
        gap[j] = sg if sk >= 0 else 0.0


@njit(cache=True)
def pair_slave_nodes_local(x, y, slave, gx, gy, normal_sign, max_gap, max_penetration, chunk, box, pad,
                           seg, coef, nx, ny, tx, ty, gap, active):
    """:func:`pair_slave_nodes` searched from each node's previous segment: the same pairs.

    ``seg`` holds on entry the segments of the previous cycle (the seeds; -1: none) and ``box``,
    ``pad`` come from :func:`guide_chunk_boxes`.  Node j first tests the segments and corners
    within :data:`WALK` of its seed; the best candidate so far bounds |g| (or max_gap /
    max_penetration when there is none), and every chunk of segments whose box lies within
    that bound (plus ``pad``) is then searched, segment by segment (their own boxes first).
    A segment or corner outside the searched ones is farther than the bound, so it can neither
    beat nor tie the winner: the result is the global search's, ties included (smallest |g|,
    then lowest index; a corner wins over the segments only when strictly closer), on the
    first cycle, after a separation, a jump or on a folded guide alike (those only cost more boxes).
    """
    for j in range(slave.size):
        _pair_node(j, x[slave[j]], y[slave[j]], gx, gy, normal_sign, max_gap, max_penetration, chunk, box, pad, seg,
                   coef, nx, ny, tx, ty, gap, active)


def guide_normal_sign(x: np.ndarray, y: np.ndarray, guide: np.ndarray, inside_x: float, inside_y: float) -> float:
    """Sign s making n = s (t_y, -t_x) point away from a point inside the guide body.

    The point is e.g. the centroid of the guide cell next to the first segment.
    """
    x0, y0 = x[guide[0]], y[guide[0]]
    dx, dy = x[guide[1]] - x0, y[guide[1]] - y0
    mx, my = x0 + 0.5 * dx, y0 + 0.5 * dy
    # with s = +1 the normal is (dy, -dx); it must point from the inside point to the segment
    return 1.0 if (mx - inside_x) * dy - (my - inside_y) * dx > 0.0 else -1.0


def slave_tributary_lengths(x: np.ndarray, y: np.ndarray, slave: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Half lengths of the slave segments before and after each slave node (0 at the ends).

    The nodal contact length is their sum; the weights also split a node's heat
    between its two adjacent slave cells.
    """
    dx = np.diff(x[slave])
    dy = np.diff(y[slave])
    half = 0.5 * np.hypot(dx, dy)
    before = np.concatenate(([0.0], half))
    after = np.concatenate((half, [0.0]))
    return before, after


def slave_nodal_areas(x: np.ndarray, y: np.ndarray, slave: np.ndarray, axisymmetric: bool,
                      radius_axis: int = 1) -> np.ndarray:
    """Nodal contact surface S_g (thesis's undefined S(X_g), section 5.4 of the digest).

    S_g = integral of N_g r dl over the two slave segments next to the node (N_g its hat
    function): the consistent load of a uniform traction.  Planar (r = 1, per unit depth): half
    of the two segment lengths.  Axisymmetric (per radian, like the nodal masses): L (2 r_g +
    r_other)/6 per segment.  ``radius_axis`` is 0 if x is the radius, 1 if y is.
    """
    if not axisymmetric:
        before, after = slave_tributary_lengths(x, y, slave)
        return before + after
    r = (x if radius_axis == 0 else y)[slave]
    xs, ys = x[slave], y[slave]
    seg_len = np.hypot(np.diff(xs), np.diff(ys))
    # integral over the segment of the hat of node a (b) times r: L (2 r_a + r_b)/6
    ra, rb = r[:-1], r[1:]
    near_a = seg_len * (2.0 * ra + rb) / 6.0
    near_b = seg_len * (ra + 2.0 * rb) / 6.0
    area = np.zeros(slave.size)
    area[:-1] += near_a
    area[1:] += near_b
    return area


@njit(cache=True, inline="always")
def _closest_on_segment(px, py, gx, gy, k):
    """(squared distance, u) of the point of segment k closest to (px, py); inf for a zero-length segment."""
    dx = gx[k + 1] - gx[k]
    dy = gy[k + 1] - gy[k]
    l2 = dx * dx + dy * dy
    if l2 <= 0.0:
        return math.inf, 0.0
    u = ((px - gx[k]) * dx + (py - gy[k]) * dy) / l2
    u = min(max(u, 0.0), 1.0)
    ex = gx[k] + u * dx - px
    ey = gy[k] + u * dy - py
    return ex * ex + ey * ey, u


@njit(cache=True)
def closest_guide_coordinate(px, py, gx, gy):
    """Guide coordinate xi = k + u (segment k, u in [0, 1]) of the polyline point closest to (px, py).

    The global search (the first segment at the smallest distance), reference of
    :func:`closest_guide_coordinate_local`."""
    best = math.inf
    xi = 0.0
    for k in range(gx.size - 1):
        d2, u = _closest_on_segment(px, py, gx, gy, k)
        if d2 < best:
            best = d2
            xi = k + u
    return xi


@njit(cache=True, inline="always")
def closest_guide_coordinate_local(px, py, gx, gy, seed, chunk, box, pad):
    """:func:`closest_guide_coordinate` searched from segment ``seed``: the same coordinate.

    The segments within :data:`WALK` of the seed give a first distance; then only the chunks
    (:func:`guide_chunk_boxes`) and segments whose boxes lie within it (plus ``pad``) are
    tested.  Ties go to the lowest segment index, as in the global search."""
    nseg = gx.size - 1
    best = math.inf
    bk = nseg
    xi = 0.0
    lo = 0
    hi = -1
    if 0 <= seed < nseg:
        lo = max(seed - WALK, 0)
        hi = min(seed + WALK, nseg - 1)
        for k in range(lo, hi + 1):
            d2, u = _closest_on_segment(px, py, gx, gy, k)
            if d2 < best or (d2 == best and k < bk):
                best = d2
                bk = k
                xi = k + u
    reach = math.sqrt(best) + pad
    for c in range(box.shape[0]):
        if _box_far(px, py, box[c, 0], box[c, 1], box[c, 2], box[c, 3], reach):
            continue
        for k in range(c * chunk, min((c + 1) * chunk, nseg)):
            if lo <= k <= hi or _segment_far(px, py, gx, gy, k, reach):
                continue
            d2, u = _closest_on_segment(px, py, gx, gy, k)
            if d2 < best or (d2 == best and k < bk):
                best = d2
                bk = k
                xi = k + u
                reach = math.sqrt(best) + pad
    return xi


@njit(cache=True)
def slave_hat_coordinates(xs, ys, prev_dx, prev_dy, next_dx, next_dy, has_prev, has_next, seg, coef, active,
                          gx, gy, periodic, xi_prev, xi_node, xi_next,
                          chunk=0, box=None, pad=0.0):
    """Guide coordinates (xi = segment + u) of each slave node and of its two slave neighbours.

    They map the slave node's hat function N_j (1 at the node, 0 at the neighbours) onto the
    guide.  The neighbours are at offsets ``prev_d*``, ``next_d*`` from the node; a missing one
    (free end of the slave side) takes the node's own coordinate.  Periodic lines: the node lies
    in the guide's span; a neighbour is shifted by whole periods into it and its coordinate
    then shifted back by as many periods of the guide coordinate (xi may leave [0, Ng - 1]).
    With ``box`` (:func:`guide_chunk_boxes` of ``chunk`` segments, search ``pad``) the closest
    point is searched from the node's own segment (:func:`closest_guide_coordinate_local`, the
    same coordinates); without it over the whole guide.
    """
    for j in range(xs.size):
        _hat_node(j, xs[j], ys[j], prev_dx[j], prev_dy[j], next_dx[j], next_dy[j], has_prev[j], has_next[j], seg,
                  coef, active, gx, gy, periodic, xi_prev, xi_node, xi_next, chunk, box, pad)


@njit(cache=True, inline="always")
def _hat_node(j, xs, ys, prev_dx, prev_dy, next_dx, next_dy, has_prev, has_next, seg, coef, active, gx, gy, periodic,
              xi_prev, xi_node, xi_next, chunk, box, pad):
    """Slave node j of :func:`slave_hat_coordinates` (the node at (xs, ys), its offsets to its neighbours)."""
    period = gx.size - 1.0
    dxp = gx[-1] - gx[0]
    dyp = gy[-1] - gy[0]
    d2 = dxp * dxp + dyp * dyp
    xi0 = seg[j] + coef[j]
    xi_node[j] = xi0
    xi_prev[j] = xi0
    xi_next[j] = xi0
    if not active[j]:
        return
    for side in range(2):
        has = has_prev if side == 0 else has_next
        if not has:
            continue
        mx = xs + (prev_dx if side == 0 else next_dx)
        my = ys + (prev_dy if side == 0 else next_dy)
        shift = 0.0
        if periodic:    # the node lies in the guide's span: count the periods to its neighbour
            shift = math.floor(((mx - gx[0]) * dxp + (my - gy[0]) * dyp) / d2)
            mx -= shift * dxp
            my -= shift * dyp
        if box is None:
            xi = closest_guide_coordinate(mx, my, gx, gy)
        else:
            xi = closest_guide_coordinate_local(mx, my, gx, gy, seg[j], chunk, box, pad)
        xi += shift * period
        if side == 0:
            xi_prev[j] = xi
        else:
            xi_next[j] = xi


@njit(cache=True, inline="always")
def _add_weight(gnode, gw, j, used, node, c):
    for q in range(used):
        if gnode[j, q] == node:
            gw[j, q] += c
            return used
    gnode[j, used] = node
    gw[j, used] = c
    return used + 1


def _hat_weights_impl(xi_prev, xi_node, xi_next, seg, coef, active, gx, gy, gr, guide_nodes, periodic, gnode, gw,
                xbar, ybar):
    """Mortar-type guide weights: w_ij = int N_i N_j r dl / int N_j r dl over the guide.

    N_i are the guide's hat functions, N_j the slave node's hat mapped onto the guide by
    :func:`slave_hat_coordinates`, r the radius ``gr`` of the guide points (ones in plane
    strain), dl the guide's arc length.  Each piece between breakpoints is a cubic in the guide
    coordinate, integrated exactly by Simpson's rule.  With slave nodal forces sigma int N_j r dl
    (the consistent load of a uniform traction sigma), the guide nodes then receive exactly
    sigma int N_i r dl: a uniform pressure crosses non-matching meshes unchanged (patch test),
    in plane strain and in axisymmetry.  ``guide_nodes`` are the (representative) node indices of
    the guide points; repeated nodes (periodic seam) are merged.  A node whose hat maps to a
    zero-length interval falls back on the point share (1 - coef, coef).

    ``xbar, ybar`` receive the guide position averaged with the same weight, int N_j r X dl /
    int N_j r dl (unwrapped on periodic lines): the gap (X_g - Xbar).n is then the one whose
    rate is the constrained relative velocity (v_g - sum w_i v_i).n.
    """
    nseg = gx.size - 1
    dxp = gx[-1] - gx[0]
    dyp = gy[-1] - gy[0]
    kmax = gnode.shape[1]
    for j in prange(xi_node.size):    # row j of gnode, gw, xbar, ybar only: the nodes in any order
        for q in range(kmax):
            gnode[j, q] = guide_nodes[0]
            gw[j, q] = 0.0
        if not active[j]:
            continue
        used = 0
        total = 0.0
        sx = 0.0
        sy = 0.0
        x0 = xi_node[j]
        for side in range(2):
            far = xi_prev[j] if side == 0 else xi_next[j]
            if far == x0:
                continue
            a = min(far, x0)
            b = max(far, x0)
            kc = int(math.floor(a))
            while kc < b:
                k = kc % nseg if periodic else min(max(kc, 0), nseg - 1)
                lo = max(a, float(kc))
                hi = min(b, kc + 1.0)
                if hi > lo:
                    length = math.sqrt((gx[k + 1] - gx[k]) ** 2 + (gy[k + 1] - gy[k]) ** 2)
                    periods = (kc - k) // nseg if periodic else 0
                    c0 = 0.0
                    c1 = 0.0
                    for q, wq in ((0, 1.0), (1, 4.0), (2, 1.0)):
                        xi = lo + 0.5 * q * (hi - lo)
                        u = xi - kc
                        nj = (xi - far) / (x0 - far)
                        r = gr[k] + u * (gr[k + 1] - gr[k])
                        f = wq * nj * r * length * (hi - lo) / 6.0
                        c0 += f * (1.0 - u)
                        c1 += f * u
                        sx += f * (gx[k] + u * (gx[k + 1] - gx[k]) + periods * dxp)
                        sy += f * (gy[k] + u * (gy[k + 1] - gy[k]) + periods * dyp)
                    total += c0 + c1
                    used = _add_weight(gnode, gw, j, used, guide_nodes[k], c0)
                    used = _add_weight(gnode, gw, j, used, guide_nodes[k + 1], c1)
                kc += 1
        if total > 0.0:
            for q in range(used):
                gw[j, q] /= total
            xbar[j] = sx / total
            ybar[j] = sy / total
        else:
            for q in range(kmax):
                gw[j, q] = 0.0
            k = seg[j]
            gnode[j, 0] = guide_nodes[k]
            gnode[j, 1] = guide_nodes[k + 1]
            gw[j, 0] = 1.0 - coef[j]
            gw[j, 1] = coef[j]
            xbar[j] = gx[k] + coef[j] * (gx[k + 1] - gx[k])
            ybar[j] = gy[k] + coef[j] * (gy[k + 1] - gy[k])
            if gnode[j, 1] == gnode[j, 0]:
                gw[j, 0] = 1.0
                gw[j, 1] = 0.0

hat_weights = njit(cache=True)(_hat_weights_impl)
hat_weights_parallel = njit(cache=True, parallel=True)(_twin(_hat_weights_impl, "_parallel"))


@njit(cache=True)
def _nodal_areas(x, y, side, axisymmetric, radius_axis, periodic, area):
    """:func:`slave_nodal_areas` of the side ``side`` into ``area`` (its nodes less the periodic image)."""
    n = side.size
    ns = area.size
    first_extra = 0.0
    for j in range(n):
        a = 0.0
        if j < n - 1:
            dx = x[side[j + 1]] - x[side[j]]
            dy = y[side[j + 1]] - y[side[j]]
            if axisymmetric:
                ra = x[side[j]] if radius_axis == 0 else y[side[j]]
                rb = x[side[j + 1]] if radius_axis == 0 else y[side[j + 1]]
                a = np.hypot(dx, dy) * (2.0 * ra + rb) / 6.0
            else:
                a = 0.5 * np.hypot(dx, dy)
        b = 0.0
        if j > 0:
            dx = x[side[j]] - x[side[j - 1]]
            dy = y[side[j]] - y[side[j - 1]]
            if axisymmetric:
                ra = x[side[j - 1]] if radius_axis == 0 else y[side[j - 1]]
                rb = x[side[j]] if radius_axis == 0 else y[side[j]]
                b = np.hypot(dx, dy) * (ra + 2.0 * rb) / 6.0
            else:
                b = 0.5 * np.hypot(dx, dy)
        if axisymmetric:
            v = (0.0 + a) + b if j < n - 1 else 0.0 + b
        else:
            v = b + a
        if j < ns:
            area[j] = v
        else:
            first_extra = v
    if periodic:
        area[0] += first_extra


@njit(cache=True)
def heat_weights_kernel(x, y, side, periodic, w):
    """Share of each slave node's heat going to its cell before: tributary half lengths
    before/(before + after) (0.5 for an isolated node); ``side`` the full side, ``w`` its nodes
    less the periodic image."""
    n = side.size
    ns = w.size
    for j in range(ns):
        before = 0.0
        after = 0.0
        if j > 0:
            before = 0.5 * np.hypot(x[side[j]] - x[side[j - 1]], y[side[j]] - y[side[j - 1]])
        elif periodic:
            before = 0.5 * math.hypot(x[side[n - 1]] - x[side[n - 2]], y[side[n - 1]] - y[side[n - 2]])
        if j < n - 1:
            after = 0.5 * np.hypot(x[side[j + 1]] - x[side[j]], y[side[j + 1]] - y[side[j]])
        tot = before + after
        w[j] = before / tot if tot > 0.0 else 0.5


def _contact_geometry_impl(x, y, slave, slave_side, guide, periodic, axisymmetric, radius_axis, normal_sign, max_gap,
                           max_penetration, hat, chunk, box, gx, gy, xs, ys, seg, coef, nx, ny, tx, ty, gap, gap_point,
                           active, area, xi_prev, xi_node, xi_next):
    """One cycle's geometry of a slide line, in place; returns the columns its hat weights need.

    Guide polyline ``gx, gy`` = x[guide], y[guide]; slave coordinates ``xs, ys`` (shifted by whole
    periods into the guide's span on periodic lines); the pairing (:func:`pair_slave_nodes_local`,
    seeded by ``seg`` of the previous cycle), the nodal surfaces ``area``
    (:func:`slave_nodal_areas`), the point gap ``gap_point`` and, with ``hat``, the guide
    coordinates of the slave hats (:func:`slave_hat_coordinates`).  The returned width is
    max(2, the most guide segments a hat spans + 2).  The slave nodes' pairings and hat coordinates are
    independent of each other: ``contact_geometry_parallel`` runs them over the nodes in parallel (the same
    bytes).
    """
    ng = guide.size
    ns = slave.size
    nside = slave_side.size
    for i in range(ng):
        gx[i] = x[guide[i]]
        gy[i] = y[guide[i]]
    dxp = gx[ng - 1] - gx[0]
    dyp = gy[ng - 1] - gy[0]
    for j in range(ns):
        xs[j] = x[slave[j]]
        ys[j] = y[slave[j]]
        if periodic:
            k = math.floor(((xs[j] - gx[0]) * dxp + (ys[j] - gy[0]) * dyp) / (dxp * dxp + dyp * dyp))
            xs[j] -= k * dxp
            ys[j] -= k * dyp
    pad = guide_chunk_boxes(gx, gy, chunk, box)
    for j in prange(ns):
        # the pairing of node j (its coordinates xs, ys: slave index j of an identity map)
        _pair_node(j, xs[j], ys[j], gx, gy, normal_sign, max_gap, max_penetration, chunk, box, pad, seg, coef, nx,
                   ny, tx, ty, gap, active)
        gap_point[j] = gap[j]
        if hat:
            # offsets to the previous and next slave node along the side (periodic: across the seam)
            next_dx = 0.0
            next_dy = 0.0
            prev_dx = 0.0
            prev_dy = 0.0
            has_next = False
            has_prev = False
            if j < nside - 1:
                next_dx = x[slave_side[j + 1]] - x[slave_side[j]]
                next_dy = y[slave_side[j + 1]] - y[slave_side[j]]
                has_next = True
            if j > 0:
                prev_dx = -(x[slave_side[j]] - x[slave_side[j - 1]])
                prev_dy = -(y[slave_side[j]] - y[slave_side[j - 1]])
                has_prev = True
            elif periodic:
                prev_dx = -(x[slave_side[nside - 1]] - x[slave_side[nside - 2]])
                prev_dy = -(y[slave_side[nside - 1]] - y[slave_side[nside - 2]])
                has_prev = True
            _hat_node(j, xs[j], ys[j], prev_dx, prev_dy, next_dx, next_dy, has_prev, has_next, seg, coef, active,
                      gx, gy, periodic, xi_prev, xi_node, xi_next, chunk, box, pad)
    _nodal_areas(x, y, slave_side, axisymmetric, radius_axis, periodic, area)
    if not hat:
        return 2
    width = 0.0
    for j in range(ns):
        if active[j]:
            span = math.ceil(max(xi_prev[j], xi_next[j])) - math.floor(min(xi_prev[j], xi_next[j]))
            width = max(width, span)
    return max(2, int(width) + 2)


contact_geometry = njit(cache=True)(_contact_geometry_impl)
contact_geometry_parallel = njit(cache=True, parallel=True)(_twin(_contact_geometry_impl, "_parallel"))


@njit(cache=True)
def projection_gap(xs, ys, xbar, ybar, nx, ny, active, gap, gap_point):
    """gap = (X_g - Xbar).n of the weighted guide position (0 when inactive); gap_point = max(gap_point, gap)."""
    for j in range(xs.size):
        gap[j] = (xs[j] - xbar[j]) * nx[j] + (ys[j] - ybar[j]) * ny[j] if active[j] else 0.0
        gap_point[j] = max(gap_point[j], gap[j])
