"""The excess layer under a slide line (``far_end = "excess"``, the coupled closure): its kernel, one column at a
time (docs/theory/viscoplastic.md, "Coupled closure: the excess layer", and "Cost").

Per column (z = 0 the sliding surface), at the uniform stress s = |s(0)| of the quasi-static layer::

    W(s) = sum_c dz_c r_c(s),  r_c = max(x_c(s) - x_ref(s), 0)/dt (solid),  s/eta_c (molten)
    x(s) = (s - k)^+/(eta_vp/dt + dk/d gamma_p)          (hardening linearised over the step)
    [V*] - k_p s = W(s) + slide of the surface (> 0 only at the cap min(mu0 sigma_n, tau_stick, f branch))
    w_i (e'_i - e_i) = dt [kappa dT'/dz]_{i-1/2}^{i+1/2} + src_i   (backward Euler on the enthalpy)

with the excess plastic and viscous work of the cells and the rest of tau [V]^n at the surface as the sources,
coupled by Picard sweeps on the enthalpies that set G, Y and eta (the iteration of
:func:`~shockfriction.friction.subgrid.inertial_column._inertial_block`: the same predictor, secant at z = 0, Aitken in
the bulk, the same scalar solve and the same heat solve, so that both give the same answer to round-off).

The layer has no velocity unknowns, so a column's step is a heat problem and a scalar: each column is gathered
into contiguous arrays, stepped there (its working set stays in the first-level cache, the cell loops vectorise
along the column) and scattered back; the columns run in parallel blocks where numba has threads.
"""

from __future__ import annotations

import math

import numpy as np
from numba import get_num_threads, njit, prange

from shockfriction.jit_bits import f64_bits, f64_from_bits, fetch_add
from shockfriction.friction.subgrid.viscoplastic import (
    BAD_INPUT, E_COLUMN_WORK, E_FRICTION, E_HEAT_OUT, E_INTERFACE, E_OTHER, E_PLASTIC, E_VISCOUS, NO_CONVERGENCE, OK,
    P_BETA_Q, P_BETA_T, P_C, P_E_R, P_ETA_F, P_ETA_VP, P_F, P_HEAT_TOL, P_KAPPA, P_L, P_PICARD_TOL, P_RHO, P_T0,
    P_T_FAR, P_V_R, PHI_MIN, SMOOTH, SQRT3, _heat_residual2, _kink_stop, liquid_viscosity,
    other_body_response, temperature_of)
from shockfriction.materials.strength import (
    I_BETA, I_G, I_G0, I_H, I_N, I_TF, I_XI, I_Y0, I_YMAX, scg_hardening_power, scg_shear_ratio,
    scg_shear_ratio_simd)

INV_SQRT3 = 1.0 / SQRT3
#: columns from which :func:`excess_step` runs in parallel blocks when numba has more than one thread
PARALLEL_MIN_COLUMNS = 8
#: the Picard contraction estimate from which a sweep is accepted on its increment alone (:func:`picard_converged`)
RHO_MAX = 0.5
#: ... and up to which multiple of the tolerance the increment may then be (:func:`picard_converged`)
BOUND_GAIN = 100.0
#: the z = 0 secant is stalled, and its bracket stale, where a sweep's residual keeps its sign and more than this
#: fraction of the last one (:func:`next_iterate`)
STALL = 0.5
#: the sweep map's resolution, relative to the column's largest enthalpy: an increment below it is accepted whatever
#: the tolerance (:func:`picard_converged`; docs/theory/viscoplastic.md, "A tolerance below what the sweep map
#: resolves")
RESOLUTION = 1e-12
#: smallest overstress viscosity (Pa s) of the layer's rates: eta_vp = 0, the rate-independent limit, is taken at
#: this value (a layer slip of 1 m/s over 1 um then needs 1 Pa of overstress)
EXCESS_MIN_ETA = 1e-6
#: iterations of the layer's scalar solve (safeguarded Newton on a piecewise-linear function)
EXCESS_MAX_ITER = 200
#: the hardening Y0 (1 + beta eps)^n of a cell is carried from step to step: from its cached value at eps0 by the
#: binomial series of (1 + u)^n, u = beta (eps - eps0)/(1 + beta eps0), to u^SERIES_TERMS where |u| <= SERIES_U
#: (truncation below |binom(n, 9)| u^9 <= 1e-18 relative for n <= 1), else afresh (exp and log)
SERIES_U = 1e-2
SERIES_TERMS = 8
#: step quiet columns without their cells' material state (:func:`quiet_cap`; False: every sweep computes it, the
#: reference the quiet path is tested against)
QUIET_COLUMNS = True
#: relative margin of :func:`quiet_cap`'s yield bound (covers the ulps between the scalar and the vectorised G/G0)
QUIET_MARGIN = 1e-12


@njit(cache=True, inline="always", error_model="numpy")
def _slope_factor(y, eps, beta, n, Ymax):
    """dY/d gamma_p of the hardening y = min(Ymax, Y0 (1 + beta eps)^n), eps = gamma_p/sqrt3: n beta y/((1 + beta
    eps) sqrt3) below Ymax, 0 at it; a layer of shear ratio k_fac = (G/G0)/sqrt3 hardens by dk/d gamma_p =
    k_fac times this."""
    return n * beta * y / ((1.0 + beta * eps) * SQRT3) if y < Ymax else 0.0


@njit(cache=True)
def _linear_increment(s, k, hk, eta_dt):
    """Plastic increment over the step at the stress s of a layer of yield k and hardening slope hk = dk/d gamma:
    (s - k)^+/(eta_vp/dt + hk) (the overstress law with the hardening linearised over the step: the first iterate
    of :func:`~shockfriction.friction.subgrid.viscoplastic.return_map` with G -> 0)."""
    return (s - k) / (eta_dt + hk) if s > k else 0.0


@njit(cache=True, error_model="numpy")
def series_coefficients(n):
    """binom(n, k), k = 0 ... SERIES_TERMS: the coefficients of (1 + u)^n."""
    b = np.empty(SERIES_TERMS + 1)
    b[0] = 1.0
    for kk in range(1, SERIES_TERMS + 1):
        b[kk] = b[kk - 1] * (n - kk + 1) / kk
    return b


