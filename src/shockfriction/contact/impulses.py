"""Contact (normal) and friction (tangential) velocity corrections by impulses (thesis 3.3.2-3.3.3).

Both steps act on the free nodal velocities v* = v^{n-1/2} + dt F/m (eqs. 3.54-3.60)
of a slave node g and of its projection G on the guide (eqs. 3.61-3.63).  The
projection is a set of guide nodes i with weights w_i (sum 1), given per pair as
rows of ``gnode``/``gw``: (1 - coef, coef) on the ends of the paired segment (the
thesis's point share, :func:`point_weights`) or the mortar-type weights of
:func:`shockfriction.contact.pairing.hat_weights`.  Its velocity is
v_G = sum w_i v_i.  One consistent sign (the digest's section 5.4 errata): an
impulse P (N s) along a unit direction d acts +P d on the slave node and -P d on
the projection, shared by the guide nodes as w_i P, so momentum is conserved
exactly.  v_G then changes by -P/m_G with the projection mass

    1/m_G = sum_i w_i^2/m_i   (= (1 - coef)^2/m_0 + coef^2/m_1 for the point share),

and the relative velocity w = (v_g - v_G).d by P (1/m_g + 1/m_G).  The sticking
("welding") impulse that cancels w is therefore the reduced-mass one of eq. 3.76,

    P_* = -w m_g m_G/(m_g + m_G),

exact for every share (the thesis's m_G = (1 - coef) m_0 + coef m_1 with a velocity
share leaves a residual slip when 0 < coef < 1; both agree at coef = 0 or 1 and
for equal guide masses the impulse shares are the same).  The work of the impulses
over the step is -P (w^{n-1/2} + w^{n+1/2})/2 (:func:`impulse_work`), which is how
friction work is counted (zero for a sticking pair).

Normal step (unilateral by default): the target relative normal velocity is
w_n = -g/dt (g the gap at t^n) for an open gap, so a gap that the free motion would
overrun closes exactly at t^{n+1}, and w_n = 0 for a penetration (g <= 0: the pair
is held, never pushed apart by a velocity); the accumulated normal impulse is kept
>= 0 (no tension).  With ``bilateral`` (the thesis's permanent contact, eqs.
3.64-3.66) it may be negative.  A penetration left at t^{n+1} is removed by a
position projection (:func:`penetration_projection`): displacements +Q n/m_g on the
slave node and -w_i Q n/m_i on the guide nodes (sum m dx = 0: the centre of mass,
hence momentum, is untouched; no velocity changes).  Pushing a penetration out by a
velocity instead (w_n = -c g/dt, the former Baumgarte-type c = 0.1) makes the normal
impulses do positive work: the contact created energy (docs/theory/contact-energy-and-shear-viscosity.md).

Tangential step: free slip s* = (v_g - v_G).t after the normal step; the law gives
the traction limit tau_max(|F_N|, |[V]|, Y_g, Y_G) (eq. 3.77-3.81) and the friction
impulse is the sticking impulse capped by tau_max S_g dt (eqs. 3.82-3.85 with the signs
fixed).  |[V]| is the free slip |s*| (eq. 3.79) for ``evaluation = "free"``; by default
a velocity-dependent law sees the slip after the step's correction, relaxed over a few
steps (:mod:`shockfriction.friction.laws`).  Nodes without a compressive
normal impulse get no friction (bilateral contact uses |F_N|).

Several slave nodes may share guide nodes; the corrections are applied node after
node (Gauss-Seidel) and the sweep is repeated until the largest relative-velocity
change of a sweep falls below ``rel_tol`` times the initial one (at most
``max_sweeps``; ``max_sweeps = 1`` is the thesis's single pass).  Accumulated
impulses are projected (>= 0 normal, |P_t| <= cap), so the iteration is a
projected Gauss-Seidel on the contact conditions.
"""

from __future__ import annotations


import numpy as np
from numba import njit

from shockfriction.friction.laws import corrected_traction, relaxation_rate, slip_weight, traction_limit


@njit(cache=True, inline="always")
def _inverse_pair_mass(j, i_g, gnode, gw, mass):
    """1/m_g + 1/m_G for pair j."""
    inv = 1.0 / mass[i_g]
    for k in range(gnode.shape[1]):
        w = gw[j, k]
        if w != 0.0:
            inv += w * w / mass[gnode[j, k]]
    return inv


