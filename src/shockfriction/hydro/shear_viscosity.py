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
the cycle (:func:`~shockfriction.hydro.kernels.cell_forces_serial` adds them there), whose work
the cycle puts into the cells exactly (the energy books see it as internal energy).
With ``elastic_only`` (default, ``viscosity.shear = "elastic"``) it acts only in cells with
strength whose deviator is below 0.99 Y (sqrt(3/2 S:S) < 0.99 Y): the ringing is elastic, and
in a yielding cell the flow stress already bounds the shear (a viscous overstress there would
raise the interface traction of a plastic slide line).
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, inline="always")
def shear_viscosity_forces(g, r, s_xx, s_yy, s_xy, yld, elastic_only, cl, cq, area, vol, inv, lq, bx, by, h, u, w):
    """Corner forces F_i = -Q b_i of one cell's shear viscosity Q = 2 eta D' (module docstring):
    (active, fx0..fx3, fy0..fy3), active = False and zero forces where Q = 0.

    ``g`` the cell's shear modulus, ``r`` its density, (s_xx, s_yy, s_xy) its deviator, ``yld``
    its flow stress; ``area`` the plane area, ``vol`` the volume (= area in plane strain), ``inv`` =
    1/vol and ``lq`` = sqrt(area) (the caller has them; any value where area or vol <= 0), b_i and
    h_i the cell's gradient vectors at x^n and (u_i, w_i) the node velocities v^{n-1/2}, each a
    4-tuple (bx = (bx0, .., bx3) ...: fewer than 30 arguments, so that numba can inline it)."""
    bx0, bx1, bx2, bx3 = bx
    by0, by1, by2, by3 = by
    h0, h1, h2, h3 = h
    u0, u1, u2, u3 = u
    w0, w1, w2, w3 = w
    if g <= 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if elastic_only:
        s_tt = -(s_xx + s_yy)
        y99 = 0.99 * yld
        if y99 <= 0.0 or 1.5 * (s_xx * s_xx + s_yy * s_yy + s_tt * s_tt + 2.0 * s_xy * s_xy) >= y99 * y99:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if not (vol > 0.0 and area > 0.0):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    dxx = (bx0 * u0 + bx1 * u1 + bx2 * u2 + bx3 * u3) * inv
    dyy = (by0 * w0 + by1 * w1 + by2 * w2 + by3 * w3) * inv
    dtt = (h0 * u0 + h1 * u1 + h2 * u2 + h3 * u3) * inv
    uy = (by0 * u0 + by1 * u1 + by2 * u2 + by3 * u3) * inv
    vxg = (bx0 * w0 + bx1 * w1 + bx2 * w2 + bx3 * w3) * inv
    dxy = 0.5 * (uy + vxg)
    trd = dxx + dyy + dtt
    grad2 = dxx * dxx + dyy * dyy + dtt * dtt + uy * uy + vxg * vxg
    if grad2 == 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # transverse fraction of the velocity gradient: 1 - (tr L)^2/|L|^2 (0 for a plane longitudinal
    # wave, L = a n n; 1 for a plane shear wave, a . n = 0)
    phi = 1.0 - trd * trd / grad2
    if phi <= 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    dm = trd * (1.0 / 3.0)
    exx = dxx - dm
    eyy = dyy - dm
    ett = dtt - dm
    rate = math.sqrt(2.0 * (exx * exx + eyy * eyy + ett * ett + 2.0 * dxy * dxy))
    if rate == 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    eta = phi * lq * (cl * math.sqrt(g * r) + cq * cq * lq * rate * r)  # phi rho l (C_L sqrt(G/rho) + ...)
    qxx = 2.0 * eta * exx
    qyy = 2.0 * eta * eyy
    qtt = 2.0 * eta * ett
    qxy = 2.0 * eta * dxy
    return (True, -(qxx * bx0 + qxy * by0 + qtt * h0), -(qxx * bx1 + qxy * by1 + qtt * h1),
            -(qxx * bx2 + qxy * by2 + qtt * h2), -(qxx * bx3 + qxy * by3 + qtt * h3),
            -(qxy * bx0 + qyy * by0), -(qxy * bx1 + qyy * by1), -(qxy * bx2 + qyy * by2), -(qxy * bx3 + qyy * by3))