@njit(cache=True, inline="always", error_model="numpy")
def _hardening_carry(y0, e0, eps, Y0, beta, n, b):
    """Y0 (1 + beta eps)^n from its value y0 at e0 (nan: none) by the binomial series where
    |u| = |beta (eps - e0)/(1 + beta e0)| <= SERIES_U (u = 0: y0 itself, exactly), else nan (the caller computes
    it afresh).  Two cells with the same history of strains carry the same bits."""
    u = beta * (eps - e0) / (1.0 + beta * e0)
    p = b[8]
    p = b[7] + u * p
    p = b[6] + u * p
    p = b[5] + u * p
    p = b[4] + u * p
    p = b[3] + u * p
    p = b[2] + u * p
    p = b[1] + u * p
    y = y0 + y0 * (u * p)
    return y if abs(u) <= SERIES_U else math.nan


@njit(cache=True, error_model="numpy")
def _hardening(y0, e0, eps, Y0, beta, n, b):
    """:func:`_hardening_carry`, or afresh (:func:`scg_hardening_power`) where it cannot carry."""
    y = _hardening_carry(y0, e0, eps, Y0, beta, n, b)
    return scg_hardening_power(eps, Y0, beta, n) if math.isnan(y) else y


def excess_step(dz, w, v, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                TF, T2, c2, a2, oth, eps_ref, yhc, yhe, yrc):
    """Advance every column by dt (:func:`_excess_block`; arguments as
    :func:`~shockfriction.friction.subgrid.inertial_column.inertial_step`): in parallel blocks of consecutive
    columns where numba has more than one thread (the same bytes as one block: every column is stepped alone)."""
    nc = v.shape[1]
    threads = get_num_threads()
    if threads > 1 and nc >= PARALLEL_MIN_COLUMNS:
        _excess_parallel(dz, w, v, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                         tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                         TF, T2, c2, a2, oth, eps_ref, yhc, yhe, yrc, min(threads * 4, nc), QUIET_COLUMNS)
        return 0
    return _excess_block(dz, w, v, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                         tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                         TF, T2, c2, a2, oth, eps_ref, yhc, yhe, yrc, np.uint64(0), np.uint64(nc), QUIET_COLUMNS)


