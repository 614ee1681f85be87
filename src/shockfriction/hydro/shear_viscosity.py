"""Deviatoric (shear) artificial viscosity (docs/theory/contact-energy-and-shear-viscosity.md).

The bulk viscosity q acts only in compression, so a shear discontinuity (the transverse
wave of a pressure-shear impact) crosses the mesh undamped and rings (Gibbs overshoot of
~27% at a free surface).  This viscosity adds to each cell, at t^n with v^{n-1/2}, the
viscous deviatoric stress

    Q = 2 eta D',   eta = phi rho l (C_L c_S + C_Q^2 l |D'|),   |D'| = sqrt(2 D':D'),
    phi = 1 - (tr L)^2/|L|^2,

with D' the deviatoric strain rate (3D: the hoop rate in axisymmetry), L the velocity
gradient, c_S = sqrt(G/rho) the shear wave speed, l = sqrt(cell area) and (C_L, C_Q) the
deck's ``viscosity.shear_linear`` and ``shear_quadratic``.  phi is the transverse fraction
of the gradient: for a plane wave L = a n^T, phi = 1 - (a.n)^2/|a|^2, 1 for a shear wave and
0 for a longitudinal one (whose front the bulk q already damps: a plane compression front is
not smeared further; phi <= 0, as for isotropic compression L = a I, gives no viscosity).
Q vanishes in uniform states (plateaus keep their level) and its power -2 eta D':D' V <= 0 is
dissipative.  Its corner forces F_i = -Q b_i go into the velocity-dependent corner forces of
the cycle, whose work :func:`~shockfriction.hydro.kernels.viscous_heat_serial` puts into the
cells exactly (the energy books see it as internal energy).
With ``elastic_only`` (default, ``viscosity.shear = "elastic"``) it acts only in cells with
strength whose deviator is below 0.99 Y (sqrt(3/2 S:S) < 0.99 Y): the ringing is elastic, and
in a yielding cell the flow stress already bounds the shear (a viscous overstress there would
raise the interface traction of a plastic slide line).
"""

from __future__ import annotations

import math

from numba import njit, prange

from shockfriction.hydro.geometry import bvec_axi, bvec_planar
from shockfriction.hydro.kernels import _twin


def _shear_viscosity_impl(conn, x, y, vx, vy, rho, shear, sxx, syy, sxy, yld, axi, cl, cq, elastic_only,
                          corner, vcorner):
    """Add the shear-viscosity corner forces to ``corner`` and ``vcorner`` (cells x 8)."""
    for c in prange(conn.shape[0]):
        g = shear[c]
        if g <= 0.0:
            continue
        if elastic_only:
            s_xx = sxx[c]
            s_yy = syy[c]
            s_xy = sxy[c]
            s_tt = -(s_xx + s_yy)
            j2 = math.sqrt(1.5 * (s_xx * s_xx + s_yy * s_yy + s_tt * s_tt + 2.0 * s_xy * s_xy))
            if j2 >= 0.99 * yld[c]:
                continue
        n0 = conn[c, 0]
        n1 = conn[c, 1]
        n2 = conn[c, 2]
        n3 = conn[c, 3]
        x0 = x[n0]
        x1 = x[n1]
        x2 = x[n2]
        x3 = x[n3]
        y0 = y[n0]
        y1 = y[n1]
        y2 = y[n2]
        y3 = y[n3]
        pbx0, pbx1, pbx2, pbx3, pby0, pby1, pby2, pby3, area = bvec_planar(x0, x1, x2, x3, y0, y1, y2, y3)
        if axi:
            bx0, bx1, bx2, bx3, by0, by1, by2, by3, h0, h1, h2, h3, vol = bvec_axi(x0, x1, x2, x3, y0, y1, y2, y3)
        else:
            bx0, bx1, bx2, bx3, by0, by1, by2, by3 = pbx0, pbx1, pbx2, pbx3, pby0, pby1, pby2, pby3
            h0 = h1 = h2 = h3 = 0.0
            vol = area
        if not (vol > 0.0 and area > 0.0):
            continue
        u0 = vx[n0]
        u1 = vx[n1]
        u2 = vx[n2]
        u3 = vx[n3]
        w0 = vy[n0]
        w1 = vy[n1]
        w2 = vy[n2]
        w3 = vy[n3]
        inv = 1.0 / vol
        dxx = (bx0 * u0 + bx1 * u1 + bx2 * u2 + bx3 * u3) * inv
        dyy = (by0 * w0 + by1 * w1 + by2 * w2 + by3 * w3) * inv
        dtt = (h0 * u0 + h1 * u1 + h2 * u2 + h3 * u3) * inv
        uy = (by0 * u0 + by1 * u1 + by2 * u2 + by3 * u3) * inv
        vxg = (bx0 * w0 + bx1 * w1 + bx2 * w2 + bx3 * w3) * inv
        dxy = 0.5 * (uy + vxg)
        trd = dxx + dyy + dtt
        grad2 = dxx * dxx + dyy * dyy + dtt * dtt + uy * uy + vxg * vxg
        if grad2 == 0.0:
            continue
        # transverse fraction of the velocity gradient: 1 - (tr L)^2/|L|^2 (0 for a plane longitudinal
        # wave, L = a n n; 1 for a plane shear wave, a . n = 0)
        phi = 1.0 - trd * trd / grad2
        if phi <= 0.0:
            continue
        dm = trd / 3.0
        exx = dxx - dm
        eyy = dyy - dm
        ett = dtt - dm
        rate = math.sqrt(2.0 * (exx * exx + eyy * eyy + ett * ett + 2.0 * dxy * dxy))
        if rate == 0.0:
            continue
        r = rho[c]
        lq = math.sqrt(area)
        eta = phi * r * lq * (cl * math.sqrt(g / r) + cq * cq * lq * rate)
        qxx = 2.0 * eta * exx
        qyy = 2.0 * eta * eyy
        qtt = 2.0 * eta * ett
        qxy = 2.0 * eta * dxy
        f0 = -(qxx * bx0 + qxy * by0 + qtt * h0)
        f1 = -(qxx * bx1 + qxy * by1 + qtt * h1)
        f2 = -(qxx * bx2 + qxy * by2 + qtt * h2)
        f3 = -(qxx * bx3 + qxy * by3 + qtt * h3)
        e0 = -(qxy * bx0 + qyy * by0)
        e1 = -(qxy * bx1 + qyy * by1)
        e2 = -(qxy * bx2 + qyy * by2)
        e3 = -(qxy * bx3 + qyy * by3)
        corner[c, 0] += f0
        corner[c, 1] += f1
        corner[c, 2] += f2
        corner[c, 3] += f3
        corner[c, 4] += e0
        corner[c, 5] += e1
        corner[c, 6] += e2
        corner[c, 7] += e3
        vcorner[c, 0] += f0
        vcorner[c, 1] += f1
        vcorner[c, 2] += f2
        vcorner[c, 3] += f3
        vcorner[c, 4] += e0
        vcorner[c, 5] += e1
        vcorner[c, 6] += e2
        vcorner[c, 7] += e3


shear_viscosity_serial = njit(cache=True)(_shear_viscosity_impl)
shear_viscosity_parallel = njit(cache=True, parallel=True)(_twin(_shear_viscosity_impl, "_parallel"))
