"""The numba kernels of one Wilkins cycle (thesis Fig. 3.7, errata resolved), fused into
two passes over the cells and two over the nodes, one over the nodes in the serial cycle without
interfaces (docs/theory/fused-cycle.md).

* :func:`cell_forces_serial` (the force pass): nodal forces F^n from the cell stress
  sigma^n = S^n - (P^n + q^{n-1/2}) 1 at x^n, plus the velocity-dependent forces on v^{n-1/2}
  (Flanagan-Belytschko hourglass, optional edge viscosity, optional shear viscosity),
  :func:`cell_corner_forces` per cell; per block of cells, a loop vectorized across the cells,
  then summed into the nodes in cell order; the velocity-dependent part is kept per corner for the
  viscous heat, the kinetic energy those forces remove over the step, put into the cells by
  :func:`viscous_cell_heat` (in the cell update, or in :func:`viscous_heat_serial` /
  ``_parallel`` on the cycles that write a history row).
* :func:`sum_groups` / :func:`sync_groups`: node groups (ties, periodic sides).
* :func:`advance_velocities`: v* = v^{n-1/2} + dt F/m.
* :func:`apply_constraints`: v <- v - (v.n - value) n per constraint.
* :func:`impulse_work`: the kinetic energy that velocity jumps (constraints,
  interfaces) put into the leapfrog kinetic energy.
* :func:`move_nodes`: x^{n+1} = x^n + dt v^{n+1/2}.
* :func:`update_cells_serial` (the cell pass): per cell, volume and density at n+1, strain rate at
  x^{n+1/2}, Jaumann rotation + radial return, artificial viscosity q^{n+1/2}, energy update with
  the EOS, spall, temperature, moduli, sound speed and the cell's stable time step, reduced to the
  step of the cycle.
* :func:`velocities_serial` (steps 1-3 without interfaces), :func:`advance_serial` (positions and
  cells), :func:`cycle_serial` (both): the serial kernels above in fewer calls; :func:`cycle_serial`
  runs them over ranges (:func:`forces_of_cells`, :func:`advance_nodes`, :func:`update_blocks`), as a
  wavefront over a large mesh (the three passes a few rows apart, their values still in cache).  In plane strain
  with the bulk q (``axi`` and ``qedge`` false) they pass both flags as the constant False: numba
  types a constant argument as a literal and compiles that case apart, so LLVM drops the dead
  axisymmetric and edge-viscosity code (and the copies its branches cost), the same arithmetic.
* The parallel kernels (end of the module; docs/theory/threads.md): the serial kernels' blocks on
  partitions of the mesh (hydro/partition.py: contiguous ranges of cells, up to four per thread), which
  the force pass and the cell update hand out from a work queue (``jit_bits.fetch_add``: a thread takes
  the next partition when it has finished its last, so one whose cells cost more takes fewer):
  :func:`forces_parallel` (own nodes summed in place, border nodes from their stored corners in cell
  order), :func:`nodes_parallel`, :func:`update_parallel`, in one call :func:`cycle_parallel`; and
  parallel twins of the node kernels (``*_parallel``).

**Sums.** The history sums (internal energy, kinetic energy, viscous heat, impulse and projection
work) add their terms per chunk of ``SUM_CHUNK`` = 64 cells or nodes (or entries of a node list), then
the chunks' sums in chunk order from 0.0, in every kernel: a partition is a whole number of chunks, so
any number of threads gives the serial kernels' bytes.

Per-cell helpers take and return scalars only (no array arguments: no reference counting in the inner
loops) and are inlined (``inline="always"``); the serial kernels are compiled without reference
counting.  Every kernel takes plain arrays and floats; sign convention: compression positive.
"""

from __future__ import annotations

import math
import types

import numpy as np
from numba import njit, prange

from shockfriction.hydro.eos import eos_ab, eos_ab_r, sound_speed2, sound_speed2_ab, temperature
from shockfriction.hydro.geometry import (
    axi_volume, bvec_axi, bvec_planar, bvectors, corner_weights, min_jacobian, quad_area,
)
from shockfriction.hydro.matprops import (
    EOS_IDEAL_GAS, P_C0, P_CV, P_EOS, P_G0, P_G_CONST, P_GAMMA, P_GAMMA0, P_MU_HI, P_MU_LO, P_PMIN, P_RHO0, P_S,
    P_PSPALL, P_SCG, P_SPALL, P_STRENGTH, P_T0, P_TB_K, P_TB_LAMBDA, P_TB_SIGMA0, P_Y0, SPALL_NONE, STRENGTH_EPP,
    STRENGTH_NONE,
)
from shockfriction.hydro.shear_viscosity import shear_viscosity_forces
from shockfriction.hydro.plasticity import radial_return_s, rotate_deviator, shear_modulus_and_ratio, yield_stress
from shockfriction.hydro.spall import spall_damage
from shockfriction.jit_bits import f64_bits, f64_from_bits, fetch_add
from shockfriction.jit_options import NO_REFCOUNT, VECTORIZE
from shockfriction.materials.strength import I_BETA, I_G, I_H, I_N, I_TF, I_XI, I_Y0, I_YMAX, scg_shear_ratio_simd

def _twin(func, suffix: str):
    """A copy of ``func`` under another name, so that numba's on-disk cache keeps its serial and
    parallel compilations apart (the cache index is keyed by name and signature, not by the
    ``parallel`` flag: without this the two variants overwrite each other's cache entry)."""
    name = func.__name__ + suffix
    code = func.__code__.replace(co_name=name, co_qualname=name)
    twin = types.FunctionType(code, func.__globals__, name, func.__defaults__, func.__closure__)
    twin.__qualname__ = name
    twin.__module__ = func.__module__
    twin.__doc__ = func.__doc__
    return twin


# columns of the per-material reciprocals ``mrec`` of the cell update
R_IG0 = 0
R_IRHO0 = 1
R_TSCALE = 2
R_ICV = 3
N_MREC = 4

ERR_NONE = 0
ERR_INVERTED = 1
ERR_NAN = 2
ERR_MESSAGES = {ERR_INVERTED: "inverted or degenerate cell (non-positive volume or corner Jacobian)",
                ERR_NAN: "non-finite value (position, energy or pressure)"}


# --------------------------------------------------------------------------- forces

@njit(cache=True, inline="always")
def edge_viscosity(xa, ya, xb, yb, ua, va, ub, vb, xc, yc, rho, c, cq, cl, axi):
    """Edge artificial viscosity on the cell edge a-b (after Caramana, Shashkov & Whalen 1998).

    Active when the edge shortens ((v_b - v_a).(x_b - x_a) < 0):
    q = rho (C_Q^2 |dv|^2 + C_L c |dv|), acting along dv on the median segment from the cell
    centre (xc, yc) to the edge midpoint, of length L projected across dv (times its mean
    radius in axisymmetry).  Returns (fx, fy) on node a (node b gets the opposite) and the
    dissipated power q L |dv| >= 0."""
    dx = xb - xa
    dy = yb - ya
    du = ub - ua
    dw = vb - va
    if du * dx + dw * dy >= 0.0:
        return 0.0, 0.0, 0.0
    dvn = math.sqrt(du * du + dw * dw)
    ex = du / dvn
    ey = dw / dvn
    sx = 0.5 * (xa + xb) - xc
    sy = 0.5 * (ya + yb) - yc
    length = abs(sx * ey - sy * ex)
    if axi:
        length *= 0.5 * (0.5 * (xa + xb) + xc)
    qz = rho * (cq * cq * dvn * dvn + cl * c * dvn)
    f = qz * length
    return f * ex, f * ey, f * dvn


@njit(cache=True, inline="always")
def cell_corner_forces(xs, ys, us, ws, s_xx, s_yy, a_xy, pc, qc, rc, cc, gc, yc, axi, hg, qedge, cq, cl, svisc, scl,
                       scq, elastic_only):
    """One cell's corner forces at x^n: (f0..f3, g0..g3, vf0..vf3, vg0..vg3), (f_i, g_i) the total
    force on corner i, -sigma^n . b_i (sigma^n = S^n - (P^n + q^{n-1/2}) 1) plus the velocity-dependent
    (vf_i, vg_i) on v^{n-1/2}: Flanagan-Belytschko hourglass, the edge viscosity (``qedge``,
    :func:`edge_viscosity`) and the shear viscosity (``svisc``,
    :func:`~shockfriction.hydro.shear_viscosity.shear_viscosity_forces`).

    ``xs``, ``ys`` the corners' positions x^n and ``us``, ``ws`` their velocities v^{n-1/2} (4-tuples);
    the cell's deviator (s_xx, s_yy, a_xy), pressure ``pc``, q ``qc``, density ``rc``, sound speed
    ``cc``, shear modulus ``gc`` and flow stress ``yc``."""
    x0, x1, x2, x3 = xs
    y0, y1, y2, y3 = ys
    u0, u1, u2, u3 = us
    w0, w1, w2, w3 = ws
    pbx0, pbx1, pbx2, pbx3, pby0, pby1, pby2, pby3, area = bvec_planar(x0, x1, x2, x3, y0, y1, y2, y3)
    if axi:
        bx0, bx1, bx2, bx3, by0, by1, by2, by3, h0, h1, h2, h3, vol = bvec_axi(x0, x1, x2, x3, y0, y1, y2, y3)
    else:
        bx0, bx1, bx2, bx3, by0, by1, by2, by3 = pbx0, pbx1, pbx2, pbx3, pby0, pby1, pby2, pby3
        h0 = h1 = h2 = h3 = 0.0
        vol = area
    # 1/area and sqrt(area): hourglass and shear viscosity
    inva = 1.0
    sqa = 0.0
    if area > 0.0:
        inva = 1.0 / area
        sqa = math.sqrt(area)
    # velocity-dependent (viscous) corner forces
    vf0 = vf1 = vf2 = vf3 = 0.0
    vg0 = vg1 = vg2 = vg3 = 0.0
    if hg > 0.0 and area > 0.0:
        # Flanagan-Belytschko viscous hourglass: gamma = Gamma - (Gamma.x) b_x/A - (Gamma.y) b_y/A
        gx = x0 - x1 + x2 - x3
        gy = y0 - y1 + y2 - y3
        gam0 = 1.0 - (gx * pbx0 + gy * pby0) * inva
        gam1 = -1.0 - (gx * pbx1 + gy * pby1) * inva
        gam2 = 1.0 - (gx * pbx2 + gy * pby2) * inva
        gam3 = -1.0 - (gx * pbx3 + gy * pby3) * inva
        hu = gam0 * u0 + gam1 * u1 + gam2 * u2 + gam3 * u3
        hv = gam0 * w0 + gam1 * w1 + gam2 * w2 + gam3 * w3
        w = 0.25 * (x0 + x1 + x2 + x3) if axi else 1.0
        coef = 0.25 * hg * rc * cc * sqa * w
        vf0 -= coef * gam0 * hu
        vf1 -= coef * gam1 * hu
        vf2 -= coef * gam2 * hu
        vf3 -= coef * gam3 * hu
        vg0 -= coef * gam0 * hv
        vg1 -= coef * gam1 * hv
        vg2 -= coef * gam2 * hv
        vg3 -= coef * gam3 * hv
    if qedge:
        xc = 0.25 * (x0 + x1 + x2 + x3)
        yc_ = 0.25 * (y0 + y1 + y2 + y3)
        ex, ey, _ = edge_viscosity(x0, y0, x1, y1, u0, w0, u1, w1, xc, yc_, rc, cc, cq, cl, axi)
        vf0 += ex
        vg0 += ey
        vf1 -= ex
        vg1 -= ey
        ex, ey, _ = edge_viscosity(x1, y1, x2, y2, u1, w1, u2, w2, xc, yc_, rc, cc, cq, cl, axi)
        vf1 += ex
        vg1 += ey
        vf2 -= ex
        vg2 -= ey
        ex, ey, _ = edge_viscosity(x2, y2, x3, y3, u2, w2, u3, w3, xc, yc_, rc, cc, cq, cl, axi)
        vf2 += ex
        vg2 += ey
        vf3 -= ex
        vg3 -= ey
        ex, ey, _ = edge_viscosity(x3, y3, x0, y0, u3, w3, u0, w0, xc, yc_, rc, cc, cq, cl, axi)
        vf3 += ex
        vg3 += ey
        vf0 -= ex
        vg0 -= ey
    on = False
    sf0 = sf1 = sf2 = sf3 = sg0 = sg1 = sg2 = sg3 = 0.0
    if svisc:
        invv = (1.0 / vol if vol > 0.0 else 1.0) if axi else inva
        on, sf0, sf1, sf2, sf3, sg0, sg1, sg2, sg3 = shear_viscosity_forces(
            gc, rc, s_xx, s_yy, a_xy, yc, elastic_only, scl, scq, area, vol, invv, sqa,
            (bx0, bx1, bx2, bx3), (by0, by1, by2, by3), (h0, h1, h2, h3), us, ws)
    # stress corner forces -sigma^n . b_i, computed last (shorter live ranges), then
    # (stress + hourglass/edge) + shear viscosity, the order of the sums as before
    ptot = pc + qc
    a_xx = s_xx - ptot
    a_yy = s_yy - ptot
    f0 = -(a_xx * bx0 + a_xy * by0)
    f1 = -(a_xx * bx1 + a_xy * by1)
    f2 = -(a_xx * bx2 + a_xy * by2)
    f3 = -(a_xx * bx3 + a_xy * by3)
    if axi:  # the hoop stress on h_i (0 in plane strain): -(a + b + c) = -(a + b) - c exactly
        a_tt = -(s_xx + s_yy) - ptot
        f0 -= a_tt * h0
        f1 -= a_tt * h1
        f2 -= a_tt * h2
        f3 -= a_tt * h3
    g0 = -(a_xy * bx0 + a_yy * by0)
    g1 = -(a_xy * bx1 + a_yy * by1)
    g2 = -(a_xy * bx2 + a_yy * by2)
    g3 = -(a_xy * bx3 + a_yy * by3)
    f0 += vf0
    f1 += vf1
    f2 += vf2
    f3 += vf3
    g0 += vg0
    g1 += vg1
    g2 += vg2
    g3 += vg3
    if on:
        f0 += sf0
        f1 += sf1
        f2 += sf2
        f3 += sf3
        g0 += sg0
        g1 += sg1
        g2 += sg2
        g3 += sg3
        vf0 += sf0
        vf1 += sf1
        vf2 += sf2
        vf3 += sf3
        vg0 += sg0
        vg1 += sg1
        vg2 += sg2
        vg3 += sg3
    return f0, f1, f2, f3, g0, g1, g2, g3, vf0, vf1, vf2, vf3, vg0, vg1, vg2, vg3


