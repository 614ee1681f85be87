"""Pluggable friction laws: the largest admissible shear traction at an interface point.

Every law is a law id plus a parameter array ``[mu0, mu_inf, gamma, mu_T]``, so
that numba kernels evaluate it per node without Python objects.  The traction
limit tau_max >= 0 (Pa) depends on the normal stress |F_N| (compression
positive; ARCHITECTURE.md), the slip speed |[V]| and the yield stresses Y1, Y2
of the two materials at the interface point:

====================  ===========================================================
law                   tau_max
====================  ===========================================================
FRICTIONLESS (0)      0
COULOMB (1)           mu0 |F_N|                                      (eq. 2.87, 3.77)
MODIFIED_COULOMB (2)  mu(|[V]|) |F_N|,
                      mu = mu_inf + (mu0 - mu_inf) exp(-gamma |[V]|)  (eq. 2.88-2.90, 3.78-3.79)
TRESCA (3)            mu_T min(Y1, Y2)/sqrt(3)                       (eq. 2.91)
COULOMB_TRESCA (4)    min(mu |F_N|, mu_T min(Y1, Y2)/sqrt(3))        (eq. 2.92 without "/S",
                      mu as in law 2; mu_T = NaN means mu_T = mu       eq. 2.164-2.166, 3.80-3.81)
====================  ===========================================================

Which slip speed (docs/theory/slide-lines.md, section 4): the thesis evaluates mu with
the *free* slip s* of the step (eq. 3.79), which exceeds the slip after the step's own
friction correction by tau S dt (1/m_g + 1/m_G), a bias that does not vanish under
refinement at fixed CFL (``evaluation = "free"``).  The default ``"corrected"`` evaluates
the law at the corrected slip through a first-order relaxation over ``n`` steps,

    s_law^n = (s_law^{n-1} + |s^{n+1/2}|/n)/(1 + 1/n),   s^{n+1/2} = s* - tau S dt (1/m_g + 1/m_G) sign(s*),

(backward Euler of t_r ds_law/dt = |s| - s_law, t_r = n dt -> 0 under refinement), a
monotone scalar equation per node solved by :func:`corrected_traction`.  Without the
relaxation (n = 0) the velocity-weakening law feeds the near-cutoff lattice mode of the
interface nodes, whose discrete radiation impedance vanishes, and the node flutters.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

FRICTIONLESS = 0
COULOMB = 1
MODIFIED_COULOMB = 2
TRESCA = 3
COULOMB_TRESCA = 4

LAW_IDS: dict[str, int] = {
    "frictionless": FRICTIONLESS,
    "coulomb": COULOMB,
    "modified_coulomb": MODIFIED_COULOMB,
    "tresca": TRESCA,
    "coulomb_tresca": COULOMB_TRESCA,
}

I_MU0, I_MU_INF, I_GAMMA, I_MU_T, I_THETA, I_RELAX = range(6)
SQRT3 = math.sqrt(3.0)

#: theta of the slip a velocity-dependent law sees, s* - theta tau S dt (1/m_g + 1/m_G)
EVALUATIONS: dict[str, float] = {"corrected": 1.0, "free": 0.0}
#: default relaxation of the corrected evaluation, in time steps (t_r = n dt)
RELAXATION_STEPS = 5.0


def law_parameters(mu0: float = 0.0, mu_inf: float | None = None, gamma: float = 0.0,
                   mu_T: float | None = None, evaluation: str = "corrected",
                   relaxation_steps: float = RELAXATION_STEPS) -> np.ndarray:
    """Parameter array ``[mu0, mu_inf, gamma, mu_T, theta, 1/n]``.

    mu_inf defaults to mu0; mu_T None -> NaN = 'same as mu'; ``evaluation`` (a key of
    :data:`EVALUATIONS`) gives theta; ``relaxation_steps`` n >= 0 the relaxation of the
    corrected evaluation (stored as the per-step rate 1/n, 0 for n = 0).  A 4-entry
    array means "free" (eq. 3.79).
    """
    rate = 1.0 / relaxation_steps if relaxation_steps > 0.0 else 0.0
    return np.array([mu0, mu0 if mu_inf is None else mu_inf, gamma,
                     math.nan if mu_T is None else mu_T, EVALUATIONS[evaluation], rate], dtype=np.float64)


@njit(cache=True)
def velocity_dependent_mu(slip_speed, p):
    """mu(|[V]|) = mu_inf + (mu0 - mu_inf) exp(-gamma |[V]|)  (eq. 2.90 / 3.79)."""
    return p[I_MU_INF] + (p[I_MU0] - p[I_MU_INF]) * math.exp(-p[I_GAMMA] * abs(slip_speed))


@njit(cache=True)
def traction_limit(law, p, normal_stress, slip_speed, y1, y2):
    """Largest admissible shear traction tau_max >= 0 (Pa) for the law ``law`` and parameters ``p``.

    ``normal_stress`` is used as |F_N|; ``y1``, ``y2`` are the yield stresses of
    the two sides (only the Tresca laws use them).
    """
    fn = abs(normal_stress)
    if law == FRICTIONLESS:
        return 0.0
    if law == COULOMB:
        return p[I_MU0] * fn
    mu = velocity_dependent_mu(slip_speed, p)
    if law == MODIFIED_COULOMB:
        return mu * fn
    mu_t = mu if math.isnan(p[I_MU_T]) else p[I_MU_T]
    cap = mu_t * min(y1, y2) / SQRT3
    if cap < 0.0:
        cap = 0.0
    if law == TRESCA:
        return cap
    # COULOMB_TRESCA
    return min(mu * fn, cap)


@njit(cache=True)
def slip_weight(law, p):
    """theta of the slip evaluation, 0 when the traction limit does not depend on the slip speed."""
    if p.size <= I_THETA or law == FRICTIONLESS or law == COULOMB:
        return 0.0
    if law == TRESCA and not math.isnan(p[I_MU_T]):
        return 0.0
    if p[I_GAMMA] == 0.0 or p[I_MU0] == p[I_MU_INF]:
        return 0.0
    return p[I_THETA]


@njit(cache=True)
def relaxation_rate(p):
    """1/n, the per-step rate of the relaxed slip of the corrected evaluation (0: none)."""
    return p[I_RELAX] if p.size > I_RELAX else 0.0


@njit(cache=True)
def corrected_traction(law, p, normal_stress, slip_law, slip_free, compliance, theta, y1, y2):
    """Traction limit evaluated at a slip that includes this step's friction correction.

    Solves  tau = tau_max(|F_N|, s_law - theta tau c, Y1, Y2)  for tau in [0, tau_stick],
    tau_stick = |s*|/c, where s* is the free slip, c = S dt (1/m_g + 1/m_G) (m/s per Pa)
    the slip change per unit traction of the step, and s_law - theta tau c >= 0 the slip
    speed the law sees (s_law = |s*|: theta = 1 the corrected slip |s*| - tau c, theta = 0
    the free slip of eq. 3.79).  With g(tau) = tau - tau_max(s_law - theta tau c):
    g(0) <= 0; if g(tau_stick) <= 0 the pair sticks and tau_max(s_law - theta tau_stick c)
    (>= tau_stick) is returned; otherwise the root in (0, tau_stick) is bracketed and found
    by Illinois false position (g is monotone when |d tau_max/ds| theta c < 1, the usual
    case; otherwise one root of the bracket is returned).
    """
    s_free = abs(slip_free)
    if theta == 0.0 or compliance <= 0.0:
        return traction_limit(law, p, normal_stress, slip_law, y1, y2)
    tau_stick = s_free / compliance
    t_stick = traction_limit(law, p, normal_stress, max(slip_law - theta * s_free, 0.0), y1, y2)
    if t_stick >= tau_stick:
        return t_stick
    lo, g_lo = 0.0, -traction_limit(law, p, normal_stress, slip_law, y1, y2)
    if g_lo == 0.0:
        return 0.0
    hi, g_hi = tau_stick, tau_stick - t_stick
    tol = 1e-14 * tau_stick
    side = 0
    tau = hi
    for _ in range(200):
        tau = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
        if not (lo < tau < hi):
            tau = 0.5 * (lo + hi)
        g = tau - traction_limit(law, p, normal_stress, max(slip_law - theta * tau * compliance, 0.0), y1, y2)
        if g == 0.0:
            return tau
        if g < 0.0:
            lo, g_lo = tau, g
            if side == -1:
                g_hi *= 0.5
            side = -1
        else:
            hi, g_hi = tau, g
            if side == 1:
                g_lo *= 0.5
            side = 1
        if hi - lo <= tol:
            break
    return tau


def traction_limit_array(law: int, p: np.ndarray, normal_stress, slip_speed, y1=np.inf, y2=np.inf) -> np.ndarray:
    """Vectorised convenience wrapper of :func:`traction_limit` over numpy arrays (broadcast)."""
    fn, s, a, b = np.broadcast_arrays(np.asarray(normal_stress, float), np.asarray(slip_speed, float),
                                      np.asarray(y1, float), np.asarray(y2, float))
    out = np.empty(fn.shape)
    flat = out.reshape(-1)
    for i, (f_, s_, a_, b_) in enumerate(zip(fn.ravel(), s.ravel(), a.ravel(), b.ravel())):
        flat[i] = traction_limit(law, p, f_, s_, a_, b_)
    return out
