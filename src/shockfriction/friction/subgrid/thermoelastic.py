"""Thermoelastic interface model (thesis ch. 7, §7.3.3 Algorithm 1), one scalar equation per column.

Friction law (eq. 7.12 / 7.76) with the caps of Table 6.1 inside the min::

    tau(Theta) = min( mu0 F_N, tau_stick, f Ymax/sqrt(3) G(F_N, Theta)/G0 ),
    G/G0 = (1 + g F_N - h (Theta - 300)) exp(-xi Theta/(T_F - Theta))   (0 at T_F)

Macroscopic slip (eq. 7.99-7.100, sign erratum fixed, digest §9 item 6)::

    [V]^{n+1/2} = sign([V*]) (|[V*]| - tau k),   k = S dt (1/m_s + 1/m_g)
    [V]^n = ([V]^{n+1/2} + [V]^{n-1/2}) / 2,      [v] = [V]^n   (eq. 7.101)

Heat entering the column q_in = beta_T tau |[v]| (eq. 7.102) and the affine
interface temperature Theta = Theta_ad(0) + a0 q_in (eq. 7.70, a0 = theta_unit[0]).
Unknown: Theta = Theta^n(0); residual (eq. 7.97)::

    R(Theta) = Theta - Theta_ad(0) - a0 beta_T tau(Theta) |[v](Theta)|

R(Theta_ad(0)) <= 0 and R -> T_F - Theta_ad(0) > 0 as Theta -> T_F (tau -> 0), so the
root is bracketed in [Theta_ad(0), T_F) and found by Brent's method.  Taking the caps
inside the min (instead of the thesis's a-posteriori limiter, step 4) makes the
accepted state satisfy the friction law, the flux and the heat equation together.
The accepted state is the bracket end with R > 0, so the column temperature
Theta_ad(0) + a0 q_in = Theta - R stays strictly below T_F.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from shockfriction.friction.subgrid.rootfind import B, BRENT_STATE, C, FB, brent_feed, brent_next, brent_start
from shockfriction.materials.strength import I_G, I_H, I_TF, I_XI, I_YMAX, scg_shear_ratio

SQRT3 = math.sqrt(3.0)

# status codes returned by the kernels
OK, ABOVE_MELT, NO_CONVERGENCE, BAD_INPUT = 0, 1, 2, 3


@njit(cache=True)
def step_inputs(sig, vf, vp, ms, mg, S, dt, mu0, k, tau_stick, tau_cap, tau_coulomb, F_N):
    """Per-node inputs of a step (see interface.py): k = S dt (1/m_s + 1/m_g) (eq. 7.99), the sticking cap
    tau_stick = |[V*]|/k (0 without free slip, inf for two rigid partners), the Coulomb cap mu0 F_N and
    tau_cap = min(mu0 F_N, tau_stick) in contact (F_N = sigma_n > 0), else 0.  Returns the first node
    with bad input (non-finite, a mass <= 0, an area < 0 or 0 in contact), else -1, before writing."""
    n = k.shape[0]
    for j in range(n):
        s, a = sig[j], S[j]
        if not (math.isfinite(s) and math.isfinite(vf[j]) and math.isfinite(vp[j]) and ms[j] > 0.0 and mg[j] > 0.0
                and a >= 0.0 and math.isfinite(a) and (a > 0.0 or s <= 0.0)):
            return j
    for j in range(n):
        inv_sum = 1.0 / ms[j] + 1.0 / mg[j]
        kj = S[j] * dt * inv_sum
        k[j] = kj
        v = vf[j]
        ts = abs(v) / (kj if kj > 0.0 else 1.0) if inv_sum > 0.0 else math.inf
        if v == 0.0:
            ts = 0.0
        tau_stick[j] = ts
        s = sig[j]
        fn = s if s > 0.0 else 0.0
        c = mu0 * fn
        tau_coulomb[j] = c
        F_N[j] = fn
        tau_cap[j] = (c if c <= ts else ts) if s > 0.0 else 0.0
    return -1


@njit(cache=True)
def first_nonfinite(arrays):
    """(k, j): the first non-finite value, in array k (the first such array) at node j; (-1, -1) if none."""
    for k in range(len(arrays)):
        a = arrays[k]
        for j in range(a.shape[0]):
            if not math.isfinite(a[j]):
                return k, j
    return -1, -1


@njit(cache=True)
def first_nonzero(status):
    """Index of the first nonzero entry of ``status``, -1 if none."""
    for j in range(status.shape[0]):
        if status[j] != 0:
            return j
    return -1


@njit(cache=True)
def book_step(ad0, unit0, q_in, tau, v_half, v_prev, dt, deposited, plastic, active, theta_interface, slip_macro,
              friction_work, heat_interface, heat_plastic):
    """End of a step, per node: interface temperature theta_ad(0) + q_in a0 (eq. 7.70), |[V]^n| =
    |([V]^{n+1/2} + [V]^{n-1/2})/2| (eq. 7.100), the energy sums (friction work tau |[V]^n| dt, interface
    heat q_in dt, deposited plastic heat) and ``active`` |= heated this step."""
    for j in range(q_in.shape[0]):
        q = q_in[j]
        heated = q != 0.0
        if plastic:
            d = deposited[j]
            heat_plastic[j] += d
            heated = heated or d != 0.0
        if heated:
            active[j] = True
        theta_interface[j] = ad0[j] + q * unit0
        sm = abs(0.5 * (v_half[j] + v_prev[j]))
        slip_macro[j] = sm
        friction_work[j] += tau[j] * sm * dt
        heat_interface[j] += q * dt


@njit(cache=True)
def tresca_stress(F_N, theta, f, p):
    """SCG ("Tresca") branch of eq. 7.12: f Ymax/sqrt(3) G(F_N, Theta)/G0 (0 at or above T_F)."""
    return f * p[I_YMAX] / SQRT3 * scg_shear_ratio(F_N, theta, p[I_G], p[I_H], p[I_XI], p[I_TF])


@njit(cache=True)
def friction_stress(F_N, theta, tau_cap, f, p):
    """tau = min(tau_cap, Tresca branch); tau_cap = min(mu0 F_N, tau_stick)."""
    t = tresca_stress(F_N, theta, f, p)
    return t if t < tau_cap else tau_cap


@njit(cache=True)
def corrected_slip(v_free, tau, k):
    """[V]^{n+1/2} = [V*] - sign([V*]) tau k, never reversing the slip (tau <= tau_stick)."""
    mag = abs(v_free) - tau * k
    if mag < 0.0:
        mag = 0.0
    return mag if v_free >= 0.0 else -mag


@njit(cache=True)
def _residual(theta, theta_ad0, a0, F_N, v_free, v_prev, k, tau_cap, beta_T, f, p):
    tau = friction_stress(F_N, theta, tau_cap, f, p)
    v_n = abs(0.5 * (corrected_slip(v_free, tau, k) + v_prev))
    return theta - theta_ad0 - a0 * beta_T * tau * v_n


@njit(cache=True)
def solve_thermoelastic(theta_ad0, a0, F_N, v_free, v_prev, k, tau_cap, beta_T, f, p, xtol, max_iter,
                        theta_s, tau, v_half, v_local, q_in, iters, status):
    """Per-column interface solve (Algorithm 1).  Inputs (n,) arrays except a0, beta_T, f, p, xtol, max_iter.

    Outputs (filled): theta_s trial interface temperature, tau, v_half = [V]^{n+1/2},
    v_local = |[v]^n|, q_in = beta_T tau |[v]| (W/m^2 entering), iters, status.
    """
    st = np.empty(BRENT_STATE)
    T_F = p[I_TF]
    for j in range(theta_ad0.shape[0]):
        iters[j] = 0
        status[j] = OK
        t_ad = theta_ad0[j]
        if not (math.isfinite(t_ad) and math.isfinite(F_N[j]) and math.isfinite(v_free[j])
                and math.isfinite(v_prev[j]) and math.isfinite(k[j]) and tau_cap[j] >= 0.0):
            status[j] = BAD_INPUT
            continue
        if t_ad >= T_F:
            status[j] = ABOVE_MELT
            continue
        lo = t_ad
        r_lo = _residual(lo, t_ad, a0, F_N[j], v_free[j], v_prev[j], k[j], tau_cap[j], beta_T, f, p)
        x = lo
        if r_lo < 0.0:
            hi = T_F
            r_hi = T_F - t_ad  # tau(T_F) = 0
            brent_start(lo, r_lo, hi, r_hi, xtol, st)
            converged = False
            for it in range(max_iter):
                done, x = brent_next(st)
                if done:
                    converged = True
                    break
                brent_feed(st, _residual(x, t_ad, a0, F_N[j], v_free[j], v_prev[j], k[j], tau_cap[j], beta_T, f, p))
                iters[j] = it + 1
            if not converged:
                status[j] = NO_CONVERGENCE
            # accept the bracket end with R >= 0: the column then stays below it
            x = st[B] if st[FB] >= 0.0 else st[C]
        t = friction_stress(F_N[j], x, tau_cap[j], f, p)
        vh = corrected_slip(v_free[j], t, k[j])
        vn = abs(0.5 * (vh + v_prev[j]))
        theta_s[j] = x
        tau[j] = t
        v_half[j] = vh
        v_local[j] = vn
        q_in[j] = beta_T * t * vn