# the force pass works on blocks of FORCE_BLOCK cells; a block's scratch (the serial kernel's ``corner``
# argument, a row per thread of the parallel one's) holds FORCE_SCRATCH = 32 rows of FORCE_BLOCK values: the
# corners' x, y, vx, vy (rows 0-15), then their forces f, g and viscous forces vf, vg (rows 16-31)
FORCE_BLOCK = 64
FORCE_SCRATCH = 32 * FORCE_BLOCK
# the history sums (internal energy, leapfrog kinetic energy, viscous heat) add their terms per chunk of SUM_CHUNK
# cells or nodes (cells c with the same c >> SUM_SHIFT), then the chunks' sums in chunk order, in every kernel:
# a thread that owns whole chunks computes the same sums (module docstring, "Sums")
SUM_SHIFT = 6
SUM_CHUNK = 1 << SUM_SHIFT
assert SUM_CHUNK == FORCE_BLOCK


@njit(cache=True, error_model="numpy", **NO_REFCOUNT, **VECTORIZE)
def _force_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl, scq,
                 elastic_only, out):
    """:func:`cell_corner_forces` of cells c0 .. c0 + nb - 1, corners' node values from ``nodal``
    (row r = 4 (x, y, vx, vy) + corner, FORCE_BLOCK apart), forces into ``out`` (rows f0..f3, g0..g3,
    vf0..vf3, vg0..vg3).  No calls, exits or branches that LLVM cannot predicate (``axi``, ``qedge``
    constants; numpy's error model: no ZeroDivisionError exit, which the edge viscosity's 1/|dv| would
    keep, |dv| > 0 there), compiled with ``VECTORIZE``: a loop vectorized across cells."""
    B = FORCE_BLOCK
    for j in range(nb):
        c = np.uint64(c0 + j)
        r = np.uint64(j)
        xs = (nodal[r], nodal[r + B], nodal[r + 2 * B], nodal[r + 3 * B])
        ys = (nodal[r + 4 * B], nodal[r + 5 * B], nodal[r + 6 * B], nodal[r + 7 * B])
        us = (nodal[r + 8 * B], nodal[r + 9 * B], nodal[r + 10 * B], nodal[r + 11 * B])
        ws = (nodal[r + 12 * B], nodal[r + 13 * B], nodal[r + 14 * B], nodal[r + 15 * B])
        (out[r], out[r + B], out[r + 2 * B], out[r + 3 * B], out[r + 4 * B], out[r + 5 * B], out[r + 6 * B],
         out[r + 7 * B], out[r + 8 * B], out[r + 9 * B], out[r + 10 * B], out[r + 11 * B], out[r + 12 * B],
         out[r + 13 * B], out[r + 14 * B], out[r + 15 * B]) = cell_corner_forces(
            xs, ys, us, ws, sxx[c], syy[c], sxy[c], p[c], q[c], rho[c], cs[c], shear[c], yld[c], axi, hg, qedge, cq,
            cl, svisc, scl, scq, elastic_only)


@njit(cache=True, inline="always")
def _gather_block(conn, x, y, vx, vy, c0, nb, nodal):
    """The node values of cells c0 .. c0 + nb - 1's corners into ``nodal`` (row r = 4 (x, y, vx, vy) + corner,
    FORCE_BLOCK apart), for :func:`_force_block`."""
    B = FORCE_BLOCK
    for j in range(nb):
        c = np.uint64(c0 + j)
        for k in range(4):
            n = np.uint64(conn[c, k])
            nodal[j + k * B] = x[n]
            nodal[j + (4 + k) * B] = y[n]
            nodal[j + (8 + k) * B] = vx[n]
            nodal[j + (12 + k) * B] = vy[n]


@njit(cache=True, inline="always")
def _forces_of_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl,
                     scq, elastic_only, out):
    """:func:`_force_block` with the flags as constants (each case compiled apart, module docstring): a runtime
    flag keeps branches in the loop that LLVM does not vectorize."""
    if axi and qedge:
        _force_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, True, hg, True, cq, cl, svisc, scl,
                     scq, elastic_only, out)
    elif axi:
        _force_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, True, hg, False, cq, cl, svisc, scl,
                     scq, elastic_only, out)
    elif qedge:
        _force_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, False, hg, True, cq, cl, svisc, scl,
                     scq, elastic_only, out)
    else:
        _force_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, False, hg, False, cq, cl, svisc, scl,
                     scq, elastic_only, out)


@njit(cache=True, **NO_REFCOUNT)
def cell_forces_serial(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc,
                       scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, want_ie):
    """One pass over the cells for the nodal forces F^n (the cycle's step 1), serial:
    :func:`cell_corner_forces` per cell, the velocity-dependent part into ``vcorner[c, 0:8]`` (fx0..fx3,
    fy0..fy3) for the viscous heat, the forces summed into fx, fy in cell order (:func:`forces_of_cells`
    over all cells, fx and fy zeroed first).  Returns the internal energy sum_c m_c (e_c + e_el,c) at t^n
    when ``want_ie`` (else 0)."""
    for n in range(fx.shape[0]):
        fx[n] = 0.0
        fy[n] = 0.0
    return forces_of_cells(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl,
                           svisc, scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, want_ie, 0,
                           conn.shape[0], 0.0)


@njit(cache=True, **NO_REFCOUNT)
def forces_of_cells(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc,
                    scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, want_ie, start, stop, ie):
    """The serial force pass over cells start .. stop - 1, added into fx, fy: per block of
    FORCE_BLOCK cells, the corners' node values gathered into ``corner`` (the scratch,
    FORCE_SCRATCH values), the forces by :func:`_force_block` (vectorized across cells), then the
    velocity-dependent part into ``vcorner`` and the forces into the nodes in cell order.
    ``vcorner`` has a row per cell, or is a ring of R rows (cell c in row c mod R; R a multiple of
    FORCE_BLOCK, ``start`` one too: a block never wraps).  Returns ``ie`` + sum_c m_c (e_c + e_el,c)
    over the cells in cell order when ``want_ie`` (else ``ie``)."""
    B = FORCE_BLOCK
    nodal = corner[:16 * B]
    out = corner[16 * B:32 * B]
    ring = vcorner.shape[0]
    for c0 in range(start, stop, B):
        nb = min(B, stop - c0)
        _gather_block(conn, x, y, vx, vy, c0, nb, nodal)
        _forces_of_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl,
                         scq, elastic_only, out)
        r0 = c0 % ring
        blk = 0.0
        for j in range(nb):
            c = np.uint64(c0 + j)
            if want_ie:
                blk += cmass[c] * (e[c] + e_el[c])
            r = np.uint64(r0 + j)
            for k in range(8):
                vcorner[r, k] = out[j + (8 + k) * B]
            for k in range(4):
                fx[np.uint64(conn[c, k])] += out[j + k * B]
            for k in range(4):
                fy[np.uint64(conn[c, k])] += out[j + (4 + k) * B]
        ie += blk  # the sum of a block of SUM_CHUNK cells, then the blocks in order (module docstring, "Sums")
    return ie


@njit(cache=True, **NO_REFCOUNT)
def viscous_heat_serial(conn, vcorner, vx0, vy0, vx1, vy1, dt, cmass, e):
    """Put the work of the viscous corner forces over the velocity step, -dt f . (v^{n-1/2} +
    v^{n+1/2})/2, into each cell's energy (exactly the kinetic energy they removed); return the sum (per
    chunk of SUM_CHUNK cells, then the chunks in order: module docstring, "Sums").  (Used on the cycles
    that write a history row; otherwise the cell update does it.)"""
    total = 0.0
    nc = conn.shape[0]
    for c0 in range(0, nc, SUM_CHUNK):
        part = 0.0
        for c in range(c0, min(c0 + SUM_CHUNK, nc)):
            heat = viscous_cell_heat(conn, vcorner, vx0, vy0, vx1, vy1, dt, c)
            e[c] += heat * (1.0 / cmass[c])  # as the cell update: times 1/m
            part += heat
        total += part
    return total


@njit(cache=True, inline="always")
def viscous_cell_heat(conn, vcorner, vx0, vy0, vx1, vy1, dt, c):
    """-dt/2 sum_i f_i . (v_i^{n-1/2} + v_i^{n+1/2}) of cell c's viscous corner forces f_i."""
    w = 0.0
    for k in range(4):
        n = np.uint64(conn[c, k])
        w += vcorner[c, k] * (vx0[n] + vx1[n]) + vcorner[c, 4 + k] * (vy0[n] + vy1[n])
    return -0.5 * dt * w


@njit(cache=True, **NO_REFCOUNT)
def viscous_heat_sum(conn, vcorner, vx0, vy0, vx1, vy1, dt):
    """The sum of :func:`viscous_cell_heat` in the order of :func:`viscous_heat_serial` (per chunk, then the
    chunks in order)."""
    total = 0.0
    nc = conn.shape[0]
    for c0 in range(0, nc, SUM_CHUNK):
        part = 0.0
        for c in range(c0, min(c0 + SUM_CHUNK, nc)):
            part += viscous_cell_heat(conn, vcorner, vx0, vy0, vx1, vy1, dt, c)
        total += part
    return total


# --------------------------------------------------------------------------- nodes

