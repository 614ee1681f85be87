"""Noh's implosion problem (Noh 1987, J. Comput. Phys. 72, 78) for the ideal gas.

Cold gas (p = 0, density rho0) flows towards the origin at speed u0 in planar
(j = 1), cylindrical (j = 2) or spherical (j = 3) geometry.  A shock leaves the
origin at constant speed D and stagnates the gas.  Mass, momentum and energy
jumps across the shock, with the stagnated gas at rest, give
(docs/theory/exact-solutions.md):

    D = (gamma - 1) u0 / 2
    rho_shocked = rho0 ((gamma + 1)/(gamma - 1))^j,  u = 0,
    e_shocked = u0^2 / 2,  p_shocked = (gamma - 1) rho_shocked u0^2 / 2
    ahead (r > D t): rho = rho0 (1 + u0 t / r)^(j - 1), u = -u0, p = 0.

For gamma = 5/3 the shocked density is 4, 16 and 64 rho0 and D = u0/3.
"""

from __future__ import annotations

import numpy as np


def _check(geometry: int, gamma: float) -> None:
    if geometry not in (1, 2, 3):
        raise ValueError(f"geometry must be 1 (planar), 2 (cylindrical) or 3 (spherical), got {geometry}")
    if gamma <= 1.0:
        raise ValueError(f"gamma must exceed 1, got {gamma}")


def shock_speed(u0: float, gamma: float) -> float:
    """Speed of the reflected shock, D = (gamma - 1) u0 / 2 (any geometry)."""
    _check(1, gamma)
    return 0.5 * (gamma - 1.0) * u0


def shocked_density(rho0: float, gamma: float, geometry: int) -> float:
    """Density of the stagnated gas, rho0 ((gamma + 1)/(gamma - 1))^j."""
    _check(geometry, gamma)
    return rho0 * ((gamma + 1.0) / (gamma - 1.0)) ** geometry


def profile(r: np.ndarray, t: float, geometry: int, gamma: float = 5.0 / 3.0,
            rho0: float = 1.0, u0: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Density, radial velocity, pressure and specific internal energy at radius r, time t."""
    _check(geometry, gamma)
    r = np.abs(np.asarray(r, dtype=float))
    behind = r < shock_speed(u0, gamma) * t
    with np.errstate(divide="ignore"):
        rho = np.where(behind, shocked_density(rho0, gamma, geometry),
                       rho0 * (1.0 + u0 * t / np.where(r > 0, r, np.inf)) ** (geometry - 1))
    u = np.where(behind, 0.0, -u0)
    e = np.where(behind, 0.5 * u0 * u0, 0.0)
    p = (gamma - 1.0) * rho * e
    return rho, u, p, e