@njit(cache=True, parallel=True, error_model="numpy")
def _excess_parallel(dz, w, v, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                     tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                     TF, T2, c2, a2, oth, eps_ref, yhc, yhe, yrc, nblocks, quiet_ok):
    """:func:`_excess_block` over ``nblocks`` blocks of consecutive columns in parallel, taken from a work queue
    (``jit_bits.fetch_add``: a thread takes the next block when it has finished its last, so the threads share
    the pressed columns' work however it lies; docs/theory/threads.md, "A work queue for the partitions")."""
    nc = v.shape[1]
    queue = np.zeros(1, np.int64)
    for _ in prange(nblocks):  # a thread's first iteration takes blocks until none is left, its others none
        while True:
            b = fetch_add(queue, 0)
            if b >= nblocks:
                break
            _excess_block(dz, w, v, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                          tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                          TF, T2, c2, a2, oth, eps_ref, yhc, yhe, yrc, np.uint64(b * nc // nblocks),
                          np.uint64((b + 1) * nc // nblocks), quiet_ok)


@njit(cache=True, error_model="numpy", fastmath={"reassoc"})
def _layer_rate(s, M, G, kc, hden, eta, dz, kref, hrden, dt, melt):
    """W(s) = sum_c dz_c r_c(s) and dW/ds of one column (cell data: G > 0 solid, kc = Y k_fac its shear yield,
    hden = eta_vp/dt + dk/d gamma_p; eta = eta_L of a molten cell, melt: some cell is; the reference layer's kref
    and hrden = eta_vp/dt + its slope): r_c = max(x_c - x_ref, 0)/dt, x = (s - k)^+/hden (solid), s/eta_c
    (molten).  The sums are reassociated (partial sums: the loop vectorises; round-off only)."""
    W = 0.0
    dW = 0.0
    xr = (s - kref) / hrden if s > kref else 0.0
    dr = 1.0 / hrden if s > kref else 0.0
    for c in range(M):
        xc = (s - kc[c]) / hden[c]
        on = G[c] > 0.0 and s > kc[c] and xc > xr
        W += dz[c] * ((xc - xr) / dt) if on else 0.0
        dW += dz[c] * ((1.0 / hden[c] - dr) / dt) if on else 0.0
    if melt:
        for c in range(M):
            if G[c] <= 0.0:
                W += dz[c] * (s / eta[c])
                dW += dz[c] * (1.0 / eta[c])
    return W, dW


@njit(cache=True, error_model="numpy")
def _layer_solve(V, kj, cap, M, G, kc, hden, eta, dz, kref, hrden, dt, melt, s0=0.0, rigid=False):
    """Uniform stress s in [0, cap] of one column's layer: the root of g(s) = V - k s - W(s) (V = |[V*]|, k the
    partner compliance), or s = cap where g(cap) >= 0 (the surface slides at the cap).  g(0) = V > 0, g continuous
    and piecewise linear: a safeguarded Newton from s0 (the last sweep's or step's stress where it lies in
    (0, cap), else 0; exact on each linear piece, bisection where a step leaves the bracket).  ``rigid``: no cell
    can flow on [0, cap] (:func:`quiet_cap`), W = 0 without the cells (their arrays are not read).  Returns
    (s, W(s), ok)."""
    if V <= 0.0 or cap <= 0.0:
        return 0.0, 0.0, True
    Wc = 0.0
    if not rigid:
        Wc, _ = _layer_rate(cap, M, G, kc, hden, eta, dz, kref, hrden, dt, melt)
    if V - kj * cap - Wc >= 0.0:
        return cap, Wc, True
    lo = 0.0
    hi = cap
    s = s0 if 0.0 < s0 < cap else 0.0
    tol = 1e-14 * (V + 1e-6)
    W = 0.0
    for _ in range(EXCESS_MAX_ITER):
        W = 0.0
        dW = 0.0
        if not rigid:
            W, dW = _layer_rate(s, M, G, kc, hden, eta, dz, kref, hrden, dt, melt)
        g = V - kj * s - W
        if abs(g) <= tol:
            return s, W, True
        if g > 0.0:
            lo = s
        else:
            hi = s
        d = kj + dW
        sn = s + g / d if d > 0.0 else 0.5 * (lo + hi)
        if not (lo < sn < hi):
            sn = 0.5 * (lo + hi)
        if hi - lo <= 1e-15 * cap:
            W = 0.0
            if not rigid:
                W, _ = _layer_rate(hi, M, G, kc, hden, eta, dz, kref, hrden, dt, melt)
            return hi, W, True  # g is continuous: the root is located to the resolution of s
        s = sn
    return s, W, False


@njit(cache=True, error_model="numpy")
def _cells_hardening(j, M, eps, yhc, yhe, yrc, yr, eps_ref, epsl, yh, hfac, Y0, beta, n, Ymax, bser):
    """Column j's cells' hardening over the step: epsl = eps, yh = min(Ymax, Y0 (1 + beta eps)^n) carried from the
    cache yhc, yhe (:func:`_hardening_carry`; afresh where it cannot carry), hfac its slope factor; the cache and
    the reference's (yrc: yr at eps_ref) stored together, so that a cell that never flowed in excess keeps the
    reference's bits.  Returns min_c yh."""
    fresh = False
    for c in range(M):  # (vectorised; a cell that never flowed in excess shares the reference's yield exactly)
        epsl[c] = eps[c, j]
        y = _hardening_carry(yhc[c, j], yhe[c, j], epsl[c], Y0, beta, n, bser)
        yh[c] = y
        fresh |= math.isnan(y)
    if fresh:
        for c in range(M):
            if math.isnan(yh[c]):
                yh[c] = scg_hardening_power(epsl[c], Y0, beta, n)
    ymin = Ymax
    for c in range(M):
        yhc[c, j] = yh[c]
        yhe[c, j] = epsl[c]
        yh[c] = min(yh[c], Ymax)
        ymin = min(ymin, yh[c])
        hfac[c] = _slope_factor(yh[c], epsl[c], beta, n, Ymax)  # fixed over the step
    yrc[0, j] = yr
    yrc[1, j] = eps_ref[j]
    return ymin


@njit(cache=True, inline="always", error_model="numpy")
def cell_shear_ratio(Tm, phm, c, F, g_p, h_p, xi, TF):
    """Cell c's melt fraction, the mean of its nodes' phm, and its G/G0 at the mean of its nodes' temperatures Tm, 0
    where it holds melt (both kernels' material state; inlined into loops that vectorise)."""
    ph = 0.5 * (phm[c] + phm[c + 1])
    r = scg_shear_ratio_simd(F, 0.5 * (Tm[c] + Tm[c + 1]), g_p, h_p, xi, TF)
    return ph, (r if ph <= 0.0 else 0.0)


@njit(cache=True, inline="always", error_model="numpy")
def surface_cap(cap0, tresca, f, F, T_s, g_p, h_p, xi, TF):
    """The cap of the layer's stress: min(cap0 = min(mu0 sigma_n, tau_stick), the Tresca branch f Ymax/sqrt3
    (G/G0)(p, T(0))) at the surface temperature T_s; cap0 where f < 0 (no Tresca branch)."""
    return min(cap0, tresca * scg_shear_ratio(F, T_s, g_p, h_p, xi, TF)) if f >= 0.0 else cap0


@njit(cache=True, error_model="numpy")
def quiet_cap(x, F, ymin, cap0, tresca, f, rho_c, T0, es, g_p, h_p, xi, TF):
    """Is no cell able to flow at the enthalpies x?  Every cell's shear yield k_c = Y_c (G/G0)(p, T_c)/sqrt3 is at
    least ymin (G/G0)(p, max T)/sqrt3 (G/G0 falls with T where h, xi >= 0, the caller's condition; ymin = min_c Y_c),
    so where that bound, less QUIET_MARGIN, is not below the cap min(cap0, the Tresca branch at T(x_0)) and no node
    is on the melt plateau, no cell flows whatever the layer's stress s <= cap: the sweep's outcome does not depend
    on the cells' material state (docs/theory/viscoplastic.md, "Quiet columns").  Returns (the cap, whether the
    Coulomb cap cap0 sets it) where it holds, (-1, False) where it does not."""
    emax = x[0]
    for i in range(1, x.size):
        emax = max(emax, x[i])
    if not emax <= es:
        return -1.0, False
    kmin = ymin * scg_shear_ratio(F, T0 + emax / rho_c, g_p, h_p, xi, TF) * INV_SQRT3 * (1.0 - QUIET_MARGIN)
    cap = surface_cap(cap0, tresca, f, F, T0 + x[0] / rho_c, g_p, h_p, xi, TF)
    if not (kmin > 0.0 and cap <= kmin):
        return -1.0, False
    return cap, cap == cap0


@njit(cache=True, error_model="numpy", fastmath={"reassoc"})
def _aitken_sums(en, Em, rb):
    """sum r_i dr_i and sum dr_i^2 over the bulk nodes i >= 1 (r the last Picard residual rb, dr its change):
    the Aitken factor's sums (reassociated: the loop vectorises)."""
    anum = 0.0
    aden = 0.0
    for i in range(1, en.size):
        dr = (en[i] - Em[i]) - rb[i]
        anum += rb[i] * dr
        aden += dr * dr
    return anum, aden


@njit(cache=True, error_model="numpy")
def gather_predict(e, de, de2, j, el, d1, d2, Em, pw):
    """Gather column j's enthalpies and their changes over the last two steps into el, d1, d2, and its first Picard
    iterate Em = el + a1 d1 + a2 d2: quadratic (pw[0], pw[1]: :func:`~shockfriction.friction.subgrid.viscoplastic.
    predictor_weights`) on a smooth history, max|d1 - d2| <= SMOOTH max|d1|, else linear (pw[2], 0).  (The maxima
    as the bits of non-negative floats, ordered as integers: the loop vectorises.)"""
    m1 = np.int64(0)
    m2 = np.int64(0)
    for i in range(el.size):
        el[i] = e[i, j]
        d1[i] = de[i, j]
        d2[i] = de2[i, j]
        m1 = max(m1, np.int64(f64_bits(abs(d1[i]))))
        m2 = max(m2, np.int64(f64_bits(abs(d1[i] - d2[i]))))
    quad = f64_from_bits(m2) <= SMOOTH * f64_from_bits(m1)
    a1 = pw[0] if quad else pw[2]
    a2 = pw[1] if quad else 0.0
    for i in range(el.size):
        Em[i] = el[i] + a1 * d1[i] + a2 * d2[i]


@njit(cache=True, error_model="numpy")
def forget_history(de, de2, j):
    """Column j's step failed or was refused: no enthalpy history for the next step's predictor."""
    for i in range(de.shape[0]):
        de[i, j] = 0.0
        de2[i, j] = 0.0


@njit(cache=True, error_model="numpy")
def commit_heat(e, T, de, de2, j, el, en, d1, Tout):
    """Scatter column j's new enthalpies en and temperatures Tout, and its history for the predictor: the last
    step's change d1 and this one's, en - el."""
    for i in range(el.size):
        de2[i, j] = d1[i]
        de[i, j] = en[i] - el[i]
        e[i, j] = en[i]
        T[i, j] = Tout[i]


@njit(cache=True, error_model="numpy")
def picard_converged(pic, en, Em, rb, omega, xprev, rprev, tol):
    """Has the step's Picard iteration converged?  d = max_i |en_i - Em_i|, the sweep's increment (the heat solve's
    enthalpies en against the enthalpies Em that set the sweep's material state).  Converged where d <= tol or
    d <= RESOLUTION max_i |en_i| (below that the map's own noise, round-off and its mechanics solved to 1e-13, moves
    the increment, and a tighter tolerance would only run the sweeps out: docs/theory/viscoplastic.md, "A tolerance
    below what the sweep map resolves"), or,
    from the second sweep on, where the error bound of en against the step's coupled solution (the fixed point
    x* = Phi(x*) of the sweep map en = Phi(Em)) is: |en - x*| <= rho/(1 - rho) d, with rho the map's contraction
    estimated along its last step, max|en - en'| / max|Em - Em'| (primes: the last sweep), if rho < RHO_MAX, the
    increment has fallen since the last sweep and d <= BOUND_GAIN tol (far from convergence, where the iteration
    may be outside its contracting regime, the estimate is not trusted: the increment test alone).  en'
    and Em' follow from :func:`next_iterate`'s update without being kept: in the bulk Em = Em' + omega rb and
    en' = Em' + rb, at z = 0 Em' = xprev and en' = xprev + rprev (docs/theory/viscoplastic.md, "The Picard
    test").  (The maxima as the bits of non-negative floats: integer maxima vectorise; one pass.)"""
    if pic == 0:
        mb = np.int64(0)
        me = np.int64(0)
        for i in range(en.size):
            mb = max(mb, np.int64(f64_bits(abs(en[i] - Em[i]))))
            me = max(me, np.int64(f64_bits(abs(en[i]))))
        d = f64_from_bits(mb)
        return d <= tol or d <= RESOLUTION * f64_from_bits(me)
    keep = 1.0 - omega
    mb = np.int64(f64_bits(abs(en[0] - Em[0])))
    mn = np.int64(f64_bits(abs(en[0] - xprev - rprev)))
    mm = np.int64(f64_bits(abs(Em[0] - xprev)))
    mp = np.int64(f64_bits(abs(rprev)))
    me = np.int64(f64_bits(abs(en[0])))
    for i in range(1, en.size):
        r = en[i] - Em[i]
        mb = max(mb, np.int64(f64_bits(abs(r))))
        mn = max(mn, np.int64(f64_bits(abs(r - keep * rb[i]))))
        mm = max(mm, np.int64(f64_bits(abs(omega * rb[i]))))
        mp = max(mp, np.int64(f64_bits(abs(rb[i]))))
        me = max(me, np.int64(f64_bits(abs(en[i]))))
    d = f64_from_bits(mb)
    if d <= tol or d <= RESOLUTION * f64_from_bits(me):
        return True
    dm = f64_from_bits(mm)
    if not (d <= BOUND_GAIN * tol and d < f64_from_bits(mp) and dm > 0.0):
        return False  # far from converged, or not contracting: the increment test alone
    rho = f64_from_bits(mn) / dm
    return rho < RHO_MAX and rho * d <= (1.0 - rho) * tol


@njit(cache=True, error_model="numpy")
def next_iterate(pic, Em, en, rb, blo, bhi, xprev, rprev, omega, tol):
    """The next sweep's material enthalpies Em (in place) from the heat solve's en: at z = 0 (where the Tresca branch
    and the steepest softening act) a safeguarded secant on r(E) = e_heat(0; E) - E (the enthalpy, not T: T is flat
    while the surface melts) within its bracket [blo, bhi]; in the bulk Picard with Aitken (Irons-Tuck) relaxation
    omega, which damps the period-2 cycle of a melt front (rb: the last bulk residuals).  tol: the Picard tolerance
    in J/m^3.  Returns the updated (blo, bhi, xprev, rprev, omega)."""
    x = Em[0]
    r = en[0] - x
    if pic > 0 and r * rprev > 0.0 and abs(r) > STALL * abs(rprev) and abs(r) > tol:
        # stalled: the map moved under the bracket (the bulk's nodes still move, e.g. one just below its solidus);
        # keep only what this sweep says
        blo = -np.inf
        bhi = np.inf
    if r > 0.0:
        blo = max(blo, x)
    else:
        bhi = min(bhi, x)
    if pic == 0:
        xn = en[0]
    else:
        den = r - rprev
        xn = x - r * (x - xprev) / den if den != 0.0 else en[0]
    if bhi - blo <= 1e-3 * tol and abs(r) > tol:
        # the bracket closed on a point that is not a root: it was built while the bulk below still moved
        blo = -np.inf
        bhi = np.inf
        xn = x + omega * r
    if not (blo < xn < bhi):
        if math.isfinite(blo) and math.isfinite(bhi):
            xn = 0.5 * (blo + bhi)
        else:  # one-sided bracket: the plain Picard value lies on its open side
            xn = en[0]
    Em[0] = xn
    if pic > 0:
        anum, aden = _aitken_sums(en, Em, rb)
        if aden > 0.0:
            omega = min(max(-omega * anum / aden, 0.05), 1.0)
    for i in range(1, en.size):
        rr = en[i] - Em[i]
        rb[i] = rr
        Em[i] += omega * rr
    return blo, bhi, x, r, omega


@njit(cache=True, error_model="numpy")
def commit_surface(energy, j, ts, vh, vp, v0m, q_in, q2, hout, dt, T2, oth, ts2):
    """Book column j's step at its surface and ends (J/m^2): the friction work ts [V]^n dt, the interface heat
    q_in dt, the column's work ts v(0) dt, the heat to the other body q2 and out of a held far end hout; and the
    other body's temperatures at the interface temperature ts2 (:func:`other_body_response`)."""
    energy[E_FRICTION, j] += ts * 0.5 * (vh + vp) * dt
    energy[E_INTERFACE, j] += q_in * dt
    energy[E_COLUMN_WORK, j] += ts * v0m * dt
    energy[E_OTHER, j] += q2
    energy[E_HEAT_OUT, j] += hout
    n2 = T2.shape[0]
    if n2 > 0:
        T2[0, j] = ts2
        for kk in range(1, n2):
            T2[kk, j] = oth[0, kk, j] + oth[1, kk, j] * ts2


@njit(cache=True, error_model="numpy", fastmath={"contract"})
def _substitute(e, en, rhs, fm, fr, fh):
    """The solid heat solve's two sweeps, whose chains are latency bound (fused multiply-adds): forward
    elimination rhs_i -= fm_i rhs_(i-1), back substitution x_i = fr_i rhs_i - fh_i x_(i+1); en = e + x."""
    nn = e.size
    for i in range(1, nn):
        rhs[i] -= fm[i] * rhs[i - 1]
    x = rhs[nn - 1] * fr[nn - 1]
    en[nn - 1] = e[nn - 1] + x
    for i in range(nn - 2, -1, -1):
        x = rhs[i] * fr[i] - fh[i] * x
        en[i] = e[i] + x


@njit(cache=True, error_model="numpy")
def _heat_factor(w, cl, cu, rho_c, al2, fixed_far, fm, fd, fu):
    """The Thomas factorisation of the heat Newton matrix of a column with no node on the melt plateau
    (dT/de = 1/rho c everywhere; the same for every column of a step): multipliers fm, pivots fd, upper diagonal
    fu, by the operations of :func:`_column_heat`'s own elimination (the same bits)."""
    nn = w.size
    M = nn - 1
    s = 1.0 / rho_c
    for i in range(nn):
        d = w[i]
        lo_i = 0.0
        up_i = 0.0
        if i == 0:
            d += al2 * s
        if i > 0:
            d += cl[i] * s
            lo_i = -cl[i] * s
        if i < M:
            d += cu[i] * s
            up_i = -cu[i] * s
        if i == M and fixed_far:
            d = 1.0
            lo_i = 0.0
        fu[i] = up_i
        if i > 0:
            m = lo_i / fd[i - 1]
            fm[i] = m
            d -= m * fu[i - 1]
        fd[i] = d


@njit(cache=True, error_model="numpy")
def _heat_solid(e, en, Tout, src, w, cl, cu, rho_c, rho_L, T0, TF, al2, be2, fm, fr, fh, Tk, rhs):
    """:func:`_column_heat` where every node is solid before and after the step (the common case): the Newton's
    single, exact iteration from e' = e with the precomputed factorisation (multipliers fm, reciprocal pivots fr,
    fh = upper diagonal/pivot: the back substitution x_i = fr_i g_i - fh_i x_(i+1) without a division in its
    chain), then the conservative update; the ends are peeled so that the interior loops vectorise.  Returns q2,
    or nan where a node is or would be on the melt plateau (the caller then takes the general path)."""
    nn = e.size
    M = nn - 1
    es = rho_c * (TF - T0)
    over = False
    for i in range(nn):
        over |= e[i] > es
        Tk[i] = T0 + e[i] / rho_c
    if over:
        return math.nan
    # the residual at e' = e
    res = -src[0]
    res += al2 * Tk[0] + be2
    res += cu[0] * (Tk[0] - Tk[1])
    rhs[0] = -res
    for i in range(1, M):
        res = -src[i]
        res += cl[i] * (Tk[i] - Tk[i - 1])
        res += cu[i] * (Tk[i] - Tk[i + 1])
        rhs[i] = -res
    res = -src[M]
    res += cl[M] * (Tk[M] - Tk[M - 1])
    rhs[M] = -res
    _substitute(e, en, rhs, fm, fr, fh)
    for i in range(nn):
        over |= en[i] > es
        Tk[i] = T0 + en[i] / rho_c
    if over:
        return math.nan
    # the conservative update from the solution's temperatures
    q2 = al2 * Tk[0] + be2
    flux = src[0] - q2
    flux -= cu[0] * (Tk[0] - Tk[1])
    en[0] = e[0] + flux / w[0]
    for i in range(1, M):
        flux = src[i]
        flux -= cl[i] * (Tk[i] - Tk[i - 1])
        flux -= cu[i] * (Tk[i] - Tk[i + 1])
        en[i] = e[i] + flux / w[i]
    flux = src[M]
    flux -= cl[M] * (Tk[M] - Tk[M - 1])
    en[M] = e[M] + flux / w[M]
    for i in range(nn):
        over |= en[i] > es
        Tout[i] = T0 + en[i] / rho_c
    if over:  # round-off of the update across the solidus
        for i in range(nn):
            Tout[i], _, _ = temperature_of(en[i], rho_c, rho_L, T0, TF)
    return q2


@njit(cache=True, error_model="numpy")
def _column_heat(e, en, Tout, src, w, cl, cu, dt, rho_c, rho_L, T0, TF, fixed_far, tol, max_iter, al2, be2,
                 fal2, fm, fd, fu, fr, fh, Tk, dT, lo, di, up, rhs, trial, dz, kap):
    """Backward Euler on one column's enthalpy (Newton in e', stopping at the kinks of T(e); then the
    conservative update e' = e + (src + dt flux(T'))/w): the heat solve of both kernels (this one's and
    :mod:`shockfriction.friction.subgrid.inertial_column`'s); cl[i], cu[i] = dt kappa/dz of the cells below and
    above node i.  Where no node is on the melt plateau and al2 = fal2 the matrix is the
    precomputed factorisation (fm, fd, fu: :func:`_heat_factor`).  Fills en, Tout (T(en)) and Tk (T of the last
    Newton iterate); returns (heat out at a fixed far end, nan if not converged; q2 the heat to the other body)."""
    nn = e.size
    M = nn - 1
    if al2 == fal2 and not fixed_far and nn > 2:
        q2 = _heat_solid(e, en, Tout, src, w, cl, cu, rho_c, rho_L, T0, TF, al2, be2, fm, fr, fh, Tk, rhs)
        if not math.isnan(q2):
            return 0.0, q2
    es = rho_c * (TF - T0)  # solidus and liquidus enthalpies
    for i in range(nn):
        en[i] = e[i]
    live = True
    for it in range(max_iter):
        plateau = False
        for i in range(nn):
            Tk[i], dT[i], _ = temperature_of(en[i], rho_c, rho_L, T0, TF)
            plateau |= dT[i] == 0.0
        general = plateau or al2 != fal2
        r0 = 0.0
        for i in range(nn):
            res = w[i] * (en[i] - e[i]) - src[i]
            if i == 0:
                res += al2 * Tk[0] + be2
            if i > 0:
                res += cl[i] * (Tk[i] - Tk[i - 1])
            if i < M:
                res += cu[i] * (Tk[i] - Tk[i + 1])
            if i == M and fixed_far:
                res = 0.0
            rhs[i] = -res
            r0 += res * res
        if general:
            for i in range(nn):
                d = w[i]
                lo[i] = 0.0
                up[i] = 0.0
                if i == 0:
                    d += al2 * dT[0]
                if i > 0:
                    d += cl[i] * dT[i]
                    lo[i] = -cl[i] * dT[i - 1]
                if i < M:
                    d += cu[i] * dT[i]
                    up[i] = -cu[i] * dT[i + 1]
                if i == M and fixed_far:
                    d = 1.0
                    lo[i] = 0.0
                di[i] = d
            for i in range(1, nn):
                m = lo[i] / di[i - 1]
                di[i] -= m * up[i - 1]
                rhs[i] -= m * rhs[i - 1]
            rhs[nn - 1] /= di[nn - 1]
            for i in range(nn - 2, -1, -1):
                rhs[i] = (rhs[i] - up[i] * rhs[i + 1]) / di[i]
        else:
            for i in range(1, nn):
                rhs[i] -= fm[i] * rhs[i - 1]
            rhs[nn - 1] /= fd[nn - 1]
            for i in range(nn - 2, -1, -1):
                rhs[i] = (rhs[i] - fu[i] * rhs[i + 1]) / fd[i]
        exact = True
        for i in range(nn):
            dT[i], stop = _kink_stop(en[i], en[i] + rhs[i], es, es + rho_L, rho_L)
            if stop:
                exact = False
        if not exact:
            lam = 1.0
            same = True
            for _ in range(8):
                same = True
                for i in range(nn):
                    trial[i], stop = _kink_stop(en[i], en[i] + lam * rhs[i], es, es + rho_L, rho_L)
                    if stop:
                        same = False
                if same or _heat_residual2(trial, e, src, w, dz, dt, kap, rho_c, rho_L, T0, TF, fixed_far, al2,
                                           be2) < r0:
                    break
                lam *= 0.5
            exact = same and lam == 1.0
            for i in range(nn):
                dT[i] = trial[i]
        dmx = 0.0
        for i in range(nn):
            dmx = max(dmx, abs(dT[i] - en[i]))
            en[i] = dT[i]
        if exact or dmx <= tol * rho_c:
            live = False
            break
    hout = math.nan if live else 0.0
    for i in range(nn):
        Tk[i], dT[i], _ = temperature_of(en[i], rho_c, rho_L, T0, TF)
    q2 = 0.0
    for i in range(nn):
        flux = src[i]
        if i == 0:
            q2 = al2 * Tk[0] + be2
            flux -= q2
        if i > 0:
            flux -= cl[i] * (Tk[i] - Tk[i - 1])
        if i < M:
            flux -= cu[i] * (Tk[i] - Tk[i + 1])
        if i == M and fixed_far:
            if not live:
                hout = flux  # what node M would gain: it leaves through z = h
            en[i] = e[i]
        else:
            en[i] = e[i] + flux / w[i]
        Tout[i], _, _ = temperature_of(en[i], rho_c, rho_L, T0, TF)
    return hout, q2


@njit(cache=True, error_model="numpy")
def _excess_block(dz, w, v, eps, e, T, F_N, v_free, v_prev, k, tau_cap, p, par, dt, max_iter,
                  tau, v_half, v_local, q_in, film, iters, status, energy, de, de2, pw, retry,
                  TF, T2, c2, a2, oth, eps_ref, yhc, yhe, yrc, j0, j1, quiet_ok=True):
    """Advance the columns j0 <= j < j1 (unsigned) by dt, one at a time (see the module docstring; arrays and
    outputs as :func:`~shockfriction.friction.subgrid.inertial_column._inertial_block` with far_end = "excess").  A
    column whose Picard iteration does not converge in max_iter sweeps is left as it was for the caller to redo
    where retry[j] (iters = -max_iter), else committed; one whose scalar or heat solve fails gets
    status NO_CONVERGENCE and is left as it was."""
    nn, nc = v.shape
    M = nn - 1
    rho, cth, kap, L, T0 = par[P_RHO], par[P_C], par[P_KAPPA], par[P_L], par[P_T0]
    rho_c, rho_L = rho * cth, rho * L
    eta_vp, eta_F, E_R = par[P_ETA_VP], par[P_ETA_F], par[P_E_R]
    beta_T, beta_Q, f = par[P_BETA_T], par[P_BETA_Q], par[P_F]
    T_far = par[P_T_FAR]
    fixed_far = math.isfinite(T_far)
    htol, ptol = par[P_HEAT_TOL], par[P_PICARD_TOL]
    G0, T_F0 = p[I_G0], p[I_TF]
    V_R = par[P_V_R]
    Y0, beta_h, n_h, Ymax = p[I_Y0], p[I_BETA], p[I_N], p[I_YMAX]
    g_p, h_p, xi = p[I_G], p[I_H], p[I_XI]
    tresca = f * Ymax / SQRT3
    eta_dt = max(eta_vp, EXCESS_MIN_ETA) / dt
    # G/G0 falls with T and the hardening grows with eps: quiet_cap's bound holds
    can_quiet = quiet_ok and h_p >= 0.0 and xi >= 0.0 and beta_h >= 0.0 and n_h >= 0.0
    al2v = np.zeros(nc)  # the other body: heat taken from node 0 over the step, al2 T'(0) + be2
    be2v = np.zeros(nc)
    other_body_response(T2, c2, a2, dt, oth, al2v, be2v, j0, j1)
    bser = series_coefficients(n_h)
    # one column's contiguous arrays (nodes, cells)
    # the heat equation's conductances dt kappa/dz below (cl) and above (cu) each node, and the factorisation of
    # its Newton matrix where no node is on the melt plateau (the same for every column)
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
    nodes = np.empty((18, nn))
    el, en, Em, Tm, phm, Tit, src, rb, d1, d2 = (nodes[0], nodes[1], nodes[2], nodes[3], nodes[4], nodes[5],
                                                nodes[6], nodes[7], nodes[8], nodes[9])
    Tk, dTk, lo, di, up, rhs, trial, vl = (nodes[10], nodes[11], nodes[12], nodes[13], nodes[14], nodes[15],
                                          nodes[16], nodes[17])
    cells = np.empty((12, M))
    rc, hc = cells[9], cells[10]  # each cell's excess rate and heat over the step
    hfac = cells[11]
    epsl, yh, G, kc, hden, eta, phc, dgp, gdm = (cells[0], cells[1], cells[2], cells[3], cells[4], cells[5],
                                                 cells[6], cells[7], cells[8])
    for j in range(j0, j1):
        F, vf, vp, kj = F_N[j], v_free[j], v_prev[j], k[j]
        TFj = TF[j]
        status[j] = OK
        iters[j] = 0
        sgn = 1.0 if vf >= 0.0 else -1.0
        if not (math.isfinite(F) and math.isfinite(vf) and math.isfinite(vp) and math.isfinite(kj)
                and tau_cap[j] >= 0.0):
            status[j] = BAD_INPUT
            forget_history(de, de2, j)
            continue
        # the reference layer (the body at T0 and the column's pressure, hardened by its own homogeneous flow
        # eps_ref, frozen over the step)
        # (the hardening carried from the last step: yrc[0, j], yrc[1, j] the reference's Y0 (1 + beta eps)^n and
        # its strain; yhc, yhe (M, nc) the cells')
        yr = _hardening(yrc[0, j], yrc[1, j], eps_ref[j], Y0, beta_h, n_h, bser)
        yref = min(yr, Ymax)
        kfr = scg_shear_ratio_simd(F, T0, g_p, h_p, xi, TFj) * INV_SQRT3  # as the cells' (the same bits at T0)
        kref = yref * kfr
        href = kfr * _slope_factor(yref, eps_ref[j], beta_h, n_h, Ymax)
        hrden = eta_dt + href
        gather_predict(e, de, de2, j, el, d1, d2, Em, pw)  # the first Picard iterate
        # the cells' hardening, computed at the first sweep that needs it; until then a lower bound of its minimum
        # (the hardening grows with eps) for quiet_cap
        hard = False
        ymin = 0.0
        if can_quiet:
            emin = eps[0, j]
            for c in range(1, M):
                emin = min(emin, eps[c, j])
            ymin = min(Ymax, scg_hardening_power(max(emin, 0.0), Y0, beta_h, n_h))
        es_j = rho_c * (TFj - T0)  # the solidus enthalpy
        quiet = False
        fin = False
        failed = False
        blo = -np.inf  # bracket of the interface enthalpy root
        bhi = np.inf
        xprev = 0.0
        rprev = 0.0
        omega = 1.0  # Aitken relaxation factor of the bulk Picard update
        ts = 0.0
        s_x = 0.0
        wlay = 0.0
        vh = vm = v0m = 0.0
        hfin = 0.0
        q2fin = 0.0
        ts2 = 0.0
        for pic in range(max_iter):
            quiet = False
            if can_quiet:  # no cell can flow at these enthalpies: the material state is not needed
                cap, _ = quiet_cap(Em, F, ymin, tau_cap[j], tresca, f, rho_c, T0, es_j, g_p, h_p, xi, TFj)
                quiet = cap >= 0.0
            if not quiet and not hard:
                ymin = _cells_hardening(j, M, eps, yhc, yhe, yrc, yr, eps_ref, epsl, yh, hfac, Y0, beta_h, n_h,
                                        Ymax, bser)
                hard = True
            if quiet:
                s_x, wlay, ok_x = _layer_solve(abs(vf), kj, cap, M, G, kc, hden, eta, dz, kref, hrden, dt, False,
                                               abs(tau[j]) if pic == 0 else s_x, True)
                for i in range(nn):
                    vl[i] = 0.0
                    src[i] = 0.0
            else:
                # ---- material state at the trial enthalpies
                for i in range(nn):
                    Tm[i], _, phm[i] = temperature_of(Em[i], rho_c, rho_L, T0, TFj)
                # (loops without branches, which vectorise along the column: the exponential and the power inlined)
                melt = False
                for c in range(M):
                    phc[c], r = cell_shear_ratio(Tm, phm, c, F, g_p, h_p, xi, TFj)
                    melt |= r <= 0.0
                    G[c] = G0 * r
                    kf = r * INV_SQRT3
                    kc[c] = yh[c] * kf
                    hden[c] = eta_dt + kf * hfac[c]  # + d k/d gamma_p
                if melt:  # a cell with melt: a liquid layer ph dz in series with rigid solid (sub-cell film)
                    for c in range(M):
                        eta[c] = 0.0
                        if G[c] <= 0.0:
                            hden[c] = 1.0
                            eta[c] = liquid_viscosity(0.5 * (Tm[c] + Tm[c + 1]), eta_F, E_R, T_F0, TFj,
                                                      max(F, 0.0) * V_R) / max(phc[c], PHI_MIN)
                cap = surface_cap(tau_cap[j], tresca, f, F, Tm[0], g_p, h_p, xi, TFj)
                # ---- the layer's uniform stress
                s_x, wlay, ok_x = _layer_solve(abs(vf), kj, cap, M, G, kc, hden, eta, dz, kref, hrden, dt, melt,
                                               abs(tau[j]) if pic == 0 else s_x)
                # ---- cell rates, heat sources, the velocity profile
                xr = (s_x - kref) / hrden if s_x > kref else 0.0
                for c in range(M):  # solid cells (vectorised)
                    xc = (s_x - kc[c]) / hden[c]
                    r = (xc - xr) / dt if s_x > kc[c] and xc > xr else 0.0
                    rc[c] = r
                    dgp[c] = sgn * r * dt
                    gdm[c] = 0.0
                    hc[c] = beta_Q * s_x * r * dt * dz[c]
                if melt:
                    for c in range(M):
                        if G[c] <= 0.0:
                            r = s_x / eta[c]
                            rc[c] = r
                            dgp[c] = 0.0
                            gdm[c] = sgn * r
                            hc[c] = eta[c] * r * r * dt * dz[c]
                vl[M] = 0.0
                for c in range(M - 1, -1, -1):
                    vl[c] = vl[c + 1] + sgn * rc[c] * dz[c]
                src[0] = 0.5 * hc[0]  # each cell's heat, half to each of its nodes
                for i in range(1, M):
                    src[i] = 0.5 * hc[i] + 0.5 * hc[i - 1]
                src[M] = 0.5 * hc[M - 1]
            ts = sgn * s_x
            if not ok_x:
                failed = True
                break
            # the friction work ts [V]^n: the layer takes ts W, the surface the rest
            vh = vf - ts * kj
            vm = 0.5 * (vh + vp)
            v0m = sgn * wlay
            v_half[j] = vh
            v_local[j] = sgn * (vm - v0m)
            tau[j] = sgn * ts
            q_in[j] = beta_T * ts * (vm - v0m)
            src[0] += q_in[j] * dt
            # ---- heat
            hout, q2 = _column_heat(el, en, Tit, src, w, cl, cu, dt, rho_c, rho_L, T0, TFj, fixed_far, htol, 100,
                                    al2v[j], be2v[j], fal2, fm, fd, fu, fr, fh, Tk, dTk, lo, di, up, rhs, trial, dz,
                                    kap)
            hfin = hout
            q2fin = q2
            ts2 = Tk[0]
            if not math.isfinite(hout):
                failed = True
                break
            # ---- Picard convergence on the enthalpies that set G, Y and eta; else the next sweep's
            iters[j] = pic + 1
            if quiet and cap == tau_cap[j]:  # the Coulomb cap and no flow: is that so at en too?
                cap_n, coul_n = quiet_cap(en, F, ymin, tau_cap[j], tresca, f, rho_c, T0, es_j, g_p, h_p, xi, TFj)
                if cap_n >= 0.0 and coul_n:  # then the sweep map is constant: en is its fixed point
                    fin = True
                    break
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
        commit_surface(energy, j, ts, vh, vp, v0m, q_in[j], q2fin, hfin, dt, T2, oth, ts2)
        # the reference's plastic strain increment at the step's stress, which every solid cell shares
        dref = _linear_increment(abs(ts), kref, href, eta_dt) / SQRT3
        eps_ref[j] += dref
        if quiet:  # no cell flowed, none is molten: the same bits as the loop below with dgp = 0
            if dref != 0.0:  # (eps + 0 = eps: nothing to write)
                for c in range(M):
                    eps[c, j] = eps[c, j] + dref
            film[j] = 0.0
            if v[0, j] != 0.0:  # (the profile sums flows of one sign from the far end: zero at z = 0, zero all along)
                for i in range(nn):
                    v[i, j] = 0.0
            commit_heat(e, T, de, de2, j, el, en, d1, Tit)
            continue
        thick = 0.0
        wpl = energy[E_PLASTIC, j]
        wvi = energy[E_VISCOUS, j]
        for c in range(M):
            wpl += ts * dgp[c] * dz[c]
            if G[c] > 0.0:
                eps[c, j] = epsl[c] + abs(dgp[c]) / SQRT3 + dref
            else:
                wvi += eta[c] * gdm[c] * gdm[c] * dt * dz[c]
                if phc[c] >= 1.0:
                    eps[c, j] = 0.0  # a fully molten cell forgets its hardening
                thick += min(phc[c], 1.0) * dz[c]
        energy[E_PLASTIC, j] = wpl
        energy[E_VISCOUS, j] = wvi
        film[j] = thick
        for i in range(nn):
            v[i, j] = vl[i]
        commit_heat(e, T, de, de2, j, el, en, d1, Tit)
    return 0