@njit(cache=True, **NO_REFCOUNT)
def apply_constraints(vx, vy, vx_old, vy_old, mass_own, cnode, cnx, cny, cval, dt):
    """Project each constrained node: v <- v - (v.n - value) n, in list order.

    Returns the work of the reactions over the step, sum m dv . (v_old + v_new)/2,
    with v_old the velocity at the start of the step.
    """
    work = 0.0
    for k in range(cnode.shape[0]):
        n = cnode[k]
        d = vx[n] * cnx[k] + vy[n] * cny[k] - cval[k]
        if d != 0.0:
            dvx = -d * cnx[k]
            dvy = -d * cny[k]
            work += 0.5 * mass_own[n] * (dvx * (vx_old[n] + vx[n] + dvx) + dvy * (vy_old[n] + vy[n] + dvy))
            vx[n] += dvx
            vy[n] += dvy
    return work


@njit(inline="always")
def _jump_work(n, mass_own, vx_old, vy_old, jx, jy, jx_prev, jy_prev):
    """Node n's term m v^{n-1/2}.(J^n + J^{n-1}) of :func:`impulse_work` (twice the work); J^n kept in J_prev (the
    one body of :func:`impulse_work` and :func:`jump_works`; inlined into both)."""
    w = mass_own[n] * (vx_old[n] * (jx + jx_prev[n]) + vy_old[n] * (jy + jy_prev[n]))
    jx_prev[n] = jx
    jy_prev[n] = jy
    return w


@njit(cache=True, inline="always")
def _impulse_work_range(nodes, mass_own, vx_old, vy_old, vx, vy, vx_ref, vy_ref, jx_prev, jy_prev, carry, cx, cy,
                        k0, k1):
    w = 0.0
    for k in range(k0, k1):
        n = nodes[k]
        jx = vx[n] - vx_ref[n]
        jy = vy[n] - vy_ref[n]
        w += _jump_work(n, mass_own, vx_old, vy_old, jx, jy, jx_prev, jy_prev)
        if carry:
            cx[n] += jx
            cy[n] += jy
    return w


@njit(cache=True, **NO_REFCOUNT)
def impulse_work(nodes, mass_own, vx_old, vy_old, vx, vy, vx_ref, vy_ref, jx_prev, jy_prev, carry, cx, cy):
    """Kinetic-energy change that velocity jumps J = v - v_ref (constraints, interfaces) make in the
    leapfrog kinetic energy K^n = sum m v^{n-1/2}.v^{n+1/2}/2 at t^n: sum m v^{n-1/2}.(J^n + J^{n-1})/2
    over ``nodes`` (ascending; all nodes, or a set outside which J^n = J^{n-1} = 0), per chunk of SUM_CHUNK
    entries of ``nodes``, then the chunks in order (module docstring, "Sums").
    Copies J into J_prev for the next step; with ``carry`` also adds J to (cx, cy) (the interfaces'
    jumps carried into the reference of the constraints' jumps)."""
    w = 0.0
    m = nodes.shape[0]
    for k0 in range(0, m, SUM_CHUNK):
        w += _impulse_work_range(nodes, mass_own, vx_old, vy_old, vx, vy, vx_ref, vy_ref, jx_prev, jy_prev, carry, cx,
                                 cy, k0, min(k0 + SUM_CHUNK, m))
    return 0.5 * w


@njit(cache=True, parallel=True)
def impulse_work_parallel(nodes, mass_own, vx_old, vy_old, vx, vy, vx_ref, vy_ref, jx_prev, jy_prev, carry, cx, cy,
                          parts):
    """:func:`impulse_work`, chunks in parallel (the same sum; ``parts`` scratch of a value per chunk)."""
    m = nodes.shape[0]
    nch = (m + SUM_CHUNK - 1) >> SUM_SHIFT
    for i in prange(nch):
        parts[i] = _impulse_work_range(nodes, mass_own, vx_old, vy_old, vx, vy, vx_ref, vy_ref, jx_prev, jy_prev, carry,
                                       cx, cy, i << SUM_SHIFT, min((i + 1) << SUM_SHIFT, m))
    return 0.5 * chunk_total(parts, nch)


def _jump_works_impl(mass_own, vx_old, vy_old, vx, vy, vx_free, vy_free, jx_int, jy_int, vx_pre, vy_pre, jx_bc, jy_bc,
                     cnx, cny, cval, bc_nodes, bc_ptr, bc_cons, parts):
    """After the interfaces, over all nodes in one pass (chunks of SUM_CHUNK nodes; in parallel in the twin):
    the interfaces' jumps' work (:func:`impulse_work` of J = v - v_free, carried into (vx_pre, vy_pre)), the
    constraints (:func:`apply_constraints`, each node's in list order: ``bc_cons[bc_ptr[k]:bc_ptr[k + 1]]`` of
    ``bc_nodes[k]``), then the constraints' jumps' work (:func:`impulse_work` of J = v - v_pre).  Per node the
    operations of those three calls in their order, so the same bytes; the two works per chunk into ``parts[0]``
    and ``parts[1]``, then the chunks in order.  Returns (interface work, boundary work)."""
    nn = vx.shape[0]
    nch = (nn + SUM_CHUNK - 1) >> SUM_SHIFT
    nbc = bc_nodes.shape[0]
    for i in prange(nch):
        n0 = i << SUM_SHIFT
        kb = np.searchsorted(bc_nodes, n0)
        nxt = bc_nodes[kb] if kb < nbc else -1
        wi = 0.0
        wb = 0.0
        for n in range(n0, min(n0 + SUM_CHUNK, nn)):
            u = vx[n]
            w = vy[n]
            jx = u - vx_free[n]
            jy = w - vy_free[n]
            wi += _jump_work(n, mass_own, vx_old, vy_old, jx, jy, jx_int, jy_int)
            px = vx_pre[n] + jx
            py = vy_pre[n] + jy
            vx_pre[n] = px
            vy_pre[n] = py
            if n == nxt:
                u, w = _project_node(u, w, bc_ptr[kb], bc_ptr[kb + 1], bc_cons, cnx, cny, cval)
                vx[n] = u
                vy[n] = w
                kb += 1
                nxt = bc_nodes[kb] if kb < nbc else -1
            wb += _jump_work(n, mass_own, vx_old, vy_old, u - px, w - py, jx_bc, jy_bc)
        parts[0, i] = wi
        parts[1, i] = wb
    return 0.5 * chunk_total(parts[0], nch), 0.5 * chunk_total(parts[1], nch)


jump_works = njit(cache=True, **NO_REFCOUNT)(_jump_works_impl)
jump_works_parallel = njit(cache=True, parallel=True)(_twin(_jump_works_impl, "_parallel"))


@njit(inline="always")
def _shift_node(x, y, sx, sy, fx, fy, mass_own, mass, moved, n):
    """Node n: x^n moved by its position shift (sx, sy), the shift zeroed, ``moved[n]`` whether it moved; returns
    (m_own/m) F . dx (the one body of :func:`shift_nodes` and :func:`shift_listed_nodes`)."""
    u = sx[n]
    w = sy[n]
    moved[n] = u != 0.0 or w != 0.0
    x[n] += u
    y[n] += w
    sx[n] = 0.0
    sy[n] = 0.0
    return mass_own[n] / mass[n] * (fx[n] * u + fy[n] * w)


def _shift_nodes_impl(x, y, sx, sy, fx, fy, mass_own, mass, parts, moved):
    """Move x^n by the position shifts (sx, sy) and zero them; returns sum (m_own/m) F . dx (per chunk of
    SUM_CHUNK nodes, then the chunks in order: module docstring, "Sums").  moved[n]: whether node n moved."""
    nn = x.shape[0]
    nch = (nn + SUM_CHUNK - 1) >> SUM_SHIFT
    for i in prange(nch):
        part = 0.0
        for n in range(i << SUM_SHIFT, min((i + 1) << SUM_SHIFT, nn)):
            part += _shift_node(x, y, sx, sy, fx, fy, mass_own, mass, moved, n)
        parts[i] = part
    t = 0.0
    for i in range(nch):
        t += parts[i]
    return t


@njit(cache=True, **NO_REFCOUNT)
def shift_listed_nodes(x, y, sx, sy, fx, fy, mass_own, mass, nodes, moved):
    """:func:`shift_nodes` on the listed ``nodes`` only (ascending; every node whose shift may be non-zero, the
    others' x^n, shifts and ``moved`` flags stay as they are).  The same sum: a node left out adds (m_own/m) F . 0
    = +-0 to its chunk's part, which changes no part (a part is never -0: it starts at +0 and exact cancellation
    rounds to +0), and a chunk with no listed node adds its part +0 to the total, which changes nothing either."""
    t = 0.0
    part = 0.0
    chunk = -1
    for k in range(nodes.shape[0]):
        n = nodes[k]
        if n >> SUM_SHIFT != chunk:
            t += part
            part = 0.0
            chunk = n >> SUM_SHIFT
        part += _shift_node(x, y, sx, sy, fx, fy, mass_own, mass, moved, n)
    return t + part


@njit(cache=True, **NO_REFCOUNT)
def sum_groups(fx, fy, grp_ptr, grp_nodes):
    """Sum the forces of each node group (tie, periodic pair) and give the sum to every member."""
    for g in range(grp_ptr.shape[0] - 1):
        sx = 0.0
        sy = 0.0
        for k in range(grp_ptr[g], grp_ptr[g + 1]):
            sx += fx[grp_nodes[k]]
            sy += fy[grp_nodes[k]]
        for k in range(grp_ptr[g], grp_ptr[g + 1]):
            fx[grp_nodes[k]] = sx
            fy[grp_nodes[k]] = sy


@njit(cache=True, **NO_REFCOUNT)
def sync_groups(vx, vy, vx_ref, vy_ref, grp_ptr, grp_nodes):
    """Give every member of a group the sum of the members' velocity changes since (vx_ref, vy_ref).

    Interfaces apply impulses J to one member as J/m_group, so the summed change is
    the group's change (momentum is kept)."""
    for g in range(grp_ptr.shape[0] - 1):
        dx = 0.0
        dy = 0.0
        for k in range(grp_ptr[g], grp_ptr[g + 1]):
            n = grp_nodes[k]
            dx += vx[n] - vx_ref[n]
            dy += vy[n] - vy_ref[n]
        for k in range(grp_ptr[g], grp_ptr[g + 1]):
            n = grp_nodes[k]
            vx[n] = vx_ref[n] + dx
            vy[n] = vy_ref[n] + dy


@njit(inline="always")
def _project_node(u, w, j0, j1, bc_cons, cnx, cny, cval):
    """(u, w) projected onto the node's constraints bc_cons[j0:j1] in turn, n_k . v = cval_k (the one body of the
    jump pass and the plain node pass; inlined into both)."""
    for j in range(j0, j1):
        k = bc_cons[j]
        d = u * cnx[k] + w * cny[k] - cval[k]
        if d != 0.0:
            u += -d * cnx[k]
            w += -d * cny[k]
    return u, w


@njit(inline="always")
def _advance_node(vx, vy, fx, fy, mass, dt, vx_old, vy_old, vx_pre, vy_pre, keep_pre, n):
    """Node n: v* = v + dt F/m, v kept in (vx_old, vy_old) and, with ``keep_pre``, v* in (vx_pre, vy_pre) (the one
    body of :func:`advance_velocities` and :func:`border_velocities_parallel`; inlined into both)."""
    u = vx[n]
    w = vy[n]
    vx_old[n] = u
    vy_old[n] = w
    a = dt / mass[n]
    u += a * fx[n]
    w += a * fy[n]
    vx[n] = u
    vy[n] = w
    if keep_pre:
        vx_pre[n] = u
        vy_pre[n] = w


def _advance_velocities(vx, vy, fx, fy, mass, dt, vx_old, vy_old, vx_pre, vy_pre, keep_pre):
    """v* = v + dt F/m (m: the group mass of the node); v is kept in (vx_old, vy_old) and, with
    ``keep_pre``, v* in (vx_pre, vy_pre) (the velocities before the constraints)."""
    for n in prange(vx.shape[0]):
        _advance_node(vx, vy, fx, fy, mass, dt, vx_old, vy_old, vx_pre, vy_pre, keep_pre, n)