@njit(cache=True)
def _inverse_pair_masses(slave, gnode, gw, mass, active):
    """:func:`_inverse_pair_mass` of every active pair (0 for the others), once per step: the masses do not change
    during the sweeps."""
    ns = slave.size
    inv = np.zeros(ns)
    for j in range(ns):
        if active[j]:
            inv[j] = _inverse_pair_mass(j, slave[j], gnode, gw, mass)
    return inv


@njit(cache=True, inline="always")
def _relative_velocity(vx, vy, j, i_g, gnode, gw, dx, dy):
    """(v_g - v_G).d with v_G = sum_i w_i v_i."""
    ux = vx[i_g]
    uy = vy[i_g]
    for k in range(gnode.shape[1]):
        w = gw[j, k]
        if w != 0.0:
            ux -= w * vx[gnode[j, k]]
            uy -= w * vy[gnode[j, k]]
    return ux * dx + uy * dy


@njit(cache=True, inline="always")
def _apply(vx, vy, mass, j, i_g, gnode, gw, dx, dy, p):
    """Impulse +p d on the slave node, -p d on its projection shared w_i p by the guide nodes."""
    vx[i_g] += p * dx / mass[i_g]
    vy[i_g] += p * dy / mass[i_g]
    for k in range(gnode.shape[1]):
        w = gw[j, k]
        if w != 0.0:
            i = gnode[j, k]
            vx[i] -= w * p * dx / mass[i]
            vy[i] -= w * p * dy / mass[i]


@njit(cache=True)
def normal_step(vx, vy, mass, slave, gnode, gw, nx, ny, gap, active, dt, bilateral,
                max_sweeps, rel_tol, lam_n):
    """Contact step: normal impulses ``lam_n`` (N s, >= 0 compressive unless bilateral).

    ``dt`` is the step over which the positions advance: the target relative normal
    velocity is -gap/dt for an open gap (closed exactly at t^{n+1}) and 0 for a
    penetration (held; :func:`penetration_projection` removes it).  ``gnode[j, :]``, ``gw[j, :]`` are the guide nodes and weights of
    pair j (weight 0 pads).  Corrects ``vx, vy`` in place.  Returns the number of sweeps done.
    """
    ns = slave.size
    for j in range(ns):
        lam_n[j] = 0.0
    inv = _inverse_pair_masses(slave, gnode, gw, mass, active)
    scale = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        sweeps += 1
        change = 0.0
        for j in range(ns):
            if not active[j]:
                continue
            i_g = slave[j]
            inv_pair = inv[j]
            w = _relative_velocity(vx, vy, j, i_g, gnode, gw, nx[j], ny[j])
            target = -gap[j] / dt if gap[j] > 0.0 else 0.0
            new = lam_n[j] + (target - w) / inv_pair
            if not bilateral and new < 0.0:
                new = 0.0
            dp = new - lam_n[j]
            if dp == 0.0:
                continue
            lam_n[j] = new
            _apply(vx, vy, mass, j, i_g, gnode, gw, nx[j], ny[j], dp)
            dv = abs(dp * inv_pair)
            if dv > change:
                change = dv
        if sweep == 0:
            scale = change
        if change <= rel_tol * scale:
            break
    return sweeps


