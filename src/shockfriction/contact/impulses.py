"""Contact (normal) and friction (tangential) velocity corrections by impulses (thesis 3.3.2-3.3.3).

Both steps act on the free nodal velocities v* = v^{n-1/2} + dt F/m (eqs. 3.54-3.60)
of a slave node g and of its projection G on the guide segment [X_0, X_1] at
``coef`` (eqs. 3.61-3.63).  One consistent sign (the digest's section 5.4 errata):
an impulse P (N s) along a unit direction d acts +P d on the slave node and -P d on
the projection, and the projection's impulse is shared by the guide nodes as
(1 - coef) P and coef P, so momentum is conserved exactly.  The velocity at the
projection v_G = (1 - coef) v_0 + coef v_1 then changes by -P/m_G with the
projection mass

    1/m_G = (1 - coef)^2/m_0 + coef^2/m_1,

and the relative velocity w = (v_g - v_G).d by P (1/m_g + 1/m_G).  The sticking
("welding") impulse that cancels w is therefore the reduced-mass one of eq. 3.76,

    P_* = -w m_g m_G/(m_g + m_G),

exact for every coef (the thesis's m_G = (1 - coef) m_0 + coef m_1 with a velocity
share leaves a residual slip when 0 < coef < 1; both agree at coef = 0 or 1 and
for equal guide masses the impulse shares are the same).  Such an impulse does the
work P (w_before + w_after)/2 on the kinetic energy, which is how friction work is
counted.

Normal step (unilateral by default): the target relative normal velocity is
w_n = -g/dt (g the gap at t^n), so an open gap that the free motion would overrun
closes exactly at t^{n+1} and a penetration is pushed out; the accumulated normal
impulse is kept >= 0 (no tension).  With ``bilateral`` (the thesis's permanent
contact, eqs. 3.64-3.66) it may be negative.

Tangential step: free slip s* = (v_g - v_G).t after the normal step; the law gives
the traction limit tau_max(|F_N|, |s*|, Y_g, Y_G) (eq. 3.77-3.81, free slip as in
eq. 3.79) and the friction impulse is the sticking impulse capped by
tau_max S_g dt (eqs. 3.82-3.85 with the signs fixed).  Nodes without a compressive
normal impulse get no friction (bilateral contact uses |F_N|).

Several slave nodes may share guide nodes; the corrections are applied node after
node (Gauss-Seidel) and the sweep is repeated until the largest relative-velocity
change of a sweep falls below ``rel_tol`` times the initial one (at most
``max_sweeps``; ``max_sweeps = 1`` is the thesis's single pass).  Accumulated
impulses are projected (>= 0 normal, |P_t| <= cap), so the iteration is a
projected Gauss-Seidel on the contact conditions.
"""

from __future__ import annotations

import math

from numba import njit

from shockfriction.friction.laws import traction_limit


@njit(cache=True)
def _pair_geometry(j, slave, guide, seg, coef, mass):
    i_g = slave[j]
    i0 = guide[seg[j]]
    i1 = guide[seg[j] + 1]
    c = coef[j]
    w0 = 1.0 - c
    inv_mg = 1.0 / mass[i_g]
    inv_mG = w0 * w0 / mass[i0] + c * c / mass[i1]
    return i_g, i0, i1, w0, c, inv_mg + inv_mG


@njit(cache=True)
def _relative_velocity(vx, vy, i_g, i0, i1, w0, w1, dx, dy):
    return ((vx[i_g] - w0 * vx[i0] - w1 * vx[i1]) * dx
            + (vy[i_g] - w0 * vy[i0] - w1 * vy[i1]) * dy)


@njit(cache=True)
def _apply(vx, vy, mass, i_g, i0, i1, w0, w1, dx, dy, p):
    """Impulse +p d on the slave node, -p d on its projection shared (w0, w1) by the guide nodes."""
    vx[i_g] += p * dx / mass[i_g]
    vy[i_g] += p * dy / mass[i_g]
    vx[i0] -= w0 * p * dx / mass[i0]
    vy[i0] -= w0 * p * dy / mass[i0]
    vx[i1] -= w1 * p * dx / mass[i1]
    vy[i1] -= w1 * p * dy / mass[i1]


@njit(cache=True)
def normal_step(vx, vy, mass, slave, guide, seg, coef, nx, ny, gap, active, dt, bilateral,
                max_sweeps, rel_tol, lam_n, work_n):
    """Contact step: normal impulses ``lam_n`` (N s, >= 0 compressive unless bilateral).

    ``dt`` is the step over which the positions advance: the target relative normal
    velocity is -gap/dt.
    Corrects ``vx, vy`` in place; ``work_n[j]`` receives the kinetic energy removed by the
    normal impulse of node j (the inelastic-impact loss of an explicit contact step).
    Returns the number of sweeps done.
    """
    ns = slave.size
    for j in range(ns):
        lam_n[j] = 0.0
        work_n[j] = 0.0
    scale = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        sweeps += 1
        change = 0.0
        for j in range(ns):
            if not active[j]:
                continue
            i_g, i0, i1, w0, w1, inv_pair = _pair_geometry(j, slave, guide, seg, coef, mass)
            w = _relative_velocity(vx, vy, i_g, i0, i1, w0, w1, nx[j], ny[j])
            target = -gap[j] / dt
            new = lam_n[j] + (target - w) / inv_pair
            if not bilateral and new < 0.0:
                new = 0.0
            dp = new - lam_n[j]
            if dp == 0.0:
                continue
            lam_n[j] = new
            _apply(vx, vy, mass, i_g, i0, i1, w0, w1, nx[j], ny[j], dp)
            w_after = w + dp * inv_pair
            work_n[j] -= 0.5 * dp * (w + w_after)
            dv = abs(dp * inv_pair)
            if dv > change:
                change = dv
        if sweep == 0:
            scale = change
        if change <= rel_tol * scale:
            break
    return sweeps


