"""Viscoplastic interface columns with shear inertia, enthalpy melting and a Newtonian melt
(the thesis's announced third sub-grid model; theory and sources in docs/theory/viscoplastic.md).

Per column (z = 0 the sliding surface, z = h the macroscopic body), with s = -sigma_xz the shear
stress in the loading sense, v the material velocity relative to the body, gamma_dot = -dv/dz::

    rho dv/dt = -ds/dz                      (inertia = False: ds/dz = 0)
    s = s_sol + eta_L(T) gamma_dot          (eta_L only where G(p, T) = 0: the melt)
    s_sol = G(p, T) gamma_e,  d gamma_e/dt = gamma_dot - gamma_p_dot
    |s_sol| - Y(eps, p, T)/sqrt(3) = eta_vp gamma_p_dot  (Perzyna/Duvaut-Lions overstress; eps = gamma_p/sqrt(3))
    d e/dt = d/dz(kappa dT/dz) + beta_Q s_sol gamma_p_dot + eta_L gamma_dot^2 (+ softening release)
    e = rho c (T - T0) + rho L phi           (enthalpy; phi in [0, 1] the melt fraction at T_F)

G and Y are the SCG functions of materials/strength.py with p = sigma_n; the melting temperature T_F is the SCG
melt law T_m(sigma_n) of each column (``pressure_melting``) and the melt viscosity carries exp(p V*/(R T)).
Surface traction (the thesis's law, the column's own resistance as the model stress)::

    |s(0)| = min(mu0 sigma_n, tau_stick, f Ymax/sqrt(3) G(sigma_n, T(0))/G0 [optional], column stress at sticking)

The slip heat |s(0)| (V - v(0)) enters at z = 0: all of it, the other body taking its part by conduction through
its own thermal column (two-sided heat, continuity of temperature and flux at z = 0), or the fixed share beta_T of
it (the thesis's eq. 2.101).  Far end: impedance s = rho c_s v, or held at a given velocity (``far_end = "held"``:
0 stand-alone, the hydro's shear of the layer under a slide line), or v = 0 (quasi-static); thermally insulated,
or a fixed temperature.  Under a slide line (``far_end = "excess"``, the coupled closure) the column is a
quasi-static layer at the uniform stress s = |s(0)| that slips by its flow in excess of the reference layer (the
body at T0, hardened by its own homogeneous flow, which every solid cell shares)::

    W(s) = sum_c dz_c r_c,  r_c = max(x_c(s) - x_ref(s), 0)/dt (solid),  s/eta_c (molten),
    x(s) = (s - k)^+/(eta_vp/dt + dk/d gamma_p)  (hardening linearised over the step)
    [V] = [V*] - k s = W(s) + slide of the surface (> 0 only at the cap)

Discretisation: staggered grid, v and e at the nodes z_i (lumped masses rho w_i), s, gamma_e, eps in the
cells.  Time: backward Euler (first order, L-stable; ``time_scheme = "backward_euler"``, the default), or the
option ``time_scheme = "bdf2"``: variable-step BDF2 (second order, L-stable) of the whole column state, written as
the backward-Euler kernel over beta dt from the extrapolated state y + c (y - y_old)
(:meth:`ViscoplasticColumns._bdf2_step`), for imposed slip (k = 0) on columns without melt; the first step of a
run in sub-steps growing from dt/64; backward Euler where the ratio of steps exceeds 2, a column's last mean
traction exceeds its new cap, a partner mass is given (k > 0, slide lines) or a column has melt
(docs/theory/viscoplastic.md, "Time accuracy").  The kernel
(:func:`~shockfriction.friction.subgrid.inertial_column._inertial_block`): mechanics by backward Euler, a Newton on
the node velocities with an exact line search on the step's convex incremental energy, on a window of the column
that holds its plastic cells (the linear far field condensed onto it); plastic return by backward Euler with
implicit hardening (scalar convex Newton per cell); heat by backward Euler on the enthalpy with a conservative
final update; mechanics and heat coupled by Picard iterations.  The schemes' dissipation (backward Euler's, and
what BDF2's extrapolation adds or takes) is deposited as heat and booked (rows E_NUMERICAL: kinetic,
E_SOFTENING: elastic), so the energy balance is exact.  A column that does not converge is redone on sub-steps
(dt/2 ... dt/16); one that still fails raises.
All 2D arrays are (n_nodes or n_cells, n_columns), stored column by column (each column contiguous); the columns
are independent: each kernel steps one column at a time, in parallel blocks of columns where numba has threads
(:mod:`shockfriction.friction.subgrid.inertial_column`; the excess layer, which has no velocity unknowns:
:mod:`shockfriction.friction.subgrid.excess_layer`; cost: docs/theory/viscoplastic.md, "Cost").
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from shockfriction.friction.subgrid.column import column_sums, per_column
from shockfriction.materials.strength import exp_inline, log_inline, scg_melt_temperature

SQRT3 = math.sqrt(3.0)
#: smallest melt fraction of a film cell in its viscosity eta_L/phi (a cell of the SCG solid whose G vanishes
#: before any melt, within microkelvins of T_F, is a film of this fraction)
PHI_MIN = 1e-3
#: a node of the enthalpy Newton that crosses the solidus or liquidus stops this fraction of the latent heat past it
KINK = 1e-15
#: the first Picard iterate extrapolates the last two enthalpy increments (quadratic) where the history is smooth,
#: max|de1 - de2| <= SMOOTH max|de1|, else the last one (linear): a period-2 melt-front history extrapolates badly
SMOOTH = 0.2
OK, NO_CONVERGENCE, BAD_INPUT = 0, 2, 3
#: a step of an imposed-slip column (k = 0) whose Picard iteration does not converge is redone as two half steps,
#: recursively down to dt/2**MAX_SPLIT; a sub-step still unconverged there is kept (energy exact) and flagged
MAX_SPLIT = 4
#: time integration of the columns (``time_scheme``): "backward_euler" (default, as version 0.4) or "bdf2"
#: (variable-step BDF2 for imposed slip on solid columns, the first step in sub-steps; docs/theory/viscoplastic.md,
#: "Time accuracy")
TIME_SCHEMES = ("bdf2", "backward_euler")
#: a BDF2 step longer than this ratio times the last one is taken by backward Euler (variable-step BDF2 is
#: zero-stable below 1 + sqrt 2)
BDF2_MAX_RATIO = 2.0
#: the first BDF2 step of a run is taken in START_LEVELS + 1 sub-steps growing from dt/2**START_LEVELS (the jump of
#: the loading at t = 0 would otherwise leave a start error that decays only as dt**0.6)
START_LEVELS = 6
#: default Picard tolerance (K): a step's sweeps stop when no node's temperature (sensible enthalpy / rho c) moves more
PICARD_TOL = 1e-6
# parameter vector of the kernel (besides the SCG array)
(P_RHO, P_C, P_KAPPA, P_L, P_T0, P_ETA_VP, P_ETA_F, P_E_R, P_BETA_T, P_BETA_Q, P_F, P_Z, P_INERTIA,
 P_T_FAR, P_MECH_TOL, P_HEAT_TOL, P_PICARD_TOL, P_V_R, P_MAX_NEWTON) = range(19)
N_PAR = 19
#: far-end conditions: "impedance" rho c_s (stand-alone), "held" (at a given velocity), "excess" (a quasi-static layer
#: whose slip is its flow in excess of the reference layer's: the coupled closure, docs/theory/viscoplastic.md,
#: stepped by its own kernel, :mod:`shockfriction.friction.subgrid.excess_layer`)
FAR_ENDS = ("impedance", "held", "excess")
#: iterations of the mechanics Newton in one Picard sweep (a column that needs more fails its step, which is then
#: redone in sub-steps)
MAX_NEWTON = 200
#: gas constant (J/mol/K), for the melt viscosity's activation volume
R_GAS = 8.314462618
# energy accumulators per column (J/m^2), rows of the ``energy`` array
(E_FRICTION, E_INTERFACE, E_COLUMN_WORK, E_PLASTIC, E_VISCOUS, E_SOFTENING, E_RADIATED, E_HEAT_OUT,
 E_NUMERICAL, E_OTHER) = range(10)
N_ENERGY = 10


@njit(cache=True, error_model="numpy")
def liquid_viscosity(T, eta_F, E_R, T_F, T_m=0.0, pV_R=0.0):
    """Melt viscosity eta_L = eta_F exp(E_R (1/T - 1/T_F) + p V*/(R T)) at T >= T_m (eta_F at the ambient melting
    point T_F; T_m the melting temperature at the pressure p, default T_F; pV_R = p V*/R in kelvin, the activation
    volume's pressure factor, 0: none)."""
    T = max(T, T_F, T_m)
    return eta_F * math.exp(E_R * (1.0 / T - 1.0 / T_F) + pV_R / T)


@njit(cache=True, error_model="numpy")
def temperature_of(e, rho_c, rho_L, T0, T_F):
    """T(e) of the enthalpy e = rho c (T - T0) + rho L phi; returns (T, dT/de, phi)."""
    es = rho_c * (T_F - T0)
    if e <= es:
        return T0 + e / rho_c, 1.0 / rho_c, 0.0
    if e <= es + rho_L:
        return T_F, 0.0, (e - es) / rho_L
    return T_F + (e - es - rho_L) / rho_c, 1.0 / rho_c, 1.0


@njit(cache=True)
def temperatures_of(e, rho_c, rho_L, T0, TF, out, slope):
    """out[i, j], slope[i, j] = T(e[i, j]), dT/de of :func:`temperature_of` with column j's melting temperature
    TF[j] (dT/de = 0 on the melt plateau)."""
    for i in range(e.shape[0]):
        for j in range(e.shape[1]):
            out[i, j], slope[i, j], _ = temperature_of(e[i, j], rho_c, rho_L, T0, TF[j])


#: |u| up to which (1 + u)^n is summed by :func:`binomial_power` (its first omitted term is below u^9 = 1e-18)
BINOMIAL_U = 1e-2


@njit(cache=True, error_model="numpy", inline="always")
def binomial_power(u, n):
    """(1 + u)^n by its binomial series to u^8 in nested form, 1 + n u (1 + (n - 1)/2 u (1 + ... (1 + (n - 7)/8 u))):
    no pow, no division; for |u| <= BINOMIAL_U its truncation is below 1e-18, so it is the power to round-off
    (measured within one ulp; docs/theory/viscoplastic.md, "The return map without pow")."""
    p = 1.0 + (n - 7.0) * 0.125 * u
    p = 1.0 + (n - 6.0) * (1.0 / 7.0) * u * p
    p = 1.0 + (n - 5.0) * (1.0 / 6.0) * u * p
    p = 1.0 + (n - 4.0) * 0.2 * u * p
    p = 1.0 + (n - 3.0) * 0.25 * u * p
    p = 1.0 + (n - 2.0) * (1.0 / 3.0) * u * p
    p = 1.0 + (n - 1.0) * 0.5 * u * p
    return 1.0 + n * u * p


@njit(cache=True, error_model="numpy", inline="always")
def linear_return(a, cc, ys, kf, ub, n, Ymax):
    """The return's first iterate: the root of a - cc x - k(x) = 0 with k linearised at x = 0, k(0) = y_start k_fac
    and slope k_fac n ub y_start (0 where y_start >= Ymax: saturated, the return is then exact);
    u = x ub as in :func:`return_correction`."""
    return (a - ys * kf) / (cc + (kf * n * ub * ys if ys < Ymax else 0.0))


@njit(cache=True, error_model="numpy", inline="always")
def return_correction(a, cc, x, ys, ub, kf, n, Ymax):
    """One Newton correction of the return equation a - cc x - k(x) = 0 at x (a = |s_tr|, cc = G + eta_vp/dt),
    k = min(Ymax, y_start (1 + u)^n) k_fac, u = x ub, ub = beta/(sqrt3 (1 + beta eps)): the hardening by
    :func:`binomial_power` where |u| <= BINOMIAL_U, by the inlined exp and log beyond (no branch, no call: a loop of
    these vectorises).  Returns (x + dx, dx, dk/dx at x, k'' at x, cc + dk/dx); k'' = n (n - 1) ub^2 Y k_fac/(1 + u)^2
    sizes the next correction, |k''|/(2 (cc + dk)) dx^2 (docs/theory/viscoplastic.md, "The return map's last
    correction")."""
    u = x * ub
    hb = 1.0 + u
    p = binomial_power(u, n) if abs(u) <= BINOMIAL_U else exp_inline(n * log_inline(hb))
    y = ys * p
    below = y < Ymax
    dk = kf * n * ub * y / hb if below else 0.0
    den = cc + dk
    dx = (a - cc * x - (y if below else Ymax) * kf) / den
    kpp = n * (n - 1.0) * ub * ub * kf * y / (hb * hb) if below else 0.0
    return x + dx, dx, dk, kpp, den


@njit(cache=True, error_model="numpy")
def return_map(s_abs, G, eta_dt, eps, y_start, k_fac, beta, n, Ymax, x0=-1.0):
    """Plastic increment x = d gamma_p >= 0 of |s_tr| - (G + eta_vp/dt) x - Y(eps + x/sqrt3) k_fac = 0,
    k_fac = (G/G0)/sqrt(3); returns (x, d|s'|/d|s_tr|).  The left side is convex and decreasing in x,
    so Newton from x = 0 climbs monotonically to the root (no overshoot).  ``y_start`` = min(Ymax, Y0 (1 + beta
    eps)^n), the hardening at the start of the step (computed once per step).  Scalars only (no arrays: an
    array argument of a per-cell call costs an atomic reference-count pair).

    Cost (docs/theory/viscoplastic.md, "Cost"): the first Newton iterate is the closed-form linear return with the
    hardening frozen at y_start (no pow); a saturated cell (y_start = Ymax) stops there, exactly; otherwise each
    correction is :func:`return_correction` (Y = y_start (1 + u)^n, u = beta (x/sqrt3)/(1 + beta eps), the hardening
    slope from Y itself).
    The iteration stops where the correction is within 1e-15 of x, or where the next one, estimated from the
    curvature of the hardening (Newton's error e' = |f''|/(2 |f'|) e^2), is (docs/theory/viscoplastic.md, "The return
    map's last correction"); the tangent is then carried to the returned x by k'' dx.
    ``x0`` >= 0: the first iterate instead (a guess from the same cell's last return within the step; Newton from
    either side of the root of a convex decreasing function lands left of it in one step, then climbs)."""
    if G <= 0.0:
        return 0.0, 0.0
    k = y_start * k_fac
    if s_abs <= k:
        return 0.0, 1.0
    c = G + eta_dt
    if y_start >= Ymax:  # saturated: Y stays at Ymax, the linear return is exact
        return (s_abs - k) / c, eta_dt / c
    ub = beta / (SQRT3 * (1.0 + beta * eps))  # Y = y_start (1 + u)^n, u = x ub
    x = linear_return(s_abs, c, y_start, k_fac, ub, n, Ymax) if x0 < 0.0 else x0
    dk = 0.0
    last = math.inf
    for _ in range(100):
        x, dx, dk, kpp, den = return_correction(s_abs, c, x, y_start, ub, k_fac, n, Ymax)
        if abs(dx) <= 1e-15 * x or abs(dx) >= last:  # converged, or stalled at the round-off of the residual
            break
        if dk == 0.0:  # Y saturated: the step just taken was exact
            break
        if 0.5 * abs(kpp) / den * (dx * dx) <= 1e-15 * x:  # the next correction is within the tolerance
            dk += kpp * dx  # the tangent at the new x (to O(dx^2))
            break
        last = abs(dx)
    return x, (eta_dt + dk) / (c + dk)


@njit(cache=True, error_model="numpy")
def _cell_state(dv, dvn, dzc, dt, g, gec, epsc, yhc, etac, kfc, soldc, beta, n, Ymax, eta_vp, th, x0=-1.0):
    """Strain rate, new solid stress, plastic increment, step stress and stiffness dS/dv' of one cell
    (dv, dvn = v_c - v_{c+1} at the old and new velocities; the other arguments the cell's values; x0 a guess of
    the plastic increment |d gamma_p| for :func:`return_map`, < 0: none).

    th = 1: backward Euler, what the kernel uses (1/2 would be the implicit midpoint); gd and S are the
    th-weighted strain rate and stress that enter the momentum balance."""
    gd = ((1.0 - th) * dv + th * dvn) / dzc
    if g <= 0.0:  # molten cell: no solid stress; its stored elastic strain is released as plastic strain
        S = (1.0 - th) * soldc + etac * gd
        return gd, 0.0, gec + dt * gd, S, etac * th / dzc
    s_tr = g * (gec + dt * gd)
    if abs(s_tr) <= yhc * kfc:  # elastic: return_map's own first test, here where it is inlined into the pass
        return gd, s_tr, 0.0, (1.0 - th) * soldc + th * s_tr + etac * gd, (th * g * dt + etac) * th / dzc
    x, dsds = return_map(abs(s_tr), g, eta_vp / dt, epsc, yhc, kfc, beta, n, Ymax, x0)
    sg = 1.0 if s_tr >= 0.0 else -1.0
    snew = s_tr - sg * g * x
    S = (1.0 - th) * soldc + th * snew + etac * gd
    K = (th * dsds * g * dt + etac) * th / dzc
    return gd, snew, sg * x, S, K


@njit(cache=True)
def _heat_residual2(x, e, src, w, dz, dt, kap, rho_c, rho_L, T0, T_F, fixed_far, al2, be2):
    """Sum of squares of one column's backward-Euler enthalpy residuals at the enthalpies x (n_nodes,; e, src the
    column's old enthalpies and sources); node 0 loses al2 T(0) + be2 to the other body (0, 0: none)."""
    nn = x.size
    total = 0.0
    Tp = 0.0
    for i in range(nn):
        Ti, _, _ = temperature_of(x[i], rho_c, rho_L, T0, T_F)
        if i == nn - 1 and fixed_far:
            break
        res = w[i] * (x[i] - e[i]) - src[i]
        if i == 0:
            res += al2 * Ti + be2
        if i > 0:
            res += dt * kap / dz[i - 1] * (Ti - Tp)
        if i < nn - 1:
            Tn, _, _ = temperature_of(x[i + 1], rho_c, rho_L, T0, T_F)
            res += dt * kap / dz[i] * (Ti - Tn)
        total += res * res
        Tp = Ti
    return total


@njit(cache=True)
def _kink_stop(a, b, es, es_l, rho_L):
    """Newton target b of a node at enthalpy a, stopped at the first breakpoint of T(e) (solidus es, liquidus es_l)
    on its way: KINK rho_L past it going up, at it going down; returns (target, stopped)."""
    if a <= es < b:
        return es + KINK * rho_L, True
    if a <= es_l < b:
        return es_l + KINK * rho_L, True
    if b <= es_l < a:
        return es_l, True
    if b <= es < a:
        return es, True
    return b, False


@njit(cache=True)
def other_body_response(T2, c2, a2, dt, oth, al2, be2, j0, j1):
    """The other body's thermal column under a surface temperature T_s' (backward Euler, insulated far end), per
    column j: T2' = A + B T_s' (oth[0] = A, oth[1] = B), and the heat it takes from the interface node over the
    step, Q2 = al2 T_s' + be2 = c2[0] (T_s' - T2[0]) + dt a2[0] (T_s' - T2'[1]) (J/m^2).  Node 0 of T2 is the
    interface (its half cell c2[0]), continuous with the column's node 0."""
    n2, nc = T2.shape
    if n2 == 0:
        for j in range(j0, j1):
            al2[j] = 0.0
            be2[j] = 0.0
        return
    A = oth[0]
    B = oth[1]
    # rows 1..n2-1: (c_k + dt a_{k-1} + dt a_k) T'_k - dt a_{k-1} T'_{k-1} - dt a_k T'_{k+1} = c_k T_k (+ dt a_0 Ts)
    # Thomas with two right-hand sides (A: the old temperatures, B: a unit surface temperature); the pivots are
    # the same for every column (linear, constant properties): kept in A[0]/B[0] of column 0's slot is avoided by
    # a local array
    piv = np.empty(n2)
    for kk in range(1, n2):
        d = c2[kk] + dt * a2[kk - 1] + (dt * a2[kk] if kk < n2 - 1 else 0.0)
        if kk > 1:
            d -= (dt * a2[kk - 1]) * (dt * a2[kk - 1]) / piv[kk - 1]
        piv[kk] = d
    for j in range(j0, j1):
        for kk in range(1, n2):
            ra = c2[kk] * T2[kk, j]
            rb = dt * a2[0] if kk == 1 else 0.0
            if kk > 1:
                m = -dt * a2[kk - 1] / piv[kk - 1]
                ra -= m * A[kk - 1, j]
                rb -= m * B[kk - 1, j]
            A[kk, j] = ra
            B[kk, j] = rb
        for kk in range(n2 - 1, 0, -1):
            if kk < n2 - 1:
                A[kk, j] = (A[kk, j] + dt * a2[kk] * A[kk + 1, j]) / piv[kk]
                B[kk, j] = (B[kk, j] + dt * a2[kk] * B[kk + 1, j]) / piv[kk]
            else:
                A[kk, j] = A[kk, j] / piv[kk]
                B[kk, j] = B[kk, j] / piv[kk]
        A[0, j] = 0.0
        B[0, j] = 1.0
        if n2 > 1:
            al2[j] = c2[0] + dt * a2[0] * (1.0 - B[1, j])
            be2[j] = -c2[0] * T2[0, j] - dt * a2[0] * A[1, j]
        else:
            al2[j] = c2[0]
            be2[j] = -c2[0] * T2[0, j]


@njit(cache=True)
def melt_temperatures(F_N, law, TF):
    """TF[j] = T_m(F_N[j]) by the SCG melt law (law = (T_m0, K0, s, gamma0, a), Material.melt_law)."""
    for j in range(F_N.shape[0]):
        TF[j] = scg_melt_temperature(F_N[j], law[0], law[1], law[2], law[3], law[4])


def predictor_weights(h, h1, h2):
    """Weights (a1, a2, a1_lin) of the first Picard iterate E = e + a1 de1 + a2 de2: the quadratic through the
    enthalpies of the last three steps (increments de1 over h1, de2 over h2) at the step h (capped at h1),
    e + d1 h + D2 h (h + h1) with d1 = de1/h1, D2 = (de1/h1 - de2/h2)/(h1 + h2); a1_lin = h/h1 the linear one
    (also used with one step of history); zeros without."""
    if h1 <= 0.0:
        return np.zeros(3)
    h = min(h, h1)
    if h2 <= 0.0:
        return np.array([h / h1, 0.0, h / h1])
    q = h * (h + h1) / (h1 + h2)
    return np.array([h / h1 + q / h1, -q / h2, h / h1])


# --------------------------------------------------------------------------- the columns
#: default overstress viscosity eta_vp (Pa s) when the material has none (see docs/theory/viscoplastic.md)
DEFAULT_ETA_VP = 50.0
#: Arrhenius activation temperature of liquid Al, Assael et al. 2006: log10(eta/mPa s) = -0.7324 + 803.49/T
AL_LIQUID_E_R = 803.49 * math.log(10.0)


class ViscoplasticColumns:
    """``n_columns`` viscoplastic columns of one material (arrays (n_nodes, n_columns), SI).

    Construct, then call :meth:`step` once per time step with per-column arrays (scalars broadcast):
    ``sigma_n`` (Pa, compression > 0), ``v_free`` = [V*]^{n+1/2}, ``slip_prev`` = [V]^{n-1/2} (m/s),
    ``k`` = S dt (1/m_s + 1/m_g) (0: imposed slip), ``tau_cap`` = min(mu0 sigma_n, tau_stick) (Pa).
    It returns ``(tau, v_half)``: |s(0)| and [V]^{n+1/2} = v_free - sign tau k.

    Parameters: ``beta_T`` heat share entering the column; ``f`` the optional SCG "Tresca" branch
    f Ymax/sqrt3 G/G0 on the surface traction (None: the column's own resistance only); ``eta_vp`` overstress
    viscosity (Pa s; default the material's ``viscoplastic_viscosity`` or :data:`DEFAULT_ETA_VP`);
    ``inertia`` (False: quasi-static, v = 0 at z = h; True: impedance rho c_s at z = h);
    ``far_end = "held"`` holds v = 0 at z = h also with inertia (a column between a driven surface and a fixed
    base: the eigenmodes of the linear analysis, used by the localisation test);
    ``depth`` (m, optional): the column is continued below ``thickness`` by geometric cells (ratio
    ``depth_ratio``) down to this depth, so that the body's own plastic flow is inside the column: with inertia and
    depth >= c_s t_end nothing reaches the far end and the answer no longer depends on the column (the issue-10
    well-posedness fix; ``thickness``/``n_cells`` then set the uniformly resolved interface layer);
    ``far_temperature`` (None: insulated far end).  Melt data from the material (``latent_heat``,
    ``liquid_viscosity`` at T_F, ``liquid_viscosity_activation``, ``liquid_viscosity_activation_volume``) or the
    keyword arguments.  ``other`` (a material): two-sided heat, the other body gets a thermal column (first cell
    as the column's, geometric by ``other_ratio``, down to sqrt(alpha2/alpha1) times the column's depth) joined at
    z = 0 by continuity of temperature and flux; ``beta_T`` is then unused (1: all the slip heat enters at z = 0).
    ``pressure_melting`` (default True): each column melts at the SCG melt law's T_m(sigma_n)
    (:meth:`~shockfriction.materials.library.Material.melt_law`) and the melt viscosity takes its pressure factor;
    False: the ambient T_F and eta_L (version 0.3).  ``step(..., v_far)``: velocity of a held far end.
    ``time_scheme``: "backward_euler" (default) or "bdf2" (second order for imposed slip on solid columns; see
    :meth:`step` and docs/theory/viscoplastic.md, "Time accuracy").

    Diagnostics after a step (n_columns,): ``tau``, ``theta_interface`` (K), ``slip_local`` (V - v(0)),
    ``slip_macro`` (|[V]^n|), ``flux_in`` (W/m^2), ``film_thickness`` (m, cells with no strength left),
    ``iterations`` (Picard sweeps; < 0: a step kept unconverged), ``substeps`` (> 1: an imposed-slip step
    redone in sub-steps, :data:`MAX_SPLIT`); profiles ``theta``, ``eps_p`` (n_columns, n_nodes / n_cells,
    copies), ``velocity``, ``stress``; :meth:`energies` (J/m^2 per column) and :meth:`energy_residual`.
    """

    def __init__(self, n_columns: int, material, *, beta_T: float, thickness: float = 20e-6, n_cells: int = 500,
                 grading: float = 1.0, depth: float | None = None, depth_ratio: float = 1.05,
                 f: float | None = None, taylor_quinney: float = 0.9,
                 eta_vp: float | None = None, inertia: bool = True, T0: float = 300.0,
                 far_temperature: float | None = None, latent_heat: float | None = None,
                 liquid_viscosity: float | None = None, liquid_activation: float | None = None,
                 far_end: str = "impedance", mech_tol: float = 1e-13, heat_tol: float = 1e-11,
                 picard_tol: float = PICARD_TOL, max_picard: int = 100, other=None,
                 pressure_melting: bool = True, other_ratio: float = 1.05,
                 liquid_activation_volume: float | None = None, time_scheme: str = "backward_euler"):
        from shockfriction.friction.subgrid.column import control_weights, extend_grid, make_grid
        from shockfriction.materials.library import get_material
        m = get_material(material) if isinstance(material, str) else material
        self.material = m
        if n_columns < 1:
            raise ValueError(f"n_columns must be >= 1, got {n_columns!r}")
        if not 0.0 <= beta_T <= 1.0:
            raise ValueError(f"heat share must lie in [0, 1], got {beta_T!r}")
        if other is not None:  # two-sided heat: the other body conducts its share, beta_T is not used
            other = get_material(other) if isinstance(other, str) else other
            beta_T = 1.0
        self.other = other
        T_F = m.melting_temperature
        self.z = make_grid(thickness, int(n_cells), grading)
        if depth is not None:
            self.z = extend_grid(self.z, float(depth), float(depth_ratio))
        self.dz = np.diff(self.z)
        self.weights = control_weights(self.z)

        def pick(arg, key, default):
            if arg is not None:
                return float(arg)
            return m.parameters[key].value if m.has(key) else default
        self.eta_vp = pick(eta_vp, "viscoplastic_viscosity", DEFAULT_ETA_VP)
        L = pick(latent_heat, "latent_heat", math.nan)
        eta_F = pick(liquid_viscosity, "liquid_viscosity", math.nan)
        E_R = pick(liquid_activation, "liquid_viscosity_activation", AL_LIQUID_E_R)
        if not (L > 0.0 and eta_F > 0.0 and E_R >= 0.0 and self.eta_vp >= 0.0):
            raise ValueError(f"material {m.name!r}: the viscoplastic model needs latent_heat > 0 and "
                             f"liquid_viscosity > 0 (got {L!r}, {eta_F!r}) and eta_vp >= 0 (got {self.eta_vp!r})")
        if not (T0 < T_F or far_temperature is not None):
            raise ValueError(f"initial temperature {T0} K must be below the melting temperature {T_F} K")
        self.inertia = bool(inertia)
        rho = m.rho0
        self.rho_c = rho * m.heat_capacity
        self.rho_L = rho * L
        self.par = np.zeros(N_PAR)
        self.par[[P_RHO, P_C, P_KAPPA, P_L, P_T0]] = rho, m.heat_capacity, m.conductivity, L, T0
        self.par[[P_ETA_VP, P_ETA_F, P_E_R]] = self.eta_vp, eta_F, E_R
        self.par[[P_BETA_T, P_BETA_Q, P_F]] = beta_T, taylor_quinney, (-1.0 if f is None else float(f))
        if far_end not in FAR_ENDS:
            raise ValueError(f"far_end must be one of {FAR_ENDS}, got {far_end!r}")
        if far_end == "excess":  # a quasi-static layer (its inertia is the hydro cells')
            inertia = False
            self.inertia = False
        self.par[P_Z] = rho * m.shear_wave_speed if far_end == "impedance" else (
            math.inf if far_end == "held" else 0.0)
        self.far_end = far_end
        self.par[P_INERTIA] = 1.0 if inertia else 0.0
        self.par[P_T_FAR] = math.nan if far_temperature is None else float(far_temperature)
        V_act = pick(liquid_activation_volume, "liquid_viscosity_activation_volume", 0.0)
        self.par[P_V_R] = V_act / R_GAS if pressure_melting else 0.0
        self.par[P_MAX_NEWTON] = MAX_NEWTON
        self.par[[P_MECH_TOL, P_HEAT_TOL, P_PICARD_TOL]] = mech_tol, heat_tol, picard_tol
        self.max_picard = int(max_picard)
        self.scg = m.scg_params()
        # melting temperature T_m(sigma_n) of each column (SCG melt law), or the constant T_F
        self.melt_law = m.melt_law() if pressure_melting else (T_F, 0.0, 0.0, 0.0, 0.0)
        self._melt_law = np.array(self.melt_law, float)  # the kernel's argument (an array: no reflection per call)
        self.pressure_melting = bool(pressure_melting) and self.melt_law[1] > 0.0
        self.T0, self.T_F, self.beta_T = float(T0), T_F, float(beta_T)
        nn, nc = self.z.size, int(n_columns)
        # both kernels step one column at a time: the profiles are stored column by column (Fortran order, each
        # column contiguous)
        self._order = "F"
        order = self._order
        self.v = np.zeros((nn, nc), order=order)
        self.ge = np.zeros((nn - 1, nc), order=order)
        self.Gs = np.zeros((nn - 1, nc), order=order)
        self.eps = np.zeros((nn - 1, nc), order=order)
        self.eps_ref = np.zeros(nc)  # the reference layer's plastic strain (far_end = "excess")
        self._reach = np.zeros(nc, np.int64)  # deepest plastic cell + 1 of the last step (the mechanics window)
        self.e = np.zeros((nn, nc), order=order)
        self.T = np.full((nn, nc), self.T0, order=order)
        self.energy = np.zeros((N_ENERGY, nc))
        for name in ("tau", "slip_local", "slip_macro", "flux_in", "film_thickness", "_v_half"):
            setattr(self, name, np.zeros(nc))
        self.iterations = np.zeros(nc, dtype=np.int64)
        self.status = np.zeros(nc, dtype=np.int64)
        self.substeps = np.ones(nc, dtype=np.int64)  # sub-steps of the last step (> 1: split, see MAX_SPLIT)
        self._de = np.zeros((nn, nc), order=order)  # enthalpy changes of the last two steps (the Picard predictor)
        self._de2 = np.zeros((nn, nc), order=order)
        # the excess layer's hardening carried from step to step (excess_layer._hardening_carry): the cells'
        # Y0 (1 + beta eps)^n and the strain it was computed at, the reference's (row 0) and its strain (row 1);
        # nan: none (computed afresh)
        mc = nn - 1 if far_end == "excess" else 0
        self._yh = np.full((mc, nc), math.nan, order=order)
        self._yh_eps = np.full((mc, nc), math.nan, order=order)
        self._yref = np.full((2, nc), math.nan)
        self._dt_prev = np.zeros(2)  # their time steps (0: none); the three are checkpointed with the state
        # the kernel's scratch, allocated once (the excess layer's kernel keeps its own per column)
        self.TF = np.full(nc, float(T_F))  # melting temperature of each column at its last step
        # the other body's thermal column (two-sided heat): first cell as the column's, geometric (other_ratio) down
        # to the column's thermal reach scaled by the diffusivities, sqrt(alpha2/alpha1) z[-1]
        if other is not None:
            from shockfriction.friction.subgrid.column import control_weights
            d2 = max(self.z[-1] * math.sqrt(other.diffusivity / m.diffusivity), 50.0 * self.dz[0])
            y = [0.0]
            step = self.dz[0]
            while y[-1] < d2:
                y.append(y[-1] + step)
                step *= float(other_ratio)
            self.z_other = np.array(y)
            rc2 = other.rho0 * other.heat_capacity
            self._c2 = rc2 * control_weights(self.z_other)
            self._a2 = other.conductivity / np.diff(self.z_other)
            self.T_other = np.full((self.z_other.size, nc), self.T0)
        else:
            self.z_other = np.zeros(0)
            self._c2 = np.zeros(0)
            self._a2 = np.zeros(0)
            self.T_other = np.zeros((0, nc))
        self._oth = np.empty((2, self.z_other.size, nc))
        if time_scheme not in TIME_SCHEMES:
            raise ValueError(f"time_scheme must be one of {TIME_SCHEMES}, got {time_scheme!r}")
        self.time_scheme = time_scheme
        # BDF2 history (docs/theory/viscoplastic.md, "Time accuracy"): the state at the start of the last step, its
        # per-node mechanical energy, the energy rows it booked, its impulse per area (signed) and its length
        # (0: none, the next step is backward Euler)
        self._v_o, self._e_o = np.zeros((nn, nc)), np.zeros((nn, nc))
        self._ge_o, self._eps_o = np.zeros((nn - 1, nc)), np.zeros((nn - 1, nc))
        self._T2_o = np.zeros_like(self.T_other)
        self._mech_o = np.zeros((2, nn, nc))
        self._rows_o = np.zeros((N_ENERGY, nc))
        self._imp = np.zeros(nc)
        self._h = 0.0
        self._keep = True
        self._e_initial = self.mechanical_energy() + self.heat_stored()

    @property
    def n_columns(self) -> int:
        return self.v.shape[1]

    def set_temperature(self, T) -> None:
        """Impose a temperature field (K; scalar or (n_nodes, n_columns)) at melt fraction 1 above T_F (tests)."""
        T = np.broadcast_to(np.asarray(T, float), self.T.shape)
        liquid = T >= self.T_F
        self.e[...] = self.rho_c * (T - self.T0) + np.where(liquid, self.rho_L, 0.0)
        self.T[...] = T
        self._dt_prev[:] = 0.0  # no prediction across an imposed state
        self._h = 0.0  # nor a BDF2 step
        self._e_initial = self.mechanical_energy() + self.heat_stored()

    def step(self, sigma_n, v_free, slip_prev, k, tau_cap, dt: float, v_far=0.0):
        """Advance all columns by dt; return (tau, v_half) (see the class docstring).  ``v_far``: velocity of the
        held far end relative to the hydro node (the coupled closure; 0 stand-alone).  A column whose solve fails
        even on dt/2**MAX_SPLIT sub-steps raises :class:`~shockfriction.errors.SimulationError` naming it (the
        columns are then left as they were before the step).

        With ``time_scheme = "bdf2"`` (an option; the default is backward Euler) the step is the variable-step BDF2
        of the whole column state (velocities, elastic strains, plastic strains, enthalpies, the other body's
        temperatures), written as the backward-Euler kernel over beta dt from the extrapolated state
        y^ = y + c (y - y_old) (:meth:`_bdf2_step`);
        tau is then the step's mean traction (its impulse over dt, what the hydro applies).  The first step, a step
        more than BDF2_MAX_RATIO times the last one, and a step where a column's last mean traction exceeds its new
        cap ``tau_cap`` (unloading, opening) are backward Euler.  So is every step with a partner mass (k > 0: the
        columns under a slide line): there BDF2 left a +-5 K step-to-step scatter in Theta(0) of the Ti-6Al-4V
        pressure-shear example (docs/theory/viscoplastic.md, "Time accuracy"); and every step where a column has melt
        (a node at or above the solidus enthalpy): there BDF2's extrapolation across the enthalpy's kinks kept the
        partly molten Couette film from its steady state (tau 3.8 % off after 2.5 us).  BDF2 is used for imposed
        slip on solid columns (the first BDF2 step after such a stretch again in the start's sub-steps)."""
        nc = self.n_columns
        arr = [per_column(a, nc) for a in (sigma_n, v_free, slip_prev, k, tau_cap, v_far)]
        dt = float(dt)
        # BDF2 for imposed slip and solid columns only (see the docstring)
        imposed = self.time_scheme == "bdf2" and not np.any(arr[3] > 0.0) \
            and not np.any(self.e.max(axis=0) >= self._solidus_enthalpy())
        self._keep = imposed  # the step's state is BDF2's history
        if self.time_scheme == "bdf2" and imposed and self._h <= 0.0:
            self._start(*arr, dt)
        else:
            h = self._h
            bdf = (self.time_scheme == "bdf2" and imposed and h > 0.0 and dt <= BDF2_MAX_RATIO * h
                   and bool(np.all(np.abs(self._imp) <= h * arr[4])))
            self._bdf2_step(*arr, dt, bdf)
            if not imposed:
                self._h = 0.0
        bad = np.flatnonzero(self.status != OK)
        if bad.size:
            from shockfriction.errors import SimulationError
            j = int(bad[0])
            what = "non-finite input" if self.status[j] == BAD_INPUT else (
                f"no convergence on {2 ** MAX_SPLIT} sub-steps of {dt:.6g} s")
            raise SimulationError(f"viscoplastic column {j}: {what} (sigma_n = {arr[0][j]:.6g} Pa, "
                                  f"free slip {arr[1][j]:.6g} m/s, theta(0) = {self.T[0, j]:.6g} K; "
                                  f"{bad.size} column(s) failed)")
        self.slip_macro[:] = np.abs(0.5 * (self._v_half + arr[2]))
        return self.tau.copy(), self._v_half.copy()

    def _start(self, F_N, v_free, v_prev, k, tau_cap, v_far, dt: float) -> None:
        """The first BDF2 step (no history): sub-steps dt/2**L, dt/2**L, dt/2**(L-1), ..., dt/2 (L = START_LEVELS;
        backward Euler, then BDF2 at ratios 1 and 2), so that the loading's jump at t = 0 is resolved; tau is the
        step's mean traction, the other outputs the last sub-step's (substeps > 1 only where one was split).  With
        a partner mass (k > 0) each sub-step takes its share of k and the free slip the last one left, as in
        :meth:`_split`."""
        subs = [dt / 2**START_LEVELS] + [dt / 2**j for j in range(START_LEVELS, 0, -1)]
        vf, vp = v_free.copy(), v_prev.copy()
        imp = np.zeros(self.n_columns)
        sweeps = np.zeros(self.n_columns, np.int64)
        split = np.ones(self.n_columns, np.int64)
        failed = np.zeros(self.n_columns, bool)
        for n, d in enumerate(subs):
            self._bdf2_step(F_N, vf, vp, k * (d / dt), tau_cap, v_far, d, n > 0)
            if np.any(self.status != OK):
                return
            imp += np.where(vf >= 0.0, 1.0, -1.0) * self.tau * d
            sweeps += np.abs(self.iterations)
            split = np.maximum(split, self.substeps)
            failed |= self.iterations < 0
            vp = self._v_half.copy()
            vf = np.where(k > 0.0, self._v_half, vf)
        self.tau[:] = np.where(v_free >= 0.0, 1.0, -1.0) * imp / dt
        self.iterations[:] = np.where(failed, -sweeps, sweeps)
        self.substeps[:] = split  # > 1 only where a sub-step was split (the start's own sub-steps are the scheme's)

    def _node_mechanical(self) -> np.ndarray:
        """Kinetic energy of each node (out[0]) and half the elastic energy of each adjacent cell (out[1])
        (J/m^2, (2, nn, nc))."""
        rho = self.par[P_RHO] if self.inertia else 0.0
        out = np.zeros((2,) + self.v.shape)
        out[0] = (0.5 * rho) * self.weights[:, None] * self.v**2
        el = 0.25 * self.dz[:, None] * self.Gs * self.ge**2
        out[1, :-1] += el
        out[1, 1:] += el
        return out

    def _temperature(self, e) -> tuple[np.ndarray, np.ndarray]:
        """T(e) and dT/de of :func:`temperature_of` at every node, with each column's melting temperature TF."""
        out, slope = np.empty_like(e), np.empty_like(e)
        temperatures_of(e, self.rho_c, self.rho_L, self.T0, self.TF, out, slope)
        return out, slope

    def _bdf2_step(self, F_N, v_free, v_prev, k, tau_cap, v_far, dt: float, bdf: bool) -> None:
        """One step of dt: backward Euler (bdf False), or variable-step BDF2 (ratio w = dt/h to the last step h):
        y' = y^ + beta dt f(y'), y^ = y + c (y - y_old), c = w^2/(1 + 2w), beta = (1 + w)/(1 + 2w), i.e. the
        backward-Euler kernel over beta dt from y^.  The books stay exact: every energy row takes c times the last
        step's increment plus the kernel's (the enthalpy is linear in the state, so the heat rows are what was
        deposited); the mechanical energy that the extrapolation creates beyond c times the last step's change,
        mu_i = M_i(y^) - M_i(y) - c (M_i(y) - M_i(y_old)) per node, is taken from the node's heat and booked
        (negative) as numerical heat; the friction work is the hydro's, tau [V] dt with tau = impulse/dt, and the
        interface heat closes beta_T (friction work - column work), its difference from the rows deposited at
        node 0 (docs/theory/viscoplastic.md, "Time accuracy").  A failed column is left as it was."""
        hist = self.time_scheme == "bdf2" and self._keep  # this step's start is BDF2's history
        y = (self.v.copy(), self.ge.copy(), self.eps.copy(), self.e.copy(), self.T.copy(), self.T_other.copy()) \
            if bdf or hist else None
        mech = self._node_mechanical() if hist else None
        E0 = self.energy.copy()
        c, beta = 0.0, 1.0
        vf, kk = v_free, k
        if bdf:
            w = dt / self._h
            c, beta = w * w / (1.0 + 2.0 * w), (1.0 + w) / (1.0 + 2.0 * w)
            self.v += c * (self.v - self._v_o)
            self.ge += np.where(self.Gs > 0.0, c * (self.ge - self._ge_o), 0.0)
            self.eps += c * np.maximum(self.eps - self._eps_o, 0.0)
            self.e += c * (self.e - self._e_o)
            self.T[...] = self._temperature(self.e)[0]
            self.T_other += c * (self.T_other - self._T2_o)
            mu = self._node_mechanical() - mech - c * (mech - self._mech_o)
            # the step's impulse I = c I_old + beta dt ts': [V]^{n+1/2} = v_free - k I/dt
            vf = v_free - k * (c / dt) * self._imp
            kk = beta * k
        e_hat = self.e.copy() if bdf else None
        self._advance(F_N, vf, v_prev, kk, tau_cap, v_far, beta * dt, 0, dt_real=dt, shift=c)
        bad = self.status != OK
        if bdf and bad.any():  # leave the failed columns as they were (the kernel left them at y^)
            for a, b in zip((self.v, self.ge, self.eps, self.e, self.T, self.T_other), y):
                a[:, bad] = b[:, bad]
            return
        sgn_k = np.where(vf >= 0.0, 1.0, -1.0)
        imp = c * self._imp + beta * dt * sgn_k * self.tau  # signed impulse per area of the step
        rows = self.energy - E0
        if bdf:
            rows += c * self._rows_o
            fw = imp * 0.5 * (self._v_half + v_prev)
            hi = self.beta_T * (fw - rows[E_COLUMN_WORK])
            corr = -mu.sum(axis=0)
            corr[0] += hi - rows[E_INTERFACE]
            rows[E_FRICTION], rows[E_INTERFACE] = fw, hi
            rows[E_NUMERICAL] -= mu[0].sum(axis=0)  # kinetic part; the elastic part, as the kernel's, is softening
            rows[E_SOFTENING] -= mu[1].sum(axis=0)
            if self.z_other.size:  # node 0 is the interface of both bodies: its correction raises both (continuity)
                sensible = self._temperature(self.e[:1])[1][0] > 0.0  # off the melt plateau: dT/de = 1/rho c
                dT0 = np.where(sensible, corr[0] / (self.weights[0] * self.rho_c + self._c2[0]), 0.0)
                corr[0] -= self._c2[0] * dT0
                self.T_other[0] += dT0
                rows[E_OTHER] += self._c2[0] * dT0
            self.e += corr / self.weights[:, None]
            self.T[...] = self._temperature(self.e)[0]
            self._de += (e_hat - y[3]) + corr / self.weights[:, None]  # the predictor's history: e' - e
            self.energy[...] = E0 + rows
            self.tau[:] = np.where(v_free >= 0.0, 1.0, -1.0) * imp / dt
            self.flux_in[:] = rows[E_INTERFACE] / dt
        if bad.any():
            return
        if hist:
            self._v_o, self._ge_o, self._eps_o, self._e_o, _, self._T2_o = y
            self._mech_o = mech
            self._rows_o = rows
            self._imp = imp
            self._h = dt

    def _advance(self, F_N, v_free, v_prev, k, tau_cap, v_far, dt: float, level: int, dt_real=None,
                 shift=0.0) -> None:
        """One step of dt (per-column input arrays); a column whose Picard iteration does not converge, or whose
        solve fails, is redone as two steps of dt/2 (:meth:`_split`), down to dt/2**MAX_SPLIT.  ``dt_real``, ``shift``
        (a BDF2 step: the kernel's dt is beta dt_real from e^ = e + shift de): the Picard predictor's step and
        offset."""
        h1, h2 = self._dt_prev
        step = dt if dt_real is None else dt_real
        pw = predictor_weights(step, h1, h2)
        pw[0] -= shift
        pw[2] -= shift
        self._dt_prev[:] = step, h1
        if self.pressure_melting:
            melt_temperatures(F_N, self._melt_law, self.TF)
        retry = np.full(self.n_columns, level < MAX_SPLIT)
        if self.far_end == "excess":  # the layer under a slide line: its own kernel, one column at a time
            from shockfriction.friction.subgrid.excess_layer import excess_step
            excess_step(self.dz, self.weights, self.v, self.eps, self.e, self.T, F_N, v_free, v_prev, k,
                        tau_cap, self.scg, self.par, dt, self.max_picard, self.tau, self._v_half, self.slip_local,
                        self.flux_in, self.film_thickness, self.iterations, self.status, self.energy, self._de,
                        self._de2, pw, retry, self.TF, self.T_other, self._c2, self._a2, self._oth, self.eps_ref,
                        self._yh, self._yh_eps, self._yref)
        else:  # the column with its velocities: its own kernel, one column at a time, the mechanics on a window
            from shockfriction.friction.subgrid.inertial_column import inertial_step
            inertial_step(self.dz, self.weights, self.v, self.ge, self.Gs, self.eps, self.e, self.T,
                          F_N, v_free, v_prev, k, tau_cap, self.scg, self.par, dt, self.max_picard, self.tau,
                          self._v_half, self.slip_local, self.flux_in, self.film_thickness, self.iterations,
                          self.status, self.energy, self._de, self._de2, pw, retry,
                          self.TF, v_far, self.T_other, self._c2, self._a2, self._oth, self._reach)
        self.substeps[:] = 1
        redo = np.flatnonzero(retry & (((self.iterations < 0) & (self.status == OK))
                                       | (self.status == NO_CONVERGENCE)))
        if redo.size:
            self._split(redo, F_N, v_free, v_prev, k, tau_cap, v_far, dt, level, (h1, h2))

    def _split(self, cols, F_N, v_free, v_prev, k, tau_cap, v_far, dt, level, dt_prev) -> None:
        """Redo the step of columns ``cols`` (left unchanged by the kernel) as two steps of dt/2 on a copy of them;
        tau, slip_local and flux_in become the means over the step, iterations the sweeps of all sub-steps
        (negative if one of them still did not converge), substeps their number.  With a finite partner mass
        (k > 0) each half step takes k/2 and the free slip the first half left: the two impulses add up to the
        step's, tau being their mean (what the hydrocode applies over dt)."""
        sub = object.__new__(ViscoplasticColumns)
        sub.__dict__.update(self.__dict__)  # the grid and the parameters; the arrays below are the columns' own
        for name in ("v", "ge", "Gs", "eps", "e", "T", "_de", "_de2", "_yh", "_yh_eps"):
            setattr(sub, name, np.array(getattr(self, name)[:, cols], order=self._order))
        for name in ("energy", "T_other", "_yref"):
            setattr(sub, name, np.ascontiguousarray(getattr(self, name)[:, cols]))
        n = cols.size
        for name in ("tau", "slip_local", "slip_macro", "flux_in", "film_thickness", "_v_half"):
            setattr(sub, name, np.zeros(n))
        sub.TF = self.TF[cols].copy()
        sub.eps_ref = self.eps_ref[cols].copy()
        sub._reach = self._reach[cols].copy()
        sub.iterations, sub.status, sub.substeps = (np.zeros(n, np.int64) for _ in range(3))
        sub._dt_prev = np.array(dt_prev, float)
        sub._oth = np.empty((2, self.z_other.size, n))
        e_start, de_prev = sub.e.copy(), sub._de.copy()
        args = [np.ascontiguousarray(a[cols]) for a in (F_N, v_free, v_prev, k, tau_cap, v_far)]
        args[3] = 0.5 * args[3]
        tau, slip, flux = np.zeros(n), np.zeros(n), np.zeros(n)
        sweeps, steps = np.zeros(n, np.int64), np.zeros(n, np.int64)
        failed = np.zeros(n, bool)
        status = np.zeros(n, np.int64)
        for _ in range(2):
            sub._advance(*args, 0.5 * dt, level + 1)
            tau += 0.5 * sub.tau
            slip += 0.5 * sub.slip_local
            flux += 0.5 * sub.flux_in
            sweeps += np.abs(sub.iterations)
            failed |= sub.iterations < 0
            status = np.maximum(status, sub.status)  # a failed sub-step fails the step
            steps += sub.substeps
            args[2] = sub._v_half.copy()  # the next sub-step's [V]^{n-1/2}
            args[1] = np.where(args[3] > 0.0, sub._v_half, args[1])  # and, with a partner mass, its free slip
        ok = status == OK
        if ok.any():
            keep = cols[ok]
            for name in ("v", "ge", "Gs", "eps", "e", "T", "energy", "T_other", "_yh", "_yh_eps", "_yref"):
                getattr(self, name)[:, keep] = getattr(sub, name)[:, ok]
            self.eps_ref[keep] = sub.eps_ref[ok]
            self._reach[keep] = sub._reach[ok]
            self._de[:, keep] = (sub.e - e_start)[:, ok]  # the predictor's history: the change over the whole dt
            self._de2[:, keep] = de_prev[:, ok]
        self.tau[cols], self.slip_local[cols], self.flux_in[cols] = tau, slip, flux
        self._v_half[cols] = sub._v_half
        self.film_thickness[cols] = sub.film_thickness
        self.TF[cols] = sub.TF
        self.status[cols] = status
        self.iterations[cols] = np.where(failed, -sweeps, sweeps)
        self.substeps[cols] = steps

    # ------------------------------------------------------------------ diagnostics
    @property
    def theta_interface(self) -> np.ndarray:
        return self.T[0].copy()

    @property
    def theta(self) -> np.ndarray:
        return self.T.T.copy()

    @property
    def eps_p(self) -> np.ndarray:
        return self.eps.T.copy()

    @property
    def velocity(self) -> np.ndarray:
        return self.v.T.copy()

    @property
    def stress(self) -> np.ndarray:
        """Solid shear stress per cell (Pa), (n_columns, n_cells)."""
        return (self.Gs * self.ge).T.copy()

    def _solidus_enthalpy(self) -> np.ndarray:
        """rho c (T_m - T0) (J/m^3) of each column, at its melting temperature of the last step."""
        return self.rho_c * (self.TF - self.T0)

    def melt_fraction(self) -> np.ndarray:
        return np.clip((self.e - self._solidus_enthalpy()) / self.rho_L, 0.0, 1.0)

    def heat_stored(self) -> np.ndarray:
        """Enthalpy per unit area (J/m^2): sensible + latent."""
        return column_sums(self.weights, self.e)

    def other_heat_stored(self) -> np.ndarray:
        """Heat in the other body's thermal column (J/m^2; two-sided heat, zeros otherwise): equals
        ``energies()["heat_conducted_other"]`` to round-off."""
        if self.z_other.size == 0:
            return np.zeros(self.n_columns)
        return column_sums(self._c2, self.T_other - self.T0)

    def latent_stored(self) -> np.ndarray:
        # (the books call this every step: without a node above its solidus it is zero, without the full pass)
        if not np.any(self.e.max(axis=0) > self._solidus_enthalpy()):
            return np.zeros(self.n_columns)
        return self.rho_L * column_sums(self.weights, self.melt_fraction())

    def kinetic(self) -> np.ndarray:
        if not self.inertia:  # a quasi-static column (the excess layer) carries none
            return np.zeros(self.n_columns)
        return 0.5 * self.par[P_RHO] * column_sums(self.weights, self.v**2)

    def elastic(self) -> np.ndarray:
        if self.far_end == "excess":  # the excess layer stores no elastic strain (its cells' is the hydro's)
            return np.zeros(self.n_columns)
        return 0.5 * column_sums(self.dz, self.Gs * self.ge**2)

    def mechanical_energy(self) -> np.ndarray:
        return self.kinetic() + self.elastic()

    def energies(self) -> dict[str, np.ndarray]:
        """Cumulative energies per column (J/m^2)."""
        E = self.energy
        out = {name: E[i].copy() for i, name in enumerate(
            ("friction_work", "heat_interface", "column_work", "plastic_work", "viscous_heat", "softening_heat",
             "radiated", "heat_out", "numerical_heat", "heat_conducted_other"))}
        bQ = self.par[P_BETA_Q]
        # the other body's heat: its fixed share (1 - beta_T) of the slip heat, or (two-sided heat) what it conducted
        out["heat_other_body"] = out["friction_work"] - out["heat_interface"] - out["column_work"] \
            + out["heat_conducted_other"]
        out["cold_work"] = (1.0 - bQ) * out["plastic_work"]
        out["kinetic"] = self.kinetic()
        out["elastic"] = self.elastic()
        out["heat_stored"] = self.heat_stored()
        out["latent"] = self.latent_stored()
        return out

    def energy_residual(self) -> np.ndarray:
        """friction work - (heat to the other body + stored heat (sensible + latent) + heat out + cold work +
        kinetic + elastic + radiated - initial), relative to the friction work (per column)."""
        d = self.energies()
        other = d["friction_work"] - d["heat_interface"] / self.beta_T - d["column_work"] if self.beta_T > 0 else 0.0
        total = ((1.0 - self.beta_T) / self.beta_T * d["heat_interface"] if self.beta_T > 0 else 0.0) + other
        total = total + d["heat_stored"] + d["heat_out"] + d["cold_work"] + d["kinetic"] + d["elastic"] \
            + d["radiated"] + d["heat_conducted_other"] - self._e_initial
        scale = np.maximum(np.abs(d["friction_work"]), np.abs(d["column_work"]))
        return (d["friction_work"] - total) / np.where(scale > 0, scale, 1.0)
