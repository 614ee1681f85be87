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
from numba import get_num_threads, njit, prange

from shockfriction.friction.subgrid.column import sweep_block, sweep_span
from shockfriction.friction.subgrid.rootfind import B, BRENT_STATE, C, FB, brent_feed, brent_next, brent_start
from shockfriction.friction.subgrid.thermoelastic import (ABOVE_MELT, BAD_INPUT, NO_CONVERGENCE, OK, SQRT3,
                                                           corrected_slip, friction_stress)
from shockfriction.jit_options import NO_REFCOUNT
from shockfriction.materials.strength import I_BETA, I_G, I_H, I_N, I_TF, I_XI, I_Y0, scg_shear_ratio_simd


# The kernels of the root iteration allocate nothing: the per-column solve is compiled without numba's
# reference counting (``_nrt=False``) and its helpers are inlined into it (``inline='always'``), so that the
# array views and arguments of each evaluation cost no atomic increment/decrement
# (docs/theory/subgrid-layout.md, section 6; shockfriction.jit_options).  The solve and the helpers that tests
# call alone use numpy's error model (a division by zero gives inf, no check): the first two passes of
# plastic_increments are then loops without exits, vectorised across the nodes (section 9).


# ln of the largest closed-form (1 + beta eps_target) used: x^(1/n) is capped at exp(300) ~ 1e130, so that
# n_nodes such increments, their integral / dt and the kinematic scaling all stay finite
LOG_TARGET_MAX = 300.0
TARGET_MAX = math.exp(LOG_TARGET_MAX)
# Lazy hardening (plastic_increments): a stale node flows for sure when x^(1/n) > (1 + beta eps)(1 + LAZY_MARGIN).
# With pow and 1/n within one ulp (x^(1/n) by root_power: within 2 ROOT_POWER_MAX ulp, 1.5e-14 more in ln), that gives
# ln x - ln H >= n ln(1 + LAZY_MARGIN) - 1.2e-13 n - 2.3e-16 > 0 for n >= LAZY_N_MIN (ln H <= 710); below it (or
# beta < 0) H is computed at every update, as before.
LAZY_MARGIN = 1e-9
LAZY_N_MIN = 1e-6
# a stale entry holds -H_old (1 - STALE_SHRINK): below every later H (eps only grows, pow is within an ulp)
STALE_SHRINK = 2.0 ** -50


# x^(1/n) by binary powering where 1/n is an integer up to this (n = 0.1 for most of the library's SCG fits)
ROOT_POWER_MAX = 64
ROOT_POWER_BITS = 7  # bits of the integers up to ROOT_POWER_MAX
# plastic-front bound (nodes) from which a column's theta_ad is copied for the vectorised first pass of
# plastic_increments; below it the pass reads the strided column and forms G/G0 only where needed (measured:
# the uncoupled benchmark's columns, ~18 nodes deep, ran 20 % slower with the copy and every node's G/G0)
SIMD_MIN_NODES = 32


@njit(cache=True, inline="always")
def root_exponent(n):
    """The integer k = 1/n when 1/n is one in [1, ROOT_POWER_MAX] (x^(1/n) = x^k by products), else 0 (pow)."""
    r = 1.0 / n
    return int(r) if 1.0 <= r <= ROOT_POWER_MAX and r == math.floor(r) else 0


@njit(cache=True, inline="always", error_model="numpy")
def integer_power(x, k):
    """x^k for 1 <= k <= ROOT_POWER_MAX by binary powering (r *= x^(2^b) for each set bit b of k, low bits
    first; k - 1 products at most, relative error below 2 k ulp; x^10 is four products).  A loop of fixed length
    without exits, so that a loop over nodes calling it vectorises; the squarings past k's top bit are not used
    (they may overflow)."""
    r = 1.0
    b = x
    for bit in range(ROOT_POWER_BITS):
        r = r * b if (k >> bit) & 1 else r
        b = b * b
    return r


@njit(cache=True, inline="always", error_model="numpy")
def root_power(x, inv_n, k):
    """x^(1/n) (the strain target of eq. 8.42): x^k by :func:`integer_power` when k > 0 (against pow's one
    ulp), else ``x ** inv_n``."""
    if k <= 0:
        return x ** inv_n
    return integer_power(x, k)


@njit(cache=True, inline="always")
def visited(q, depth, q_hi, nn):
    """Number of leading nodes that an evaluation at q writes: ``depth`` for 0 <= q <= q_hi, else all."""
    return depth if (depth >= 0 and 0.0 <= q <= q_hi) else nn