@njit(cache=True)
def tangential_step(vx, vy, mass, slave, guide, seg, coef, tx, ty, active, dt, area,
                    law, law_params, y_slave, y_guide, lam_n, max_sweeps, rel_tol,
                    lam_t, slip_free, slip, work_t):
    """Friction step: tangential impulses ``lam_t`` (N s, on the slave along t).

    ``slip_free[j]`` is the free slip s* = (v_g - v_G).t after the normal step (the
    law's velocity, eq. 3.79) and ``slip[j]`` the corrected slip; ``work_t[j]`` the
    friction work of this step (J; >= 0).  ``y_slave[j]``, ``y_guide[j]`` are the yield
    stresses of the two sides at node j (Tresca laws only).  Returns the sweeps done.
    """
    ns = slave.size
    cap = lam_n.copy()
    for j in range(ns):
        lam_t[j] = 0.0
        work_t[j] = 0.0
        slip_free[j] = 0.0
        slip[j] = 0.0
        cap[j] = 0.0
        if not active[j]:
            continue
        i_g, i0, i1, w0, w1, inv_pair = _pair_geometry(j, slave, guide, seg, coef, mass)
        s = _relative_velocity(vx, vy, i_g, i0, i1, w0, w1, tx[j], ty[j])
        slip_free[j] = s
        if lam_n[j] == 0.0 or area[j] <= 0.0:
            continue
        sigma_n = lam_n[j] / (dt * area[j])
        cap[j] = traction_limit(law, law_params, sigma_n, abs(s), y_slave[j], y_guide[j]) * area[j] * dt
    scale = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        sweeps += 1
        change = 0.0
        for j in range(ns):
            if cap[j] <= 0.0:
                continue
            i_g, i0, i1, w0, w1, inv_pair = _pair_geometry(j, slave, guide, seg, coef, mass)
            s = _relative_velocity(vx, vy, i_g, i0, i1, w0, w1, tx[j], ty[j])
            new = lam_t[j] - s / inv_pair
            if new > cap[j]:
                new = cap[j]
            elif new < -cap[j]:
                new = -cap[j]
            dp = new - lam_t[j]
            if dp == 0.0:
                continue
            lam_t[j] = new
            _apply(vx, vy, mass, i_g, i0, i1, w0, w1, tx[j], ty[j], dp)
            s_after = s + dp * inv_pair
            work_t[j] -= 0.5 * dp * (s + s_after)
            dv = abs(dp * inv_pair)
            if dv > change:
                change = dv
        if sweep == 0:
            scale = change
        if change <= rel_tol * scale:
            break
    for j in range(ns):
        if active[j]:
            i_g, i0, i1, w0, w1, inv_pair = _pair_geometry(j, slave, guide, seg, coef, mass)
            slip[j] = _relative_velocity(vx, vy, i_g, i0, i1, w0, w1, tx[j], ty[j])
    return sweeps


@njit(cache=True)
def deposit_friction_heat(work, active, seg, slave_share, slave_cell_before, slave_cell_after,
                          weight_before, guide_cell, cell_mass, energy):
    """Frictional heat into the cells on both sides (option (b) of the digest's section 5.6).

    The slave side receives ``slave_share`` (beta_T of the slave material, eq. 2.101) of
    node j's friction work, split between its two adjacent slave cells with weights
    ``weight_before`` and 1 - weight_before (tributary half lengths); the guide side receives
    the rest in the guide cell next to segment ``seg[j]``.  ``energy`` is the specific
    internal energy (J/kg) of the cells and ``cell_mass`` their masses; a cell index < 0 is
    skipped and its share goes to the other slave cell.
    """
    for j in range(work.size):
        if not active[j] or work[j] == 0.0:
            continue
        q_slave = slave_share * work[j]
        q_guide = work[j] - q_slave
        cb = slave_cell_before[j]
        ca = slave_cell_after[j]
        wb = weight_before[j]
        if cb < 0:
            wb = 0.0
        if ca < 0:
            wb = 1.0
        if cb >= 0 and wb > 0.0:
            energy[cb] += wb * q_slave / cell_mass[cb]
        if ca >= 0 and wb < 1.0:
            energy[ca] += (1.0 - wb) * q_slave / cell_mass[ca]
        cg = guide_cell[seg[j]]
        energy[cg] += q_guide / cell_mass[cg]
