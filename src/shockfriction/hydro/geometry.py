"""Quad geometry for the compatible (energy-conserving) Galerkin forces.

For a bilinear quad with nodes 0..3 counter-clockwise and weight w = 1 (plane
strain, per unit depth) or w = r (axisymmetric, per radian) the kernels need

    V   = int w dA                        (cell volume)
    bx_i = int dN_i/dx w dA,  by_i = int dN_i/dy w dA
    h_i = int N_i dA                      (hoop term, axisymmetric only)

so that the nodal force is F_i = -(sxx bx_i + sxy by_i + s_tt h_i, sxy bx_i + syy by_i)
and the strain rate V D = (sum bx u, sum by v, sum h u, (sum by u + bx v)/2): the
nodal force work equals -V sigma:D exactly (docs/theory/hydrocode.md, sec. forces).
Plane strain uses the closed form (Wilkins's formulas); axisymmetric uses 2x2
Gauss quadrature, exact for these polynomial integrands.
"""

from __future__ import annotations

import math

from numba import njit

_XI = (-1.0, 1.0, 1.0, -1.0)
_ETA = (-1.0, -1.0, 1.0, 1.0)
_G = 1.0 / math.sqrt(3.0)


@njit(cache=True)
def quad_area(x0, x1, x2, x3, y0, y1, y2, y3):
    """Signed area of the quad (positive counter-clockwise)."""
    return 0.5 * ((x2 - x0) * (y3 - y1) - (x3 - x1) * (y2 - y0))


@njit(cache=True)
def bvec_planar(x0, x1, x2, x3, y0, y1, y2, y3):
    """Plane strain: (bx0..bx3, by0..by3, area), bx_i = dA/dx_i (Wilkins's formulas)."""
    return (0.5 * (y1 - y3), 0.5 * (y2 - y0), 0.5 * (y3 - y1), 0.5 * (y0 - y2),
            0.5 * (x3 - x1), 0.5 * (x0 - x2), 0.5 * (x1 - x3), 0.5 * (x2 - x0),
            0.5 * ((x2 - x0) * (y3 - y1) - (x3 - x1) * (y2 - y0)))


@njit(cache=True, inline="always")
def bvec_axi(x0, x1, x2, x3, y0, y1, y2, y3):
    """Axisymmetric (x = r, per radian): (bx0..3, by0..3, h0..3, V) in closed form.

    V = int r dA of the straight-edged quad = sum over edges (y_b - y_a)(x_a^2 + x_a x_b + x_b^2)/6;
    dV/dx_i = bx_i + h_i and dV/dy_i = by_i (moving node i moves the field N_i);
    h_i = int N_i dA = J0 + (J1 xi_i + J2 eta_i)/3 with the Jacobian J = J0 + J1 xi + J2 eta.
    Equal to the 2x2 Gauss quadrature of :func:`bvec_axi_gauss` (tested)."""
    vol = ((y1 - y0) * (x0 * x0 + x0 * x1 + x1 * x1) + (y2 - y1) * (x1 * x1 + x1 * x2 + x2 * x2)
           + (y3 - y2) * (x2 * x2 + x2 * x3 + x3 * x3) + (y0 - y3) * (x3 * x3 + x3 * x0 + x0 * x0)) / 6.0
    s6 = 1.0 / 6.0
    dvx0 = s6 * ((y1 - y0) * (2.0 * x0 + x1) + (y0 - y3) * (x3 + 2.0 * x0))
    dvx1 = s6 * ((y2 - y1) * (2.0 * x1 + x2) + (y1 - y0) * (x0 + 2.0 * x1))
    dvx2 = s6 * ((y3 - y2) * (2.0 * x2 + x3) + (y2 - y1) * (x1 + 2.0 * x2))
    dvx3 = s6 * ((y0 - y3) * (2.0 * x3 + x0) + (y3 - y2) * (x2 + 2.0 * x3))
    by0 = s6 * (x3 * x3 + x3 * x0 - x0 * x1 - x1 * x1)
    by1 = s6 * (x0 * x0 + x0 * x1 - x1 * x2 - x2 * x2)
    by2 = s6 * (x1 * x1 + x1 * x2 - x2 * x3 - x3 * x3)
    by3 = s6 * (x2 * x2 + x2 * x3 - x3 * x0 - x0 * x0)
    a1 = 0.25 * (-x0 + x1 + x2 - x3)
    a2 = 0.25 * (-x0 - x1 + x2 + x3)
    a3 = 0.25 * (x0 - x1 + x2 - x3)
    b1 = 0.25 * (-y0 + y1 + y2 - y3)
    b2 = 0.25 * (-y0 - y1 + y2 + y3)
    b3 = 0.25 * (y0 - y1 + y2 - y3)
    j0 = a1 * b2 - a2 * b1
    j1 = (a1 * b3 - a3 * b1) / 3.0
    j2 = (a3 * b2 - a2 * b3) / 3.0
    h0 = j0 - j1 - j2
    h1 = j0 + j1 - j2
    h2 = j0 + j1 + j2
    h3 = j0 - j1 + j2
    return (dvx0 - h0, dvx1 - h1, dvx2 - h2, dvx3 - h3, by0, by1, by2, by3, h0, h1, h2, h3, vol)