def _move_nodes(x, y, vx, vy, dt, x_half, y_half):
    """x^{n+1} = x^n + dt v^{n+1/2}, and the mid-step positions x^{n+1/2} = (x^n + x^{n+1})/2 into
    (x_half, y_half) for the cell update (once per node, not per corner)."""
    for n in prange(x.shape[0]):
        u = x[n]
        w = y[n]
        u1 = u + dt * vx[n]
        w1 = w + dt * vy[n]
        x[n] = u1
        y[n] = w1
        x_half[n] = 0.5 * (u + u1)
        y_half[n] = 0.5 * (w + w1)


advance_velocities = njit(cache=True, **NO_REFCOUNT)(_advance_velocities)
advance_velocities_parallel = njit(cache=True, parallel=True)(_twin(_advance_velocities, "_parallel"))
move_nodes = njit(cache=True, **NO_REFCOUNT)(_move_nodes)
shift_nodes = njit(cache=True, **NO_REFCOUNT)(_shift_nodes_impl)
shift_nodes_parallel = njit(cache=True, parallel=True)(_twin(_shift_nodes_impl, "_parallel"))
move_nodes_parallel = njit(cache=True, parallel=True)(_twin(_move_nodes, "_parallel"))


@njit(cache=True, **NO_REFCOUNT)
def any_shifted(sx, sy, nodes):
    """True when a position shift (sx, sy) of one of ``nodes`` is not zero (stops at the first one)."""
    for k in range(nodes.shape[0]):
        n = nodes[k]
        if sx[n] != 0.0 or sy[n] != 0.0:
            return True
    return False


def _shifted_volumes_impl(conn, moved, x, y, axi, out, cells):
    """out[c] = the volume of cell c at (x, y) for each listed cell c (``cells``: every cell, or those touching a
    node that a shift may move) with a node marked in ``moved`` (others untouched): the cells that a position shift
    moved (:func:`cell_volumes`' arithmetic, in blocks of 1024 listed cells)."""
    nc = cells.shape[0]
    nch = (nc + 1023) >> 10
    for i in prange(nch):
        xs = np.empty(4)
        ys = np.empty(4)
        bx = np.empty(4)
        by = np.empty(4)
        hh = np.empty(4)
        for k in range(i << 10, min((i + 1) << 10, nc)):
            c = cells[k]
            if moved[conn[c, 0]] or moved[conn[c, 1]] or moved[conn[c, 2]] or moved[conn[c, 3]]:
                for j in range(4):
                    xs[j] = x[conn[c, j]]
                    ys[j] = y[conn[c, j]]
                out[c] = bvectors(xs, ys, axi, bx, by, hh)


shifted_volumes = njit(cache=True)(_shifted_volumes_impl)
shifted_volumes_parallel = njit(cache=True, parallel=True)(_twin(_shifted_volumes_impl, "_parallel"))


@njit(cache=True, **NO_REFCOUNT)
def kinetic_energy(vx, vy, mass_own):
    s = 0.0
    for n in range(vx.shape[0]):
        s += mass_own[n] * (vx[n] * vx[n] + vy[n] * vy[n])
    return 0.5 * s


@njit(cache=True, **NO_REFCOUNT)
def kinetic_energy_product(vx0, vy0, vx1, vy1, mass_own):
    """Leapfrog kinetic energy at t^n: sum m v^{n-1/2}.v^{n+1/2} / 2 (per chunk of SUM_CHUNK nodes, then the
    chunks in order: module docstring, "Sums")."""
    s = 0.0
    nn = vx0.shape[0]
    for n0 in range(0, nn, SUM_CHUNK):
        part = 0.0
        for n in range(n0, min(n0 + SUM_CHUNK, nn)):
            part += mass_own[n] * (vx0[n] * vx1[n] + vy0[n] * vy1[n])
        s += part
    return 0.5 * s


@njit(cache=True, **NO_REFCOUNT)
def momentum(vx, vy, mass_own):
    px = 0.0
    py = 0.0
    for n in range(vx.shape[0]):
        px += mass_own[n] * vx[n]
        py += mass_own[n] * vy[n]
    return px, py


@njit(cache=True, **NO_REFCOUNT)
def internal_energy(e, e_el, cmass):
    s = 0.0
    for c in range(e.shape[0]):
        s += cmass[c] * (e[c] + e_el[c])
    return s


# --------------------------------------------------------------------------- cells

@njit(cache=True, inline="always")
def energy_pressure(et, p0, qmid, dv, a, b, pfloor):
    """(e, P) at n+1 from P = A + B e and e = e~ - ((P^n + q) + P)/2 dv (q: the mid-step q
    ``qmid`` counted once), P floored at ``pfloor`` (then e from the floored P)."""
    e1 = (et - (0.5 * p0 + qmid) * dv - 0.5 * a * dv) / (1.0 + 0.5 * b * dv)
    p1 = a + b * e1
    if p1 < pfloor:
        p1 = pfloor
        e1 = et - (0.5 * (p0 + p1) + qmid) * dv
    return e1, p1


@njit(cache=True, inline="always")
def material_run_end(mat, c0, nc):
    """The end of the run of cells c0, c0 + 1, ... (unsigned) of material mat[c0]: any cell order is
    right, and a body whose cells are consecutive is one run."""
    c = c0 + np.uint64(1)
    while c < nc and mat[c] == mat[c0]:
        c += np.uint64(1)
    return c


UPDATE_BLOCK = 2048  # cells per block of the serial update (update_serial)


