"""Thermoelastoplastic interface model (thesis ch. 8, §8.2-8.3, Algorithm 2).

Same friction law, caps and macroscopic slip as :mod:`.thermoelastic`; in addition the
uniform shear tau (eq. 8.34) yields the layer where it exceeds the local SCG strength.
Closed-form plastic strain (eq. 8.13 / 8.42, unsaturated SCG as in the thesis)::

    eps_target(z) = ( (sqrt(3) tau G0 / (G(F_N, Theta(z)) Y0))^(1/n) - 1 ) / beta
    d_eps(z) = max(0, eps_target(z) - eps_prev(z))

(the spurious "* dt" of 8.39/8.41 dropped, digest §9 item 13).  Local slip (eq. 8.35-8.37,
trapezoid rule with the column's control-volume weights)::

    [v] = |[V]^n| - sqrt(3)/dt * integral d_eps dz

Kinematic limit (our choice; the thesis is silent): where the closed-form increments would shear
the layer faster than the macroscopic slip, they are scaled down so that the plastic slip equals
|[V]^n| and [v] = 0.  The plastic work sqrt(3) tau int d_eps dz then never exceeds the friction
work tau |[V]^n| dt, and friction work = interface heat / beta_T + plastic work holds exactly.  Heat: q_in =
beta_T tau [v] at z = 0 and the plastic heat beta_Q sqrt(3) tau d_eps (J/m^3, Taylor-Quinney)
deposited in the next step's adiabatic solve (lagged source, eq. 8.46; depositing the energy
rather than the rate keeps the balance exact when dt changes).

Unknown: the interface temperature Theta; the trial profile is
theta(z) = theta_ad(z) + q(Theta) theta_unit(z), q(Theta) = (Theta - theta_ad(0))/a0 (eq. 8.67, 8.47).
Residual (eq. 8.66, written in kelvin by multiplying by a0)::

    R(Theta) = Theta - theta_ad(0) - a0 beta_T tau(Theta) [v](Theta)

Bracket: lower end theta_ad(0) (R <= 0); upper end the interface temperature at which the
first node of the trial profile reaches T_F, q_max = min_i (T_F - theta_ad_i)/theta_unit_i
(there tau [v] = 0: either tau = 0 at T_F, or G = 0 at a sub-surface node and the layer
takes all the slip), so R(upper) > 0 and no node of the accepted column reaches T_F.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from shockfriction.friction.subgrid.rootfind import B, BRENT_STATE, C, FB, brent_feed, brent_next, brent_start
from shockfriction.friction.subgrid.thermoelastic import (ABOVE_MELT, BAD_INPUT, NO_CONVERGENCE, OK, SQRT3,
                                                           corrected_slip, friction_stress)
from shockfriction.materials.strength import I_BETA, I_G, I_H, I_N, I_TF, I_XI, I_Y0, scg_shear_ratio


@njit(cache=True)
def plastic_increments(tau, F_N, theta_ad, theta_unit, q, eps_prev, hard, weights, ad_max, unit_max, p, out):
    """Fill ``out`` with d_eps (eq. 8.42) for shear ``tau`` on the trial profile theta_ad + q theta_unit;
    return the trapezoid integral sum_i w_i d_eps_i, or -1 if some node has no strength left (G = 0).

    ``hard`` = (1 + beta eps_prev)^n: a node flows iff sqrt(3) tau/(Y0 G/G0) > hard.  Nodes that
    cannot flow are skipped without an exponential, using G/G0 >= (1 + g F_N - h (T - 300)) E_min,
    E_min the melt factor at an upper bound of the trial temperatures (ad_max + q unit_max, or the
    exact maximum near melting).
    """
    Y0, beta, n = p[I_Y0], p[I_BETA], p[I_N]
    g, h, xi, T_F = p[I_G], p[I_H], p[I_XI], p[I_TF]
    nn = theta_ad.shape[0]
    if tau <= 0.0:
        for i in range(nn):
            out[i] = 0.0
        return 0.0
    th_max = ad_max + q * unit_max
    if th_max >= T_F:  # the bound is too loose near melting: take the exact maximum
        th_max = -math.inf
        for i in range(nn):
            th = theta_ad[i] + q * theta_unit[i]
            if th > th_max:
                th_max = th
        if th_max >= T_F:
            return -1.0
    e_min = math.exp(-xi * th_max / (T_F - th_max))
    s = SQRT3 * tau / Y0
    lin0 = 1.0 + g * F_N + h * 300.0
    integral = 0.0
    for i in range(nn):
        out[i] = 0.0
        th = theta_ad[i] + q * theta_unit[i]
        if (lin0 - h * th) * e_min * hard[i] >= s:
            continue  # G/G0 * hardening already carries tau: elastic
        r = scg_shear_ratio(F_N, th, g, h, xi, T_F)
        if r <= 0.0:
            return -1.0
        x = s / r
        if x <= hard[i]:
            continue
        d = (x ** (1.0 / n) - 1.0) / beta - eps_prev[i]
        if d > 0.0:
            out[i] = d
            integral += weights[i] * d
    return integral


@njit(cache=True)
def update_hardening(eps, deps, hard, p):
    """eps += deps and hard = (1 + beta eps)^n where the strain grew (all columns)."""
    beta, n = p[I_BETA], p[I_N]
    for j in range(eps.shape[0]):
        for i in range(eps.shape[1]):
            if deps[j, i] > 0.0:
                eps[j, i] += deps[j, i]
                hard[j, i] = (1.0 + beta * eps[j, i]) ** n


@njit(cache=True)
def _evaluate(theta, theta_ad, theta_unit, weights, a0, eps_prev, hard, ad_max, unit_max, F_N, v_free, v_prev,
              k, tau_cap, beta_T, f, p, dt, deps):
    """Residual and state at trial interface temperature ``theta``: (R, tau, v_half, v_local, plastic_rate)."""
    tau = friction_stress(F_N, theta, tau_cap, f, p)
    vh = corrected_slip(v_free, tau, k)
    v_mac = abs(0.5 * (vh + v_prev))
    q = (theta - theta_ad[0]) / a0
    integral = plastic_increments(tau, F_N, theta_ad, theta_unit, q, eps_prev, hard, weights, ad_max, unit_max,
                                  p, deps)
    if integral >= 0.0:
        rate = SQRT3 * integral / dt
        if rate > v_mac:  # kinematic limit: the layer takes at most the macroscopic slip of the step
            scale = v_mac / rate
            for i in range(deps.shape[0]):
                deps[i] *= scale
            rate = v_mac
        v_loc = v_mac - rate
    else:
        rate = math.inf
        v_loc = 0.0
    return theta - theta_ad[0] - a0 * beta_T * tau * v_loc, tau, vh, v_loc, rate


@njit(cache=True)
def solve_thermoelastoplastic(theta_ad, theta_unit, weights, eps_prev, hard, F_N, v_free, v_prev, k, tau_cap,
                              beta_T, f, p, dt, xtol, max_iter,
                              theta_s, tau, v_half, v_local, plastic_rate, q_in, deps, iters, status):
    """Per-column interface solve with plasticity (Algorithm 2).  2D arrays are (n_columns, n_nodes).

    Outputs: theta_s, tau, v_half = [V]^{n+1/2}, v_local = [v]^n, plastic_rate (m/s),
    q_in = beta_T tau [v] (W/m^2), deps (plastic strain increments), iters, status.
    """
    st = np.empty(BRENT_STATE)
    T_F = p[I_TF]
    a0 = theta_unit[0]
    nn = theta_unit.shape[0]
    unit_max = 0.0
    for i in range(nn):
        if theta_unit[i] > unit_max:
            unit_max = theta_unit[i]
    for j in range(theta_ad.shape[0]):
        iters[j] = 0
        status[j] = OK
        row = theta_ad[j]
        t_ad = row[0]
        if not (math.isfinite(t_ad) and math.isfinite(F_N[j]) and math.isfinite(v_free[j])
                and math.isfinite(v_prev[j]) and math.isfinite(k[j]) and tau_cap[j] >= 0.0):
            status[j] = BAD_INPUT
            continue
        q_max = math.inf
        ad_max = -math.inf
        for i in range(nn):
            if row[i] > ad_max:
                ad_max = row[i]
            if row[i] >= T_F:
                q_max = -1.0
                break
            if theta_unit[i] > 0.0:
                qi = (T_F - row[i]) / theta_unit[i]
                if qi < q_max:
                    q_max = qi
        if q_max < 0.0:
            status[j] = ABOVE_MELT
            continue
        hi = t_ad + a0 * q_max
        lo = t_ad
        r_lo, _, _, _, _ = _evaluate(lo, row, theta_unit, weights, a0, eps_prev[j], hard[j], ad_max, unit_max,
                                     F_N[j], v_free[j], v_prev[j], k[j], tau_cap[j], beta_T, f, p, dt, deps[j])
        x = lo
        if r_lo < 0.0:
            r_hi = hi - t_ad  # at the upper end tau [v] = 0
            brent_start(lo, r_lo, hi, r_hi, xtol, st)
            converged = False
            for it in range(max_iter):
                done, x = brent_next(st)
                if done:
                    converged = True
                    break
                r, _, _, _, _ = _evaluate(x, row, theta_unit, weights, a0, eps_prev[j], hard[j], ad_max, unit_max,
                                          F_N[j], v_free[j], v_prev[j], k[j], tau_cap[j], beta_T, f, p, dt, deps[j])
                brent_feed(st, r)
                iters[j] = it + 1
            if not converged:
                status[j] = NO_CONVERGENCE
            x = st[B] if st[FB] >= 0.0 else st[C]
        r, t, vh, vl, rate = _evaluate(x, row, theta_unit, weights, a0, eps_prev[j], hard[j], ad_max, unit_max,
                                       F_N[j], v_free[j], v_prev[j], k[j], tau_cap[j], beta_T, f, p, dt, deps[j])
        if not math.isfinite(rate):  # accepted point on the melting edge of a sub-surface node
            status[j] = ABOVE_MELT
        theta_s[j] = x
        tau[j] = t
        v_half[j] = vh
        v_local[j] = vl
        plastic_rate[j] = rate
        q_in[j] = beta_T * t * vl
