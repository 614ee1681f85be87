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
candidates the one with the smallest |g| wins; a node with no candidate (past a free end
of the guide, or far from it) is inactive for this cycle.  The search is redone every
cycle over all segments, so a node that slides past a segment end is re-associated with
the next segment; with the few hundred interface nodes of the thesis this costs
O(N_slave N_guide) flops per cycle, small next to the hydro step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

COEF_TOL = 1e-9


@njit(cache=True)
def pair_slave_nodes(x, y, slave, gx, gy, normal_sign, max_gap, max_penetration,
                     seg, coef, nx, ny, tx, ty, gap, active):
    """Associate every slave node with its guide segment (or convex corner); fill the output arrays.

    ``x, y`` are the nodal coordinates, ``slave`` the slave node indices and ``gx, gy`` the
    coordinates of the guide polyline's points (``x[guide], y[guide]``, or with periodic
    ghost points added at both ends, see :mod:`shockfriction.contact.slideline`).

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
            x0 = gx[k]
            y0 = gy[k]
            dx = gx[k + 1] - x0
            dy = gy[k + 1] - y0
            l2 = dx * dx + dy * dy
            if l2 <= 0.0:
                continue
            c = ((xs - x0) * dx + (ys - y0) * dy) / l2
            if c < -COEF_TOL or c > 1.0 + COEF_TOL:
                continue
            inv_l = 1.0 / math.sqrt(l2)
            t_x = dx * inv_l
            t_y = dy * inv_l
            n_x = normal_sign * t_y
            n_y = -normal_sign * t_x
            g = (xs - x0) * n_x + (ys - y0) * n_y
            if g > max_gap or g < -max_penetration:
                continue
            if abs(g) < best_abs:
                best_abs = abs(g)
                best = k
                bc = min(max(c, 0.0), 1.0)
                bnx = n_x
                bny = n_y
                btx = t_x
                bty = t_y
                bg = g
        # convex corners: slave node beyond the end of segment k-1 and before the start of segment k
        for k in range(1, ng - 1):
            xc = gx[k]
            yc = gy[k]
            ax = xc - gx[k - 1]
            ay = yc - gy[k - 1]
            bx = gx[k + 1] - xc
            by = gy[k + 1] - yc
            rx = xs - xc
            ry = ys - yc
            if rx * ax + ry * ay <= 0.0 or rx * bx + ry * by >= 0.0:
                continue
            # convex when the guide turns away from its outward normal: n_prev . b < 0
            la = math.sqrt(ax * ax + ay * ay)
            npx = normal_sign * ay / la
            npy = -normal_sign * ax / la
            if npx * bx + npy * by >= 0.0:
                continue
            d = math.sqrt(rx * rx + ry * ry)
            if d > max_gap or d >= best_abs:
                continue
            if rx * npx + ry * npy <= 0.0:
                continue
            best_abs = d
            best = k - 1
            bc = 1.0
            if d > 0.0:
                bnx = rx / d
                bny = ry / d
            else:
                bnx = npx
                bny = npy
            btx = -normal_sign * bny
            bty = normal_sign * bnx
            bg = d
        seg[j] = best
        active[j] = best >= 0
        coef[j] = bc
        nx[j] = bnx
        ny[j] = bny
        tx[j] = btx
        ty[j] = bty
        gap[j] = bg if best >= 0 else 0.0


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

    Planar: the tributary length (per unit depth).  Axisymmetric: each half segment is
    rotated about the axis, per radian: integral of r dl over the half segment, so that
    the areas match nodal masses given per radian.  ``radius_axis`` is 0 if x is the
    radius, 1 if y is.
    """
    if not axisymmetric:
        before, after = slave_tributary_lengths(x, y, slave)
        return before + after
    r = (x if radius_axis == 0 else y)[slave]
    xs, ys = x[slave], y[slave]
    seg_len = np.hypot(np.diff(xs), np.diff(ys))
    # half segment next to node a: length L/2, mean radius (3 r_a + r_b)/4
    ra, rb = r[:-1], r[1:]
    near_a = 0.5 * seg_len * (3.0 * ra + rb) / 4.0
    near_b = 0.5 * seg_len * (ra + 3.0 * rb) / 4.0
    area = np.zeros(slave.size)
    area[:-1] += near_a
    area[1:] += near_b
    return area


@njit(cache=True)
def closest_guide_coordinate(px, py, gx, gy):
    """Guide coordinate xi = k + u (segment k, u in [0, 1]) of the polyline point closest to (px, py)."""
    best = math.inf
    xi = 0.0
    for k in range(gx.size - 1):
        dx = gx[k + 1] - gx[k]
        dy = gy[k + 1] - gy[k]
        l2 = dx * dx + dy * dy
        if l2 <= 0.0:
            continue
        u = ((px - gx[k]) * dx + (py - gy[k]) * dy) / l2
        u = min(max(u, 0.0), 1.0)
        ex = gx[k] + u * dx - px
        ey = gy[k] + u * dy - py
        d2 = ex * ex + ey * ey
        if d2 < best:
            best = d2
            xi = k + u
    return xi


