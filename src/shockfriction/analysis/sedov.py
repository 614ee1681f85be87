"""Sedov-Taylor point-blast similarity solution (planar, cylindrical, spherical).

Energy E released at t = 0 at the centre of cold ideal gas (p = 0, density rho0).
The shock radius is R(t) = xi0 (E t^2 / rho0)^(1/(j+2)), j = 1, 2, 3.  With
lambda = r/R and the shock speed Rdot = 2 R / ((j+2) t), the flow behind the shock is

    u = Rdot f(lambda),  rho = rho0 g(lambda),  p = rho0 Rdot^2 h(lambda),

and the Euler equations reduce to three ODEs (w = f - lambda, derived in
docs/theory/exact-solutions.md):

    w g' + g (f' + (j-1) f/lambda) = 0
    w f' + h'/g = (j/2) f
    w h' - gamma (h/g) w g' = j h

integrated inward from the strong-shock state f = h = 2/(gamma+1),
g = (gamma+1)/(gamma-1) at lambda = 1.  The energy integral

    E = alpha rho0 R^(j+2) / t^2,   alpha = sigma_j (2/(j+2))^2 int_0^1 (g f^2/2 + h/(gamma-1)) lambda^(j-1) dlambda

with sigma_j = 2, 2 pi, 4 pi gives xi0 = alpha^(-1/(j+2)).  E is the whole blast
energy: per unit area of the symmetric slab (both sides of x = 0) for j = 1, per unit
length for j = 2.  A half-space computation holding energy E_half is the blast with
E = 2 E_half (j = 1).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.integrate import solve_ivp

GEOMETRY_FACTOR = {1: 2.0, 2: 2.0 * np.pi, 3: 4.0 * np.pi}
#: inward integration stops here: below it the inward ODE is unstable (f/lambda leaves its
#: limit 1/gamma, a growing mode); the centre is then the asymptotic core f = lambda f_min/lambda_min,
#: h = h_min, g = g_min (lambda/lambda_min)^(j/(gamma-1)), whose energy is added analytically.
LAMBDA_MIN = 1e-3


def _rhs(s: float, y: np.ndarray, j: int, gamma: float) -> list[float]:
    """The similarity ODEs in s = ln(lambda), plus the energy integrand (4th component)."""
    lam = np.exp(s)
    f, g, h, _ = y
    w = f - lam
    div = (j - 1) * f / lam
    fp = (0.5 * j * f * w * g - j * h + gamma * h * div) / (w * w * g - gamma * h)
    gp = -g * (fp + div) / w
    hp = (j * h - gamma * h * (fp + div)) / w
    energy_density = (0.5 * g * f * f + h / (gamma - 1.0)) * lam ** (j - 1)
    return [lam * fp, lam * gp, lam * hp, -lam * energy_density]


@dataclass(frozen=True)
class SedovSolution:
    """Similarity functions of one (geometry, gamma) pair and its energy constant."""

    geometry: int
    gamma: float
    alpha: float
    xi0: float
    lam: np.ndarray  # increasing, from LAMBDA_MIN to 1
    f: np.ndarray
    g: np.ndarray
    h: np.ndarray

    def shock_radius(self, energy: float, t: float, rho0: float = 1.0) -> float:
        """R(t) = xi0 (E t^2 / rho0)^(1/(j+2))."""
        return self.xi0 * (energy * t * t / rho0) ** (1.0 / (self.geometry + 2))

    def profile(self, r: np.ndarray, t: float, energy: float, rho0: float = 1.0
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Density, velocity and pressure at radius r (cold gas at rest ahead of the shock)."""
        radius = self.shock_radius(energy, t, rho0)
        speed = 2.0 * radius / ((self.geometry + 2) * t)
        lam = np.abs(np.asarray(r, dtype=float)) / radius
        inside = lam < 1.0
        x = np.clip(lam, self.lam[0], 1.0)
        core = lam < self.lam[0]
        ratio = np.where(core, lam / self.lam[0], 1.0)
        g = np.interp(x, self.lam, self.g) * ratio ** (self.geometry / (self.gamma - 1.0))
        f = np.interp(x, self.lam, self.f) * ratio
        rho = np.where(inside, rho0 * g, rho0)
        u = np.where(inside, speed * f, 0.0)
        p = np.where(inside, rho0 * speed * speed * np.interp(x, self.lam, self.h), 0.0)
        return rho, u, p


@lru_cache(maxsize=32)
def solve(geometry: int, gamma: float, rtol: float = 1e-12) -> SedovSolution:
    """Integrate the similarity ODEs and the energy integral (cached per geometry, gamma)."""
    if geometry not in GEOMETRY_FACTOR:
        raise ValueError(f"geometry must be 1, 2 or 3, got {geometry}")
    if gamma <= 1.0:
        raise ValueError(f"gamma must exceed 1, got {gamma}")
    y0 = [2.0 / (gamma + 1.0), (gamma + 1.0) / (gamma - 1.0), 2.0 / (gamma + 1.0), 0.0]
    s_grid = np.linspace(0.0, np.log(LAMBDA_MIN), 4001)
    sol = solve_ivp(_rhs, (0.0, np.log(LAMBDA_MIN)), y0, args=(geometry, gamma), method="DOP853",
                    t_eval=s_grid, rtol=rtol, atol=1e-14)
    if not sol.success:
        raise RuntimeError(f"Sedov ODE integration failed: {sol.message}")
    f_min, g_min, h_min = sol.y[0, -1], sol.y[1, -1], sol.y[2, -1]
    # core 0 < lambda < LAMBDA_MIN: pressure term plus the kinetic term of the asymptotic core
    core = (h_min / (gamma - 1.0) * LAMBDA_MIN**geometry / geometry
            + 0.5 * g_min * f_min**2 * LAMBDA_MIN**geometry / (geometry + 2 + geometry / (gamma - 1.0)))
    integral = sol.y[3, -1] + core
    alpha = GEOMETRY_FACTOR[geometry] * (2.0 / (geometry + 2)) ** 2 * integral
    order = np.argsort(np.exp(sol.t))
    return SedovSolution(geometry=geometry, gamma=gamma, alpha=alpha,
                         xi0=alpha ** (-1.0 / (geometry + 2)), lam=np.exp(sol.t)[order],
                         f=sol.y[0][order], g=sol.y[1][order], h=sol.y[2][order])


def energy_integral_residual(solution: SedovSolution) -> np.ndarray:
    """Sedov's algebraic energy integral, zero on the exact solution:

    (g f^2/2 + h/(gamma-1)) (f - lambda) + h f = 0
    (no energy crosses a sphere r = lambda R(t) moving with the similarity flow).
    """
    f, g, h, lam = solution.f, solution.g, solution.h, solution.lam
    return (0.5 * g * f * f + h / (solution.gamma - 1.0)) * (f - lam) + h * f
