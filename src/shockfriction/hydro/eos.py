"""Equations of state, written P = A(rho) + B(rho) e (linear in the specific energy e).

Mie-Grueneisen on a linear Us = c0 + s up Hugoniot (Gamma rho = Gamma0 rho0),
eta = 1 - rho0/rho, mu = rho/rho0 - 1 (docs/theory/hydrocode.md, sec. EOS)::

    compression (eta > 0): P_H = rho0 c0^2 eta/(1 - s eta)^2,  A = P_H (1 - Gamma0 eta/2)
    tension     (eta <= 0): A = rho0 c0^2 mu                        (linear, default)
                            A = rho0 c0^2 mu [1 + b2 mu + b3 mu^2]  (cubic, kind EOS_MG_CUBIC)
                            b2 = 2 s - 1 - Gamma0/2,  b3 = (s - 1)(3 s - 1 - Gamma0)
      (the cubic is the Taylor expansion of the compression A to O(mu^3): C^2 at mu = 0;
      docs/theory/spall-and-tension.md)
    B = Gamma0 rho0

Ideal gas: A = 0, B = (gamma - 1) rho.

Temperature: Mie-Grueneisen T = T0 + (e - e_s(mu))/c_v, with e_s the energy on the
isentrope through (rho0, e = 0), tabulated once per body (the "cold" energy is
the isentropic compression energy, which carries no temperature rise); ideal gas
T = e/c_v.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from shockfriction.hydro.matprops import (
    EOS_IDEAL_GAS, EOS_MG_CUBIC, N_TABLE, P_C0, P_CV, P_EOS, P_GAMMA, P_GAMMA0, P_MU_HI, P_MU_LO, P_RHO0, P_S, P_T0,
)


@njit(cache=True, inline="always")
def eos_ab_s(rho, kind, rho0, c0, s, g0, gamma):
    """(A, B, dA/drho) of P = A + B e from scalar parameters (kind: 0 Mie-Grueneisen, 1 ideal gas,
    2 Mie-Grueneisen with the cubic tension branch)."""
    return eos_ab_r(rho, 1.0 / rho, rho0 / rho, rho / rho0, kind, rho0, c0, s, g0, gamma)


@njit(cache=True, inline="always")
def eos_ab_r(rho, irho, r0r, rr0, kind, rho0, c0, s, g0, gamma):
    """:func:`eos_ab_s` from 1/rho, rho0/rho and rho/rho0 (the cell update has them as products with
    reciprocals): eta = 1 - rho0/rho, mu = rho/rho0 - 1; one division, 1/(1 - s eta)."""
    if kind == EOS_IDEAL_GAS:
        return 0.0, (gamma - 1.0) * rho, 0.0
    k0 = rho0 * c0 * c0
    eta = 1.0 - r0r
    # both branches, then a select: near rho0 the sign of eta is round-off (an unpredictable branch)
    den = 1.0 - s * eta
    if den <= 1e-6:
        den = 1e-6
    iden = 1.0 / den
    iden2 = iden * iden
    ph = k0 * eta * iden2
    dph = k0 * (1.0 + s * eta) * (iden2 * iden)
    a = ph * (1.0 - 0.5 * g0 * eta)
    da = (dph * (1.0 - 0.5 * g0 * eta) - 0.5 * g0 * ph) * rho0 * (irho * irho)
    mu = rr0 - 1.0
    if kind == EOS_MG_CUBIC:
        a_t, da_dmu = tension_cubic(mu, k0, s, g0)
        da_t = da_dmu * (rr0 * irho)  # / rho0
    else:
        a_t = k0 * mu
        da_t = c0 * c0
    if eta <= 0.0:
        a = a_t
        da = da_t
    return a, g0 * rho0, da


@njit(cache=True)
def tension_cubic(mu, k0, s, g0):
    """(A, dA/dmu) of the cubic tension branch A = k0 mu [1 + b2 mu + b3 mu^2], k0 = rho0 c0^2,
    b2 = 2 s - 1 - Gamma0/2, b3 = (s - 1)(3 s - 1 - Gamma0): the compression branch
    P_H(eta) (1 - Gamma0 eta/2) expanded in mu to third order (eta = mu/(1 + mu))."""
    b2 = 2.0 * s - 1.0 - 0.5 * g0
    b3 = (s - 1.0) * (3.0 * s - 1.0 - g0)
    return k0 * mu * (1.0 + mu * (b2 + b3 * mu)), k0 * (1.0 + mu * (2.0 * b2 + 3.0 * b3 * mu))


@njit(cache=True)
def sound_speed2_s(rho, p, kind, rho0, c0, s, g0, gamma):
    """Bulk (isentropic) sound speed squared, floored.

    c^2 = dP/drho|_s = dA/drho + e dB/drho + P B/rho^2.  Mie-Grueneisen has B = Gamma0 rho0
    constant; the ideal gas has B = (gamma - 1) rho, so e dB/drho = P/rho and c^2 = gamma P/rho.
    """
    a, b, da = eos_ab_s(rho, kind, rho0, c0, s, g0, gamma)
    return sound_speed2_ab(1.0 / rho, p, kind, c0, b, da)


@njit(cache=True, inline="always")
def sound_speed2_ab(irho, p, kind, c0, b, da):
    """:func:`sound_speed2_s` from B and dA/drho of :func:`eos_ab_s` at rho (already known), irho = 1/rho."""
    c2 = da + p * b * (irho * irho)
    if kind == EOS_IDEAL_GAS:
        c2 += p * irho
    floor = 1e-12 if kind == EOS_IDEAL_GAS else 1e-6 * c0 * c0
    return c2 if c2 > floor else floor


@njit(cache=True)
def eos_ab(rho, props, m):
    """(A, B, dA/drho) of P = A + B e for body ``m`` at density ``rho``."""
    return eos_ab_s(rho, props[m, P_EOS], props[m, P_RHO0], props[m, P_C0], props[m, P_S], props[m, P_GAMMA0],
                    props[m, P_GAMMA])


@njit(cache=True)
def sound_speed2(rho, p, props, m):
    """Bulk (isentropic) sound speed squared for body m."""
    return sound_speed2_s(rho, p, props[m, P_EOS], props[m, P_RHO0], props[m, P_C0], props[m, P_S],
                          props[m, P_GAMMA0], props[m, P_GAMMA])


@njit(cache=True)
def temperature(rho, e, props, table, m):
    """T = T0 + (e - e_s(mu))/c_v (Mie-Grueneisen) or e/c_v (ideal gas)."""
    cv = props[m, P_CV]
    if props[m, P_EOS] == EOS_IDEAL_GAS:
        return e / cv
    mu = rho / props[m, P_RHO0] - 1.0
    lo = props[m, P_MU_LO]
    hi = props[m, P_MU_HI]
    f = (mu - lo) / (hi - lo) * (N_TABLE - 1)
    if f <= 0.0:
        es = table[m, 0]
    elif f >= N_TABLE - 1:
        es = table[m, N_TABLE - 1]
    else:
        k = int(f)
        w = f - k
        es = (1.0 - w) * table[m, k] + w * table[m, k + 1]
    return props[m, P_T0] + (e - es) / cv


def isentrope_table(props_row: np.ndarray) -> tuple[float, float, np.ndarray]:
    """(mu_lo, mu_hi, e_s) for a Mie-Grueneisen row: de/dmu = (A + B e)/(rho0 (1+mu)^2), e(0) = 0.

    Integrated by RK4 from mu = 0 outwards on a grid 8x finer than the table (:func:`_isentrope`).
    """
    s = props_row[P_S]
    eta_max = 0.9 / s if s > 1.0 else 0.9
    mu_top = min(1.5, eta_max / (1.0 - eta_max))
    h = (mu_top + 0.4) / (N_TABLE - 1)
    mu_lo = -round(0.4 / h) * h  # mu = 0 is a grid point
    mu_hi = mu_lo + (N_TABLE - 1) * h
    mu = mu_lo + h * np.arange(N_TABLE)
    return mu_lo, mu_hi, _isentrope(mu, int(np.argmin(np.abs(mu))), props_row[P_EOS], props_row[P_RHO0],
                                    props_row[P_C0], props_row[P_S], props_row[P_GAMMA0], props_row[P_GAMMA])


@njit(cache=True)
def _isentrope_rate(m, e, kind, rho0, c0, s, g0, gamma):
    """de/dmu = (A + B e)/(rho0 (1 + mu)^2) on the isentrope."""
    a, b, _ = eos_ab_s(rho0 * (1.0 + m), kind, rho0, c0, s, g0, gamma)
    return (a + b * e) / (rho0 * (1.0 + m) ** 2)


@njit(cache=True)
def _isentrope_leg(m, e, target, kind, rho0, c0, s, g0, gamma):
    """e at mu = target from e at mu = m: RK4 in 8 sub-steps."""
    h = (target - m) / 8
    for _ in range(8):
        k1 = _isentrope_rate(m, e, kind, rho0, c0, s, g0, gamma)
        k2 = _isentrope_rate(m + h / 2, e + h / 2 * k1, kind, rho0, c0, s, g0, gamma)
        k3 = _isentrope_rate(m + h / 2, e + h / 2 * k2, kind, rho0, c0, s, g0, gamma)
        k4 = _isentrope_rate(m + h, e + h * k3, kind, rho0, c0, s, g0, gamma)
        e += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        m += h
    return e


@njit(cache=True)
def _isentrope(mu, i0, kind, rho0, c0, s, g0, gamma):
    """e_s at the grid points mu, integrated from e = 0 at mu = 0 to mu[i0] (the grid point at 0), then outwards
    leg by leg in both directions (one RK4 leg per table interval)."""
    n = mu.size
    out = np.zeros(n)
    out[i0] = _isentrope_leg(0.0, 0.0, mu[i0], kind, rho0, c0, s, g0, gamma)
    for k in range(i0, n - 1):
        out[k + 1] = _isentrope_leg(mu[k], out[k], mu[k + 1], kind, rho0, c0, s, g0, gamma)
    for k in range(i0, 0, -1):
        out[k - 1] = _isentrope_leg(mu[k], out[k], mu[k - 1], kind, rho0, c0, s, g0, gamma)
    return out