@njit(cache=True)
def tributary_intervals(xs, ys, prev_dx, prev_dy, next_dx, next_dy, has_prev, has_next, seg, coef, active,
                        gx, gy, periodic, xi_a, xi_b):
    """Guide-coordinate interval [xi_a, xi_b] covered by each slave node's tributary segment halves.

    The ends are the projections of the midpoints to the previous and next slave nodes
    (offsets ``prev_d*``, ``next_d*`` from the node), or the node itself at a free end of the
    slave side.  Periodic lines: midpoints are shifted into the guide's period and the interval
    is unwrapped around the node's own coordinate seg + coef (it may then leave [0, Ng - 1]).
    """
    period = gx.size - 1.0
    dxp = gx[-1] - gx[0]
    dyp = gy[-1] - gy[0]
    d2 = dxp * dxp + dyp * dyp
    for j in range(xs.size):
        if not active[j]:
            xi_a[j] = 0.0
            xi_b[j] = 0.0
            continue
        xi0 = seg[j] + coef[j]
        ends = np.empty(2)
        for side in range(2):
            has = has_prev[j] if side == 0 else has_next[j]
            if not has:
                ends[side] = xi0
                continue
            mx = xs[j] + 0.5 * (prev_dx[j] if side == 0 else next_dx[j])
            my = ys[j] + 0.5 * (prev_dy[j] if side == 0 else next_dy[j])
            if periodic:
                s = ((mx - gx[0]) * dxp + (my - gy[0]) * dyp) / d2
                shift = math.floor(s)
                mx -= shift * dxp
                my -= shift * dyp
            xi = closest_guide_coordinate(mx, my, gx, gy)
            if periodic:
                while xi - xi0 > 0.5 * period:
                    xi -= period
                while xi0 - xi > 0.5 * period:
                    xi += period
            ends[side] = xi
        xi_a[j] = min(ends[0], ends[1])
        xi_b[j] = max(ends[0], ends[1])


@njit(cache=True)
def tributary_weights(xi_a, xi_b, seg, coef, active, gx, gy, guide_nodes, periodic, gnode, gw):
    """Segment-averaged guide weights: w_i = (1/L) integral of the hat function N_i over [xi_a, xi_b].

    L is the guide length of the interval.  For a uniform traction the guide nodes then receive
    exactly the consistent nodal forces (traction times their tributary length), so two blocks
    with non-matching meshes transmit a uniform pressure (patch test).  ``guide_nodes`` are the
    (representative) node indices of the guide points; a repeated node (periodic seam) is merged.
    A node whose interval has zero length falls back on the point share (1 - coef, coef).
    """
    ng = gx.size
    nseg = ng - 1
    kmax = gnode.shape[1]
    for j in range(xi_a.size):
        for k in range(kmax):
            gnode[j, k] = guide_nodes[0]
            gw[j, k] = 0.0
        if not active[j]:
            continue
        a = xi_a[j]
        b = xi_b[j]
        used = 0
        total = 0.0
        if b > a:
            kc = int(math.floor(a))
            while kc < b:
                k = kc % nseg if periodic else min(max(kc, 0), nseg - 1)
                lo = max(a - kc, 0.0)
                hi = min(b - kc, 1.0)
                if hi > lo:
                    length = math.sqrt((gx[k + 1] - gx[k]) ** 2 + (gy[k + 1] - gy[k]) ** 2)
                    c1 = length * 0.5 * (hi * hi - lo * lo)
                    c0 = length * (hi - lo) - c1
                    total += c0 + c1
                    for node, c in ((guide_nodes[k], c0), (guide_nodes[k + 1], c1)):
                        found = -1
                        for q in range(used):
                            if gnode[j, q] == node:
                                found = q
                        if found < 0:
                            found = used
                            used += 1
                            gnode[j, found] = node
                        gw[j, found] += c
                kc += 1
        if total > 0.0:
            for q in range(used):
                gw[j, q] /= total
        else:
            for q in range(kmax):
                gw[j, q] = 0.0
            gnode[j, 0] = guide_nodes[seg[j]]
            gnode[j, 1] = guide_nodes[seg[j] + 1]
            gw[j, 0] = 1.0 - coef[j]
            gw[j, 1] = coef[j]
            if gnode[j, 1] == gnode[j, 0]:
                gw[j, 0] = 1.0
                gw[j, 1] = 0.0
