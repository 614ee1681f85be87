"""Exact Riemann solver for the ideal gas (p = (gamma - 1) rho e).

The star-region pressure p* is the root of Toro's pressure function
(Toro, *Riemann Solvers and Numerical Methods for Fluid Dynamics*, ch. 4):

    f(p) = f_L(p) + f_R(p) + (u_R - u_L) = 0,

    f_K(p) = (p - p_K) sqrt(A_K / (p + B_K))                       p >  p_K (shock)
           = 2 c_K / (gamma - 1) [(p / p_K)^((gamma-1)/(2 gamma)) - 1]  p <= p_K (rarefaction)

with A_K = 2 / ((gamma + 1) rho_K), B_K = (gamma - 1) p_K / (gamma + 1).
f is monotone increasing and concave, so Newton from the two-rarefaction
guess converges; u* = (u_L + u_R)/2 + (f_R(p*) - f_L(p*))/2.  The solution
is self-similar and is sampled at xi = (x - x0)/t (docs/theory/exact-solutions.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class GasState:
    """Primitive state of an ideal gas: density, velocity, pressure."""

    rho: float
    u: float
    p: float


@dataclass(frozen=True)
class StarState:
    """Star-region solution: pressure, velocity and the two star densities."""

    p: float
    u: float
    rho_left: float
    rho_right: float
    iterations: int


def _sound_speed(state: GasState, gamma: float) -> float:
    return float(np.sqrt(gamma * state.p / state.rho))


def _wave_function(p: float, state: GasState, gamma: float) -> tuple[float, float]:
    """f_K(p) and its derivative for one side (Toro eqs. 4.6-4.7, 4.37)."""
    c = _sound_speed(state, gamma)
    if p > state.p:
        a = 2.0 / ((gamma + 1.0) * state.rho)
        b = (gamma - 1.0) / (gamma + 1.0) * state.p
        root = np.sqrt(a / (p + b))
        return (p - state.p) * root, root * (1.0 - 0.5 * (p - state.p) / (p + b))
    ratio = p / state.p
    expo = (gamma - 1.0) / (2.0 * gamma)
    value = 2.0 * c / (gamma - 1.0) * (ratio**expo - 1.0)
    derivative = ratio ** (-(gamma + 1.0) / (2.0 * gamma)) / (state.rho * c)
    return value, derivative


def _star_density(p: float, state: GasState, gamma: float) -> float:
    """Density behind the left or right wave (shock: RH; rarefaction: isentrope)."""
    if p > state.p:
        g = (gamma - 1.0) / (gamma + 1.0)
        ratio = p / state.p
        return state.rho * (ratio + g) / (g * ratio + 1.0)
    return state.rho * (p / state.p) ** (1.0 / gamma)


def solve_star(left: GasState, right: GasState, gamma: float, tol: float = 1e-14,
               max_iter: int = 100) -> StarState:
    """Star pressure and velocity: Toro's two-rarefaction formula (eq. 4.46) when it gives
    p* <= p_L, p_R (then it is exact), else Newton on Toro's pressure function from it
    (``iterations`` 0 for the closed form).

    Raises ValueError when the data generate vacuum (pressure positivity
    condition 2 (c_L + c_R)/(gamma - 1) <= u_R - u_L).
    """
    c_l, c_r = _sound_speed(left, gamma), _sound_speed(right, gamma)
    du = right.u - left.u
    if 2.0 * (c_l + c_r) / (gamma - 1.0) <= du:
        raise ValueError("the Riemann data generate vacuum; no star region")
    # two-rarefaction pressure (Toro eq. 4.46): the root itself when both waves are rarefactions
    # (p <= p_L, p_R), else Newton's start.  Near vacuum the root is tiny and the pressure function
    # there a difference of nearly equal speeds: Newton cannot reach a relative tolerance on p
    expo = (gamma - 1.0) / (2.0 * gamma)
    p = ((c_l + c_r - 0.5 * (gamma - 1.0) * du)
         / (c_l / left.p**expo + c_r / right.p**expo)) ** (1.0 / expo)
    iteration = 0
    if p > min(left.p, right.p):  # a shock on one side at least: Newton from there (p > 0)
        for iteration in range(1, max_iter + 1):
            f_l, d_l = _wave_function(p, left, gamma)
            f_r, d_r = _wave_function(p, right, gamma)
            p_new = p - (f_l + f_r + du) / (d_l + d_r)
            if p_new <= 0.0:
                p_new = 0.5 * p
            change = abs(p_new - p) / (0.5 * (p_new + p))
            p = p_new
            if change < tol:
                break
        else:
            raise ValueError(f"Newton on the pressure function did not converge in {max_iter} iterations")
    f_l, _ = _wave_function(p, left, gamma)
    f_r, _ = _wave_function(p, right, gamma)
    u = 0.5 * (left.u + right.u) + 0.5 * (f_r - f_l)
    return StarState(p=p, u=u, rho_left=_star_density(p, left, gamma),
                     rho_right=_star_density(p, right, gamma), iterations=iteration)


def sample(left: GasState, right: GasState, gamma: float, xi: np.ndarray,
           star: StarState | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Density, velocity and pressure at the similarity coordinates xi = x/t."""
    star = star or solve_star(left, right, gamma)
    xi = np.asarray(xi, dtype=float)
    rho = np.empty_like(xi)
    u = np.empty_like(xi)
    p = np.empty_like(xi)
    for side, state, rho_star, sign in ((0, left, star.rho_left, 1.0), (1, right, star.rho_right, -1.0)):
        mask = xi < star.u if side == 0 else xi >= star.u
        x = sign * xi[mask]  # mirror the right side onto the left-side formulas
        v = sign * state.u
        v_star = sign * star.u
        c = _sound_speed(state, gamma)
        r = np.full(x.shape, float(state.rho))
        w = np.full(x.shape, float(v))
        q = np.full(x.shape, float(state.p))
        if star.p > state.p:  # shock moving towards -x in the mirrored frame
            ratio = star.p / state.p
            speed = v - c * np.sqrt((gamma + 1.0) / (2.0 * gamma) * ratio + (gamma - 1.0) / (2.0 * gamma))
            behind = x >= speed
            r[behind], w[behind], q[behind] = rho_star, v_star, star.p
        else:  # rarefaction fan between head and tail
            c_star = c * (star.p / state.p) ** ((gamma - 1.0) / (2.0 * gamma))
            head, tail = v - c, v_star - c_star
            fan = (x > head) & (x < tail)
            behind = x >= tail
            r[behind], w[behind], q[behind] = rho_star, v_star, star.p
            factor = 2.0 / (gamma + 1.0) + (gamma - 1.0) / ((gamma + 1.0) * c) * (v - x[fan])
            r[fan] = state.rho * factor ** (2.0 / (gamma - 1.0))
            w[fan] = 2.0 / (gamma + 1.0) * (c + 0.5 * (gamma - 1.0) * v + x[fan])
            q[fan] = state.p * factor ** (2.0 * gamma / (gamma - 1.0))
        rho[mask], u[mask], p[mask] = r, sign * w, q
    return rho, u, p


def profile(left: GasState, right: GasState, gamma: float, x: np.ndarray, t: float,
            x0: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Density, velocity, pressure at positions x and time t > 0 (diaphragm at x0)."""
    if t <= 0.0:
        raise ValueError("t must be positive")
    return sample(left, right, gamma, (np.asarray(x, dtype=float) - x0) / t)