def _update_cells_impl(conn, xha, yha, x1a, y1a, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q,
                       sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell,
                       qedge, dmg, heat_now, vcorner, vx_old, vy_old, dtv, work, mrec, qv0, qparts):
    """The cycle's cell pass (step 6): advance every cell from t^n to t^{n+1}.

    Per cell: volume and density at n+1, strain rate at x^{n+1/2}, Jaumann rotation and radial
    return, artificial viscosity q^{n+1/2}, energy with the EOS, spall damage, temperature,
    moduli, flow stress, sound speed and the stable step dtcell[c].  With ``heat_now`` it first
    puts the viscous corner forces' work over the velocity step dtv into e (what
    :func:`viscous_heat_serial` does on history cycles: :func:`viscous_cell_heat`).
    With ``qedge`` the artificial viscosity is the edge viscosity of the force kernel (q = 0 here).
    ``dmg``: spall damage, the cell failed when >= 1 (no deviator, no tension; hydro/spall.py).
    (xha, yha): the mid-step node positions x^{n+1/2} (:func:`move_nodes`), (x1a, y1a): x^{n+1}.
    Returns (min stable dt, first bad cell or -1, its error code, qv0 + the viscous heat put in);
    the heat is summed per chunk of SUM_CHUNK cells (chunk i's sum into ``qparts[i]``), the chunks added to qv0
    in order (module docstring, "Sums");
    errcell[c] holds the code of a bad cell (only bad cells are written).

    Four loops over the cells, each a short chain of dependent divisions and roots that the
    processor overlaps across cells (one loop would be one ~300-clock chain per cell): (1)
    geometry, strain rate and q, (2) deviator, (3) energy, EOS, spall, temperature, (4) moduli,
    flow stress, sound speed, stable step.  Loops 3 and 4 run over each run of cells of one
    material (:func:`material_run_end`) with its parameters in registers and without branches
    or libm calls, so that LLVM vectorises them across cells (SIMD); loop 3's spall update
    (materials with spall only) and its temperature look-up (a table gather) are scalar loops of
    their own after it.  A bad cell's e, P and c are then written too (its error aborts the run).
    Compiled with ``error_model="numpy"`` (a division by zero gives inf/NaN, caught as a bad
    cell, instead of a ZeroDivisionError check that would stop the vectoriser).
    ``work`` (11, cells) carries the values handed from one loop to the next (tr D, dv/m, e~,
    q mid-step, D, spin, 1/rho^{n+1/2}, 1/rho^{n+1}; P^n in the row of D_xx for loop 3's spall
    step), stored exactly.  Divisions are few (docs/theory/fused-cycle.md): 1/m, 1/V^{n+1/2} and rho^{n+1} = m/V^{n+1}
    per cell, the rest are products with them and with the per-material reciprocals that the kernel
    first puts in ``mrec`` (bodies, 4): 1/G0, 1/rho0, (table size - 1)/(mu_hi - mu_lo), 1/c_v."""
    ntab = table.shape[1]
    nc = conn.shape[0]
    bad = nc
    qv = qv0
    qp = 0.0  # the viscous heat of this chunk of SUM_CHUNK cells
    for m in range(props.shape[0]):
        g0m = props[m, P_G0]
        mrec[m, R_IG0] = 1.0 / g0m if g0m != 0.0 else 0.0
        mrec[m, R_IRHO0] = 1.0 / props[m, P_RHO0] if props[m, P_RHO0] != 0.0 else 0.0
        span = props[m, P_MU_HI] - props[m, P_MU_LO]
        mrec[m, R_TSCALE] = (ntab - 1) / span if span != 0.0 else 0.0
        mrec[m, R_ICV] = 1.0 / props[m, P_CV]
    for c in range(nc):
        if c > 0 and (c & (SUM_CHUNK - 1)) == 0:
            qparts[(c >> SUM_SHIFT) - 1] = qp
            qv += qp
            qp = 0.0
        cm = cmass[c]
        im = 1.0 / cm
        # the viscous heat (loads only: the node values stay in registers for the strain rate below)
        hc = viscous_cell_heat(conn, vcorner, vx_old, vy_old, vx, vy, dtv, c) if heat_now else 0.0
        n0 = np.uint64(conn[c, 0])
        n1 = np.uint64(conn[c, 1])
        n2 = np.uint64(conn[c, 2])
        n3 = np.uint64(conn[c, 3])
        # ---- geometry at n+1
        xa0 = x1a[n0]
        xa1 = x1a[n1]
        xa2 = x1a[n2]
        xa3 = x1a[n3]
        ya0 = y1a[n0]
        ya1 = y1a[n1]
        ya2 = y1a[n2]
        ya3 = y1a[n3]
        jmin = min_jacobian(xa0, xa1, xa2, xa3, ya0, ya1, ya2, ya3)
        area1 = quad_area(xa0, xa1, xa2, xa3, ya0, ya1, ya2, ya3)
        d1 = (xa2 - xa0) ** 2 + (ya2 - ya0) ** 2
        d2 = (xa3 - xa1) ** 2 + (ya3 - ya1) ** 2
        dmax = math.sqrt(d1 if d1 > d2 else d2)
        if axi:
            v1 = axi_volume(xa0, xa1, xa2, xa3, ya0, ya1, ya2, ya3)
        else:
            v1 = area1
        if not (jmin > 0.0 and v1 > 0.0):
            if heat_now:
                e[c] += hc * im
                qp += hc
            dtcell[c] = 1e300
            if math.isnan(jmin) or math.isnan(v1):
                errcell[c] = ERR_NAN
            else:
                errcell[c] = ERR_INVERTED
            bad = min(bad, c)
            continue
        # ---- geometry at n+1/2 and strain rate
        xh0 = xha[n0]
        xh1 = xha[n1]
        xh2 = xha[n2]
        xh3 = xha[n3]
        yh0 = yha[n0]
        yh1 = yha[n1]
        yh2 = yha[n2]
        yh3 = yha[n3]
        if axi:
            bx0, bx1, bx2, bx3, by0, by1, by2, by3, h0, h1, h2, h3, vh = bvec_axi(xh0, xh1, xh2, xh3,
                                                                                  yh0, yh1, yh2, yh3)
        else:
            bx0, bx1, bx2, bx3, by0, by1, by2, by3, vh = bvec_planar(xh0, xh1, xh2, xh3, yh0, yh1, yh2, yh3)
            h0 = h1 = h2 = h3 = 0.0
        u0 = vx[n0]
        u1 = vx[n1]
        u2 = vx[n2]
        u3 = vx[n3]
        w0 = vy[n0]
        w1 = vy[n1]
        w2 = vy[n2]
        w3 = vy[n3]
        inv = 1.0 / vh
        dxx = (bx0 * u0 + bx1 * u1 + bx2 * u2 + bx3 * u3) * inv
        dyy = (by0 * w0 + by1 * w1 + by2 * w2 + by3 * w3) * inv
        dtt = (h0 * u0 + h1 * u1 + h2 * u2 + h3 * u3) * inv if axi else 0.0
        uy = (by0 * u0 + by1 * u1 + by2 * u2 + by3 * u3) * inv
        vxg = (bx0 * w0 + bx1 * w1 + bx2 * w2 + bx3 * w3) * inv
        dxy = 0.5 * (uy + vxg)
        spin = 0.5 * (uy - vxg)
        trd = dxx + dyy + dtt
        v0 = vol[c]
        rho1 = cm / v1
        rhoh = cm * inv
        work[4, c] = dxx
        work[5, c] = dyy
        work[6, c] = dtt
        work[7, c] = dxy
        work[8, c] = spin
        work[9, c] = vh * im  # 1/rho^{n+1/2}
        work[10, c] = v1 * im  # 1/rho^{n+1}
        # ---- artificial viscosity q^{n+1/2} (compression only), length along the compression
        qn = 0.0
        if trd < 0.0 and not qedge:
            cmid = 0.5 * (dxx + dyy)
            rr = math.sqrt(0.25 * (dxx - dyy) ** 2 + dxy * dxy)
            lq = -1.0
            if rr > 1e-12 * (abs(cmid) + 1e-300):
                lmax = cmid + rr
                ax = dxy
                ay = lmax - dxx
                bxv = lmax - dyy
                byv = dxy
                if ax * ax + ay * ay >= bxv * bxv + byv * byv:
                    tx = ax
                    ty = ay
                else:
                    tx = bxv
                    ty = byv
                # width across t (|t| times the width along the unnormalised t); lq = A / width
                tn = math.sqrt(tx * tx + ty * ty)
                p0_ = tx * xa0 + ty * ya0
                p1_ = tx * xa1 + ty * ya1
                p2_ = tx * xa2 + ty * ya2
                p3_ = tx * xa3 + ty * ya3
                width = max(max(p0_, p1_), max(p2_, p3_)) - min(min(p0_, p1_), min(p2_, p3_))
                if width > 0.0:
                    lq = area1 * tn / width
                    if lq > dmax:
                        lq = dmax
            if lq < 0.0:
                lq = math.sqrt(area1)
            qn = rhoh * (cq * cq * lq * lq * trd * trd - cl * cs[c] * lq * trd)
        # ---- kept for the next loops: dv, q^n (mid-step), tr D, CFL length
        vol[c] = v1
        rho[c] = rho1
        work[1, c] = (v1 - v0) * im
        work[3, c] = 0.5 * (q[c] + qn)
        q[c] = qn
        work[0, c] = trd
        dtcell[c] = area1 / dmax
        if heat_now:
            e[c] += hc * im
            qp += hc
    if nc > 0:
        qparts[(nc - 1) >> SUM_SHIFT] = qp
        qv += qp
    if bad < nc:
        return 0.0, bad, errcell[bad], qv
    # second loop: deviatoric stress (rotation, predictor, radial return), e~ = e + plastic heat
    for c in range(nc):
        m = np.uint64(mat[c])
        dxx = work[4, c]
        dyy = work[5, c]
        dtt = work[6, c]
        dxy = work[7, c]
        spin = work[8, c]
        irhoh = work[9, c]
        trd = work[0, c]
        skind = props[m, P_STRENGTH]
        sg0 = props[m, P_G0]
        gconst = props[m, P_G_CONST]
        y_epp = props[m, P_Y0]
        sy0 = props[m, P_SCG + I_Y0]
        sbeta = props[m, P_SCG + I_BETA]
        sn = props[m, P_SCG + I_N]
        symax = props[m, P_SCG + I_YMAX]
        # ---- deviatoric stress: rotation, predictor, radial return
        heat = 0.0
        hnew = 0.0
        failed = dmg[c] >= 1.0
        if skind != STRENGTH_NONE and not failed:
            # shear[c] holds G(P^n, T^n) (physical SCG modulus; G0 for EPP), set at the end of the last update
            if skind == STRENGTH_EPP:
                ratio = 1.0
                g = sg0
            else:
                ratio = shear[c] * mrec[m, R_IG0]
                g = sg0 if (gconst != 0.0 and ratio > 0.0) else shear[c]
            r_xx, r_yy, r_xy = rotate_deviator(sxx[c], syy[c], sxy[c], spin, dt)
            dm = trd * (1.0 / 3.0)
            t_xx = r_xx + 2.0 * g * dt * (dxx - dm)
            t_yy = r_yy + 2.0 * g * dt * (dyy - dm)
            t_xy = r_xy + 2.0 * g * dt * dxy
            n_xx, n_yy, n_xy, deps, yv, hnew = radial_return_s(t_xx, t_yy, t_xy, eps_p[c], g, ratio, skind, y_epp,
                                                               sy0, sbeta, sn, symax, yld[c])
            # deviatoric work per unit mass with S^{n+1/2} = (S~^n + S^{n+1})/2
            m_xx = 0.5 * (r_xx + n_xx)
            m_yy = 0.5 * (r_yy + n_yy)
            m_xy = 0.5 * (r_xy + n_xy)
            wdev = (m_xx * dxx + m_yy * dyy - (m_xx + m_yy) * dtt + 2.0 * m_xy * dxy) * dt * irhoh
            heat = yv * deps * irhoh
            sxx[c] = n_xx
            syy[c] = n_yy
            sxy[c] = n_xy
            eps_p[c] += deps
            eel = e_el[c] + wdev - heat
            if n_xx == 0.0 and n_yy == 0.0 and n_xy == 0.0:
                # no deviator left (melted): the stored shear energy is released as heat
                heat += eel
                eel = 0.0
            e_el[c] = eel
        work[2, c] = e[c] + heat
        if skind != STRENGTH_NONE and skind != STRENGTH_EPP and not failed:
            yld[c] = hnew  # (SCG) times G(P, T)/G0 in the last loop
    # third loop: energy and pressure, bulk sound speed, over each run of cells of one material with
    # its parameters in registers (vectorised across cells like the last loop); then, for a material
    # with spall, the cells that fail now (scalar); then temperature (a table look-up: scalar)
    ncu = np.uint64(nc)  # unsigned cell numbers: no negative-index wraparound, LLVM sees unit strides
    c0 = np.uint64(0)
    while c0 < ncu:
        m = np.uint64(mat[c0])
        c_end = material_run_end(mat, c0, ncu)
        ekind = props[m, P_EOS]
        rho0 = props[m, P_RHO0]
        snd0 = props[m, P_C0]
        s_ = props[m, P_S]
        g0 = props[m, P_GAMMA0]
        gam = props[m, P_GAMMA]
        irho0 = mrec[m, R_IRHO0]
        pmin = props[m, P_PMIN]
        for c in range(c0, c_end):
            rho1 = rho[c]
            irho1 = work[10, c]
            # thesis eq. 3.18 with errata, q time-centred as the forces see it:
            # e1 = e~ - ((P^n + q^{n-1/2}) + (P^{n+1} + q^{n+1/2}))/2 dv
            a, b, da = eos_ab_r(rho1, irho1, rho0 * irho1, rho1 * irho0, ekind, rho0, snd0, s_, g0, gam)
            pfloor = 0.0 if (dmg[c] >= 1.0 and pmin < 0.0) else pmin  # a failed cell carries no tension
            p0 = p[c]
            e1, p1 = energy_pressure(work[2, c], p0, work[3, c], work[1, c], a, b, pfloor)
            work[4, c] = p0  # P^n, for a cell that fails now
            e[c] = e1
            p[c] = p1
            cs[c] = sound_speed2_ab(irho1, p1, ekind, snd0, b, da)  # bulk c^2, the last loop adds the shear part
        spk = props[m, P_SPALL]
        if spk != SPALL_NONE:
            for c in range(c0, c_end):
                if dmg[c] >= 1.0:  # failed before
                    continue
                dnew = spall_damage(spk, dmg[c], p[c], sxx[c], syy[c], sxy[c], dt, props[m, P_PSPALL],
                                    props[m, P_TB_SIGMA0], props[m, P_TB_LAMBDA], props[m, P_TB_K])
                if dnew >= 1.0:
                    # the cell fails now: its deviator and stored shear energy (as heat) are released,
                    # and the EOS update is redone with no tension (the released energy stays in e)
                    dnew = 1.0
                    et = work[2, c] + e_el[c]
                    e_el[c] = 0.0
                    sxx[c] = 0.0
                    syy[c] = 0.0
                    sxy[c] = 0.0
                    rho1 = rho[c]
                    irho1 = work[10, c]
                    a, b, da = eos_ab_r(rho1, irho1, rho0 * irho1, rho1 * irho0, ekind, rho0, snd0, s_, g0, gam)
                    e1, p1 = energy_pressure(et, work[4, c], work[3, c], work[1, c], a, b, max(pmin, 0.0))
                    e[c] = e1
                    p[c] = p1
                    cs[c] = sound_speed2_ab(irho1, p1, ekind, snd0, b, da)
                dmg[c] = dnew
        c0 = c_end
    for c in range(nc):
        m = np.uint64(mat[c])
        e1 = e[c]
        if not (math.isfinite(e1) and math.isfinite(p[c])):
            errcell[c] = ERR_NAN
            bad = min(bad, c)
            continue
        # ---- temperature: T0 + (e - e_s(mu))/cv, or e/cv (ideal gas)
        if props[m, P_EOS] == EOS_IDEAL_GAS:
            t1 = e1 * mrec[m, R_ICV]
        else:
            f = (rho[c] * mrec[m, R_IRHO0] - 1.0 - props[m, P_MU_LO]) * mrec[m, R_TSCALE]
            if f <= 0.0:
                es = table[m, 0]
            elif f >= ntab - 1:
                es = table[m, ntab - 1]
            else:
                k = int(f)
                wt = f - k
                es = (1.0 - wt) * table[m, k] + wt * table[m, k + 1]
            t1 = props[m, P_T0] + (e1 - es) * mrec[m, R_ICV]
        temp[c] = t1
    if bad < nc:
        return 0.0, bad, errcell[bad], qv
    # last loop: moduli, flow stress, sound speed at n+1 and the stable time step of the cell, over
    # each run of cells of one material with its parameters in registers: no branches, no libm call,
    # so that LLVM vectorises it across cells (docs/theory/fused-cycle.md, fifth look)
    dtbits = f64_bits(1e300)  # min dtcell
    c0 = np.uint64(0)
    while c0 < ncu:
        m = np.uint64(mat[c0])
        c_end = material_run_end(mat, c0, ncu)
        skind = props[m, P_STRENGTH]
        sg0 = props[m, P_G0]
        y_epp = props[m, P_Y0]
        gconst = props[m, P_G_CONST] != 0.0
        sg = props[m, P_SCG + I_G]
        sh = props[m, P_SCG + I_H]
        sxi = props[m, P_SCG + I_XI]
        stf = props[m, P_SCG + I_TF]
        for c in range(c0, c_end):
            c2 = cs[c]
            irho1 = work[10, c]
            # G(P, T)/G0 in every cell (selects below, no branch per cell)
            ratio1 = scg_shear_ratio_simd(p[c], temp[c], sg, sh, sxi, stf)
            if skind == STRENGTH_EPP:
                g_c = sg0
                y_c = y_epp
                gpred = sg0  # G of the next predictor (the shear part of c^2)
            elif skind != STRENGTH_NONE:
                g_c = sg0 * ratio1
                y_c = yld[c] * ratio1
                gpred = sg0 if (gconst and ratio1 > 0.0) else g_c
            else:
                g_c = shear[c]
                y_c = yld[c]
                gpred = 0.0
            if dmg[c] >= 1.0:  # failed
                g_c = 0.0
                y_c = 0.0
                gpred = 0.0
            shear[c] = g_c
            yld[c] = y_c
            c2 += (4.0 / 3.0) * gpred * irho1  # + 0 exactly without strength
            c1 = math.sqrt(c2)
            cs[c] = c1
            lcfl = dtcell[c]
            trd = work[0, c]
            # aq = 0 in expansion (no branch: the sign of a resting cell's tr D is round-off)
            aq = cq * cq * lcfl * max(-trd, 0.0) + (cl * c1 if trd < 0.0 else 0.0)
            dtc = cfl * lcfl / (aq + math.sqrt(aq * aq + c2))
            atr = abs(trd)
            if dvmax < dtc * atr:  # the volume-change cap dvmax/|tr D| is the smaller
                dtc = dvmax / atr
            dtcell[c] = dtc
            dtbits = min(dtbits, f64_bits(dtc))  # dtc > 0: the order of its bits (jit_bits)
        c0 = c_end
    return f64_from_bits(dtbits), -1, ERR_NONE, qv


