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
def slave_hat_coordinates(xs, ys, prev_dx, prev_dy, next_dx, next_dy, has_prev, has_next, seg, coef, active,
                          gx, gy, periodic, xi_prev, xi_node, xi_next):
    """Guide coordinates (xi = segment + u) of each slave node and of its two slave neighbours.

    They map the slave node's hat function N_j (1 at the node, 0 at the neighbours) onto the
    guide.  The neighbours are at offsets ``prev_d*``, ``next_d*`` from the node; a missing one
    (free end of the slave side) takes the node's own coordinate.  Periodic lines: the node lies
    in the guide's span; a neighbour is shifted by whole periods into it and its coordinate
    then shifted back by as many periods of the guide coordinate (xi may leave [0, Ng - 1]).
    """
    period = gx.size - 1.0
    dxp = gx[-1] - gx[0]
    dyp = gy[-1] - gy[0]
    d2 = dxp * dxp + dyp * dyp
    for j in range(xs.size):
        xi0 = seg[j] + coef[j]
        xi_node[j] = xi0
        xi_prev[j] = xi0
        xi_next[j] = xi0
        if not active[j]:
            continue
        for side in range(2):
            has = has_prev[j] if side == 0 else has_next[j]
            if not has:
                continue
            mx = xs[j] + (prev_dx[j] if side == 0 else next_dx[j])
            my = ys[j] + (prev_dy[j] if side == 0 else next_dy[j])
            shift = 0.0
            if periodic:    # the node lies in the guide's span: count the periods to its neighbour
                shift = math.floor(((mx - gx[0]) * dxp + (my - gy[0]) * dyp) / d2)
                mx -= shift * dxp
                my -= shift * dyp
            xi = closest_guide_coordinate(mx, my, gx, gy) + shift * period
            if side == 0:
                xi_prev[j] = xi
            else:
                xi_next[j] = xi


@njit(cache=True)
def _add_weight(gnode, gw, j, used, node, c):
    for q in range(used):
        if gnode[j, q] == node:
            gw[j, q] += c
            return used
    gnode[j, used] = node
    gw[j, used] = c
    return used + 1


@njit(cache=True)
def hat_weights(xi_prev, xi_node, xi_next, seg, coef, active, gx, gy, gr, guide_nodes, periodic, gnode, gw,
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
    for j in range(xi_node.size):
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