@njit(cache=True, inline="always")
def lazy_hardening(p):
    """Whether ``hard`` may hold stale entries (see :func:`plastic_increments`): beta >= 0 and n >= LAZY_N_MIN."""
    n = p[I_N]
    return p[I_BETA] >= 0.0 and LAZY_N_MIN <= n < math.inf


@njit(cache=True, inline="always", error_model="numpy")
def plastic_increments(tau, F_N, theta_ad, near, theta_unit, q, eps_prev, hard, weights, ad_max, unit_max, p, out,
                       scratch, depth=-1, q_hi=math.inf):
    """Fill ``out`` with d_eps (eq. 8.42) for shear ``tau`` on the trial profile theta_ad + q theta_unit;
    return the trapezoid integral sum_i w_i d_eps_i, or -1 if some node has no strength left (G = 0).
    ``near`` is read instead of ``theta_ad`` by the vectorised first pass, taken when ``depth`` >= SIMD_MIN_NODES
    and the visited nodes are those above it: then it must hold theta_ad's first ``depth`` values contiguously
    (the solve copies them from its strided column; ``theta_ad`` itself will do).

    ``hard[i]`` = H_i = (1 + beta eps_prev_i)^n: a node flows iff x = sqrt(3) tau/(Y0 G/G0) > H_i.  Nodes
    that cannot flow are skipped without an exponential, using G/G0 >= (1 + g F_N - h (T - 300)) E_min,
    E_min the melt factor at an upper bound of the trial temperatures (ad_max + q unit_max, or the
    exact maximum near melting).

    Lazy hardening: ``hard[i] < 0`` marks a stale entry (eps_prev_i grew since H_i was computed;
    -hard[i] <= H_i is a lower bound, :func:`finish_column`).  Such a node flows for sure when
    t = x^(1/n) > (1 + beta eps_prev_i)(1 + LAZY_MARGIN) and (1 + g F_N - h T) E_min x < sqrt(3) tau/Y0
    (then x > H_i and the skip test above fails with H_i as well); t is the power that d_eps needs
    anyway, so H_i is not formed.  Otherwise H_i is computed, stored, and the node is treated as
    before: every d_eps is the one of the exact H_i, bit for bit.

    Near melting G -> 0 and x = sqrt(3) tau G0/(G Y0) -> inf, so x^(1/n) (n ~ 0.1) would overflow
    and the kinematic scaling would turn inf * 0 into NaN.  Where (1/n) ln x > LOG_TARGET_MAX the
    strain target is taken as exp(LOG_TARGET_MAX)/beta (~1e130): finite, and so far above every
    unsaturated node that the kinematic limit gives such nodes (equal shares of) the whole slip.

    ``depth`` (>= 0) is a plastic-front bound from :func:`plastic_depth`: for 0 <= q <= ``q_hi``
    the nodes from ``depth`` on are proven elastic, so only ``out[:depth]`` is written (the
    caller keeps the rest zero).  Outside that range, or with ``depth < 0``, every node is visited.

    The nodes are visited in three passes (``scratch``, (4, n_nodes), holds G/G0, x, x^(1/n) and the
    linear strength bound between them): the exponentials, then the powers, then the decisions in node
    order.  G/G0 comes from :func:`scg_shear_ratio_simd` (an inlined ``exp``): in a layer of SIMD_MIN_NODES or
    more, at every visited node in a loop without branches or calls, vectorised across the nodes, NaN where the
    skip test holds; in a shorter one only where the test fails (the same values).  x^(1/n) by
    :func:`integer_power` at every node with strength, vectorised likewise, kept where pass 3 needs it (with a
    non-integer 1/n, ``pow`` where needed, a scalar loop).  The third pass decides in node order.
    """
    Y0, beta, n = p[I_Y0], p[I_BETA], p[I_N]
    g, h, xi, T_F = p[I_G], p[I_H], p[I_XI], p[I_TF]
    nn = theta_ad.shape[0]
    m = visited(q, depth, q_hi, nn)
    if tau <= 0.0:
        for i in range(m):
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
    if m == 0:
        return 0.0
    e_min = math.exp(-xi * th_max / (T_F - th_max))
    s = SQRT3 * tau / Y0
    lin0 = 1.0 + g * F_N + h * 300.0
    x_big = math.exp(n * LOG_TARGET_MAX)  # beyond it x^(1/n) is replaced by exp(LOG_TARGET_MAX)
    lazy = lazy_hardening(p)
    inv_n = 1.0 / n
    k_root = root_exponent(n)
    rb, xb, tb, ab = scratch[0], scratch[1], scratch[2], scratch[3]
    # pass 1: the skip test, and G/G0 (NaN where skipped: G/G0 * hardening already carries tau, elastic; G/G0 is
    # never NaN).  A long layer: at every node, vectorised, from the contiguous copy; a short one (or every node
    # visited beyond the copy): only where the test fails, from the column.  The same values either way.
    if depth >= SIMD_MIN_NODES and m <= depth:
        for i in range(m):
            th = near[i] + q * theta_unit[i]
            a = (lin0 - h * th) * e_min
            ab[i] = a
            hv = hard[i]
            r = scg_shear_ratio_simd(F_N, th, g, h, xi, T_F)
            rb[i] = math.nan if a * (-hv if (lazy and hv < 0.0) else hv) >= s else r
    else:
        for i in range(m):
            th = theta_ad[i] + q * theta_unit[i]
            a = (lin0 - h * th) * e_min
            ab[i] = a
            hv = hard[i]
            if a * (-hv if (lazy and hv < 0.0) else hv) >= s:
                rb[i] = math.nan
            else:
                rb[i] = scg_shear_ratio_simd(F_N, th, g, h, xi, T_F)
    # pass 2: x (inf without strength) and the power x^(1/n) where pass 3 needs it (-1: not formed)
    if k_root > 0:
        for i in range(m):
            r = rb[i]
            hv = hard[i]
            x = s / r if r > 0.0 else math.inf
            t = integer_power(x, k_root)
            xb[i] = x
            tb[i] = t if (r > 0.0 and ((lazy and hv < 0.0) or not x <= hv) and x < x_big) else -1.0
    else:
        for i in range(m):
            r = rb[i]
            t = -1.0
            x = math.inf
            if r > 0.0:
                x = s / r
                hv = hard[i]
                if ((lazy and hv < 0.0) or not x <= hv) and x < x_big:
                    t = root_power(x, inv_n, k_root)
            xb[i] = x
            tb[i] = t
    # pass 3: the decisions, in node order
    integral = 0.0
    for i in range(m):
        out[i] = 0.0
        r = rb[i]
        if r != r:
            continue
        a = ab[i]
        hv = hard[i]
        x = xb[i]
        t = tb[i]
        sure = False  # x > H_i, known without H_i
        if lazy and hv < 0.0:  # stale hardening: flows for sure, or form H_i
            if t >= 0.0:
                sure = t > (1.0 + beta * eps_prev[i]) * (1.0 + LAZY_MARGIN) and a * x < s
            if not sure:
                hv = (1.0 + beta * eps_prev[i]) ** n
                hard[i] = hv
                if a * hv >= s:
                    continue
        if r <= 0.0:
            return -1.0
        if not sure and x <= hv:
            continue
        if x < x_big:
            d = ((t if t >= 0.0 else root_power(x, inv_n, k_root)) - 1.0) / beta - eps_prev[i]
        else:
            d = TARGET_MAX / beta
        if d > 0.0:
            out[i] = d
            integral += weights[i] * d
    return integral


