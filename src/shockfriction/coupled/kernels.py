"""Per-node kernels of the coupled friction step (thesis Table 6.1, eqs. 6.82-6.84).

They reuse the slide line's pair algebra (:mod:`shockfriction.contact.impulses`): an impulse
P along t acts +P t on the slave node and -P t on its projection X_G, shared by the guide
nodes with the weights w_k, so that the relative velocity changes by P (1/m_g + 1/m_G) with
1/m_G = sum_k w_k^2/m_k.
"""

from __future__ import annotations

import math

from numba import njit

from shockfriction.contact.impulses import _inverse_pair_mass, _relative_velocity, capped_update


@njit(cache=True)
def column_inputs(vx, vy, vx_old, vy_old, mass, slave, gnode, gw, tx, ty, active, lam_n, area, dt, bilateral,
                  guide_load, idle_slip, sigma_n, v_free, v_prev, m_slave, m_guide):
    """What each node's column needs (arrays of the slave nodes, filled in place).

    sigma_n = P_n/(S dt) (compression > 0; |.| with bilateral contact, 0 out of contact), the
    free slip [V*]^{n+1/2} = (v*_g - v*_G).t after the contact step, the slip of the previous
    step [V]^{n-1/2} = (v_g - v_G).t at t^{n-1/2} with the same pairing (so that the column's
    time-centred slip is the one of the hydrocode's friction work), m_g and the guide mass m_G.

    m_G is the mass the projection X_G shows under a uniform friction stress on the whole line:
    guide node k then receives sum_i w_ik tau S_i dt from all the nodes in contact, so

        1/m_G,j = sum_k w_jk (sum_i w_ik S_i / S_j) / m_k

    (the pair mass sum_k w_jk^2/m_k of a single node ignores its neighbours' pull on the shared
    guide nodes and would misjudge the slip, hence the heat, by the per-step velocity change).
    ``guide_load`` is a scratch array of the size of ``mass``.  A free slip below ``idle_slip`` (m/s)
    is round-off of the contact step (e.g. 1e-11 m/s in a normal impact): it is set to 0, so the
    node needs no friction and its column stays idle.
    """
    ns = slave.size
    for j in range(ns):
        for k in range(gnode.shape[1]):
            guide_load[gnode[j, k]] = 0.0
    for j in range(ns):
        if active[j] and lam_n[j] != 0.0 and area[j] > 0.0:
            for k in range(gnode.shape[1]):
                guide_load[gnode[j, k]] += gw[j, k] * area[j]
    for j in range(ns):
        i_g = slave[j]
        m_slave[j] = mass[i_g]
        if not active[j]:
            sigma_n[j] = 0.0
            v_free[j] = 0.0
            v_prev[j] = 0.0
            m_guide[j] = math.inf
            continue
        s = lam_n[j] / (dt * area[j]) if area[j] > 0.0 else 0.0
        if bilateral:
            s = abs(s)
        sigma_n[j] = s if s > 0.0 else 0.0
        inv = 0.0
        if lam_n[j] != 0.0 and area[j] > 0.0:
            for k in range(gnode.shape[1]):
                w = gw[j, k]
                if w != 0.0:
                    inv += w * guide_load[gnode[j, k]] / (area[j] * mass[gnode[j, k]])
        m_guide[j] = 1.0 / inv if inv > 0.0 else math.inf
        vf = _relative_velocity(vx, vy, j, i_g, gnode, gw, tx[j], ty[j])
        v_free[j] = vf if abs(vf) > idle_slip else 0.0
        v_prev[j] = _relative_velocity(vx_old, vy_old, j, i_g, gnode, gw, tx[j], ty[j])


@njit(cache=True)
def capped_tangential_step(vx, vy, mass, slave, gnode, gw, tx, ty, active, cap, max_sweeps, rel_tol, lam_t, slip):
    """Friction impulses lam_t (N s, on the slave along t) with |lam_t| <= cap (eq. 6.83).

    The cap is the column's friction force times dt, tau S dt (tau already capped by Coulomb and
    by the single-pair sticking force).  Projected Gauss-Seidel sweeps as in the slide line's own
    tangential step (nodes sharing guide nodes), until the largest relative-velocity change of a
    sweep is below ``rel_tol`` of the first.  ``slip`` receives the corrected slip (v_g - v_G).t.
    Returns the sweeps done.
    """
    ns = slave.size
    for j in range(ns):
        lam_t[j] = 0.0
    scale = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        sweeps += 1
        change = 0.0
        for j in range(ns):
            if cap[j] <= 0.0:
                continue
            i_g = slave[j]
            inv_pair = _inverse_pair_mass(j, i_g, gnode, gw, mass)
            s = _relative_velocity(vx, vy, j, i_g, gnode, gw, tx[j], ty[j])
            dv = capped_update(vx, vy, mass, j, i_g, gnode, gw, tx[j], ty[j], lam_t, cap[j], s, inv_pair)
            if dv > change:
                change = dv
        if sweep == 0:
            scale = change
        if change <= rel_tol * scale:
            break
    for j in range(ns):
        slip[j] = _relative_velocity(vx, vy, j, slave[j], gnode, gw, tx[j], ty[j]) if active[j] else 0.0
    return sweeps