update_cells_serial = njit(cache=True, error_model="numpy", **NO_REFCOUNT)(_update_cells_impl)


@njit(cache=True, **NO_REFCOUNT)
def advance_nodes(vx, vy, fx, fy, mass, dtv, vx_old, vy_old, vx_pre, vy_pre, mass_own, cnx, cny, cval, bc_nodes,
                  bc_ptr, bc_cons, record, x, y, dt, x_half, y_half, start, stop, kb, s, part):
    """Steps 3 and 5 on nodes start .. stop - 1, node by node: :func:`advance_velocities`, on a
    constrained node v* into (vx_pre, vy_pre) and its constraints (:func:`apply_constraints`, in
    list order), with ``record`` the node's term of :func:`kinetic_energy_product` (times 2) added
    to ``s`` in node order, then :func:`move_nodes`.  The same operations in the same order per node
    as those kernels.  ``bc_nodes`` (ascending) are the constrained nodes,
    ``bc_cons[bc_ptr[k]:bc_ptr[k + 1]]`` the constraints of ``bc_nodes[k]`` in list order, ``kb``
    the first of them at or after ``start``.  The kinetic energy terms are summed per chunk of SUM_CHUNK nodes
    (``part``, the chunk of ``start`` so far), each chunk's sum added to ``s`` when the next chunk begins (the
    last one by the caller): module docstring, "Sums".  Returns (s, part, kb at ``stop``)."""
    nb = bc_nodes.shape[0]
    nxt = bc_nodes[kb] if kb < nb else -1
    for n in range(start, stop):
        u = vx[n]
        w = vy[n]
        vx_old[n] = u
        vy_old[n] = w
        a = dtv / mass[n]
        u1 = u + a * fx[n]
        w1 = w + a * fy[n]
        if n == nxt:
            vx_pre[n] = u1
            vy_pre[n] = w1
            u1, w1 = _project_node(u1, w1, bc_ptr[kb], bc_ptr[kb + 1], bc_cons, cnx, cny, cval)
            kb += 1
            nxt = bc_nodes[kb] if kb < nb else -1
        vx[n] = u1
        vy[n] = w1
        if record:
            if (n & (SUM_CHUNK - 1)) == 0:
                s += part
                part = 0.0
            part += mass_own[n] * (u * u1 + w * w1)
        p = x[n]
        r = y[n]
        p1 = p + dt * u1
        r1 = r + dt * w1
        x[n] = p1
        y[n] = r1
        x_half[n] = 0.5 * (p + p1)
        y_half[n] = 0.5 * (r + r1)
    return s, part, kb


@njit(cache=True, **NO_REFCOUNT)
def update_serial(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx, syy,
                  sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg,
                  heat_now, vcorner, vx_old, vy_old, dtv, work, mrec, qparts):
    """:func:`update_cells_serial` over blocks of ``UPDATE_BLOCK`` cells (:func:`update_blocks` over all of
    them), so that the values its four loops hand on (``work``, (11, >= min(cells, UPDATE_BLOCK))) and the
    cell arrays they share stay in cache.  Returns (min stable dt, first bad cell or -1, its code, viscous
    heat)."""
    nb = (conn.shape[0] + UPDATE_BLOCK - 1) // UPDATE_BLOCK
    dtmin, bad, code, qv = update_blocks(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e,
                                         e_el, p, q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl,
                                         dvmax, dtcell, errcell, qedge, dmg, heat_now, vcorner, vx_old, vy_old, dtv,
                                         work, mrec, 0, nb, 1e300, -1, ERR_NONE, 0.0, qparts)
    if bad >= 0:
        dtmin = 0.0
    return dtmin, bad, code, qv


@njit(cache=True, **NO_REFCOUNT)
def update_blocks(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx, syy,
                  sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg,
                  heat_now, vcorner, vx_old, vy_old, dtv, work, mrec, start, stop, dtmin, bad, code, qv, qparts):
    """:func:`update_cells_serial` over the blocks start .. stop - 1 of ``UPDATE_BLOCK`` cells (block k: cells
    k UPDATE_BLOCK .. (k + 1) UPDATE_BLOCK - 1), in plane strain with the bulk q with both flags as the constant
    False (module docstring).  Every cell sees the same operations and the viscous heat is summed in cell
    order, as in one call.  After a bad cell the other blocks are still updated.  ``vcorner``: a row per cell,
    or a ring (:func:`forces_of_cells`) of a multiple of UPDATE_BLOCK rows.  Carries (dtmin over the good
    blocks, first failing block's first bad cell or -1, its code, viscous heat) on from the blocks before."""
    nc = conn.shape[0]
    bs = max(1, min(nc, UPDATE_BLOCK))
    ring = vcorner.shape[0]
    wb = work.reshape(-1)[:11 * bs].reshape(11, bs)
    for k in range(start, stop):
        b0 = k * UPDATE_BLOCK
        b1 = min(b0 + bs, nc)
        dtb, badb, codeb, qv = _update_block(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho,
                                             e, e_el, p, q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq,
                                             cl, cfl, dvmax, dtcell, errcell, qedge, dmg, heat_now, vcorner, vx_old,
                                             vy_old, dtv, wb, mrec, qv, qparts, b0, b1, b0 % ring)
        if badb >= 0:
            if bad < 0:
                bad = b0 + badb
                code = codeb
        else:
            dtmin = min(dtmin, dtb)
    return dtmin, bad, code, qv


@njit(cache=True, **NO_REFCOUNT)
def _update_block(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx, syy,
                  sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg,
                  heat_now, vcorner, vx_old, vy_old, dtv, work, mrec, qv0, qparts, b0, b1, r0):
    """:func:`update_cells_serial` on the cells b0 .. b1 - 1, the one block call of :func:`update_blocks` (serial)
    and :func:`update_range` (a partition): the cell arrays cut to the block here, ``vcorner`` from its row ``r0``
    (a ring's row, or b0), ``qparts`` from the block's chunk; with the literal flags of plane strain with the bulk
    q."""
    nb = b1 - b0
    if axi or qedge:
        return update_cells_serial(conn[b0:b1], x_half, y_half, x, y, vx, vy, mat[b0:b1], props, table, cmass[b0:b1],
                                   vol[b0:b1], rho[b0:b1], e[b0:b1], e_el[b0:b1], p[b0:b1], q[b0:b1], sxx[b0:b1],
                                   syy[b0:b1], sxy[b0:b1], eps_p[b0:b1], temp[b0:b1], shear[b0:b1], yld[b0:b1],
                                   cs[b0:b1], axi, dt, cq, cl, cfl, dvmax, dtcell[b0:b1], errcell[b0:b1], qedge,
                                   dmg[b0:b1], heat_now, vcorner[r0:r0 + nb], vx_old, vy_old, dtv, work, mrec, qv0,
                                   qparts[b0 >> SUM_SHIFT:])
    return update_cells_serial(conn[b0:b1], x_half, y_half, x, y, vx, vy, mat[b0:b1], props, table, cmass[b0:b1],
                               vol[b0:b1], rho[b0:b1], e[b0:b1], e_el[b0:b1], p[b0:b1], q[b0:b1], sxx[b0:b1],
                               syy[b0:b1], sxy[b0:b1], eps_p[b0:b1], temp[b0:b1], shear[b0:b1], yld[b0:b1],
                               cs[b0:b1], False, dt, cq, cl, cfl, dvmax, dtcell[b0:b1], errcell[b0:b1], False,
                               dmg[b0:b1], heat_now, vcorner[r0:r0 + nb], vx_old, vy_old, dtv, work, mrec, qv0,
                               qparts[b0 >> SUM_SHIFT:])


@njit(cache=True, **NO_REFCOUNT)
def velocities_serial(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc,
                      scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, record, grp_ptr, grp_nodes,
                      mass, dtv, vx_old, vy_old, vx_pre, vy_pre, mass_own, cnode, cnx, cny, cval, bc_nodes, jx_prev,
                      jy_prev):
    """Steps 1-3 of a serial cycle without interfaces (this step or the last) in one call:
    :func:`cell_forces_serial`, :func:`sum_groups`, :func:`advance_velocities`,
    :func:`apply_constraints`, the constraints' :func:`impulse_work` over ``bc_nodes`` (0 without
    constraints) and, with ``record``, :func:`kinetic_energy_product`, in the order of
    ``Simulation._velocity_stage``.  Returns (internal energy at t^n if ``record``, boundary work,
    leapfrog kinetic energy at t^n if ``record``)."""
    ie = cell_forces_serial(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl,
                            svisc, scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, record)
    if grp_ptr.shape[0] > 1:
        sum_groups(fx, fy, grp_ptr, grp_nodes)
    # v* is needed only where the constraints act (their jumps v - v*): kept on bc_nodes alone
    advance_velocities(vx, vy, fx, fy, mass, dtv, vx_old, vy_old, vx_pre, vy_pre, False)
    for k in range(bc_nodes.shape[0]):
        n = bc_nodes[k]
        vx_pre[n] = vx[n]
        vy_pre[n] = vy[n]
    apply_constraints(vx, vy, vx_old, vy_old, mass_own, cnode, cnx, cny, cval, dtv)
    wbc = 0.0
    if cnode.shape[0]:
        wbc = impulse_work(bc_nodes, mass_own, vx_old, vy_old, vx, vy, vx_pre, vy_pre, jx_prev, jy_prev, False,
                           vx_pre, vy_pre)
    ke = 0.0
    if record:
        ke = kinetic_energy_product(vx_old, vy_old, vx, vy, mass_own)
    return ie, wbc, ke


@njit(cache=True, **NO_REFCOUNT)
def advance_serial(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx, syy,
                   sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg,
                   heat_now, vcorner, vx_old, vy_old, dtv, work, mrec, qparts):
    """Steps 5-6 in one call: :func:`move_nodes` (x^{n+1/2} into x_half, y_half), then
    :func:`update_serial` (same arguments and result)."""
    move_nodes(x, y, vx, vy, dt, x_half, y_half)
    return update_serial(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx,
                         syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge,
                         dmg, heat_now, vcorner, vx_old, vy_old, dtv, work, mrec, qparts)


# cells per step of the serial cycle's wavefront (cycle_serial): forces of this many cells, then the nodes and
# the update blocks they complete; on meshes of WAVE_MIN_CELLS cells or more (smaller ones, whose arrays stay in
# the last-level cache, run one step of all the cells: the three passes one after the other, measured faster
# there; docs/theory/fused-cycle.md, "Wavefront")
WAVE_CELLS = 4 * FORCE_BLOCK
WAVE_MIN_CELLS = 1 << 17