# relative safety margin of the plastic-front bound (far above round-off in the strength bound)
FRONT_MARGIN = 1e-9


@njit(cache=True, inline="always")
def suffix_max(ad, blk, m):
    """max_{i >= m} ad[i] from the block suffix maxima blk[b] = max_{i >= 8b} ad[i] (m < len(ad))."""
    nn = ad.shape[0]
    b = (m + 7) // 8
    e = 8 * b
    top = -math.inf
    if e < nn:
        top = blk[b]
    else:
        e = nn
    for i in range(m, e):
        if ad[i] > top:
            top = ad[i]
    return top


@njit(cache=True, inline="always")
def suffix_min(values, blk, m):
    """min_{i >= m} |values[i]| from the block suffix minima blk[b] = min_{i >= 8b} |values[i]| (m < len(values))."""
    nn = values.shape[0]
    b = (m + 7) // 8
    e = 8 * b
    low = math.inf
    if e < nn:
        low = blk[b]
    else:
        e = nn
    for i in range(m, e):
        v = abs(values[i])
        if v < low:
            low = v
    return low


@njit(cache=True)
def block_suffix_min(values, blk, top):
    """blk[b] = min_{i >= 8b} |values[i]| for the blocks b <= top (those below already hold theirs)."""
    nn = values.shape[0]
    nb = blk.shape[0]
    for b in range(min(top, nb - 1), -1, -1):
        low = blk[b + 1] if b + 1 < nb else math.inf
        for i in range(8 * b, min(8 * b + 8, nn)):
            v = abs(values[i])
            if v < low:
                low = v
        blk[b] = low


