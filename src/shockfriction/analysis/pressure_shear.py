"""Exact 1D elastic pressure-shear plate impact with Coulomb friction (materials-data.md section 4).

A flyer (1) hits a target (2) at speed V inclined by theta to the impact normal:
V_n = V cos(theta) (normal), V_t = V sin(theta) (transverse).  Both plates are
linear elastic with impedances Z = rho c_L (longitudinal) and Z_s = rho c_S (shear).
Until reflections return to the interface, plane waves give

    sigma_n = V_n/(1/Z_1 + 1/Z_2)                 (normal stress, compression > 0)
    tau_s   = V_t/(1/Z_1s + 1/Z_2s)               (shear that welds the plates)
    tau     = min(tau_s, mu sigma_n)              (Coulomb)
    [V]     = V_t - tau (1/Z_1s + 1/Z_2s)         (slip rate, 0 when sticking)
    u_t     = 2 tau/Z_2s,  u_n = 2 sigma_n/Z_2    (target rear free-surface velocities
                                                   once the waves arrive there)

and the target side of the interface moves with sigma_n/Z_2 (normal) and tau/Z_2s
(transverse).

With the velocity-dependent law mu(|[V]|) = mu_inf + (mu0 - mu_inf) exp(-gamma |[V]|)
(eq. 2.90) the slip rate is the root of

    [V] = V_t - mu([V]) sigma_n (1/Z_1s + 1/Z_2s)        (:func:`pressure_shear_velocity_dependent`)

unique when the plates cannot stick (mu0 sigma_n < tau_s): f(s) = s - V_t + mu(s) sigma_n
(1/Z_1s + 1/Z_2s) is convex (mu is), f(0) < 0 < f(V_t).  Steady sliding there is stable when
|dmu/d[V]| sigma_n (1/Z_1s + 1/Z_2s) < 1 at the root (radiation damping beats the weakening).
When mu0 sigma_n >= tau_s the welded state is a solution; with a weakening steep at low slip
f may still have two roots in (0, V_t) (welded and sliding states coexist and the history
selects one); the welded one is returned, the only one when f > 0 on (0, V_t).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from scipy.optimize import brentq


@dataclass(frozen=True)
class PressureShearSolution:
    sigma_n: float          #: interface normal stress (Pa, compression positive)
    tau_stick: float        #: shear stress needed to weld the plates (Pa)
    tau: float              #: interface shear stress (Pa)
    sticking: bool          #: True when tau_stick <= mu sigma_n
    slip_rate: float        #: flyer minus target transverse velocity at the interface (m/s)
    target_normal_velocity: float      #: target particle velocity behind the wave (m/s)
    target_transverse_velocity: float  #: target transverse particle velocity (m/s)
    rear_normal_fs_velocity: float     #: target rear free-surface normal velocity (m/s)
    rear_transverse_fs_velocity: float  #: target rear free-surface transverse velocity (m/s)


def elastic_wave_speeds(rho: float, bulk_modulus: float, shear_modulus: float) -> tuple[float, float]:
    """(c_L, c_S) = (sqrt((K + 4G/3)/rho), sqrt(G/rho))."""
    return math.sqrt((bulk_modulus + 4.0 * shear_modulus / 3.0) / rho), math.sqrt(shear_modulus / rho)


def pressure_shear(speed: float, angle_rad: float, mu: float,
                   rho1: float, cl1: float, cs1: float,
                   rho2: float, cl2: float, cs2: float) -> PressureShearSolution:
    """Exact elastic pressure-shear solution for an impact at ``speed`` inclined by ``angle_rad``."""
    vn = speed * math.cos(angle_rad)
    vt = speed * math.sin(angle_rad)
    z1, z2 = rho1 * cl1, rho2 * cl2
    z1s, z2s = rho1 * cs1, rho2 * cs2
    compliance_s = 1.0 / z1s + 1.0 / z2s
    sigma_n = vn / (1.0 / z1 + 1.0 / z2)
    tau_s = vt / compliance_s
    sticking = tau_s <= mu * sigma_n
    tau = tau_s if sticking else mu * sigma_n
    slip = vt - tau * compliance_s
    return PressureShearSolution(
        sigma_n=sigma_n, tau_stick=tau_s, tau=tau, sticking=sticking, slip_rate=slip,
        target_normal_velocity=sigma_n / z2, target_transverse_velocity=tau / z2s,
        rear_normal_fs_velocity=2.0 * sigma_n / z2, rear_transverse_fs_velocity=2.0 * tau / z2s,
    )


def pressure_shear_velocity_dependent(speed: float, angle_rad: float, mu0: float, mu_inf: float, gamma: float,
                                      rho1: float, cl1: float, cs1: float,
                                      rho2: float, cl2: float, cs2: float) -> PressureShearSolution:
    """Exact elastic pressure-shear solution with the modified Coulomb law (eq. 2.90).

    Sticks when tau_stick <= mu0 sigma_n; otherwise the slip rate is the root in (0, V_t) of
    s = V_t - mu(s) sigma_n (1/Z_1s + 1/Z_2s), unique (module docstring).
    """
    base = pressure_shear(speed, angle_rad, mu0, rho1, cl1, cs1, rho2, cl2, cs2)
    if base.sticking:
        return base
    compliance_s = 1.0 / (rho1 * cs1) + 1.0 / (rho2 * cs2)
    vt = speed * math.sin(angle_rad)

    def mu(s):
        return mu_inf + (mu0 - mu_inf) * math.exp(-gamma * s)

    slip = brentq(lambda s: s - vt + mu(s) * base.sigma_n * compliance_s, 0.0, vt, xtol=1e-13, rtol=1e-15)
    tau = mu(slip) * base.sigma_n
    return replace(base, tau=tau, slip_rate=slip, target_transverse_velocity=tau / (rho2 * cs2),
                   rear_transverse_fs_velocity=2.0 * tau / (rho2 * cs2))