@njit(cache=True, **NO_REFCOUNT)
def cycle_serial(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl,
                 scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, record, grp_ptr, grp_nodes, mass, dtv,
                 vx_old, vy_old, vx_pre, vy_pre, mass_own, cnx, cny, cval, bc_nodes, bc_ptr, bc_cons, jx_prev, jy_prev,
                 dt, x_half, y_half, mat, props, table, vol, eps_p, temp, dtcell, errcell, cfl, dvmax, dmg, work,
                 mrec, qparts, node_wait, cell_wait, zero_wait, wave):
    """One whole serial cycle without interfaces, the viscous heat in the cell update (no history row
    with probes or observers this cycle), as a wavefront over the mesh: the forces of the next
    ``wave`` cells (:func:`forces_of_cells`), then the nodes whose cells all have their forces
    (:func:`advance_nodes`: velocities, constraints, kinetic energy, positions), then the blocks of
    the cell update whose nodes all have moved (:func:`update_blocks`), and again; the constraints'
    :func:`impulse_work` at the end.  ``node_wait[n]`` is the last cell of nodes 0 .. n,
    ``cell_wait[c]`` the last node of cells 0 .. c, ``zero_wait[n]`` the first cell of nodes n ..
    (hydro/cycle.py, ``_wavefront``): a node's force is zeroed just before the first wave that adds to
    it (or before it moves, a node of no cell), nodes go in node order,
    update blocks in cell order, so every node and cell sees the same operations in the same order,
    and every sum the same terms in the same order, as :func:`velocities_serial` then
    :func:`advance_serial`; what changes is that the corner forces, nodes and cells of a few rows are
    still in cache when the next pass needs them.  With node groups (:func:`sum_groups` needs all the
    forces) the nodes wait for the whole force pass.  Returns (internal energy at t^n (``record``),
    boundary work, leapfrog kinetic energy at t^n (``record``), min stable dt, first bad cell or -1, its
    code, viscous heat)."""
    nc = conn.shape[0]
    nn = vx.shape[0]
    nblocks = (nc + UPDATE_BLOCK - 1) // UPDATE_BLOCK
    grouped = grp_ptr.shape[0] > 1
    ie = 0.0
    s = 0.0
    part = 0.0
    kb = 0
    dtmin = 1e300
    bad = -1
    code = ERR_NONE
    qv = 0.0
    done_cells = 0  # cells with their forces
    done_nodes = 0  # nodes moved
    done_blocks = 0  # update blocks
    zeroed = 0  # nodes with their force zeroed
    while done_blocks < nblocks:
        if done_cells < nc:
            c1 = min(done_cells + wave, nc)
            # the nodes that may move once cells up to c1 have their forces (stop), and the forces to zero first:
            # every node a cell up to c1 adds to, and those that move now (a node of no cell among them)
            stop = nn
            zero = nn
            if c1 < nc:
                stop = done_nodes
                if not grouped:
                    while stop < nn and node_wait[stop] < c1:
                        stop += 1
                zero = zeroed
                while zero < nn and zero_wait[zero] < c1:
                    zero += 1
                zero = max(zero, stop)
            for n in range(zeroed, zero):
                fx[n] = 0.0
                fy[n] = 0.0
            zeroed = zero
            ie = forces_of_cells(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq,
                                 cl, svisc, scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, record,
                                 done_cells, c1, ie)
            done_cells = c1
            if done_cells == nc and grouped:
                sum_groups(fx, fy, grp_ptr, grp_nodes)
            if stop > done_nodes:
                s, part, kb = advance_nodes(vx, vy, fx, fy, mass, dtv, vx_old, vy_old, vx_pre, vy_pre, mass_own,
                                            cnx, cny, cval, bc_nodes, bc_ptr, bc_cons, record, x, y, dt, x_half,
                                            y_half, done_nodes, stop, kb, s, part)
                done_nodes = stop
        k1 = done_blocks
        while k1 < nblocks and cell_wait[min((k1 + 1) * UPDATE_BLOCK, nc) - 1] < done_nodes:
            k1 += 1
        if k1 > done_blocks:
            dtmin, bad, code, qv = update_blocks(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol,
                                                 rho, e, e_el, p, q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi,
                                                 dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg, True, vcorner,
                                                 vx_old, vy_old, dtv, work, mrec, done_blocks, k1, dtmin, bad, code,
                                                 qv, qparts)
            done_blocks = k1
    wbc = 0.0
    if bc_cons.shape[0]:
        wbc = impulse_work(bc_nodes, mass_own, vx_old, vy_old, vx, vy, vx_pre, vy_pre, jx_prev, jy_prev, False,
                           vx_pre, vy_pre)
    if bad >= 0:
        dtmin = 0.0
    return ie, wbc, 0.5 * (s + part), dtmin, bad, code, qv


@njit(cache=True, **NO_REFCOUNT)
def initial_time_step(conn, x, y, vx, vy, cs, cfl, dvmax, axi):
    """First step: cfl (area / max diagonal)/c, and <= dvmax/|div v^0| (the volume-change cap
    with the initial velocity field)."""
    dtmin = 1e300
    for c in range(conn.shape[0]):
        n0, n1, n2, n3 = conn[c, 0], conn[c, 1], conn[c, 2], conn[c, 3]
        x0, x1, x2, x3 = x[n0], x[n1], x[n2], x[n3]
        y0, y1, y2, y3 = y[n0], y[n1], y[n2], y[n3]
        area = quad_area(x0, x1, x2, x3, y0, y1, y2, y3)
        d1 = (x2 - x0) ** 2 + (y2 - y0) ** 2
        d2 = (x3 - x1) ** 2 + (y3 - y1) ** 2
        dt = cfl * area / math.sqrt(max(d1, d2)) / cs[c]
        if axi:
            bx0, bx1, bx2, bx3, by0, by1, by2, by3, h0, h1, h2, h3, vol = bvec_axi(x0, x1, x2, x3, y0, y1, y2, y3)
        else:
            bx0, bx1, bx2, bx3, by0, by1, by2, by3, vol = bvec_planar(x0, x1, x2, x3, y0, y1, y2, y3)
            h0 = h1 = h2 = h3 = 0.0
        div = ((bx0 + h0) * vx[n0] + (bx1 + h1) * vx[n1] + (bx2 + h2) * vx[n2] + (bx3 + h3) * vx[n3]
               + by0 * vy[n0] + by1 * vy[n1] + by2 * vy[n2] + by3 * vy[n3]) / vol
        if div != 0.0 and dvmax / abs(div) < dt:
            dt = dvmax / abs(div)
        if dt < dtmin:
            dtmin = dt
    return dtmin


@njit(cache=True)
def cell_volumes(conn, x, y, axi, out):
    xs = np.empty(4)
    ys = np.empty(4)
    bx = np.empty(4)
    by = np.empty(4)
    hh = np.empty(4)
    for c in range(conn.shape[0]):
        for k in range(4):
            xs[k] = x[conn[c, k]]
            ys[k] = y[conn[c, k]]
        out[c] = bvectors(xs, ys, axi, bx, by, hh)


@njit(cache=True)
def nodal_masses(conn, x, y, rho, axi, out):
    """Lumped nodal masses: sum over cells of rho int N_i w dA (V/4 per node in plane strain)."""
    xs = np.empty(4)
    ys = np.empty(4)
    w = np.empty(4)
    out[:] = 0.0
    for c in range(conn.shape[0]):
        for k in range(4):
            xs[k] = x[conn[c, k]]
            ys[k] = y[conn[c, k]]
        corner_weights(xs, ys, axi, w)
        for k in range(4):
            out[conn[c, k]] += rho[c] * w[k]


@njit(cache=True)
def initial_cell_state(mat, props, table, rho, e, p, temp, shear, yld, cs, eps_p):
    """Pressure, temperature, moduli and sound speed from (rho, e) at t = 0."""
    for c in range(rho.shape[0]):
        m = mat[c]
        a, b, _ = eos_ab(rho[c], props, m)
        p[c] = a + b * e[c]
        temp[c] = temperature(rho[c], e[c], props, table, m)
        c2 = sound_speed2(rho[c], p[c], props, m)
        if props[m, P_STRENGTH] != STRENGTH_NONE:
            g, ratio = shear_modulus_and_ratio(p[c], temp[c], props, m)
            shear[c] = props[m, P_G0] * ratio  # the physical G(P, T) (G0 for EPP)
            yld[c] = yield_stress(eps_p[c], ratio, props, m)
            c2 += 4.0 * g / (3.0 * rho[c])
        cs[c] = math.sqrt(c2)



# --------------------------------------------------------------------------- partitions (threads)
# The parallel kernels: the cells split into contiguous ranges of whole SUM_CHUNKs (hydro/partition.py), a range
# per thread, each running the serial kernels' blocks on its range; a node whose cells all lie in one range is
# that range's ("interior"), the others ("border") get their corner forces summed afterwards, in cell order.
# Every node and cell sees the operations of the serial kernels in the same order, and every sum the same terms
# in the same order, whatever the number of ranges (docs/theory/threads.md).


@njit(cache=True, **NO_REFCOUNT)
def chunk_total(parts, n):
    """parts[0] + parts[1] + ... + parts[n - 1] in order, from 0.0: the chunks' sums (module docstring, "Sums")."""
    t = 0.0
    for i in range(n):
        t += parts[i]
    return t


@njit(cache=True, **NO_REFCOUNT)
def forces_of_range(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc,
                    scl, scq, elastic_only, corner, vcorner, fx, fy, e, e_el, cmass, want_ie, start, stop, border,
                    bcorner, iparts):
    """:func:`forces_of_cells` over the cells start .. stop - 1 of one partition (``start`` a multiple of
    SUM_CHUNK), a row of ``vcorner`` per cell: a corner's force is added into its node when the node is the
    partition's own (``border[n] == 0``), else stored in ``bcorner[c, k], bcorner[c, 4 + k]`` for
    :func:`forces_parallel`'s border loop.  With ``want_ie`` the internal energy of each chunk of SUM_CHUNK cells
    goes to ``iparts[chunk]``."""
    B = FORCE_BLOCK
    nodal = corner[:16 * B]
    out = corner[16 * B:32 * B]
    for c0 in range(start, stop, B):
        nb = min(B, stop - c0)
        _gather_block(conn, x, y, vx, vy, c0, nb, nodal)
        _forces_of_block(c0, nb, nodal, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl,
                         scq, elastic_only, out)
        blk = 0.0
        for j in range(nb):
            c = np.uint64(c0 + j)
            if want_ie:
                blk += cmass[c] * (e[c] + e_el[c])
            for k in range(8):
                vcorner[c, k] = out[j + (8 + k) * B]
            for k in range(4):
                n = np.uint64(conn[c, k])
                f = out[j + k * B]
                g = out[j + (4 + k) * B]
                if border[n]:
                    bcorner[c, k] = f
                    bcorner[c, 4 + k] = g
                else:
                    fx[n] += f
                    fy[n] += g
        if want_ie:
            iparts[c0 >> SUM_SHIFT] = blk


@njit(cache=True, inline="always")
def border_sums(fx, fy, bcorner, bnodes, bptr, bcorn, j0, j1):
    """The forces of the border nodes ``bnodes[j0:j1]``: each the sum of its corners' forces from ``bcorner`` in
    cell order (``bcorn[bptr[j]:bptr[j + 1]]`` = 4 c + k of border node ``bnodes[j]``, ascending), from 0.0, as
    the serial pass adds them."""
    for j in range(j0, j1):
        sx = 0.0
        sy = 0.0
        for k in range(bptr[j], bptr[j + 1]):
            cc = bcorn[k] >> 2
            kk = bcorn[k] & 3
            sx += bcorner[cc, kk]
            sy += bcorner[cc, 4 + kk]
        n = bnodes[j]
        fx[n] = sx
        fy[n] = sy