@njit(cache=True)
def bvec_axi_gauss(x0, x1, x2, x3, y0, y1, y2, y3):
    """Axisymmetric (x = r, per radian): (bx0..3, by0..3, h0..3, V) by 2x2 Gauss quadrature."""
    bx0 = bx1 = bx2 = bx3 = 0.0
    by0 = by1 = by2 = by3 = 0.0
    h0 = h1 = h2 = h3 = 0.0
    vol = 0.0
    for gi in range(2):
        xi = -_G if gi == 0 else _G
        for gj in range(2):
            eta = -_G if gj == 0 else _G
            # shape-function derivatives of nodes (-1,-1), (1,-1), (1,1), (-1,1)
            a0 = -0.25 * (1.0 - eta)
            a1 = 0.25 * (1.0 - eta)
            a2 = 0.25 * (1.0 + eta)
            a3 = -0.25 * (1.0 + eta)
            c0 = -0.25 * (1.0 - xi)
            c1 = -0.25 * (1.0 + xi)
            c2 = 0.25 * (1.0 + xi)
            c3 = 0.25 * (1.0 - xi)
            n0 = 0.25 * (1.0 - xi) * (1.0 - eta)
            n1 = 0.25 * (1.0 + xi) * (1.0 - eta)
            n2 = 0.25 * (1.0 + xi) * (1.0 + eta)
            n3 = 0.25 * (1.0 - xi) * (1.0 + eta)
            x_xi = a0 * x0 + a1 * x1 + a2 * x2 + a3 * x3
            x_eta = c0 * x0 + c1 * x1 + c2 * x2 + c3 * x3
            y_xi = a0 * y0 + a1 * y1 + a2 * y2 + a3 * y3
            y_eta = c0 * y0 + c1 * y1 + c2 * y2 + c3 * y3
            r = n0 * x0 + n1 * x1 + n2 * x2 + n3 * x3
            jac = x_xi * y_eta - x_eta * y_xi
            vol += jac * r
            bx0 += (a0 * y_eta - c0 * y_xi) * r
            bx1 += (a1 * y_eta - c1 * y_xi) * r
            bx2 += (a2 * y_eta - c2 * y_xi) * r
            bx3 += (a3 * y_eta - c3 * y_xi) * r
            by0 += (c0 * x_xi - a0 * x_eta) * r
            by1 += (c1 * x_xi - a1 * x_eta) * r
            by2 += (c2 * x_xi - a2 * x_eta) * r
            by3 += (c3 * x_xi - a3 * x_eta) * r
            h0 += n0 * jac
            h1 += n1 * jac
            h2 += n2 * jac
            h3 += n3 * jac
    return bx0, bx1, bx2, bx3, by0, by1, by2, by3, h0, h1, h2, h3, vol


@njit(cache=True)
def axi_volume(x0, x1, x2, x3, y0, y1, y2, y3):
    """int r dA over the quad (straight edges): sum over edges of (y_b - y_a)(x_a^2 + x_a x_b + x_b^2)/6."""
    return ((y1 - y0) * (x0 * x0 + x0 * x1 + x1 * x1) + (y2 - y1) * (x1 * x1 + x1 * x2 + x2 * x2)
            + (y3 - y2) * (x2 * x2 + x2 * x3 + x3 * x3) + (y0 - y3) * (x3 * x3 + x3 * x0 + x0 * x0)) / 6.0


@njit(cache=True)
def min_jacobian(x0, x1, x2, x3, y0, y1, y2, y3):
    """Smallest corner cross product (<= 0: inverted or bow-tie cell)."""
    j0 = (x1 - x0) * (y3 - y0) - (y1 - y0) * (x3 - x0)
    j1 = (x2 - x1) * (y0 - y1) - (y2 - y1) * (x0 - x1)
    j2 = (x3 - x2) * (y1 - y2) - (y3 - y2) * (x1 - x2)
    j3 = (x0 - x3) * (y2 - y3) - (y0 - y3) * (x2 - x3)
    return min(min(j0, j1), min(j2, j3))