@njit(cache=True)
def tally_branches(sigma_n, v_free, tau, tau_coulomb, tau_stick, counts):
    """counts += the friction node-steps (in contact, free slip) whose tau is the Coulomb cap (tau >= mu0 F_N <=
    tau_stick), else the sticking cap (tau >= tau_stick), else the sub-grid branch."""
    for j in range(tau.shape[0]):
        if not (sigma_n[j] > 0.0 and v_free[j] != 0.0):
            continue
        if tau[j] >= tau_coulomb[j] and tau_coulomb[j] <= tau_stick[j]:
            counts[0] += 1
        elif tau[j] >= tau_stick[j]:
            counts[1] += 1
        else:
            counts[2] += 1


@njit(cache=True)
def stash_sums(friction_work, heat_interface, heat_plastic, plastic_work, melt_energy, before):
    """before[k] = the k-th per-node running sum (the column energies before a step)."""
    for j in range(friction_work.shape[0]):
        before[0, j] = friction_work[j]
        before[1, j] = heat_interface[j]
        before[2, j] = heat_plastic[j]
        before[3, j] = plastic_work[j]
        before[4, j] = melt_energy[j]


@njit(cache=True)
def step_increments(friction_work, heat_interface, heat_plastic, plastic_work, melt_energy, before, tau, slip_local,
                    slip_plastic, slip_macro, area, dt, beta_T, beta_Q, cap, parts, win_local, win_plastic, win_macro):
    """Per node after a column step: the impulse cap tau S dt, the energy increments per unit area (parts:
    friction work, heat put in the column (interface + plastic), the other body's share (1 - beta_T) tau [v] dt,
    cold work (1 - beta_Q) d(plastic work), clipped melt energy) and the window sums of the slips times dt."""
    for j in range(tau.shape[0]):
        cap[j] = tau[j] * (area[j] * dt)
        parts[0, j] = friction_work[j] - before[0, j]
        parts[1, j] = (heat_interface[j] - before[1, j]) + (heat_plastic[j] - before[2, j])
        parts[2, j] = (1.0 - beta_T) * (tau[j] * slip_local[j] * dt)
        parts[3, j] = (1.0 - beta_Q) * (plastic_work[j] - before[3, j])
        parts[4, j] = melt_energy[j] - before[4, j]
        win_local[j] += slip_local[j] * dt
        win_plastic[j] += slip_plastic[j] * dt
        win_macro[j] += slip_macro[j] * dt


@njit(cache=True)
def layer_shear_velocity(x, y, vx, vy, conn, cell_a, cell_b, tx, ty, nx, ny, active, h, v_far):
    """v_far[j] = -2 (t . D . n) h: the velocity, relative to node j and in its column's sense (the column's v is
    -t . (u - u_node)), that the hydro's own shear of the layer gives its far end at depth h, D the symmetric part
    of L = grad u averaged over the cells cell_a[j], cell_b[j] (-1: none) next to the node (the spin is left out: a
    rigid rotation does not shear the layer), n the contact normal (pointing into the slave body), t the tangent.
    The gradient of each quadrilateral is the mean gradient of its bilinear field,
    du/dx = ((u3 - u1)(y4 - y2) - (u4 - u2)(y3 - y1))/(2A), du/dy = ((u4 - u2)(x3 - x1) - (u3 - u1)(x4 - x2))/(2A),
    2A = (x3 - x1)(y4 - y2) - (x4 - x2)(y3 - y1) (either orientation).  Inactive nodes get 0."""
    for j in range(v_far.shape[0]):
        v_far[j] = 0.0
        if not active[j]:
            continue
        acc = 0.0
        cnt = 0
        for which in range(2):
            c = cell_a[j] if which == 0 else cell_b[j]
            if c < 0:
                continue
            i1, i2, i3, i4 = conn[c, 0], conn[c, 1], conn[c, 2], conn[c, 3]
            ax, ay = x[i3] - x[i1], y[i3] - y[i1]
            bx, by = x[i4] - x[i2], y[i4] - y[i2]
            A2 = ax * by - bx * ay
            if A2 == 0.0:
                continue
            dux = ((vx[i3] - vx[i1]) * by - (vx[i4] - vx[i2]) * ay) / A2
            duy = ((vx[i4] - vx[i2]) * ax - (vx[i3] - vx[i1]) * bx) / A2
            dvx = ((vy[i3] - vy[i1]) * by - (vy[i4] - vy[i2]) * ay) / A2
            dvy = ((vy[i4] - vy[i2]) * ax - (vy[i3] - vy[i1]) * bx) / A2
            # 2 t . D . n = t . L . n + n . L . t (L_ik = du_i/dx_k): the layer's engineering shear rate; the spin
            # (a rigid rotation of the cell) does not shear the layer
            acc += (tx[j] * (dux * nx[j] + duy * ny[j]) + ty[j] * (dvx * nx[j] + dvy * ny[j])
                    + nx[j] * (dux * tx[j] + duy * ty[j]) + ny[j] * (dvx * tx[j] + dvy * ty[j]))
            cnt += 1
        if cnt > 0:
            v_far[j] = -(acc / cnt) * h
