"""Linear stability of the quasi-static plastic boundary layer (thesis ch. 6).

A locally homogeneous plastic base state (shear stress tau0 = Y/sqrt(3), plastic
strain eps0, temperature theta0, contact pressure P = |F_N|) is stable against
normal-mode perturbations exp(i(k z - omega t)) if and only if (eq. 6.56)::

    Y_eps > -Y_theta sqrt(3) tau0 alpha/kappa,        alpha/kappa = 1/(rho c)

with the SCG moduli (eqs. 6.63-6.68)::

    dG/dtheta = -G0 h exp(-xi theta/(T_F - theta)) - xi T_F G(theta)/(T_F - theta)^2     (6.65)
    Y_eps     = n beta Y0 (1 + beta eps0)^(n-1) G/G0      (0 at saturation, 6.61)   (6.63)
    Y_theta   = min(Ymax, Y0 (1 + beta eps0)^n) dG/dtheta / G0                      (6.64)

For a non-saturated base state the condition is a largest stable plastic strain
(eq. 6.72)::

    eps_max = ((n beta kappa/(alpha Y0)) (G0/(-dG/dtheta)))^(1/(n+1)) / beta - 1/beta

The growth rate of a mode of wavenumber k is (eq. 6.48, dimensional form)::

    s = Im(omega) = -alpha k^2 Y_eps / (Y_eps + sqrt(3) tau0 Y_theta alpha/kappa)

Everything here is numpy (vectorised over temperature and pressure); SI units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from shockfriction.materials.strength import T_REF

SQRT3 = float(np.sqrt(3.0))


@dataclass(frozen=True)
class ScgConstants:
    """The SCG constants, the volumetric heat capacity rho c and the conductivity kappa (SI)."""

    G0: float
    Y0: float
    Ymax: float
    beta: float
    n: float
    g: float
    h: float
    xi: float
    T_melt: float
    rho_c: float
    kappa: float

    @classmethod
    def of(cls, material, xi: float | None = None) -> "ScgConstants":
        """From a library :class:`~shockfriction.materials.library.Material`; ``xi`` overrides
        the Ball & Winter melt factor (xi = 0 is Steinberg's original form)."""
        m = material
        return cls(m.G0, m.Y0, m.Ymax, m.scg_beta, m.scg_n, m.scg_g, m.scg_h,
                   m.scg_xi if xi is None else float(xi), m.melting_temperature,
                   m.rho0 * m.heat_capacity, m.conductivity)

    @property
    def saturation_strain(self) -> float:
        """eps_sat with Y0 (1 + beta eps_sat)^n = Ymax: beyond it Y_eps = 0 (eq. 6.61)."""
        return ((self.Ymax / self.Y0) ** (1.0 / self.n) - 1.0) / self.beta


@dataclass(frozen=True)
class ScgModuli:
    """Base-state yield stress and its derivatives (arrays broadcast from the inputs)."""

    Y: np.ndarray          #: Y(eps0, theta0, P) = sqrt(3) tau0 (eq. 6.69)
    Y_eps: np.ndarray      #: hardening modulus dY/d eps (eq. 6.63)
    Y_theta: np.ndarray    #: thermal softening modulus dY/d theta (eq. 6.64)
    dG_dtheta: np.ndarray  #: dG/d theta (eq. 6.65)
    G: np.ndarray          #: G(theta0, P)


def shear_modulus_and_slope(c: ScgConstants, theta, pressure):
    """G(theta, P) and dG/dtheta (eq. 6.58 and 6.65), nan where theta >= T_F or G <= 0."""
    theta = np.asarray(theta, float)
    pressure = np.asarray(pressure, float)
    valid = theta < c.T_melt
    gap = np.where(valid, c.T_melt - theta, 1.0)
    melt = np.exp(-c.xi * theta / gap)
    G = c.G0 * (1.0 + c.g * pressure - c.h * (theta - T_REF)) * melt
    dG = -c.G0 * c.h * melt - c.xi * c.T_melt * G / gap**2
    valid = valid & (G > 0.0)
    return np.where(valid, G, np.nan), np.where(valid, dG, np.nan)


def scg_moduli(c: ScgConstants, eps0, theta, pressure) -> ScgModuli:
    """Y, Y_eps, Y_theta of the SCG law at the base state (eps0, theta, P = |F_N|)."""
    eps0 = np.asarray(eps0, float)
    G, dG = shear_modulus_and_slope(c, theta, pressure)
    base = 1.0 + c.beta * eps0
    hard = c.Y0 * base**c.n
    saturated = hard >= c.Ymax
    flow = np.minimum(hard, c.Ymax)
    Y = flow * G / c.G0
    Y_eps = np.where(saturated, 0.0, c.n * c.beta * c.Y0 * base ** (c.n - 1.0) * G / c.G0)
    Y_theta = flow * dG / c.G0
    return ScgModuli(Y, Y_eps, Y_theta, dG, G)


def stability_margin(c: ScgConstants, eps0, theta, pressure):
    """Y_eps + Y_theta sqrt(3) tau0 alpha/kappa (eq. 6.56 as 'margin > 0'), with sqrt(3) tau0 = Y."""
    m = scg_moduli(c, eps0, theta, pressure)
    return m.Y_eps + m.Y_theta * m.Y / c.rho_c


def growth_rate(c: ScgConstants, eps0, theta, pressure, wavenumber):
    """Growth rate Im(omega) (1/s) of the mode of wavenumber k (eq. 6.48, dimensional).

    0 at saturation (marginal); positive means the perturbation grows.
    """
    m = scg_moduli(c, eps0, theta, pressure)
    alpha = c.kappa / c.rho_c
    k2 = np.asarray(wavenumber, float) ** 2
    return -alpha * k2 * m.Y_eps / (m.Y_eps + m.Y * m.Y_theta / c.rho_c)


def strain_limit_unclipped(c: ScgConstants, theta, pressure):
    """The right-hand side of eq. 6.72 as printed (may be negative near melting; nan at/after melt).

    Evaluated in logarithms: near T_F the melt factor exp(-xi theta/(T_F - theta)) underflows,
    and -dG/dtheta = exp(-xi theta/(T_F - theta)) G0 (h + xi T_F (1 + g P - h (theta - 300))/(T_F - theta)^2).
    """
    theta = np.asarray(theta, float)
    pressure = np.asarray(pressure, float)
    linear = 1.0 + c.g * pressure - c.h * (theta - T_REF)
    valid = (theta < c.T_melt) & (linear > 0.0)
    gap = np.where(valid, c.T_melt - theta, 1.0)
    with np.errstate(divide="ignore"):
        log_slope = -c.xi * theta / gap + np.log(c.G0 * (c.h + c.xi * c.T_melt * linear / gap**2))
        # alpha/kappa = 1/(rho c): n beta kappa/(alpha Y0) = n beta rho c / Y0
        log_ratio = np.log(c.n * c.beta * c.rho_c / c.Y0) + np.log(c.G0) - log_slope
    with np.errstate(over="ignore"):
        limit = np.exp(log_ratio / (c.n + 1.0)) / c.beta - 1.0 / c.beta
    return np.where(valid, limit, np.nan)


def max_stable_strain(c: ScgConstants, theta, pressure):
    """Largest base-state plastic strain for which the layer is (strictly) stable.

    eq. 6.72, limited by the saturation strain (beyond it Y_eps = 0: marginal, eq. 6.61)
    and by 0 (a negative bound means no plastic state is stable); nan at or above T_F
    or where G <= 0 (no strength).
    """
    limit = strain_limit_unclipped(c, theta, pressure)
    return np.where(np.isnan(limit), np.nan, np.clip(limit, 0.0, c.saturation_strain))


def inertial_growth_rate(c: ScgConstants, eps0: float, theta: float, pressure: float, wavenumber: float,
                         density: float, plastic_rate: float = 0.0) -> complex:
    """Most unstable root s of the linearised layer WITH shear inertia (not analysed in the thesis).

    Normal modes exp(i k z + s t) of rho s dv = ik dtau, ik dv = sqrt(3) s deps, (6.28) and
    (6.29) give the cubic [DERIVED, docs/theory/analyses.md]::

        3 rho (rho c) s^3 + 3 rho (kappa k^2 - epsdot0 Y_theta) s^2
            + (rho c Y_eps + sqrt(3) tau0 Y_theta) k^2 s + kappa Y_eps k^4 = 0

    As rho -> 0 one root tends to eq. 6.48; the other two are thermoplastic shear waves
    s ~ +-i k sqrt(Y_eps/(3 rho)) whose real part does not vanish with rho: by Routh-Hurwitz
    they grow for k^2 > epsdot0 (rho c) margin/(kappa Y) (all k if epsdot0 = 0), at most at
    :func:`inertial_growth_limit`.  Returns the root of largest real part.
    """
    m = scg_moduli(c, eps0, theta, pressure)
    Y_eps, Y_theta, Y = float(m.Y_eps), float(m.Y_theta), float(m.Y)
    k2 = float(wavenumber) ** 2
    coefficients = [3.0 * density * c.rho_c,
                    3.0 * density * (c.kappa * k2 - plastic_rate * Y_theta),
                    (c.rho_c * Y_eps + Y * Y_theta) * k2,
                    c.kappa * Y_eps * k2 * k2]
    roots = np.roots(coefficients)
    return complex(roots[np.argmax(roots.real)])


def inertial_critical_wavenumber(c: ScgConstants, eps0, theta, pressure, plastic_rate: float):
    """k_c = sqrt(epsdot0 (rho c) margin/(kappa Y)): with inertia, modes with k > k_c grow (Routh-Hurwitz)."""
    m = scg_moduli(c, eps0, theta, pressure)
    margin = m.Y_eps + m.Y * m.Y_theta / c.rho_c
    return np.sqrt(np.maximum(plastic_rate * c.rho_c * margin / (c.kappa * m.Y), 0.0))


def inertial_growth_limit(c: ScgConstants, eps0, theta, pressure, density: float):
    """Short-wave limit of the inertial growth rate: -Y Y_theta/(6 rho kappa) (> 0 whenever Y_theta < 0)."""
    m = scg_moduli(c, eps0, theta, pressure)
    return -m.Y * m.Y_theta / (6.0 * density * c.kappa)


def stable_strain_limit(material, theta, pressure, xi: float | None = None):
    """:func:`max_stable_strain` for a library material: theta (K) and |F_N| (Pa) broadcast."""
    return max_stable_strain(ScgConstants.of(material, xi), theta, pressure)
