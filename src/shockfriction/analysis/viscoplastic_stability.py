"""Linear stability of a homogeneously shearing elasto-viscoplastic layer with inertia and heat conduction.

The base problem of thesis ch. 5 (shear momentum, hypoelasticity, heat with plastic dissipation) with a
rate-dependent flow rule gamma_p_dot = F(tau, eps, theta) instead of the rate-independent yield of ch. 6.
A homogeneous base state (tau0, plastic shear rate gp0, eps0, theta0; v_z = gp0) is perturbed by normal
modes exp(i k z + s t).  With eps the equivalent plastic strain (d eps/dt = gamma_p_dot/sqrt(3)), the
linearised system::

    rho s V        = i k T_au                                     (shear momentum)
    s T_au         = G (i k V - Gp)                               (hypoelasticity)
    s E            = Gp / sqrt(3)                                  (plastic strain)
    rho c s Th     = -kappa k^2 Th + chi (tau0 Gp + gp0 T_au)      (heat, Taylor-Quinney chi)
    Gp             = F_tau T_au + F_eps E + F_theta Th             (linearised flow rule)

is x' = A x for x = (V, T_au, E, Th).  A total-form elasticity tau = G(theta) gamma_e (G softening with
temperature at fixed elastic strain) adds dG/dtheta gamma_e0 s Th to the stress row (``G_theta_gamma_e``); the growth rate of wavenumber k is the largest real part of the
eigenvalues of A (frozen coefficients: valid while the base state changes slowly over 1/s).  Without
inertia (rho -> 0) the perturbation stress vanishes for k != 0 and the system reduces to (E, Th).

For a linear overstress (Perzyna) rule tau = Y(eps, p, theta)/sqrt(3) + eta gamma_p_dot the partial
derivatives are F_tau = 1/eta, F_eps = -Y_eps/(sqrt(3) eta), F_theta = -Y_theta/(sqrt(3) eta); as
eta -> 0 and rho -> 0 the quasi-static growth rate tends to eq. 6.48 (:func:`stability.growth_rate`).
"""

from __future__ import annotations

import math

import numpy as np

SQRT3 = math.sqrt(3.0)


def layer_matrix(k: float, *, rho: float, G: float, rho_c: float, kappa: float, chi: float, tau0: float,
                 gp0: float, F_tau: float, F_eps: float, F_theta: float, inertia: bool = True,
                 G_theta_gamma_e: float = 0.0) -> np.ndarray:
    """The matrix A of x' = A x (x = (V, T_au, E, Th) with inertia, (E, Th) without)."""
    if inertia:
        A = np.array([
            [0.0, 1j * k / rho, 0.0, 0.0],
            [1j * k * G, -G * F_tau, -G * F_eps, -G * F_theta],
            [0.0, F_tau / SQRT3, F_eps / SQRT3, F_theta / SQRT3],
            [0.0, chi * (tau0 * F_tau + gp0) / rho_c, chi * tau0 * F_eps / rho_c,
             (-kappa * k * k + chi * tau0 * F_theta) / rho_c],
        ], dtype=complex)
        A[1] += G_theta_gamma_e * A[3]  # d(G gamma_e)/dt = G d gamma_e/dt + gamma_e dG/dtheta dtheta/dt
        return A
    return np.array([
        [F_eps / SQRT3, F_theta / SQRT3],
        [chi * tau0 * F_eps / rho_c, (-kappa * k * k + chi * tau0 * F_theta) / rho_c],
    ], dtype=complex)


def growth_rate(k: float, **base) -> complex:
    """Eigenvalue of largest real part of :func:`layer_matrix` (1/s): the mode's growth rate and frequency."""
    eig = np.linalg.eigvals(layer_matrix(k, **base))
    return complex(eig[np.argmax(eig.real)])


def eigenmode(k: float, **base) -> tuple[complex, np.ndarray]:
    """The most unstable eigenvalue and its eigenvector (amplitude ratios of V, T_au, E, Th)."""
    w, vecs = np.linalg.eig(layer_matrix(k, **base))
    i = int(np.argmax(w.real))
    return complex(w[i]), vecs[:, i]


def overstress_partials(eta: float, Y_eps: float, Y_theta: float) -> dict[str, float]:
    """F_tau, F_eps, F_theta of the linear overstress rule tau = Y/sqrt(3) + eta gamma_p_dot."""
    return {"F_tau": 1.0 / eta, "F_eps": -Y_eps / (SQRT3 * eta), "F_theta": -Y_theta / (SQRT3 * eta)}
