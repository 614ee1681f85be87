"""The viscoplastic column with its velocity unknowns (far end "impedance" or "held", with or without inertia): its
kernel, one column at a time (equations and scheme: :mod:`shockfriction.friction.subgrid.viscoplastic` and
docs/theory/viscoplastic.md; cost: "Cost").

Each column is gathered into contiguous arrays, stepped there and scattered back, as the excess layer's kernel
does (:mod:`shockfriction.friction.subgrid.excess_layer`): a converged column stops where it is (no masked sweeps
over the columns still iterating), the material state vectorises along the column, and the heat solve of a solid
column is the excess layer's factored one.  The iteration is the shared one: Picard sweeps on the enthalpies that
set G, Y and eta (the same predictor, secant at z = 0, Aitken in the bulk); in each, the backward-Euler mechanics
by Newton on the node velocities with an exact line search on the step's convex incremental energy and a
slip/stick switch at z = 0; then the heat.

The mechanics of a sweep runs on a window: the cells beyond the last one that may flow plastically (the deepest
cell plastic at the start of the sweep or in the last one, plus :data:`WINDOW_MARGIN`) are linear (elastic or
molten at the sweep's fixed G and eta_L), so the node rows below the window are eliminated once per sweep into a
linear reaction at the window's last node (a Schur complement: the far field's velocities follow from the window's
by back substitution), and the Newton iterates only on the window.  A far cell found plastic at the solution
grows the window and the sweep's mechanics is solved again.
"""

from __future__ import annotations

import math

import numpy as np
from numba import get_num_threads, njit, prange

from shockfriction.friction.subgrid.excess_layer import (
    _column_heat, _heat_factor, cell_shear_ratio, commit_heat, commit_surface, forget_history, gather_predict,
    next_iterate, picard_converged, surface_cap)
from shockfriction.friction.subgrid.viscoplastic import (
    BAD_INPUT, E_NUMERICAL, E_PLASTIC, E_RADIATED,
    E_SOFTENING, E_VISCOUS, NO_CONVERGENCE, OK, P_BETA_Q, P_BETA_T, P_C, P_E_R, P_ETA_F, P_ETA_VP, P_F,
    P_HEAT_TOL, P_INERTIA, P_KAPPA, P_L, P_MAX_NEWTON, P_MECH_TOL, P_PICARD_TOL, P_RHO, P_T0, P_T_FAR, P_V_R, P_Z,
    PHI_MIN, SQRT3, _cell_state, linear_return, liquid_viscosity, other_body_response, return_correction,
    return_map, temperature_of)
from shockfriction.jit_bits import fetch_add
from shockfriction.materials.strength import (
    I_BETA, I_G, I_G0, I_H, I_N, I_TF, I_XI, I_Y0, I_YMAX)

#: cells kept in the mechanics window below the deepest cell that flowed plastically (docs/theory/viscoplastic.md,
#: "Cost"); a far cell that flows at the solution grows the window
WINDOW_MARGIN = 16
INV_SQRT3 = 1.0 / SQRT3
#: the largest relative Newton correction after which the mechanics may stop on its quadratic estimate of the next
#: one (:func:`_newton_converged`)
NEWTON_TRUST = 1e-5
#: columns from which :func:`inertial_step` runs in parallel blocks when numba has more than one thread
PARALLEL_MIN_COLUMNS = 8


def inertial_step(dz, w, v, ge, Gs, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                  tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                  TF, v_far, T2, c2, a2, oth, reach):
    """Advance every column by dt (:func:`_inertial_block`; arguments as
    :func:`~shockfriction.friction.subgrid.excess_layer.excess_step`, ``v_far`` the held far end's velocity,
    ``reach`` (nc,) int64 the deepest
    plastic cell + 1 of each column's last step, updated): in parallel blocks of consecutive columns where numba has
    more than one thread (the same bytes as one block: every column is stepped alone)."""
    nc = v.shape[1]
    threads = get_num_threads()
    if threads > 1 and nc >= PARALLEL_MIN_COLUMNS:
        _inertial_parallel(dz, w, v, ge, Gs, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                           tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                           TF, v_far, T2, c2, a2, oth, reach, min(threads * 4, nc))
        return 0
    return _inertial_block(dz, w, v, ge, Gs, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                           tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                           TF, v_far, T2, c2, a2, oth, reach, np.uint64(0), np.uint64(nc))