@njit(cache=True)
def penetration_projection(vx, vy, mass, slave, gnode, gw, nx, ny, gap, active, dt, max_sweeps, rel_tol,
                           sx, sy, lam_p):
    """Position projection of the penetrations left at t^{n+1}; returns the sweeps done.

    The predicted gap of pair j is g_j + dt (v_g - v_G).n + (dx_g - dx_G).n (``gap`` at t^n,
    the corrected velocities ``vx, vy``, the position shifts ``sx, sy`` accumulated in place).
    A "position impulse" Q_j >= 0 (kg m) shifts the slave node by +Q n/m_g and guide node i by
    -w_i Q n/m_i, the same mass weighting as the velocity impulses, so sum m dx = 0 (momentum
    and the centre of mass are untouched) and no velocity changes.  Projected Gauss-Seidel on
    predicted gap >= 0 (Q_j = -g_pred/(1/m_g + 1/m_G) for one isolated pair), ``lam_p[j]`` = Q_j.
    """
    ns = slave.size
    for j in range(ns):
        lam_p[j] = 0.0
    inv = _inverse_pair_masses(slave, gnode, gw, mass, active)
    scale = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        sweeps += 1
        change = 0.0
        for j in range(ns):
            if not active[j]:
                continue
            i_g = slave[j]
            pred = (gap[j] + dt * _relative_velocity(vx, vy, j, i_g, gnode, gw, nx[j], ny[j])
                    + _relative_velocity(sx, sy, j, i_g, gnode, gw, nx[j], ny[j]))
            if pred >= 0.0 and lam_p[j] == 0.0:
                continue
            inv_pair = inv[j]
            new = lam_p[j] - pred / inv_pair
            if new < 0.0:
                new = 0.0
            dq = new - lam_p[j]
            if dq == 0.0:
                continue
            lam_p[j] = new
            _apply(sx, sy, mass, j, i_g, gnode, gw, nx[j], ny[j], dq)
            dd = abs(dq * inv_pair)
            if dd > change:
                change = dd
        if sweep == 0:
            scale = change
        if change <= rel_tol * scale:
            break
    return sweeps


@njit(cache=True, inline="always")
def capped_update(vx, vy, mass, j, i_g, gnode, gw, tx, ty, lam_t, cap, s, inv_pair):
    """One projected Gauss-Seidel update of pair j: move its tangential impulse toward the value
    that cancels the slip s, clipped to [-cap, cap], and apply the change (equal and opposite on
    the slave node and the guide).  Returns the change of the relative velocity."""
    new = lam_t[j] - s / inv_pair
    if new > cap:
        new = cap
    elif new < -cap:
        new = -cap
    dp = new - lam_t[j]
    if dp == 0.0:
        return 0.0
    lam_t[j] = new
    _apply(vx, vy, mass, j, i_g, gnode, gw, tx, ty, dp)
    return abs(dp * inv_pair)


@njit(cache=True)
def tangential_step(vx, vy, mass, slave, gnode, gw, tx, ty, active, dt, area,
                    law, law_params, y_slave, y_guide, lam_n, max_sweeps, rel_tol,
                    lam_t, slip_free, slip, slip_law=None):
    """Friction step: tangential impulses ``lam_t`` (N s, on the slave along t).

    ``slip_free[j]`` is the free slip s* = (v_g - v_G).t after the normal step and
    ``slip[j]`` the corrected slip.  ``y_slave[j]``, ``y_guide[j]`` are the yield stresses
    of the two sides at node j (Tresca laws only); ``dt`` is the velocity step (force =
    impulse/dt).  A law that does not depend on the slip speed, or ``evaluation = "free"``
    (theta = 0 in ``law_params``), is evaluated once at |s*| (eq. 3.79).  Otherwise each
    visit of node j solves the law at the slip after its own correction
    (:func:`~shockfriction.friction.laws.corrected_traction`), relaxed over n steps through
    ``slip_law[j]`` (the law's slip speed, kept between steps; updated in place; None: a
    state starting from rest).  Returns the sweeps done.
    """
    ns = slave.size
    cap = lam_n.copy()
    sigma = lam_n.copy()
    theta = slip_weight(law, law_params)
    relax = relaxation_rate(law_params)
    if slip_law is None:
        state = np.zeros(ns)
    else:
        state = slip_law
    for j in range(ns):
        lam_t[j] = 0.0
        slip_free[j] = 0.0
        slip[j] = 0.0
        cap[j] = 0.0
        sigma[j] = 0.0
        if not active[j]:
            continue
        s = _relative_velocity(vx, vy, j, slave[j], gnode, gw, tx[j], ty[j])
        slip_free[j] = s
        if lam_n[j] == 0.0 or area[j] <= 0.0:
            state[j] = abs(s)     # the law's slip follows the slip while the pair carries no friction
            continue
        sigma[j] = lam_n[j] / (dt * area[j])
        cap[j] = traction_limit(law, law_params, sigma[j], abs(s), y_slave[j], y_guide[j]) * area[j] * dt
    inv = _inverse_pair_masses(slave, gnode, gw, mass, active)
    scale = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        sweeps += 1
        change = 0.0
        for j in range(ns):
            if sigma[j] == 0.0 or (theta == 0.0 and cap[j] <= 0.0):
                continue
            i_g = slave[j]
            inv_pair = inv[j]
            s = _relative_velocity(vx, vy, j, i_g, gnode, gw, tx[j], ty[j])
            if theta > 0.0:    # the law at the slip after this node's correction (s - lam_t/inv is its free slip)
                s_own = abs(s - lam_t[j] * inv_pair)
                if relax > 0.0:
                    w = (state[j] + relax * s_own) / (1.0 + relax)
                    th = theta * relax / (1.0 + relax)
                else:
                    w = s_own
                    th = theta
                cap[j] = corrected_traction(law, law_params, sigma[j], w, s_own,
                                            area[j] * dt * inv_pair, th, y_slave[j], y_guide[j]) * area[j] * dt
            dv = capped_update(vx, vy, mass, j, i_g, gnode, gw, tx[j], ty[j], lam_t, cap[j], s, inv_pair)
            if dv > change:
                change = dv
        if sweep == 0:
            scale = change
        if change <= rel_tol * scale:
            break
    for j in range(ns):
        if active[j]:
            slip[j] = _relative_velocity(vx, vy, j, slave[j], gnode, gw, tx[j], ty[j])
            if theta > 0.0 and relax > 0.0 and sigma[j] > 0.0:
                state[j] = (state[j] + relax * abs(slip[j])) / (1.0 + relax)
    return sweeps


