"""Growth rates of the linearised 1D boundary layer, computed numerically (thesis ch. 6).

This is the independent check of the closed-form criterion in :mod:`.stability`: the
linearised layer problem (eqs. 6.26-6.29) is discretised on a finite layer
z in [0, h] by Chebyshev collocation and its growth rates are the eigenvalues s of
the generalised problem A x = s B x (perturbations ~ exp(s t), s = Im(omega)).

Unknowns at the N+1 Chebyshev nodes: dv (tangential velocity), deps (plastic
strain), dtheta (temperature), dtau (shear stress).  Equations::

    d(dtau)/dz = 0                                   (6.26, quasi-static momentum)
    d(dv)/dz   = sqrt(3) s deps                      (6.27, kinematics)
    sqrt(3) dtau = Y_eps deps + Y_theta dtheta        (6.28, linearised yield)
    kappa d2(dtheta)/dz2 - rho c s dtheta
        = -sqrt(3) (tau0 s deps + epsdot0 dtau)      (6.29, heat)

Boundary conditions (the thesis's layer, frozen): the interface shear stress is
given by the macroscopic problem, dtau(0) = 0 (5.183); the velocity is continuous
with the macroscopic one at z = h, dv(h) = 0 (4.86); the heat-flux perturbation
vanishes at both ends (frictional flux frozen at z = 0, adiabatic edge 4.95 at z = h).

To keep the matrices well conditioned the problem is solved in the units
z ~ h, t ~ h^2 rho c/kappa, stress ~ sqrt(3) tau0, temperature ~ sqrt(3) tau0/(rho c).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

SQRT3 = float(np.sqrt(3.0))


def chebyshev_nodes_and_matrix(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Lobatto nodes x_j = cos(pi j/n) on [-1, 1] and the collocation derivative matrix."""
    j = np.arange(n + 1)
    x = np.cos(np.pi * j / n)
    c = np.where((j == 0) | (j == n), 2.0, 1.0) * (-1.0) ** j
    dx = x[:, None] - x[None, :]
    D = np.outer(c, 1.0 / c) / (dx + np.eye(n + 1))
    D -= np.diag(D.sum(axis=1))
    return x, D


@dataclass(frozen=True)
class LayerModes:
    """Finite eigenvalues (growth rates, 1/s) with their temperature eigenvectors."""

    growth_rates: np.ndarray   #: real parts, sorted from largest to smallest
    imaginary: np.ndarray      #: imaginary parts (oscillation), same order
    temperature: np.ndarray    #: dtheta at the nodes, one column per mode
    z: np.ndarray              #: node positions in m (z = 0 on the contact)

    def nonuniform(self, tol: float = 1e-6) -> np.ndarray:
        """Growth rates of the modes whose temperature is not uniform (drops the neutral k = 0 mode)."""
        t = self.temperature
        spread = np.ptp(t.real, axis=0) + np.ptp(t.imag, axis=0)
        scale = np.max(np.abs(t), axis=0)
        return self.growth_rates[spread > tol * scale]


def layer_modes(Y_eps: float, Y_theta: float, tau0: float, rho_c: float, kappa: float,
                depth: float, n: int = 40, plastic_rate: float = 0.0) -> LayerModes:
    """Eigen-growth-rates of the discretised linearised layer of thickness ``depth``.

    ``Y_eps`` (Pa), ``Y_theta`` (Pa/K), ``tau0`` (Pa), ``rho_c`` (J/(m^3 K)), ``kappa``
    (W/(m K)), ``plastic_rate`` = base equivalent plastic strain rate (1/s).
    """
    S = SQRT3 * tau0                       # stress unit
    t_unit = depth**2 * rho_c / kappa      # diffusion time across the layer
    a = Y_eps / S                          # dimensionless hardening
    b = Y_theta / rho_c                    # dimensionless softening (temperature unit S/rho c)
    r = plastic_rate * t_unit              # dimensionless base plastic rate

    x, Dx = chebyshev_nodes_and_matrix(n)
    z = 0.5 * (1.0 - x)                    # z/h in [0, 1]: node 0 on the contact, node n at z = h
    D = -2.0 * Dx                          # d/d(z/h)
    D2 = D @ D
    m = n + 1
    I = np.eye(m)
    iv, ie, it, is_ = (slice(k * m, (k + 1) * m) for k in range(4))
    A = np.zeros((4 * m, 4 * m))
    B = np.zeros((4 * m, 4 * m))

    # momentum: D dtau = 0, with dtau(0) = 0 on the contact (row of node 0)
    A[iv, is_] = D
    A[0, :] = 0.0
    A[0, 3 * m + 0] = 1.0
    # kinematics: D dv = sqrt(3) s deps, with dv(h) = 0 (row of node n)
    A[ie, iv] = D
    B[ie, ie] = SQRT3 * I
    A[m + n, :] = 0.0
    B[m + n, :] = 0.0
    A[m + n, n] = 1.0
    # yield: a deps + b dtheta - dtau = 0 (dtau in units S, so sqrt(3) dtau/S -> dtau_hat)
    A[it, ie] = a * I
    A[it, it] = b * I
    A[it, is_] = -I
    # heat: D2 dtheta + r dtau = s (dtheta - deps); Neumann rows at both ends
    A[is_, it] = D2
    A[is_, is_] = r * I
    B[is_, it] = I
    B[is_, ie] = -I
    for row_node in (0, n):
        row = 3 * m + row_node
        A[row, :] = 0.0
        B[row, :] = 0.0
        A[row, 2 * m: 3 * m] = D[row_node]

    w, vr = scipy.linalg.eig(A, B)
    finite = np.isfinite(w)
    w, vr = w[finite], vr[:, finite]
    order = np.argsort(-w.real)
    w, vr = w[order], vr[:, order]
    return LayerModes(w.real / t_unit, w.imag / t_unit, vr[2 * m: 3 * m, :], z * depth)