@njit(cache=True, parallel=True, error_model="numpy")
def _inertial_parallel(dz, w, v, ge, Gs, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                       tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                       TF, v_far, T2, c2, a2, oth, reach, nblocks):
    """:func:`_inertial_block` over ``nblocks`` blocks of consecutive columns in parallel, taken from a work
    queue (as :func:`~shockfriction.friction.subgrid.excess_layer._excess_parallel`)."""
    nc = v.shape[1]
    queue = np.zeros(1, np.int64)
    for _ in prange(nblocks):  # a thread's first iteration takes blocks until none is left, its others none
        while True:
            b = fetch_add(queue, 0)
            if b >= nblocks:
                break
            _inertial_block(dz, w, v, ge, Gs, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                            tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                            TF, v_far, T2, c2, a2, oth, reach, np.uint64(b * nc // nblocks),
                            np.uint64((b + 1) * nc // nblocks))


@njit(cache=True, error_model="numpy")
def _returns(nq, qa, qg, qkf, qy, qeps, qx, qd, qok, eta_dt, beta, n, Ymax):
    """The return maps of the nq plastic cells gathered by :func:`_cells` (|s_tr| qa, G qg, k_fac qkf, y_start qy,
    eps qeps, the first iterate qx: the cell's last increment in this step, < 0: none), in one loop without
    branches that vectorises: from the first iterate (else the closed-form linear return with the hardening slope at
    the start of the step), two Newton corrections
    (:func:`~shockfriction.friction.subgrid.viscoplastic.return_correction`, ``return_map``'s own) and the estimate
    of the next one, the tangent carried to the new x; qx, qd the increment and d|s'|/d|s_tr|, qok 1 where the
    estimate is within the tolerance, else 0 (the caller redoes the cell by ``return_map``)."""
    for q in range(nq):
        a = qa[q]
        kf = qkf[q]
        ys = qy[q]
        cc = qg[q] + eta_dt
        ub = beta / (SQRT3 * (1.0 + beta * qeps[q]))  # Y = y_start (1 + u)^n, u = x ub
        x1 = qx[q] if qx[q] >= 0.0 else linear_return(a, cc, ys, kf, ub, n, Ymax)
        x2, _, _, _, _ = return_correction(a, cc, x1, ys, ub, kf, n, Ymax)
        x3, dx, dk, kpp, den = return_correction(a, cc, x2, ys, ub, kf, n, Ymax)
        ok = 0.5 * abs(kpp) / den * (dx * dx) <= 1e-15 * x3 or abs(dx) <= 1e-15 * x3
        dk2 = dk + kpp * dx
        qx[q] = x3
        qd[q] = (eta_dt + dk2) / (cc + dk2)
        qok[q] = 1.0 if ok else 0.0


@njit(cache=True, error_model="numpy")
def _cells(vt, nw, idz, dt, G, ge, eps, yh, eta, kf, beta, n, Ymax, eta_vp, S, Kc, gdm, snew, dgp, qi, qa,
           qg, qkf, qy, qeps, qx, qd, qok):
    """Stresses S[c + 1], stiffnesses Kc[c], strain rates gdm, solid stresses snew and plastic increments dgp of the
    cells c < nw at the trial velocities vt (backward Euler, the plastic increment that of
    :func:`~shockfriction.friction.subgrid.viscoplastic.return_map`; idz = 1/dz); returns the number of solid cells
    that flow plastically and the deepest one + 1 (0: none).  In passes (docs/theory/viscoplastic.md, "The return
    maps across the cells"): every cell's trial state (vectorised), the linear (elastic, molten) cells' values, the
    plastic cells' return maps in one vectorised loop (:func:`_returns`; each started from its last increment in
    this step; where they are the cells 0 .. deep - 1, the common case, on the column's own arrays, else gathered
    into q*, qi their indices), a cell whose estimate was not within the tolerance redone by ``return_map``."""
    eta_dt = eta_vp / dt
    npl = 0
    deep = 0
    for c in range(nw):  # (no branches)
        gd = (vt[c] - vt[c + 1]) * idz[c]
        s_tr = G[c] * (ge[c] + dt * gd)
        gdm[c] = gd
        snew[c] = s_tr
        pl = G[c] > 0.0 and abs(s_tr) > yh[c] * kf[c]
        npl += 1 if pl else 0
        deep = max(deep, c + 1 if pl else 0)
    dense = npl == deep
    for c in range(npl if dense else 0, nw):  # elastic and molten cells (no branches; the plastic ones redone below)
        solid = G[c] > 0.0
        gd = gdm[c]
        sn = snew[c] if solid else 0.0
        snew[c] = sn
        S[c + 1] = sn + eta[c] * gd
        Kc[c] = (G[c] * dt + eta[c]) * idz[c]
        dgp[c] = 0.0 if solid else ge[c] + dt * gd  # a molten cell releases its stored elastic strain
    if npl == 0:
        return 0, 0
    if dense:
        for c in range(npl):
            qa[c] = abs(snew[c])
            qx[c] = abs(dgp[c]) if dgp[c] != 0.0 else -1.0  # the cell's last increment in this step
        _returns(npl, qa, G, kf, yh, eps, qx, qd, qok, eta_dt, beta, n, Ymax)
    else:
        q = 0
        for c in range(deep):
            if G[c] > 0.0 and abs(snew[c]) > yh[c] * kf[c]:
                qi[q] = c
                qa[q] = abs(snew[c])
                qg[q] = G[c]
                qkf[q] = kf[c]
                qy[q] = yh[c]
                qeps[q] = eps[c]
                qx[q] = abs(dgp[c]) if dgp[c] != 0.0 else -1.0
                q += 1
        _returns(npl, qa, qg, qkf, qy, qeps, qx, qd, qok, eta_dt, beta, n, Ymax)
    for q in range(npl):
        c = q if dense else qi[q]
        x = qx[q]
        d = qd[q]
        if qok[q] == 0.0:
            x0 = abs(dgp[c]) if dgp[c] != 0.0 else -1.0
            x, d = return_map(qa[q], G[c], eta_dt, eps[c], yh[c], kf[c], beta, n, Ymax, x0)
        s_tr = snew[c]
        g = G[c]
        sg = 1.0 if s_tr >= 0.0 else -1.0
        sn = s_tr - sg * g * x
        snew[c] = sn
        S[c + 1] = sn + eta[c] * gdm[c]
        Kc[c] = (d * g * dt + eta[c]) * idz[c]
        dgp[c] = sg * x
    return npl, deep


@njit(cache=True, error_model="numpy", inline="always")
def _newton_converged(r, nq, full, mtol):
    """Has the mechanics Newton converged?  r = the last correction relative to the velocity scale.  Converged where
    r <= mtol, or where the next correction of a quadratically converging Newton, nq r^2 (nq = r_k/r_(k-1)^2 from
    the column's last two full steps in this step, carried across its sweeps), is, provided the step was a full
    Newton step on an unchanged plastic set (``full``) and r <= NEWTON_TRUST (docs/theory/viscoplastic.md, "The
    mechanics Newton's last iteration")."""
    return r <= mtol or (full and nq >= 0.0 and r <= NEWTON_TRUST and nq * r * r <= mtol)


@njit(cache=True, error_model="numpy")
def _slope(vt, vo, d, S, mass, dt, stick, kj, vf, ts, nw, far_a, far_z):
    """g = sum_i d_i R_i at the trial velocities vt over the window's rows 0..nw (rows with a Dirichlet condition
    left out; row nw's reaction far_a + far_z v_nw): the derivative of the step's convex incremental energy along
    the Newton direction d."""
    g = 0.0
    if not (stick and kj <= 0.0):
        S0 = (vf - vt[0]) / kj if stick else ts
        g += d[0] * (mass[0] * (vt[0] - vo[0]) / dt - S0 + S[1])
    for i in range(1, nw):
        g += d[i] * (mass[i] * (vt[i] - vo[i]) / dt - S[i] + S[i + 1])
    if math.isfinite(far_z) and nw > 0:
        g += d[nw] * (mass[nw] * (vt[nw] - vo[nw]) / dt - S[nw] + far_a + far_z * vt[nw])
    return g


@njit(cache=True, error_model="numpy")
def _condense(vo, dz, dt, mass, G, ge, eta, nw, M, imped, Zc, held_v, pf, qf):
    """Eliminate the node rows nw + 1 .. M below the window (cells nw .. M - 1 linear: S_(c+1) = A_c + K_c (v_c -
    v_(c+1)), A_c = G_c ge_c, K_c = (G_c dt + eta_c)/dz_c) from the bottom: v_i = pf_i + qf_i v_(i-1).  The far
    end: the impedance Zc (imped), else held at held_v.  Returns the far field's reaction on node nw,
    S_(nw+1) = a + z v_nw, as (a, z)."""
    if imped:
        KM = (G[M - 1] * dt + eta[M - 1]) / dz[M - 1]
        den = mass[M] / dt + KM + Zc
        pf[M] = (mass[M] / dt * vo[M] + G[M - 1] * ge[M - 1]) / den
        qf[M] = KM / den
    else:
        pf[M] = held_v
        qf[M] = 0.0
    for i in range(M - 1, nw, -1):
        Kl = (G[i - 1] * dt + eta[i - 1]) / dz[i - 1]
        Ku = (G[i] * dt + eta[i]) / dz[i]
        den = mass[i] / dt + Kl + Ku - Ku * qf[i + 1]
        pf[i] = (mass[i] / dt * vo[i] + G[i - 1] * ge[i - 1] - G[i] * ge[i] + Ku * pf[i + 1]) / den
        qf[i] = Kl / den
    Kw = (G[nw] * dt + eta[nw]) / dz[nw]
    return G[nw] * ge[nw] - Kw * pf[nw + 1], Kw * (1.0 - qf[nw + 1])


@njit(cache=True, error_model="numpy")
def _inertial_block(dz, w, v, ge, Gs, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                    tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                    TF, v_far, T2, c2, a2, oth, reach, j0, j1):
    """Advance the columns j0 <= j < j1 by dt, one at a time (j0, j1 unsigned: the column index is then known to be
    non-negative, so numba indexes without the negative-index wrap) (state arrays updated in place; see the module
    docstring and :mod:`shockfriction.friction.subgrid.viscoplastic`'s).

    State: v (nn, nc) velocity, ge (M, nc) elastic shear strain, Gs (M, nc) modulus of the stored stress
    (s = Gs ge), eps (M, nc) equivalent plastic strain, e (nn, nc) enthalpy density rel. T0, T (nn, nc); each
    column contiguous (Fortran order).  Per column inputs: F_N normal stress, v_free = [V*], v_prev = [V]^{n-1/2},
    k = S dt (1/m_s + 1/m_g), tau_cap = min(mu0 F_N, tau_stick).  Outputs: tau = |s(0)|, v_half = [V]^{n+1/2},
    v_local = slip at the surface (V - v(0), midpoint), q_in = beta_T tau v_local, film = molten thickness (m),
    iters (Picard), status, energy (N_ENERGY, nc) accumulated.  de, de2 (nn, nc): the enthalpy changes of the last
    two steps (updated); the first Picard iterate is the extrapolation E = e + a1 de + a2 de2, pw = (a1, a2, a1 of
    the linear one) from predictor_weights (zeros: none), linear where the history is not smooth (see SMOOTH); it
    moves the answer within the Picard tolerance only.  retry (nc,) bool: a column whose Picard iteration does not
    converge is left as it was (state, energy, de, de2 unchanged; outputs of its last sweep; iters = -max_iter) for
    the caller to redo in sub-steps; without retry it is committed (its energy balance is exact) with
    iters = -max_iter.  A column whose mechanics or heat solve fails gets status NO_CONVERGENCE and is left as it was.
    TF (nc,): each column's melting temperature this step (T_m(sigma_n)).  v_far (nc,): velocity of the far end
    z = h relative to the hydro node where it is held (far_end = "held"; docs/theory/viscoplastic.md, "Coupled
    closure"); 0 stand-alone.  T2 (n2, nc), c2 (n2,), a2 (n2 - 1,): the other body's thermal column (two-sided
    heat; n2 = 0: none, the fixed share beta_T): temperatures (node 0 the interface, continuous with T[0]), heat
    capacities per area (J/m^2/K) and conductances kappa2/dy (W/m^2/K); oth (2, n2, nc) scratch.  reach (nc,): the
    deepest cell that flowed plastically in each column's last step + 1 (the mechanics window's start; updated).
    """
    nn, nc = v.shape
    M = nn - 1
    rho, cth, kap, L, T0 = par[P_RHO], par[P_C], par[P_KAPPA], par[P_L], par[P_T0]
    rho_c, rho_L = rho * cth, rho * L
    eta_vp, eta_F, E_R = par[P_ETA_VP], par[P_ETA_F], par[P_E_R]
    beta_T, beta_Q, f = par[P_BETA_T], par[P_BETA_Q], par[P_F]
    inertia = par[P_INERTIA] > 0.5
    held = math.isinf(par[P_Z])
    imped = inertia and not held
    T_far = par[P_T_FAR]
    fixed_far = math.isfinite(T_far)
    mtol, htol, ptol = par[P_MECH_TOL], par[P_HEAT_TOL], par[P_PICARD_TOL]
    max_newton = int(par[P_MAX_NEWTON])
    G0, T_F0 = p[I_G0], p[I_TF]
    V_R = par[P_V_R]
    Y0, beta_h, n_h, Ymax = p[I_Y0], p[I_BETA], p[I_N], p[I_YMAX]
    g_p, h_p, xi = p[I_G], p[I_H], p[I_XI]
    tresca = f * Ymax / SQRT3
    idz = 1.0 / dz  # (the cell passes multiply)
    mass = np.empty(nn)
    for i in range(nn):
        mass[i] = rho * w[i] if inertia else 0.0
    al2v = np.zeros(nc)
    be2v = np.zeros(nc)
    other_body_response(T2, c2, a2, dt, oth, al2v, be2v, j0, j1)
    cl = np.zeros(nn)
    cu = np.zeros(nn)
    for i in range(nn):
        cl[i] = dt * kap / dz[i - 1] if i > 0 else 0.0
        cu[i] = dt * kap / dz[i] if i < M else 0.0
    fm = np.zeros(nn)
    fd = np.empty(nn)
    fu = np.empty(nn)
    fal2 = al2v[j0] if j1 > j0 else 0.0
    _heat_factor(w, cl, cu, rho_c, fal2, fixed_far, fm, fd, fu)
    fr = 1.0 / fd
    fh = fu / fd
    nodes = np.empty((22, nn))
    el, en, Em, Tm, phm, Tit, src, rb, d1, d2 = (nodes[0], nodes[1], nodes[2], nodes[3], nodes[4], nodes[5],
                                                nodes[6], nodes[7], nodes[8], nodes[9])
    Tk, dTk, lo, di, up, rhs, trial, vo, vn, vt, pf, qf = (
        nodes[10], nodes[11], nodes[12], nodes[13], nodes[14], nodes[15], nodes[16], nodes[17], nodes[18],
        nodes[19], nodes[20], nodes[21])
    S = np.empty(nn + 1)
    cells = np.empty((18, M))
    gel, Gsl, epsl, yh, G, kf, eta, sold, phc, Kc, dgp, snew, gdm = (
        cells[0], cells[1], cells[2], cells[3], cells[4], cells[5], cells[6], cells[7], cells[8], cells[9],
        cells[10], cells[11], cells[12])
    gen, wpc, wvc, wsc = cells[13], cells[14], cells[15], cells[16]  # new elastic strain, works per area
    dgt = cells[17]  # the far field's plastic increments at its test
    qcells = np.empty((8, M))  # the plastic cells gathered for their return maps (_cells)
    qa, qg, qkf, qy, qeps, qx, qd, qok = (qcells[0], qcells[1], qcells[2], qcells[3], qcells[4], qcells[5],
                                          qcells[6], qcells[7])
    qi = np.empty(M, dtype=np.int64)
    for j in range(j0, j1):
        F, vf, vp, kj = F_N[j], v_free[j], v_prev[j], k[j]
        TFj = TF[j]
        held_v = v_far[j] if held else 0.0
        status[j] = OK
        iters[j] = 0
        sgn = 1.0 if vf >= 0.0 else -1.0
        if not (math.isfinite(F) and math.isfinite(vf) and math.isfinite(vp) and math.isfinite(kj)
                and tau_cap[j] >= 0.0):
            status[j] = BAD_INPUT
            forget_history(de, de2, j)
            continue
        al2 = al2v[j]
        be2 = be2v[j]
        gather_predict(e, de, de2, j, el, d1, d2, Em, pw)  # the first Picard iterate
        for i in range(nn):
            vo[i] = v[i, j]
            vn[i] = vo[i]
            Tit[i] = T[i, j]
        for c in range(M):
            gel[c] = ge[c, j]
            Gsl[c] = Gs[c, j]
            epsl[c] = eps[c, j]
            sold[c] = Gsl[c] * gel[c]
            yh[c] = min(Ymax, Y0 * (1.0 + beta_h * epsl[c]) ** n_h)
            dgp[c] = 0.0  # no return-map guess yet
        nw = min(M, reach[j] + WINDOW_MARGIN)  # window: nodes 0..nw, cells 0..nw-1
        deep_all = 0
        fin = False
        failed = False
        stick = False
        dirn = 1.0
        blo = -np.inf
        bhi = np.inf
        xprev = 0.0
        rprev = 0.0
        omega = 1.0
        ts = 0.0
        Zc = 0.0
        hfin = 0.0
        q2fin = 0.0
        ts2 = 0.0
        nq = -1.0  # the column's Newton: next relative correction ~ nq r^2 (unknown yet)
        for pic in range(max_iter):
            # ---- material state at the trial enthalpies
            for i in range(nn):
                Tm[i], _, phm[i] = temperature_of(Em[i], rho_c, rho_L, T0, TFj)
            melt = False
            for c in range(M):  # (without branches, which vectorise along the column: the exponential inlined)
                phc[c], r = cell_shear_ratio(Tm, phm, c, F, g_p, h_p, xi, TFj)
                melt |= r <= 0.0
                G[c] = G0 * r
                kf[c] = r * INV_SQRT3
                eta[c] = 0.0
            if melt:  # a cell with melt carries it as a liquid layer ph dz in series with rigid solid (sub-cell film)
                for c in range(M):
                    if G[c] <= 0.0:
                        eta[c] = liquid_viscosity(0.5 * (Tm[c] + Tm[c + 1]), eta_F, E_R, T_F0, TFj,
                                                  max(F, 0.0) * V_R) / max(phc[c], PHI_MIN)
            Zc = math.sqrt(rho * G[M - 1])
            cap = surface_cap(tau_cap[j], tresca, f, F, Tm[0], g_p, h_p, xi, TFj)
            # ---- mechanics on the window, the far field condensed
            while True:
                # row nw's reaction S_(nw+1) = far_a + far_z v_nw: the condensed far field, the impedance at
                # the far end, or none (far_z = inf: held at held_v there)
                far_a = 0.0
                far_z = Zc if imped else math.inf
                if nw < M:
                    far_a, far_z = _condense(vo, dz, dt, mass, G, gel, eta, nw, M, imped, Zc, held_v, pf, qf)
                nsw = 0
                fresh = False
                done = False
                npl = 0
                deep = 0
                ls_a = 1.0
                rlast = -1.0  # the last full Newton step's relative correction (-1: none)
                for it in range(max_newton):
                    if not fresh:
                        npl, deep = _cells(vn, nw, idz, dt, G, gel, epsl, yh, eta, kf, beta_h, n_h, Ymax, eta_vp,
                                           S, Kc, gdm, snew, dgp, qi, qa, qg, qkf, qy, qeps, qx, qd, qok)
                    # surface row
                    if stick:
                        if kj > 0.0:
                            ts = (vf - vn[0]) / kj
                            S[0] = ts
                            di[0] = mass[0] / dt + Kc[0] + 1.0 / kj
                            rhs[0] = -(mass[0] * (vn[0] - vo[0]) / dt - S[0] + S[1])
                        else:
                            di[0] = 1.0
                            rhs[0] = -(vn[0] - vf)
                        up[0] = 0.0 if kj <= 0.0 else -Kc[0]
                    else:
                        ts = dirn * sgn * cap
                        S[0] = ts
                        di[0] = mass[0] / dt + Kc[0]
                        up[0] = -Kc[0]
                        rhs[0] = -(mass[0] * (vn[0] - vo[0]) / dt - S[0] + S[1])
                    lo[0] = 0.0
                    for i in range(1, nw):
                        lo[i] = -Kc[i - 1]
                        up[i] = -Kc[i]
                        di[i] = mass[i] / dt + Kc[i - 1] + Kc[i]
                        rhs[i] = -(mass[i] * (vn[i] - vo[i]) / dt - S[i] + S[i + 1])
                    up[nw] = 0.0
                    if math.isfinite(far_z):  # the far field's reaction (condensed), or the impedance
                        S[nw + 1] = far_a + far_z * vn[nw]
                        lo[nw] = -Kc[nw - 1]
                        di[nw] = mass[nw] / dt + Kc[nw - 1] + far_z
                        rhs[nw] = -(mass[nw] * (vn[nw] - vo[nw]) / dt - S[nw] + S[nw + 1])
                    else:  # held at the hydro's velocity there (v_far), or at rest (quasi-static)
                        lo[nw] = 0.0
                        di[nw] = 1.0
                        rhs[nw] = held_v - vn[nw]
                    for i in range(1, nw + 1):
                        m = lo[i] / di[i - 1]
                        di[i] -= m * up[i - 1]
                        rhs[i] -= m * rhs[i - 1]
                    rhs[nw] /= di[nw]
                    for i in range(nw - 1, -1, -1):
                        rhs[i] = (rhs[i] - up[i] * rhs[i + 1]) / di[i]
                    # line search on the slope g(a) = d . R(vn + a d), increasing in a (convexity)
                    g0 = _slope(vn, vo, rhs, S, mass, dt, stick, kj, vf, ts, nw, far_a, far_z)
                    ls_a = 1.0
                    ls_lo = 0.0
                    ls_glo = g0
                    ls_hi = 1.0
                    ls_ghi = 0.0
                    side = 0
                    for i in range(nw + 1):
                        vt[i] = vn[i] + rhs[i]
                    plv = npl
                    npl, deep = _cells(vt, nw, idz, dt, G, gel, epsl, yh, eta, kf, beta_h, n_h, Ymax, eta_vp, S,
                                       Kc, gdm, snew, dgp, qi, qa, qg, qkf, qy, qeps, qx, qd, qok)
                    for ls in range(12):
                        g = _slope(vt, vo, rhs, S, mass, dt, stick, kj, vf, ts, nw, far_a, far_z)
                        if ls == 0:
                            ls_ghi = g
                        if not (g0 < 0.0 and g > 0.25 * abs(g0)) and not (ls > 0 and g < 0.0
                                                                         and g < -0.25 * abs(g0)):
                            break  # accepted
                        if ls == 11:
                            break
                        if g > 0.0:  # Illinois: keep the bracket [lo, hi] with g(lo) < 0 < g(hi)
                            ls_hi = ls_a
                            ls_ghi = g
                            if side == 1:
                                ls_glo *= 0.5
                            side = 1
                        else:
                            ls_lo = ls_a
                            ls_glo = g
                            if side == -1:
                                ls_ghi *= 0.5
                            side = -1
                        den = ls_ghi - ls_glo
                        a_new = (ls_lo * ls_ghi - ls_hi * ls_glo) / den if den > 0.0 else 0.5 * (ls_lo + ls_hi)
                        if not (ls_lo < a_new < ls_hi):
                            a_new = 0.5 * (ls_lo + ls_hi)
                        ls_a = a_new
                        for i in range(nw + 1):
                            vt[i] = vn[i] + ls_a * rhs[i]
                        npl, deep = _cells(vt, nw, idz, dt, G, gel, epsl, yh, eta, kf, beta_h, n_h, Ymax, eta_vp,
                                           S, Kc, gdm, snew, dgp, qi, qa, qg, qkf, qy, qeps, qx, qd, qok)
                    fresh = True
                    dmx = 0.0
                    for i in range(nw + 1):
                        dmx = max(dmx, abs(vt[i] - vn[i]))
                        vn[i] = vt[i]
                    vsc = abs(vf) + abs(vn[0]) + 1e-3
                    r = dmx / vsc
                    full = ls_a == 1.0 and plv == npl
                    if full and rlast >= 1e-12 and r >= 1e-15:
                        nq = r / (rlast * rlast)
                    rlast = r if full else -1.0
                    if _newton_converged(r, nq, full, mtol) or (plv == 0 and npl == 0 and ls_a == 1.0 and dmx <= vsc):
                        # converged on this branch: is the branch right?  (friction opposes the local slip)
                        vh = vf - ts * kj
                        if stick:
                            if kj <= 0.0:
                                S0 = mass[0] * (vn[0] - vo[0]) / dt + S[1]
                            else:
                                S0 = (vf - vn[0]) / kj
                            ts = S0
                            if abs(S0) > cap * (1.0 + 1e-12) and nsw < 8:
                                stick = False
                                dirn = 1.0 if sgn * S0 > 0.0 else -1.0
                                nsw += 1
                                rlast = -1.0
                            else:
                                done = True
                        elif dirn * sgn * (vn[0] - vh) > 0.0 and nsw < 8:
                            stick = True
                            nsw += 1
                            rlast = -1.0
                        else:
                            done = True
                    if done:
                        break
                if not done:
                    failed = True
                    break
                # the far field: back substitution, its cells' states (kept for the heat sources), and is it still
                # linear (no cell flowing)?
                grow = 0
                if nw < M:
                    for i in range(nw + 1, M + 1):
                        vn[i] = pf[i] + qf[i] * vn[i - 1]
                    for c in range(nw, M):
                        gd, sn, dg, Sm, K = _cell_state(vo[c] - vo[c + 1], vn[c] - vn[c + 1], dz[c], dt, G[c],
                                                        gel[c], epsl[c], yh[c], eta[c], kf[c], sold[c], beta_h, n_h,
                                                        Ymax, eta_vp, 1.0)
                        gdm[c] = gd
                        S[c + 1] = Sm
                        snew[c] = sn
                        dgt[c] = dg
                        if dg != 0.0 and G[c] > 0.0:
                            grow = c + 1
                    if grow == 0:  # (a grown window's Newton starts its new cells' return maps as before the test)
                        for c in range(nw, M):
                            dgp[c] = dgt[c]
                if grow == 0:
                    break
                nw = min(M, grow + WINDOW_MARGIN)
            if failed:
                break
            deep_all = max(deep_all, deep)
            # ---- heat sources from the cells' states at the solution (the window's from the Newton's last pass,
            # the far field's from its test): plastic, viscous and softening work per area, kept for the books
            for i in range(nn):
                src[i] = 0.0
            for c in range(M):
                sn = snew[c]
                gd = gdm[c]
                gen[c] = sn / G[c] if G[c] > 0.0 else 0.0
                wpc[c] = sn * dgp[c] * dz[c]
                wvc[c] = eta[c] * gd * gd * dt * dz[c]
                del_el = 0.5 * (G[c] * gen[c] * gen[c] - Gsl[c] * gel[c] * gel[c]) * dz[c]
                wsc[c] = sn * (gen[c] - gel[c]) * dz[c] - del_el
                h = beta_Q * wpc[c] + wvc[c] + wsc[c]
                src[c] += 0.5 * h
                src[c + 1] += 0.5 * h
            for i in range(nn):  # kinetic energy dissipated by backward Euler, m (v' - v)^2/2: heat at the node
                dv = vn[i] - vo[i]
                src[i] += 0.5 * mass[i] * dv * dv
            if stick and kj <= 0.0:  # imposed slip: the traction that balances node 0
                ts = mass[0] * (vn[0] - vo[0]) / dt + S[1]
            vh = vf - ts * kj
            vm = 0.5 * (vh + vp)
            v0m = vn[0]
            v_half[j] = vh
            v_local[j] = sgn * (vm - v0m)
            tau[j] = sgn * ts
            q_in[j] = beta_T * ts * (vm - v0m)
            src[0] += q_in[j] * dt
            # ---- heat
            hout, q2 = _column_heat(el, en, Tit, src, w, cl, cu, dt, rho_c, rho_L, T0, TFj, fixed_far, htol, 100,
                                    al2, be2, fal2, fm, fd, fu, fr, fh, Tk, dTk, lo, di, up, rhs, trial, dz, kap)
            hfin = hout
            q2fin = q2
            ts2 = Tk[0]
            if not math.isfinite(hout):
                failed = True
                break
            # ---- Picard convergence on the enthalpies that set G, Y and eta; else the next sweep's
            iters[j] = pic + 1
            if picard_converged(pic, en, Em, rb, omega, xprev, rprev, ptol * rho_c):  # ptol in K of sensible heat
                fin = True
                break
            blo, bhi, xprev, rprev, omega = next_iterate(pic, Em, en, rb, blo, bhi, xprev, rprev, omega, ptol * rho_c)
        if failed:
            status[j] = NO_CONVERGENCE
            forget_history(de, de2, j)
            continue
        if not fin:
            iters[j] = -max_iter  # Picard not converged: the step is kept (its energy balance is exact) ...
            if retry[j]:
                continue  # ... or left to the caller, which redoes it in sub-steps
        # ---- commit
        commit_surface(energy, j, ts, v_half[j], vp, vn[0], q_in[j], q2fin, hfin, dt, T2, oth, ts2)
        if imped:
            energy[E_RADIATED, j] += Zc * vn[M] * vn[M] * dt
        elif vn[M] != 0.0:  # held end moving with the hydro's shear: its reaction's work leaves
            S_far = S[M] - mass[M] * (vn[M] - vo[M]) / dt
            energy[E_RADIATED, j] += S_far * vn[M] * dt
        for i in range(nn):
            dv = vn[i] - vo[i]
            energy[E_NUMERICAL, j] += 0.5 * mass[i] * dv * dv
        thick = 0.0
        for c in range(M):
            energy[E_PLASTIC, j] += wpc[c]
            energy[E_VISCOUS, j] += wvc[c]
            energy[E_SOFTENING, j] += wsc[c]
            if G[c] > 0.0:
                eps[c, j] = epsl[c] + abs(dgp[c]) / SQRT3
            elif phc[c] >= 1.0:
                eps[c, j] = 0.0  # a fully molten cell forgets its hardening
            ge[c, j] = gen[c]
            Gs[c, j] = G[c]
            if G[c] <= 0.0:
                thick += min(phc[c], 1.0) * dz[c]
        film[j] = thick
        reach[j] = deep_all
        for i in range(nn):
            v[i, j] = vn[i]
        commit_heat(e, T, de, de2, j, el, en, d1, Tit)
    return 0
