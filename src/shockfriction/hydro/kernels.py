"""The numba kernels of one Wilkins cycle (thesis Fig. 3.7, errata resolved).

* :func:`forces_serial` / :func:`forces_parallel`: nodal forces F^n from the cell
  stress sigma^n = S^n - (P^n + q^{n-1/2}) 1 at x^n, plus the viscous
  Flanagan-Belytschko hourglass force on v^{n-1/2} (its dissipated power is put
  into the cell's internal energy).
* :func:`advance_velocities`: v* = v^{n-1/2} + dt F/m on node groups (ties,
  periodic sides), then the boundary constraints.
* :func:`apply_constraints`: v <- v - (v.n - value) n per constraint; returns the
  work of the reactions.
* :func:`move_nodes`: x^{n+1} = x^n + dt v^{n+1/2}.
* :func:`update_cells_serial` / :func:`update_cells_parallel`: per cell, volume and
  density at n+1, strain rate at x^{n+1/2}, Jaumann rotation + radial return,
  artificial viscosity q^{n+1/2}, energy update with the EOS, temperature,
  sound speed and the cell's stable time step.

Every kernel takes plain arrays and floats; sign convention: compression positive.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from shockfriction.hydro.eos import eos_ab, sound_speed2, temperature
from shockfriction.hydro.geometry import bvectors, corner_weights, min_corner_jacobian, quad_area
from shockfriction.hydro.matprops import P_PMIN, P_STRENGTH, STRENGTH_NONE
from shockfriction.hydro.plasticity import radial_return, rotate_deviator, shear_modulus_and_ratio, yield_stress

ERR_NONE = 0
ERR_INVERTED = 1
ERR_NAN = 2
ERR_MESSAGES = {ERR_INVERTED: "inverted or degenerate cell (non-positive volume or corner Jacobian)",
                ERR_NAN: "non-finite value (position, energy or pressure)"}

_HG_GAMMA = (1.0, -1.0, 1.0, -1.0)


# --------------------------------------------------------------------------- forces

@njit(cache=True)
def _cell_forces(c, conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, axi, hg, out, xs, ys, bx, by, hh):
    """Corner forces of cell c into out[0:8] (fx0..fx3, fy0..fy3); return the hourglass power."""
    for k in range(4):
        n = conn[c, k]
        xs[k] = x[n]
        ys[k] = y[n]
    bvectors(xs, ys, axi, bx, by, hh)
    ptot = p[c] + q[c]
    a_xx = sxx[c] - ptot
    a_yy = syy[c] - ptot
    a_tt = -(sxx[c] + syy[c]) - ptot
    a_xy = sxy[c]
    for k in range(4):
        out[k] = -(a_xx * bx[k] + a_xy * by[k] + a_tt * hh[k])
        out[4 + k] = -(a_xy * bx[k] + a_yy * by[k])
    if hg <= 0.0:
        return 0.0
    # Flanagan-Belytschko viscous hourglass: gamma = Gamma - (Gamma.x) b_x/A - (Gamma.y) b_y/A
    area = quad_area(xs[0], xs[1], xs[2], xs[3], ys[0], ys[1], ys[2], ys[3])
    if area <= 0.0:
        return 0.0
    gx = 0.0
    gy = 0.0
    for k in range(4):
        gx += _HG_GAMMA[k] * xs[k]
        gy += _HG_GAMMA[k] * ys[k]
    # planar b vectors (dA/dx_k) for the projection
    pbx0 = 0.5 * (ys[1] - ys[3])
    pbx1 = 0.5 * (ys[2] - ys[0])
    pby0 = 0.5 * (xs[3] - xs[1])
    pby1 = 0.5 * (xs[0] - xs[2])
    hu = 0.0
    hv = 0.0
    gam0 = _HG_GAMMA[0] - (gx * pbx0 + gy * pby0) / area
    gam1 = _HG_GAMMA[1] - (gx * pbx1 + gy * pby1) / area
    gam2 = _HG_GAMMA[2] - (gx * (-pbx0) + gy * (-pby0)) / area
    gam3 = _HG_GAMMA[3] - (gx * (-pbx1) + gy * (-pby1)) / area
    n0 = conn[c, 0]
    n1 = conn[c, 1]
    n2 = conn[c, 2]
    n3 = conn[c, 3]
    hu = gam0 * vx[n0] + gam1 * vx[n1] + gam2 * vx[n2] + gam3 * vx[n3]
    hv = gam0 * vy[n0] + gam1 * vy[n1] + gam2 * vy[n2] + gam3 * vy[n3]
    w = 1.0
    if axi:
        w = 0.25 * (xs[0] + xs[1] + xs[2] + xs[3])
    coef = 0.25 * hg * rho[c] * cs[c] * math.sqrt(area) * w
    out[0] -= coef * gam0 * hu
    out[1] -= coef * gam1 * hu
    out[2] -= coef * gam2 * hu
    out[3] -= coef * gam3 * hu
    out[4] -= coef * gam0 * hv
    out[5] -= coef * gam1 * hv
    out[6] -= coef * gam2 * hv
    out[7] -= coef * gam3 * hv
    return coef * (hu * hu + hv * hv)


@njit(cache=True)
def forces_serial(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, cmass, e, axi, hg, dt, fx, fy):
    """Nodal forces (scatter), hourglass heat dt*power/M added to e; serial."""
    fx[:] = 0.0
    fy[:] = 0.0
    out = np.empty(8)
    xs = np.empty(4)
    ys = np.empty(4)
    bx = np.empty(4)
    by = np.empty(4)
    hh = np.empty(4)
    for c in range(conn.shape[0]):
        pw = _cell_forces(c, conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, axi, hg, out, xs, ys, bx, by, hh)
        for k in range(4):
            n = conn[c, k]
            fx[n] += out[k]
            fy[n] += out[4 + k]
        if pw > 0.0:
            e[c] += dt * pw / cmass[c]


@njit(cache=True, parallel=True)
def forces_parallel(conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, cmass, e, axi, hg, dt, fx, fy,
                    corner, node_ptr, node_corner):
    """Nodal forces: corner forces per cell (prange), then a gather per node (prange)."""
    nc = conn.shape[0]
    for c in prange(nc):
        xs = np.empty(4)
        ys = np.empty(4)
        bx = np.empty(4)
        by = np.empty(4)
        hh = np.empty(4)
        pw = _cell_forces(c, conn, x, y, vx, vy, sxx, syy, sxy, p, q, rho, cs, axi, hg, corner[c], xs, ys, bx, by,
                          hh)
        if pw > 0.0:
            e[c] += dt * pw / cmass[c]
    for n in prange(fx.shape[0]):
        sx = 0.0
        sy = 0.0
        for k in range(node_ptr[n], node_ptr[n + 1]):
            cc = node_corner[k] // 4
            kk = node_corner[k] % 4
            sx += corner[cc, kk]
            sy += corner[cc, 4 + kk]
        fx[n] = sx
        fy[n] = sy


# --------------------------------------------------------------------------- nodes

@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
def advance_velocities(vx, vy, fx, fy, mass, dt):
    """v* = v + dt F/m (m: the group mass of the node)."""
    for n in range(vx.shape[0]):
        vx[n] += dt * fx[n] / mass[n]
        vy[n] += dt * fy[n] / mass[n]


@njit(cache=True)
def move_nodes(x, y, vx, vy, dt, x_old, y_old):
    """Keep x^n in (x_old, y_old) and set x^{n+1} = x^n + dt v^{n+1/2}."""
    for n in range(x.shape[0]):
        x_old[n] = x[n]
        y_old[n] = y[n]
        x[n] += dt * vx[n]
        y[n] += dt * vy[n]


@njit(cache=True)
def kinetic_energy(vx, vy, mass_own):
    s = 0.0
    for n in range(vx.shape[0]):
        s += mass_own[n] * (vx[n] * vx[n] + vy[n] * vy[n])
    return 0.5 * s


@njit(cache=True)
def kinetic_energy_product(vx0, vy0, vx1, vy1, mass_own):
    """Leapfrog kinetic energy at t^n: sum m v^{n-1/2}.v^{n+1/2} / 2."""
    s = 0.0
    for n in range(vx0.shape[0]):
        s += mass_own[n] * (vx0[n] * vx1[n] + vy0[n] * vy1[n])
    return 0.5 * s


@njit(cache=True)
def momentum(vx, vy, mass_own):
    px = 0.0
    py = 0.0
    for n in range(vx.shape[0]):
        px += mass_own[n] * vx[n]
        py += mass_own[n] * vy[n]
    return px, py


@njit(cache=True)
def internal_energy(e, e_el, cmass):
    s = 0.0
    for c in range(e.shape[0]):
        s += cmass[c] * (e[c] + e_el[c])
    return s


# --------------------------------------------------------------------------- cells

@njit(cache=True)
def _update_cell(c, conn, x0, y0, x1, y1, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q,
                 sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, xs, ys, bx, by, hh):
    """Advance cell c from n to n+1; return (stable dt of the cell, error code)."""
    m = mat[c]
    # ---- geometry at n+1
    for k in range(4):
        nd = conn[c, k]
        xs[k] = x1[nd]
        ys[k] = y1[nd]
    jmin = min_corner_jacobian(xs, ys)
    area1 = quad_area(xs[0], xs[1], xs[2], xs[3], ys[0], ys[1], ys[2], ys[3])
    d1 = (xs[2] - xs[0]) ** 2 + (ys[2] - ys[0]) ** 2
    d2 = (xs[3] - xs[1]) ** 2 + (ys[3] - ys[1]) ** 2
    dmax = math.sqrt(d1 if d1 > d2 else d2)
    v1 = bvectors(xs, ys, axi, bx, by, hh)
    if not (jmin > 0.0 and v1 > 0.0):
        if math.isnan(jmin) or math.isnan(v1):
            return 0.0, ERR_NAN
        return 0.0, ERR_INVERTED
    # ---- geometry at n+1/2 and strain rate
    for k in range(4):
        nd = conn[c, k]
        xs[k] = 0.5 * (x0[nd] + x1[nd])
        ys[k] = 0.5 * (y0[nd] + y1[nd])
    vh = bvectors(xs, ys, axi, bx, by, hh)
    dxx = 0.0
    dyy = 0.0
    dtt = 0.0
    uy = 0.0
    vxg = 0.0
    for k in range(4):
        nd = conn[c, k]
        dxx += bx[k] * vx[nd]
        dyy += by[k] * vy[nd]
        dtt += hh[k] * vx[nd]
        uy += by[k] * vx[nd]
        vxg += bx[k] * vy[nd]
    inv = 1.0 / vh
    dxx *= inv
    dyy *= inv
    dtt *= inv
    uy *= inv
    vxg *= inv
    dxy = 0.5 * (uy + vxg)
    spin = 0.5 * (uy - vxg)
    trd = dxx + dyy + dtt
    v0 = vol[c]
    rho1 = cmass[c] / v1
    rhoh = cmass[c] / vh
    # ---- deviatoric stress: rotation, predictor, radial return
    heat = 0.0
    if props[m, P_STRENGTH] != STRENGTH_NONE:
        g, ratio = shear_modulus_and_ratio(p[c], temp[c], props, m)
        r_xx, r_yy, r_xy = rotate_deviator(sxx[c], syy[c], sxy[c], spin, dt)
        dm = trd / 3.0
        t_xx = r_xx + 2.0 * g * dt * (dxx - dm)
        t_yy = r_yy + 2.0 * g * dt * (dyy - dm)
        t_xy = r_xy + 2.0 * g * dt * dxy
        n_xx, n_yy, n_xy, deps, y = radial_return(t_xx, t_yy, t_xy, eps_p[c], g, ratio, props, m)
        # deviatoric work per unit mass with S^{n+1/2} = (S~^n + S^{n+1})/2
        m_xx = 0.5 * (r_xx + n_xx)
        m_yy = 0.5 * (r_yy + n_yy)
        m_xy = 0.5 * (r_xy + n_xy)
        wdev = (m_xx * dxx + m_yy * dyy - (m_xx + m_yy) * dtt + 2.0 * m_xy * dxy) * dt / rhoh
        heat = y * deps / rhoh
        sxx[c] = n_xx
        syy[c] = n_yy
        sxy[c] = n_xy
        eps_p[c] += deps
        e_el[c] += wdev - heat
        if n_xx == 0.0 and n_yy == 0.0 and n_xy == 0.0:
            # no deviator left (melted): the stored shear energy is released as heat
            heat += e_el[c]
            e_el[c] = 0.0
    # ---- artificial viscosity q^{n+1/2} (compression only)
    qn = 0.0
    if trd < 0.0:
        cm = 0.5 * (dxx + dyy)
        rr = math.sqrt(0.25 * (dxx - dyy) ** 2 + dxy * dxy)
        lq = math.sqrt(area1)
        if rr > 1e-12 * (abs(cm) + 1e-300):
            lmax = cm + rr
            ax = dxy
            ay = lmax - dxx
            bxv = lmax - dyy
            byv = dxy
            if ax * ax + ay * ay >= bxv * bxv + byv * byv:
                tx, ty = ax, ay
            else:
                tx, ty = bxv, byv
            tn = math.sqrt(tx * tx + ty * ty)
            tx /= tn
            ty /= tn
            pmin_ = 1e300
            pmax_ = -1e300
            for k in range(4):
                nd = conn[c, k]
                pr = tx * x1[nd] + ty * y1[nd]
                if pr < pmin_:
                    pmin_ = pr
                if pr > pmax_:
                    pmax_ = pr
            if pmax_ > pmin_:
                lq = area1 / (pmax_ - pmin_)
                if lq > dmax:
                    lq = dmax
        qn = rhoh * (cq * cq * lq * lq * trd * trd - cl * cs[c] * lq * trd)
    # ---- energy and pressure (thesis eq. 3.18 with errata), q time-centred as the forces see it:
    # e1 = e~ - ((P^n + q^{n-1/2}) + (P^{n+1} + q^{n+1/2}))/2 dv
    dv = (v1 - v0) / cmass[c]
    et = e[c] + heat
    qmid = 0.5 * (q[c] + qn)
    a, b, _ = eos_ab(rho1, props, m)
    e1 = (et - (0.5 * p[c] + qmid) * dv - 0.5 * a * dv) / (1.0 + 0.5 * b * dv)
    p1 = a + b * e1
    pfloor = props[m, P_PMIN]
    if p1 < pfloor:
        p1 = pfloor
        e1 = et - (0.5 * (p[c] + p1) + qmid) * dv
    if not (math.isfinite(e1) and math.isfinite(p1)):
        return 0.0, ERR_NAN
    t1 = temperature(rho1, e1, props, table, m)
    vol[c] = v1
    rho[c] = rho1
    e[c] = e1
    p[c] = p1
    q[c] = qn
    temp[c] = t1
    # ---- moduli, flow stress and sound speed at n+1
    c2 = sound_speed2(rho1, p1, props, m)
    if props[m, P_STRENGTH] != STRENGTH_NONE:
        g1, ratio1 = shear_modulus_and_ratio(p1, t1, props, m)
        shear[c] = g1
        yld[c] = yield_stress(eps_p[c], ratio1, props, m)
        c2 += 4.0 * g1 / (3.0 * rho1)
    c1 = math.sqrt(c2)
    cs[c] = c1
    # ---- stable time step of the cell
    lcfl = area1 / dmax
    aq = 0.0
    if trd < 0.0:
        aq = cq * cq * lcfl * (-trd) + cl * c1
    dtc = cfl * lcfl / (aq + math.sqrt(aq * aq + c2))
    if trd != 0.0:
        dvl = dvmax / abs(trd)
        if dvl < dtc:
            dtc = dvl
    return dtc, ERR_NONE


@njit(cache=True)
def update_cells_serial(conn, x0, y0, x1, y1, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q,
                        sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax):
    """All cells, serial.  Returns (min stable dt, first bad cell or -1, error code)."""
    xs = np.empty(4)
    ys = np.empty(4)
    bx = np.empty(4)
    by = np.empty(4)
    hh = np.empty(4)
    dtmin = 1e300
    for c in range(conn.shape[0]):
        dtc, err = _update_cell(c, conn, x0, y0, x1, y1, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p,
                                q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax,
                                xs, ys, bx, by, hh)
        if err != ERR_NONE:
            return 0.0, c, err
        if dtc < dtmin:
            dtmin = dtc
    return dtmin, -1, ERR_NONE


@njit(cache=True, parallel=True)
def update_cells_parallel(conn, x0, y0, x1, y1, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p, q,
                          sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax, dtcell, errcell):
    """All cells with prange; per-cell results in dtcell/errcell, reduced here."""
    nc = conn.shape[0]
    for c in prange(nc):
        xs = np.empty(4)
        ys = np.empty(4)
        bx = np.empty(4)
        by = np.empty(4)
        hh = np.empty(4)
        dtc, err = _update_cell(c, conn, x0, y0, x1, y1, vx, vy, mat, props, table, cmass, vol, rho, e, e_el, p,
                                q, sxx, syy, sxy, eps_p, temp, shear, yld, cs, axi, dt, cq, cl, cfl, dvmax,
                                xs, ys, bx, by, hh)
        dtcell[c] = dtc if err == ERR_NONE else 1e300
        errcell[c] = err
    for c in range(nc):
        if errcell[c] != ERR_NONE:
            return 0.0, c, errcell[c]
    return dtcell.min(), -1, ERR_NONE


@njit(cache=True)
def initial_time_step(conn, x, y, cs, cfl):
    """cfl * min over cells of (area / max diagonal) / c."""
    dtmin = 1e300
    for c in range(conn.shape[0]):
        n0, n1, n2, n3 = conn[c, 0], conn[c, 1], conn[c, 2], conn[c, 3]
        area = quad_area(x[n0], x[n1], x[n2], x[n3], y[n0], y[n1], y[n2], y[n3])
        d1 = (x[n2] - x[n0]) ** 2 + (y[n2] - y[n0]) ** 2
        d2 = (x[n3] - x[n1]) ** 2 + (y[n3] - y[n1]) ** 2
        dt = cfl * area / math.sqrt(max(d1, d2)) / cs[c]
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
            shear[c] = g
            yld[c] = yield_stress(eps_p[c], ratio, props, m)
            c2 += 4.0 * g / (3.0 * rho[c])
        cs[c] = math.sqrt(c2)

