"""Linear stability of steady sliding with a velocity-dependent law on the discrete lattice.

Used to explain and pin the choice of the slip at which the slide lines evaluate a
velocity-dependent friction law (docs/theory/slide-lines.md, section 4).

Model: two identical semi-infinite shear lattices (node masses M = rho h S, springs
k = G S/h, interface nodes M/2) meet at a slide line; leapfrog in time; antisymmetric
motion, so the slip perturbation is twice the slave node's velocity perturbation.  The
law is linearised about steady sliding: weakening of slope b = |F_N| |dmu/ds| (Pa s/m)
adds the force dF = b S ds_law on the slave node (and -dF on the guide node), ds_law the
perturbation of the slip the law sees.  With u_j^n = U z^n kappa^j:

    bulk:       z - 2 + 1/z = lambda^2 (kappa - 2 + 1/kappa),      lambda = c_s dt/h
    interface:  D(z) = z - 2 + 1/z - 2 lambda^2 (kappa - 1) - 4 beta lambda Phi(z) (z - 1) = 0,

beta = b/(rho c_s), |kappa| < 1 (decaying into the bulk, analytic for |z| > 1 when
lambda <= 1), and Phi(z) = ds_law/ds^{n+1/2} the transfer of the evaluation:

====================  =================================================
"free" (eq. 3.79)     1/(1 + 4 beta lambda)   (s* = s^{n+1/2} - 4 dF dt/M)
"midpoint"            1/(1 + 2 beta lambda)   ((s* + s^{n+1/2})/2)
"corrected"           1                       (s^{n+1/2}, n = 0)
"centred"             (1 + 1/z)/2             ((s^{n-1/2} + s^{n+1/2})/2)
"relaxed"             r z/((1 + r) z - 1)     (backward Euler over n steps, r = 1/n)
====================  =================================================

A root with |z| > 1 is a mode growing by |z| per step.  z = 1 (uniform translation) is
always a root; the count is that of the annulus 1 + eps < |z| < radius, by the argument
principle (D has no pole there).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import fsolve

EVALUATIONS = ("free", "midpoint", "corrected", "centred", "relaxed")


def decaying_kappa(z, lam):
    """The root |kappa| <= 1 of kappa + 1/kappa = 2 + (z - 2 + 1/z)/lambda^2."""
    q = 2.0 + (z - 2.0 + 1.0 / z) / lam ** 2
    k = 0.5 * (q - np.sqrt(q * q - 4.0 + 0j))
    return np.where(np.abs(k) <= 1.0, k, 1.0 / k)


def transfer(z, evaluation: str, lam: float, beta: float, n: float = 5.0):
    """Phi(z) of the evaluation (module docstring)."""
    z = np.asarray(z, complex)
    if evaluation == "free":
        return np.full_like(z, 1.0 / (1.0 + 4.0 * beta * lam))
    if evaluation == "midpoint":
        return np.full_like(z, 1.0 / (1.0 + 2.0 * beta * lam))
    if evaluation == "corrected":
        return np.ones_like(z)
    if evaluation == "centred":
        return 0.5 * (1.0 + 1.0 / z)
    if evaluation == "relaxed":
        r = 1.0 / n
        return r * z / ((1.0 + r) * z - 1.0)
    raise ValueError(f"evaluation must be one of {EVALUATIONS}, not {evaluation!r}")


def characteristic(z, lam: float, beta: float, evaluation: str, n: float = 5.0):
    """D(z) of the interface equation (module docstring)."""
    z = np.asarray(z, complex)
    return (z - 2.0 + 1.0 / z - 2.0 * lam ** 2 * (decaying_kappa(z, lam) - 1.0)
            - 4.0 * beta * lam * transfer(z, evaluation, lam, beta, n) * (z - 1.0))


def _winding(lam, beta, evaluation, n, rho, samples):
    z = rho * np.exp(2j * np.pi * np.arange(samples + 1) / samples)
    phase = np.unwrap(np.angle(characteristic(z, lam, beta, evaluation, n)))
    return (phase[-1] - phase[0]) / (2.0 * np.pi)


def unstable_modes(lam: float, beta: float, evaluation: str, n: float = 5.0, eps: float = 1e-4,
                   radius: float = 4.0, samples: int = 40000) -> tuple[int, float, float]:
    """(number of growing modes, largest |z|, its frequency omega dt) for 1 + eps < |z| < radius."""
    if not 0.0 < lam <= 1.0:
        raise ValueError(f"lambda = c_s dt/h must be in (0, 1], not {lam}")
    count = round(_winding(lam, beta, evaluation, n, radius, samples)
                  - _winding(lam, beta, evaluation, n, 1.0 + eps, samples))
    if count <= 0:
        return 0, 1.0, 0.0
    # locate the largest root: Newton from the smallest |D| on a polar grid of the annulus
    rr = np.linspace(1.0 + eps, radius, 200)
    th = np.linspace(0.0, np.pi, 721)
    zz = (rr[None, :] * np.exp(1j * th[:, None])).ravel()
    d = np.abs(characteristic(zz, lam, beta, evaluation, n))
    best, omega = 1.0, 0.0
    for z0 in zz[np.argsort(d)[:80]]:
        def f(x):
            v = characteristic(x[0] + 1j * x[1], lam, beta, evaluation, n)
            return [v.real, v.imag]
        x, _, ier, _ = fsolve(f, [z0.real, z0.imag], full_output=True)
        z = complex(x[0], x[1])
        if ier == 1 and abs(z) > 1.0 + eps and abs(z) > best:
            best, omega = abs(z), abs(np.angle(z))
    return count, best, omega
