"""Spall (tensile failure) of a cell: the damage of the two models and the failed state.

``damage`` D is per cell, failed when D >= 1 (docs/theory/spall-and-tension.md):

* cut-off: D jumps to 1 when P^{n+1} < -p_spall;
* Tuler-Butcher: D^{n+1} = D^n + dt <sigma_1 - sigma_0>^lambda / K, sigma_1 the largest
  principal value of the Cauchy stress S - P 1 (tension positive, q excluded), <x> = max(x, 0);
  failure when the integral of (sigma_1 - sigma_0)^lambda dt reaches K.

A failed cell carries no deviator (its stored shear energy becomes heat), no tension
(P = max(0, A + B e): the cell's volume grows as a void at zero stress) and compression
again once it is re-compacted.
"""

from __future__ import annotations

import math

from numba import njit

from shockfriction.hydro.matprops import SPALL_CUTOFF, SPALL_TULER_BUTCHER


@njit(cache=True)
def max_principal_stress(p, sxx, syy, sxy):
    """sigma_1 = max(eigenvalues of the in-plane S, szz) - P (tension positive)."""
    c = 0.5 * (sxx + syy)
    r = math.sqrt(0.25 * (sxx - syy) ** 2 + sxy * sxy)
    s1 = c + r
    szz = -(sxx + syy)
    if szz > s1:
        s1 = szz
    return s1 - p


@njit(cache=True)
def tuler_butcher_rate(sigma, sigma0, lam, k):
    """dD/dt = <sigma - sigma_0>^lambda / K (Tuler & Butcher 1968, normalised by K)."""
    over = sigma - sigma0
    if over <= 0.0:
        return 0.0
    return over ** lam / k


@njit(cache=True)
def spall_damage(kind, d, p, sxx, syy, sxy, dt, pspall, sigma0, lam, k):
    """Damage D^{n+1} of an intact cell from its state at t^{n+1} (kind: SPALL_*)."""
    if kind == SPALL_CUTOFF:
        return 1.0 if p < -pspall else d
    if kind == SPALL_TULER_BUTCHER:
        return d + dt * tuler_butcher_rate(max_principal_stress(p, sxx, syy, sxy), sigma0, lam, k)
    return d
