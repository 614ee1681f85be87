"""Quad geometry for the compatible (energy-conserving) Galerkin forces.

For a bilinear quad with nodes 0..3 counter-clockwise and weight w = 1 (plane
strain, per unit depth) or w = r (axisymmetric, per radian) the kernels need

    V   = int w dA                        (cell volume)
    bx_i = int dN_i/dx w dA,  by_i = int dN_i/dy w dA
    h_i = int N_i dA                      (hoop term, axisymmetric only)

so that the nodal force is F_i = -(sxx bx_i + sxy by_i + s_tt h_i, sxy bx_i + syy by_i)
and the strain rate V D = (sum bx u, sum by v, sum h u, (sum by u + bx v)/2): the
nodal force work equals -V sigma:D exactly (docs/theory/30-hydro.md, sec. forces).
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
            x_xi = 0.0
            x_eta = 0.0
            y_xi = 0.0
            y_eta = 0.0
            r = 0.0
            for i in range(4):
                nxi = 0.25 * _XI[i] * (1.0 + eta * _ETA[i])
                neta = 0.25 * _ETA[i] * (1.0 + xi * _XI[i])
                n = 0.25 * (1.0 + xi * _XI[i]) * (1.0 + eta * _ETA[i])
                x_xi += nxi * xs[i]
                x_eta += neta * xs[i]
                y_xi += nxi * ys[i]
                y_eta += neta * ys[i]
                r += n * xs[i]
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
            jac = x_xi * y_eta - x_eta * y_xi
            for i in range(4):
                out[i] += 0.25 * (1.0 + xi * _XI[i]) * (1.0 + eta * _ETA[i]) * r * jac