@njit(cache=True)
def impulse_work(vx, vy, vx_old, vy_old, slave, gnode, gw, dx, dy, active, lam, work):
    """Work of the pair impulses over the step: work[j] = -lam[j] (w_old + w_new)/2 (J, >= 0 when dissipated).

    w = (v_g - v_G).d is the relative velocity along d (n or t) of node j, at t^{n-1/2}
    (``vx_old, vy_old``) and t^{n+1/2} (``vx, vy``, after all corrections).  Summed over the
    pairs and the two directions this is exactly minus the change of the leapfrog kinetic
    energy sum m dv.(v^{n-1/2} + v^{n+1/2})/2 caused by the corrections, so a sticking pair
    (no slip before and after) does no work, whatever the free slip was.
    """
    for j in range(slave.size):
        work[j] = 0.0
        if not active[j] or lam[j] == 0.0:
            continue
        w_new = _relative_velocity(vx, vy, j, slave[j], gnode, gw, dx[j], dy[j])
        w_old = _relative_velocity(vx_old, vy_old, j, slave[j], gnode, gw, dx[j], dy[j])
        work[j] = -0.5 * lam[j] * (w_old + w_new)


@njit(cache=True)
def point_weights(guide, seg, coef, active, gnode, gw):
    """The thesis's point share: guide nodes (guide[seg], guide[seg+1]) with weights (1 - coef, coef)."""
    for j in range(seg.size):
        for k in range(gnode.shape[1]):
            gnode[j, k] = guide[0]
            gw[j, k] = 0.0
        if not active[j]:
            continue
        gnode[j, 0] = guide[seg[j]]
        gnode[j, 1] = guide[seg[j] + 1]
        gw[j, 0] = 1.0 - coef[j]
        gw[j, 1] = coef[j]
        if gnode[j, 1] == gnode[j, 0]:     # one node group (periodic seam)
            gw[j, 0] = 1.0
            gw[j, 1] = 0.0


@njit(cache=True, inline="always")
def _heat_slave_cells(q, cb, ca, wb, cell_mass, energy):
    """Put the slave side's heat q (J) into its two cells, share wb to the cell before the node (cb) and the rest to
    the one after (ca); a cell index < 0 gives its share to the other cell."""
    if cb < 0:
        wb = 0.0
    if ca < 0:
        wb = 1.0
    if cb >= 0 and wb > 0.0:
        energy[cb] += wb * q / cell_mass[cb]
    if ca >= 0 and wb < 1.0:
        energy[ca] += (1.0 - wb) * q / cell_mass[ca]


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
        _heat_slave_cells(q_slave, slave_cell_before[j], slave_cell_after[j], weight_before[j], cell_mass, energy)
        cg = guide_cell[seg[j]]
        energy[cg] += q_guide / cell_mass[cg]


