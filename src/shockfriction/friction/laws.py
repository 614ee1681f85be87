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

The thesis evaluates mu with the *free* slip velocity (eq. 3.79); callers pass
whichever slip speed they use.
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

I_MU0, I_MU_INF, I_GAMMA, I_MU_T = range(4)
SQRT3 = math.sqrt(3.0)


def law_parameters(mu0: float = 0.0, mu_inf: float | None = None, gamma: float = 0.0,
                   mu_T: float | None = None) -> np.ndarray:
    """Parameter array ``[mu0, mu_inf, gamma, mu_T]`` (mu_inf defaults to mu0; mu_T None -> NaN = 'same as mu')."""
    return np.array([mu0, mu0 if mu_inf is None else mu_inf, gamma,
                     math.nan if mu_T is None else mu_T], dtype=np.float64)


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


def traction_limit_array(law: int, p: np.ndarray, normal_stress, slip_speed, y1=np.inf, y2=np.inf) -> np.ndarray:
    """Vectorised convenience wrapper of :func:`traction_limit` over numpy arrays (broadcast)."""
    fn, s, a, b = np.broadcast_arrays(np.asarray(normal_stress, float), np.asarray(slip_speed, float),
                                      np.asarray(y1, float), np.asarray(y2, float))
    out = np.empty(fn.shape)
    flat = out.reshape(-1)
    for i, (f_, s_, a_, b_) in enumerate(zip(fn.ravel(), s.ravel(), a.ravel(), b.ravel())):
        flat[i] = traction_limit(law, p, f_, s_, a_, b_)
    return out