@njit(cache=True, inline="always")
def _front_ok(m, s, F_N, q_hi, ad, ad_blk, unit_suffix_max, hard, hard_blk, g, h, xi, T_F):
    """Every node i >= m elastic: G(C_m)/G0 H_m > s (see :func:`plastic_depth`)."""
    c = suffix_max(ad, ad_blk, m) + q_hi * unit_suffix_max[m]
    if not c < T_F:
        return False
    r = (1.0 + g * F_N - h * (c - 300.0)) * math.exp(-xi * c / (T_F - c))
    return r > 0.0 and r * suffix_min(hard, hard_blk, m) > s


@njit(cache=True, inline="always")
def plastic_depth(tau_max, F_N, q_hi, ad, ad_blk, unit_suffix_max, hard, hard_blk, p, guess=-1):
    """Smallest m such that every node i >= m stays elastic for any tau <= ``tau_max`` and q in [0, q_hi].

    For i >= m: theta_i <= C_m = max_{k >= m} ad_k + q_hi unit_suffix_max[m] and hard_i >= H_m =
    min_{k >= m} hard_k, and G/G0 (1 + g F_N - h (T - 300)) exp(-xi T/(T_F - T)) decreases with T
    (h, xi >= 0), so G_i/G0 hard_i >= G(C_m)/G0 H_m.  If that exceeds sqrt(3) tau_max/Y0 (with a
    margin) no node beyond m flows (eq. 8.42 gives d_eps = 0).  The bound is monotone in m (C_m falls,
    H_m rises), so m is found by bisection, started by galloping from ``guess`` (the last step's bound)
    when one is given.  ``ad`` is the column's theta_ad, ``ad_blk[b]`` its suffix maximum from node 8b,
    ``hard`` its (1 + beta eps)^n and ``hard_blk[b]`` their suffix minimum from node 8b.  Returns
    n_nodes when no bound applies.
    """
    nn = ad.shape[0]
    Y0, g, h, xi, T_F = p[I_Y0], p[I_G], p[I_H], p[I_XI], p[I_TF]
    if not (h >= 0.0 and xi >= 0.0 and p[I_BETA] >= 0.0 and math.isfinite(q_hi) and q_hi >= 0.0
            and tau_max >= 0.0):
        return nn
    s = SQRT3 * tau_max / Y0 * (1.0 + FRONT_MARGIN)
    lo, hi = 0, nn  # the answer lies in [lo, hi]; m = nn always holds
    guess = min(guess, nn - 1)  # a last bound of nn: try nn - 1 first (a column yielding to depth stays there)
    if 0 <= guess:
        step = 1
        if _front_ok(guess, s, F_N, q_hi, ad, ad_blk, unit_suffix_max, hard, hard_blk, g, h, xi, T_F):
            hi = guess
            while hi > lo:
                m = max(hi - step, lo)
                if _front_ok(m, s, F_N, q_hi, ad, ad_blk, unit_suffix_max, hard, hard_blk, g, h, xi, T_F):
                    hi = m
                    step *= 2
                else:
                    lo = m + 1
                    break
        else:
            lo = guess + 1
            while lo < hi:
                m = min(lo + step - 1, hi - 1)
                if _front_ok(m, s, F_N, q_hi, ad, ad_blk, unit_suffix_max, hard, hard_blk, g, h, xi, T_F):
                    hi = m
                    break
                lo = m + 1
                step *= 2
    while lo < hi:
        mid = (lo + hi) // 2
        if _front_ok(mid, s, F_N, q_hi, ad, ad_blk, unit_suffix_max, hard, hard_blk, g, h, xi, T_F):
            hi = mid
        else:
            lo = mid + 1
    return lo


@njit(cache=True)
def source_span(pending_depth):
    """(s0, s1, n_src): the columns s0 <= j < s1 span those with pending_depth[j] > 0 (the pending plastic heat may
    be nonzero only there), n_src = their largest pending_depth; (0, 0, 0) when there are none."""
    s0, s1, n_src = -1, 0, 0
    for j in range(pending_depth.shape[0]):
        d = pending_depth[j]
        if d != 0:
            if s0 < 0:
                s0 = j
            s1 = j + 1
            if d > n_src:
                n_src = d
    return (s0, s1, n_src) if s0 >= 0 else (0, 0, 0)