@njit(cache=True)
def deposit_contact_heat(work, active, slave, gnode, gw, mass, slave_cell_before, slave_cell_after,
                         weight_before, guide_local, guide_cells, periodic, cell_mass, energy):
    """The normal impulses' inelastic loss into the cells on both sides; returns the heat put in (J).

    ``work[j]`` is the normal impulses' work over the step (:func:`impulse_work`, >= 0 when
    dissipated): the kinetic energy the contact step took from pair j.  The slave side receives the
    share M_G/(m_g + M_G) (the kinetic energy the slave node loses relative to the pair's centre of
    mass in a perfectly inelastic stop; 1/2 for equal masses) with M_G = sum_i w_i m_i, the
    thesis's projection mass (an average of the guide masses: the harmonic 1/m_G = sum w_i^2/m_i
    of the impulses varies from pair to pair on non-matching meshes, and a uniform contact would
    heat unevenly), split between its two adjacent slave cells by ``weight_before`` like the
    friction heat.  The guide side's rest goes to
    the guide nodes of the projection by their weights ``gw`` (the impulse's own share) and from each
    guide node half to each of its two guide cells (``guide_local[node]``: its index along the
    guide, -1 off it; ``guide_cells[k]``: the cell of guide segment k; an end node gives its cell
    all), so that a uniform contact heats a uniform guide uniformly.  The work is deposited with
    its sign (a step where a pair's impulse did positive work takes that energy from the cells: the
    books stay closed and the cycle's error counts a net contact gain;
    docs/theory/contact-energy-and-shear-viscosity.md).
    """
    total = 0.0
    nseg = guide_cells.size
    for j in range(work.size):
        if not active[j] or work[j] == 0.0:
            continue
        i_g = slave[j]
        m_guide = 0.0
        for k in range(gnode.shape[1]):
            m_guide += gw[j, k] * mass[gnode[j, k]]
        q_slave = m_guide / (mass[i_g] + m_guide) * work[j]
        q_guide = work[j] - q_slave
        _heat_slave_cells(q_slave, slave_cell_before[j], slave_cell_after[j], weight_before[j], cell_mass, energy)
        for k in range(gnode.shape[1]):
            w = gw[j, k]
            if w == 0.0:
                continue
            i = guide_local[gnode[j, k]]
            before = i - 1
            after = i
            if periodic and before < 0:
                before = nseg - 1
            if after >= nseg:
                after = 0 if periodic else -1
            q = w * q_guide
            if before >= 0 and after >= 0:
                energy[guide_cells[before]] += 0.5 * q / cell_mass[guide_cells[before]]
                energy[guide_cells[after]] += 0.5 * q / cell_mass[guide_cells[after]]
            elif before >= 0:
                energy[guide_cells[before]] += q / cell_mass[guide_cells[before]]
            else:
                energy[guide_cells[after]] += q / cell_mass[guide_cells[after]]
        total += work[j]
    return total


@njit(cache=True)
def side_yield_stress(cell_yield, cell_before, cell_after, weight_before, seg, guide_cells, y_slave, y_guide):
    """Yield stresses of the two sides at each slave node (Tresca laws), in place.

    Slave side: the two adjacent slave cells weighted by ``weight_before`` and 1 - weight_before
    (a missing cell, index < 0, gives its share to the other); guide side: the cell next to the
    paired segment ``seg`` (0 when unpaired)."""
    for j in range(seg.size):
        b = cell_before[j]
        a = cell_after[j]
        yb = cell_yield[b] if b >= 0 else 0.0
        ya = cell_yield[a] if a >= 0 else 0.0
        wb = weight_before[j] if b >= 0 else 0.0
        if a < 0:
            wb = 1.0
        y_slave[j] = wb * yb + (1.0 - wb) * ya
        y_guide[j] = cell_yield[guide_cells[seg[j]]] if seg[j] >= 0 else 0.0


@njit(cache=True)
def accumulate_step(work_t, slip, lam_n, lam_t, dt, cum_work, cum_slip, win_lam_n, win_lam_t, win_slip):
    """Running sums of a slide line after a step: friction work, slip displacement slip dt and the
    record window's impulses and slip (in place)."""
    for j in range(work_t.size):
        cum_work[j] += work_t[j]
        cum_slip[j] += slip[j] * dt
        win_lam_n[j] += lam_n[j]
        win_lam_t[j] += lam_t[j]
        win_slip[j] += slip[j] * dt