@njit(cache=True, parallel=True)
def forces_parallel(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl,
                    scq, elastic_only, blocks, vcorner, fx, fy, e, e_el, cmass, want_ie, cbounds, pnode_ptr, pnodes,
                    border, bcorner, bnodes, bptr, bcorn, iparts, sum_border=True):
    """The force pass (:func:`cell_forces_serial`) over the partitions in parallel, taken from a work queue (module
    docstring): partition i zeroes its own nodes' forces and runs :func:`forces_of_range` on its cells (``blocks[i]``
    its block scratch); then each border node's force is the sum of its corners' forces from ``bcorner`` in cell
    order (:func:`border_sums`), as the serial pass adds them: here, in a second parallel loop, with
    ``sum_border``, else by the caller (:func:`cycle_parallel` has the node pass do it, one parallel region fewer).
    Returns the internal energy at t^n when ``want_ie`` (else 0), summed as the serial pass does."""
    npart = cbounds.shape[0] - 1
    queue = np.zeros(1, np.int64)  # the next partition to take (the work queue: module docstring)
    for _ in prange(npart):  # a thread's first iteration takes partitions until none is left, its others none
        while True:
            i = fetch_add(queue, 0)
            if i >= npart:
                break
            for j in range(pnode_ptr[i], pnode_ptr[i + 1]):
                n = pnodes[j]
                fx[n] = 0.0
                fy[n] = 0.0
            forces_of_range(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl,
                            svisc, scl, scq, elastic_only, blocks[i], vcorner, fx, fy, e, e_el, cmass, want_ie,
                            cbounds[i], cbounds[i + 1], border, bcorner, iparts)
    if sum_border:
        nb = bnodes.shape[0]
        for i in prange(npart):  # the border nodes in as many groups as partitions
            border_sums(fx, fy, bcorner, bnodes, bptr, bcorn, i * nb // npart, (i + 1) * nb // npart)
    if want_ie:
        return chunk_total(iparts, (conn.shape[0] + SUM_CHUNK - 1) >> SUM_SHIFT)
    return 0.0


@njit(cache=True, **NO_REFCOUNT)
def update_range(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx, syy,
                 sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg, heat_now,
                 vcorner, vx_old, vy_old, dtv, work, mrec, start, stop, qparts):
    """:func:`update_blocks` over the cells start .. stop - 1 (``start`` a multiple of SUM_CHUNK), in blocks of
    UPDATE_BLOCK cells from ``start``, ``vcorner`` a row per cell; the viscous heat of each chunk into
    ``qparts[chunk]``.  Returns (min stable dt over the good blocks, first bad cell or -1, its code)."""
    dtmin = 1e300
    bad = -1
    code = ERR_NONE
    wb = work.reshape(-1)[:11 * UPDATE_BLOCK].reshape(11, UPDATE_BLOCK)
    for b0 in range(start, stop, UPDATE_BLOCK):
        b1 = min(b0 + UPDATE_BLOCK, stop)
        dtb, badb, codeb, _ = _update_block(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho,
                                            e, e_el, p, q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl,
                                            cfl, dvmax, dtcell, errcell, qedge, dmg, heat_now, vcorner, vx_old, vy_old,
                                            dtv, wb, mrec, 0.0, qparts, b0, b1, b0)
        if badb >= 0:
            if bad < 0:
                bad = b0 + badb
                code = codeb
        else:
            dtmin = min(dtmin, dtb)
    return dtmin, bad, code


@njit(cache=True, parallel=True)
def update_parallel(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q, sxx, syy,
                    sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell, qedge, dmg,
                    heat_now, vcorner, vx_old, vy_old, dtv, works, mrecs, qparts, cbounds, pdt, pbad):
    """The cell update (:func:`update_serial`) over the partitions in parallel, taken from a work queue (module
    docstring) (:func:`update_range`, partition i with its scratch ``works[i]``, ``mrecs[i]``).  Returns what
    update_serial returns: (min stable dt, or 0 with a bad cell; the first bad cell or -1; its code; the viscous
    heat, summed as the serial kernels do)."""
    npart = cbounds.shape[0] - 1
    queue = np.zeros(1, np.int64)  # the next partition to take (the work queue: module docstring)
    for _ in prange(npart):  # a thread's first iteration takes partitions until none is left, its others none
        while True:
            i = fetch_add(queue, 0)
            if i >= npart:
                break
            dtm, bd, cd = update_range(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e,
                                       e_el, p, q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl,
                                       dvmax, dtcell, errcell, qedge, dmg, heat_now, vcorner, vx_old, vy_old, dtv,
                                       works[i], mrecs[i], cbounds[i], cbounds[i + 1], qparts)
            pdt[i] = dtm
            pbad[i, 0] = bd
            pbad[i, 1] = cd
    dtmin = 1e300
    bad = -1
    code = ERR_NONE
    for i in range(npart):
        if pbad[i, 0] >= 0 and bad < 0:
            bad = pbad[i, 0]
            code = pbad[i, 1]
        dtmin = min(dtmin, pdt[i])
    qv = 0.0
    if heat_now:
        qv = chunk_total(qparts, (conn.shape[0] + SUM_CHUNK - 1) >> SUM_SHIFT)
    if bad >= 0:
        dtmin = 0.0
    return dtmin, bad, code, qv


@njit(cache=True, parallel=True)
def nodes_parallel(vx, vy, fx, fy, mass, dtv, vx_old, vy_old, vx_pre, vy_pre, mass_own, cnx, cny, cval, bc_nodes,
                   bc_ptr, bc_cons, record, x, y, dt, x_half, y_half, kparts, groups, bcorner, bnodes, bptr,
                   bcorn, sum_border):
    """:func:`advance_nodes` over all nodes, ``groups`` runs of whole chunks of SUM_CHUNK nodes in parallel (each
    chunk's kinetic energy sum into ``kparts``).  With ``sum_border``, first the forces of the chunk's border
    nodes (:func:`border_sums`, the force pass having left them out).  Returns the leapfrog kinetic energy at
    t^n when ``record`` (else 0), summed as the serial kernels do."""
    nn = vx.shape[0]
    nch = (nn + SUM_CHUNK - 1) >> SUM_SHIFT
    for g in prange(groups):
        for i in range(g * nch // groups, (g + 1) * nch // groups):
            n0 = i << SUM_SHIFT
            if sum_border:
                border_sums(fx, fy, bcorner, bnodes, bptr, bcorn, np.searchsorted(bnodes, n0),
                            np.searchsorted(bnodes, min(n0 + SUM_CHUNK, nn)))
            kb = np.searchsorted(bc_nodes, n0)
            _, part, _ = advance_nodes(vx, vy, fx, fy, mass, dtv, vx_old, vy_old, vx_pre, vy_pre, mass_own, cnx, cny,
                                       cval, bc_nodes, bc_ptr, bc_cons, record, x, y, dt, x_half, y_half, n0,
                                       min(n0 + SUM_CHUNK, nn), kb, 0.0, 0.0)
            kparts[i] = part
    if record:
        return 0.5 * chunk_total(kparts, nch)
    return 0.0


@njit(cache=True, parallel=True)
def border_velocities_parallel(vx, vy, fx, fy, mass, dt, vx_old, vy_old, vx_pre, vy_pre, keep_pre, bcorner, bnodes,
                               bptr, bcorn, groups):
    """:func:`advance_velocities` after a force pass that left the border nodes out (:func:`forces_parallel` with
    ``sum_border`` False): ``groups`` runs of whole chunks of SUM_CHUNK nodes in parallel, each chunk's border
    nodes' forces first (:func:`border_sums`), then its nodes' velocities, the same operations per node.  One
    parallel region where the force pass's border loop and the velocity pass took two."""
    nn = vx.shape[0]
    nch = (nn + SUM_CHUNK - 1) >> SUM_SHIFT
    for g in prange(groups):
        for i in range(g * nch // groups, (g + 1) * nch // groups):
            n0 = i << SUM_SHIFT
            n1 = min(n0 + SUM_CHUNK, nn)
            border_sums(fx, fy, bcorner, bnodes, bptr, bcorn, np.searchsorted(bnodes, n0), np.searchsorted(bnodes, n1))
            for n in range(n0, n1):
                _advance_node(vx, vy, fx, fy, mass, dt, vx_old, vy_old, vx_pre, vy_pre, keep_pre, n)


@njit(cache=True, parallel=True)
def kinetic_energy_product_parallel(vx0, vy0, vx1, vy1, mass_own, kparts):
    """:func:`kinetic_energy_product`, chunks in parallel (same sum)."""
    nn = vx0.shape[0]
    nch = (nn + SUM_CHUNK - 1) >> SUM_SHIFT
    for i in prange(nch):
        part = 0.0
        for n in range(i << SUM_SHIFT, min((i + 1) << SUM_SHIFT, nn)):
            part += mass_own[n] * (vx0[n] * vx1[n] + vy0[n] * vy1[n])
        kparts[i] = part
    return 0.5 * chunk_total(kparts, nch)


@njit(cache=True, parallel=True)
def viscous_heat_parallel(conn, vcorner, vx0, vy0, vx1, vy1, dt, cmass, e, qparts):
    """:func:`viscous_heat_serial`, chunks in parallel (same cells' energies, same sum)."""
    nc = conn.shape[0]
    nch = (nc + SUM_CHUNK - 1) >> SUM_SHIFT
    for i in prange(nch):
        part = 0.0
        for c in range(i << SUM_SHIFT, min((i + 1) << SUM_SHIFT, nc)):
            heat = viscous_cell_heat(conn, vcorner, vx0, vy0, vx1, vy1, dt, c)
            e[c] += heat * (1.0 / cmass[c])
            part += heat
        qparts[i] = part
    return chunk_total(qparts, nch)


@njit(cache=True)
def cycle_parallel(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc, scl,
                   scq, elastic_only, blocks, vcorner, fx, fy, e, e_el, cmass, record, grp_ptr, grp_nodes, mass, dtv,
                   vx_old, vy_old, vx_pre, vy_pre, mass_own, cnx, cny, cval, bc_nodes, bc_ptr, bc_cons, jx_prev,
                   jy_prev, dt, x_half, y_half, mat, props, table, vol, eps_p, temp, dtcell, errcell, cfl, dvmax, dmg,
                   works, mrecs, sums, cbounds, pnode_ptr, pnodes, border, bcorner, bnodes, bptr, bcorn, pdt, pbad):
    """:func:`cycle_serial` on the partitions, in three parallel passes: the forces (:func:`forces_parallel`),
    the nodes (:func:`nodes_parallel`), the cells (:func:`update_parallel`), with :func:`sum_groups` and the
    constraints' :func:`impulse_work` between them on one thread.  Without node groups the border nodes' force
    sums run in the node pass's region (three parallel regions per cycle; with groups, which need the border
    sums first, in the force pass's second loop: four).  ``sums`` (3, chunks): the chunk sums of the internal
    energy, kinetic energy and viscous heat.  The same bytes as :func:`cycle_serial`; returns what it returns."""
    grouped = grp_ptr.shape[0] > 1
    ie = forces_parallel(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, shear, yld, axi, hg, qedge, cq, cl, svisc,
                         scl, scq, elastic_only, blocks, vcorner, fx, fy, e, e_el, cmass, record, cbounds, pnode_ptr,
                         pnodes, border, bcorner, bnodes, bptr, bcorn, sums[0], grouped)
    if grouped:
        sum_groups(fx, fy, grp_ptr, grp_nodes)
    ke = nodes_parallel(vx, vy, fx, fy, mass, dtv, vx_old, vy_old, vx_pre, vy_pre, mass_own, cnx, cny, cval, bc_nodes,
                        bc_ptr, bc_cons, record, x, y, dt, x_half, y_half, sums[1], cbounds.shape[0] - 1, bcorner,
                        bnodes, bptr, bcorn, not grouped)
    dtmin, bad, code, qv = update_parallel(conn, x_half, y_half, x, y, vx, vy, mat, props, table, cmass, vol, rho, e,
                                           e_el, p, q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl,
                                           cfl, dvmax, dtcell, errcell, qedge, dmg, True, vcorner, vx_old, vy_old,
                                           dtv, works, mrecs, sums[2], cbounds, pdt, pbad)
    wbc = 0.0
    if bc_cons.shape[0]:
        wbc = impulse_work(bc_nodes, mass_own, vx_old, vy_old, vx, vy, vx_pre, vy_pre, jx_prev, jy_prev, False,
                           vx_pre, vy_pre)
    return ie, wbc, ke, dtmin, bad, code, qv