@njit(cache=True, inline="always")
def finish_column(j, eps, deps, scale, hard, hard_blk, beta, n, lazy, m, tau, heat_factor, weights, pending,
                  pending_depth, plastic_work, lag, rho_c, flags, pending_sum):
    """After column j's accepted solve, one pass over its yielded layer (nodes below m, the plastic-front bound):

    * deps *= scale (the kinematic limit's factor; 1 below the limit), eps += deps;
    * hard = (1 + beta eps)^n and hard_blk, its block suffix minima of |hard|;
    * plastic work += sqrt(3) tau sum_i w_i d_eps_i;
    * pending heat = heat_factor tau d_eps (J/m^3, heat_factor = beta_Q sqrt(3), deposited next step, eq. 8.46),
      zero below; pending_sum = sum_i w_i pending_i (J/m^2); lag = max pending/(rho c); flags[j] = some pending
      heat of column j is a nonzero temperature.

    ``eps``, ``deps``, ``hard``, ``hard_blk`` are column j's rows, ``pending`` is (n_nodes, n_columns), the rest
    per column; ``pending_depth[j]`` (in/out) bounds the nonzero pending heat of the column (n_nodes is always safe).

    Lazy hardening (:func:`lazy_hardening`): the power is not formed here; a yielded node's entry becomes
    stale, -H_old (1 - STALE_SHRINK) (a lower bound of the new H), and :func:`plastic_increments` forms H
    only where it is needed.
    """
    nn = eps.shape[0]
    inv_rho_c = 1.0 / rho_c
    old = pending_depth[j] if 0 <= pending_depth[j] <= nn else nn
    c = heat_factor * tau
    work = 0.0
    heat = 0.0
    top = 0.0
    flag = False
    top_changed = -1  # deepest node whose hardening changed
    for i in range(m):
        d = deps[i] * scale
        deps[i] = d
        if d > 0.0:
            e = eps[i] + d
            eps[i] = e
            if not lazy:
                hard[i] = (1.0 + beta * e) ** n
                top_changed = i
            elif hard[i] >= 0.0:  # becomes stale: its lower bound shrinks
                hard[i] = -hard[i] * (1.0 - STALE_SHRINK)
                top_changed = i
        work += weights[i] * d
        h = c * d
        pending[i, j] = h
        heat += weights[i] * h
        if h * inv_rho_c != 0.0:
            flag = True
        if h > top:
            top = h
    for i in range(m, old):
        pending[i, j] = 0.0
    if top_changed >= 0:
        block_suffix_min(hard, hard_blk, top_changed // 8)
    pending_depth[j] = m
    flags[j] = flag
    plastic_work[j] += SQRT3 * tau * work
    pending_sum[j] = heat
    lag[j] = top / rho_c


@njit(cache=True, inline="always", error_model="numpy")
def _evaluate(theta, theta_ad, near, theta_unit, weights, a0, eps_prev, hard, ad_max, unit_max, F_N, v_free, v_prev,
              k, tau_cap, beta_T, f, p, dt, deps, depth, q_hi, scratch):
    """Residual and state at trial interface temperature ``theta``: (R, tau, v_half, v_local, plastic_rate, scale).

    ``deps`` receives the closed-form increments; at the kinematic limit they are to be multiplied by ``scale``
    (< 1; else 1), which :func:`finish_column` does for the accepted point (the trial points need only the rate)."""
    tau = friction_stress(F_N, theta, tau_cap, f, p)
    vh = corrected_slip(v_free, tau, k)
    v_mac = abs(0.5 * (vh + v_prev))
    q = (theta - theta_ad[0]) / a0
    integral = plastic_increments(tau, F_N, theta_ad, near, theta_unit, q, eps_prev, hard, weights, ad_max, unit_max,
                                  p, deps, scratch, depth, q_hi)
    scale = 1.0
    if integral >= 0.0:
        rate = SQRT3 * integral / dt
        if rate > v_mac:  # kinematic limit: the layer takes at most the macroscopic slip of the step
            scale = v_mac / rate
            rate = v_mac
        v_loc = v_mac - rate
    else:
        rate = math.inf
        v_loc = 0.0
    return theta - theta_ad[0] - a0 * beta_T * tau * v_loc, tau, vh, v_loc, rate, scale


def solve_thermoelastoplastic(theta_ad, ad_blk, theta_unit, weights, eps_prev, hard, hard_blk, F_N, v_free, v_prev,
                              k, tau_cap, beta_T, f, p, dt, xtol, max_iter,
                              theta_s, tau, v_half, v_local, plastic_rate, q_in, deps, iters, status, depth,
                              heat_factor, pending, pending_depth, plastic_work, lag, rho_c, flags, pending_sum,
                              use_front=True):
    """Per-column interface solve with plasticity (Algorithm 2).  ``theta_ad`` is (n_nodes, n_columns)
    (the thermal layout, read here only above the plastic front) with ``ad_blk[b, j]`` = max_{i >= 8b}
    theta_ad[i, j] (from the sweep); ``eps_prev``, ``hard`` and ``deps`` are (n_columns, n_nodes), ``hard_blk``
    (n_columns, n_blocks) the block suffix minima of ``hard``.

    Outputs: theta_s, tau, v_half = [V]^{n+1/2}, v_local = [v]^n, plastic_rate (m/s),
    q_in = beta_T tau [v] (W/m^2), deps (plastic strain increments), iters, status.

    ``depth`` (in/out, per column): on entry, deps[j, depth[j]:] must be zero (n_nodes is always
    safe); on exit (status OK) the plastic-front bound of :func:`plastic_depth`: deps[j] is zero
    from there on, and only nodes above it are visited by the root iterations (``use_front=False``:
    every node, the reference that the tests compare against).

    Each column whose solve succeeds (status OK) is then finished at once, while its rows are in cache
    (:func:`finish_column`: eps_prev += deps, the hardening, plastic_work, the pending plastic heat
    ``pending`` (n_nodes, n_columns) = heat_factor tau deps with ``pending_depth``, ``pending_sum``, ``lag``
    and ``flags``); a column that fails is left as it was.

    The columns are independent (every output is per column); this is the serial solve, after the serial sweep
    (:func:`~shockfriction.friction.subgrid.column.sweep_columns`).  With more than one numba thread and at least
    ``PARALLEL_MIN_COLUMNS`` columns the step runs both in one parallel region instead
    (:func:`advance_and_solve_parallel`), the same bytes.
    """
    nn = theta_unit.shape[0]
    ncol = theta_ad.shape[1]
    _solve_columns(theta_ad, ad_blk, theta_unit, weights, eps_prev, hard, hard_blk, F_N, v_free, v_prev, k, tau_cap,
                   beta_T, f, p, dt, xtol, max_iter, theta_s, tau, v_half, v_local, plastic_rate, q_in, deps, iters,
                   status, depth, heat_factor, pending, pending_depth, plastic_work, lag, rho_c, flags, pending_sum,
                   bool(use_front), np.empty(BRENT_STATE), np.empty(nn), np.empty((4, nn)), np.empty(nn), 0, ncol)


#: columns from which the step's sweep and solve run in parallel (:func:`advance_and_solve_parallel`) when numba has
#: more than one thread
PARALLEL_MIN_COLUMNS = 32


#: columns of one 64-byte cache line of a row of the (n_nodes, n_columns) state: a block of the parallel step starts
#: on a multiple of it, so no two threads write the same line (arbitrary block edges would: docs/theory/threads.md)
LINE_COLUMNS = 8

#: the weight of a swept column (one with heat to carry, j0 <= j < j1) in the parallel step's blocks, against 1 for
#: any other: on the cone shot a cache line of swept columns cost ~120 us more than a line of unswept ones, pressed
#: or not (the solve of a pressed column with a uniform temperature converges at once; docs/theory/threads.md)
SWEPT_WEIGHT = 32


def parallel_blocks(ncol: int) -> int:
    """Blocks of :func:`advance_and_solve_parallel`: one per thread (of equal work, :func:`balanced_blocks`), none
    narrower than a cache line of a row."""
    return max(1, min(get_num_threads(), (ncol + LINE_COLUMNS - 1) // LINE_COLUMNS))


def solve_in_parallel(ncol: int) -> bool:
    """Whether the step runs :func:`advance_and_solve_parallel` (else the serial sweep and
    :func:`solve_thermoelastoplastic`): more than one numba thread and at least :data:`PARALLEL_MIN_COLUMNS`
    columns (the count is read here, in Python: numba's count inside a kernel would stop its caching)."""
    return get_num_threads() > 1 and ncol >= PARALLEL_MIN_COLUMNS


@njit(cache=True, parallel=True, error_model="numpy")
def advance_and_solve_parallel(sweep, theta_unit, weights, eps_prev, hard, hard_blk, F_N, v_free, v_prev, k, tau_cap,
                               beta_T, f, p, dt, xtol, max_iter, theta_s, tau, v_half, v_local, plastic_rate, q_in,
                               deps, iters, status, depth, heat_factor, pending, pending_depth, plastic_work, lag,
                               rho_c, flags, pending_sum, use_front, nblocks):
    """The columns' thermal sweep (``sweep``: the arguments of
    :func:`~shockfriction.friction.subgrid.column.sweep_columns`, a tuple, its spans resolved here as there by
    :func:`~shockfriction.friction.subgrid.column.sweep_span`) and their interface solve
    (:func:`solve_thermoelastoplastic`'s arguments) in one parallel region: each block of consecutive columns is
    swept, then solved, by one thread (``nblocks`` blocks of whole cache lines and equal work,
    :func:`balanced_blocks`: the swept columns are a few of them, early in a shot the first ones).  Every
    column's arithmetic is its own, so the bytes are those of the
    sweep of all columns followed by the serial solve (one region per step instead of a serial sweep and a
    parallel solve: docs/theory/threads.md)."""
    (X, q, unit_lazy, lazy, src, n_src, factor, rho_c_s, limit, weights_s, clipped, deposited, mult, inv_bp, c, idle,
     idle_val, sfx, j0, j1, s0, s1) = sweep
    nn = theta_unit.shape[0]
    ncol = X.shape[1]
    j0, j1, s0, s1 = sweep_span(ncol, j0, j1, s0, s1)
    bounds = np.empty(nblocks + 1, dtype=np.int64)
    balanced_blocks(ncol, j0, j1, bounds)
    for b in prange(nblocks):
        a = bounds[b]
        e = bounds[b + 1]
        sweep_block(X, q, unit_lazy, lazy, src, n_src, factor, rho_c_s, limit, weights_s, clipped, deposited, mult,
                    inv_bp, c, idle, idle_val, sfx, j0, j1, s0, s1, a, e)
        _solve_columns(X, sfx, theta_unit, weights, eps_prev, hard, hard_blk, F_N, v_free, v_prev, k, tau_cap, beta_T,
                       f, p, dt, xtol, max_iter, theta_s, tau, v_half, v_local, plastic_rate, q_in, deps, iters, status,
                       depth, heat_factor, pending, pending_depth, plastic_work, lag, rho_c, flags, pending_sum,
                       use_front, np.empty(BRENT_STATE), np.empty(nn), np.empty((4, nn)), np.empty(nn), a, e)


@njit(cache=True, inline="always")
def _column_weight(j, j0, j1):
    """A column's work in :func:`balanced_blocks`: SWEPT_WEIGHT when it is swept (j0 <= j < j1), else 1."""
    return SWEPT_WEIGHT if j0 <= j < j1 else 1


@njit(cache=True)
def balanced_blocks(ncol, j0, j1, bounds):
    """Bounds of len(bounds) - 1 blocks of whole cache lines (LINE_COLUMNS columns of a row) with equal work
    (:func:`_column_weight`) over ``ncol`` columns of which j0 .. j1 - 1 are swept."""
    nblocks = bounds.shape[0] - 1
    total = 0
    for j in range(ncol):
        total += _column_weight(j, j0, j1)
    bounds[0] = 0
    b = 1
    acc = 0
    for j in range(ncol):
        acc += _column_weight(j, j0, j1)
        if (j + 1) % LINE_COLUMNS == 0 or j == ncol - 1:
            while b < nblocks and acc * nblocks >= b * total:
                bounds[b] = j + 1
                b += 1
    while b <= nblocks:
        bounds[b] = ncol
        b += 1


@njit(cache=True, error_model="numpy", **NO_REFCOUNT)
def _solve_columns(theta_ad, ad_blk, theta_unit, weights, eps_prev, hard, hard_blk, F_N, v_free, v_prev, k, tau_cap,
                   beta_T, f, p, dt, xtol, max_iter, theta_s, tau, v_half, v_local, plastic_rate, q_in, deps, iters,
                   status, depth, heat_factor, pending, pending_depth, plastic_work, lag, rho_c, flags, pending_sum,
                   use_front, st, unit_sfx, scratch, near, j0, j1):
    """:func:`solve_thermoelastoplastic` of the columns j0 .. j1 - 1 with its scratch arrays
    (Brent state ``st``, ``unit_sfx`` of n_nodes,
    ``scratch`` (4, n_nodes) for :func:`plastic_increments`, ``near`` (n_nodes): the column's theta_ad above its
    plastic-front bound, copied once from the strided layout for all of the column's evaluations when the bound
    is SIMD_MIN_NODES or deeper)."""
    T_F = p[I_TF]
    beta, n_hard = p[I_BETA], p[I_N]
    lazy = lazy_hardening(p)
    a0 = theta_unit[0]
    nn = theta_unit.shape[0]
    # unit_sfx: suffix maxima of max(theta_unit, 0), the same for every column
    run = 0.0
    for i in range(nn - 1, -1, -1):
        if theta_unit[i] > run:
            run = theta_unit[i]
        unit_sfx[i] = run
    unit_max = 0.0
    for i in range(nn):
        if theta_unit[i] > unit_max:
            unit_max = theta_unit[i]
    for j in range(j0, j1):
        iters[j] = 0
        status[j] = OK
        row = theta_ad[:, j]
        blk = ad_blk[:, j]
        hrow = hard[j]
        t_ad = row[0]
        if not (math.isfinite(t_ad) and math.isfinite(F_N[j]) and math.isfinite(v_free[j])
                and math.isfinite(v_prev[j]) and math.isfinite(k[j]) and tau_cap[j] >= 0.0):
            status[j] = BAD_INPUT
            continue
        # theta >= t_ad in the bracket and tau(theta) falls with theta: tau <= its value at t_ad
        tau_max = friction_stress(F_N[j], t_ad, tau_cap[j], f, p)
        ad_max = blk[0]
        if use_front and tau_max <= 0.0:  # no friction at any trial temperature: nothing flows, R(lo) = 0
            if ad_max >= T_F:
                status[j] = ABOVE_MELT
                continue
            q_max = math.inf  # not needed: the root is theta_ad(0)
            q_hi = 0.0
            m = 0
        else:
            if ad_max >= T_F:
                status[j] = ABOVE_MELT
                continue
            # q_max = min_i (T_F - theta_ad_i)/theta_unit_i; every 8 nodes, stop once the rest cannot go lower:
            # (T_F - max_{k >= i} theta_ad_k)/unit_sfx[i] bounds all later quotients from below (rounding is monotone)
            q_max = math.inf
            for i in range(nn):
                if i % 8 == 0 and i > 0:
                    if unit_sfx[i] <= 0.0 or (T_F - blk[i // 8]) / unit_sfx[i] >= q_max:
                        break
                if theta_unit[i] > 0.0:
                    qi = (T_F - row[i]) / theta_unit[i]
                    if qi < q_max:
                        q_max = qi
            q_hi = q_max * (1.0 + 1e-12)
            m = plastic_depth(tau_max, F_N[j], q_hi, row, blk, unit_sfx, hrow, hard_blk[j], p, depth[j]) \
                if use_front else nn
        if m >= SIMD_MIN_NODES:  # what plastic_increments' vectorised first pass reads
            for i in range(m):
                near[i] = row[i]
        drow = deps[j]
        old = depth[j] if 0 <= depth[j] <= nn else nn
        for i in range(m, old):
            drow[i] = 0.0
        depth[j] = m
        hi = t_ad + a0 * q_max
        lo = t_ad
        # the last evaluation (point, results; its d_eps are in drow): reused when it is the accepted point.  One
        # call site of the inlined _evaluate (stage 0: the lower end; 1: Brent's points; 2: the accepted point when
        # it is not the last one evaluated): three sites compiled it three times (~2x the kernel's compile time)
        x = lo
        x_last = lo
        stage = 0
        it = 0
        converged = False
        while True:
            r, t, vh, vl, rate, scale = _evaluate(x, row, near, theta_unit, weights, a0, eps_prev[j], hrow, ad_max,
                                                  unit_max, F_N[j], v_free[j], v_prev[j], k[j], tau_cap[j], beta_T,
                                                  f, p, dt, drow, m, q_hi, scratch)
            if stage == 2:
                break
            x_last = x
            if stage == 0:
                if not r < 0.0:  # the root is the lower end
                    break
                brent_start(lo, r, hi, hi - t_ad, xtol, st)  # at the upper end tau [v] = 0
                stage = 1
            else:
                brent_feed(st, r)
                iters[j] = it
            if it < max_iter:
                done, x = brent_next(st)
                if not done:
                    it += 1
                    continue
                converged = True
            if not converged:
                status[j] = NO_CONVERGENCE
            x = st[B] if st[FB] >= 0.0 else st[C]
            if x == x_last:  # _evaluate is deterministic: the same point gives the same state
                break
            stage = 2
        if not math.isfinite(rate):  # accepted point on the melting edge of a sub-surface node
            status[j] = ABOVE_MELT
        theta_s[j] = x
        tau[j] = t
        v_half[j] = vh
        v_local[j] = vl
        plastic_rate[j] = rate
        q_in[j] = beta_T * t * vl
        if status[j] == OK:
            finish_column(j, eps_prev[j], drow, scale, hrow, hard_blk[j], beta, n_hard, lazy, m, t, heat_factor,
                          weights, pending, pending_depth, plastic_work, lag, rho_c, flags, pending_sum)