@njit(cache=True)
def _gauss_point_map(xs, ys, xi, eta):
    """Derivatives of the bilinear map and the radius at the reference point (xi, eta):
    (x_xi, x_eta, y_xi, y_eta, r) with r = sum N_i x_i."""
    x_xi = 0.0
    x_eta = 0.0
    y_xi = 0.0
    y_eta = 0.0
    r = 0.0
    for i in range(4):
        nxi = 0.25 * _XI[i] * (1.0 + eta * _ETA[i])
        neta = 0.25 * _ETA[i] * (1.0 + xi * _XI[i])
        x_xi += nxi * xs[i]
        x_eta += neta * xs[i]
        y_xi += nxi * ys[i]
        y_eta += neta * ys[i]
        r += 0.25 * (1.0 + xi * _XI[i]) * (1.0 + eta * _ETA[i]) * xs[i]
    return x_xi, x_eta, y_xi, y_eta, r


@njit(cache=True)
def bvectors(xs, ys, axi, bx, by, h):
    """Fill bx, by, h (length 4) for the quad (xs, ys); return the volume V."""
    if not axi:
        bx[0] = 0.5 * (ys[1] - ys[3])
        bx[1] = 0.5 * (ys[2] - ys[0])
        bx[2] = 0.5 * (ys[3] - ys[1])
        bx[3] = 0.5 * (ys[0] - ys[2])
        by[0] = 0.5 * (xs[3] - xs[1])
        by[1] = 0.5 * (xs[0] - xs[2])
        by[2] = 0.5 * (xs[1] - xs[3])
        by[3] = 0.5 * (xs[2] - xs[0])
        for i in range(4):
            h[i] = 0.0
        return quad_area(xs[0], xs[1], xs[2], xs[3], ys[0], ys[1], ys[2], ys[3])
    for i in range(4):
        bx[i] = 0.0
        by[i] = 0.0
        h[i] = 0.0
    vol = 0.0
    for gi in range(2):
        xi = -_G if gi == 0 else _G
        for gj in range(2):
            eta = -_G if gj == 0 else _G
            x_xi, x_eta, y_xi, y_eta, r = _gauss_point_map(xs, ys, xi, eta)
            jac = x_xi * y_eta - x_eta * y_xi
            vol += jac * r
            for i in range(4):
                nxi = 0.25 * _XI[i] * (1.0 + eta * _ETA[i])
                neta = 0.25 * _ETA[i] * (1.0 + xi * _XI[i])
                n = 0.25 * (1.0 + xi * _XI[i]) * (1.0 + eta * _ETA[i])
                bx[i] += (nxi * y_eta - neta * y_xi) * r
                by[i] += (-nxi * x_eta + neta * x_xi) * r
                h[i] += n * jac
    return vol


@njit(cache=True)
def min_corner_jacobian(xs, ys):
    """Smallest of the four corner cross products (<= 0 means an inverted or bow-tie cell)."""
    jmin = 1e300
    for i in range(4):
        ip = (i + 1) % 4
        im = (i + 3) % 4
        j = (xs[ip] - xs[i]) * (ys[im] - ys[i]) - (ys[ip] - ys[i]) * (xs[im] - xs[i])
        if j < jmin:
            jmin = j
    return jmin


@njit(cache=True)
def corner_weights(xs, ys, axi, out):
    """out[i] = int N_i w dA (w = 1 or r): the row sums of the consistent mass matrix per density.

    They sum to the cell volume; in plane strain the thesis's lumping V/4 is used instead
    (eq. 3.12), in axisymmetry these r-weighted row sums (so that a 1D state stays 1D)."""
    if not axi:
        v = quad_area(xs[0], xs[1], xs[2], xs[3], ys[0], ys[1], ys[2], ys[3])
        for i in range(4):
            out[i] = 0.25 * v
        return
    for i in range(4):
        out[i] = 0.0
    for gi in range(2):
        xi = -_G if gi == 0 else _G
        for gj in range(2):
            eta = -_G if gj == 0 else _G
            x_xi, x_eta, y_xi, y_eta, r = _gauss_point_map(xs, ys, xi, eta)
            jac = x_xi * y_eta - x_eta * y_xi
            for i in range(4):
                out[i] += 0.25 * (1.0 + xi * _XI[i]) * (1.0 + eta * _ETA[i]) * r * jac
