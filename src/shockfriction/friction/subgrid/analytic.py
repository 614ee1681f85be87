"""Exact half-space solutions for an imposed interface heat flux (thesis §7.2.1-7.2.2).

``q`` is always the flux *entering* the body (beta_T times the generated flux).
kappa conductivity (W/m/K), alpha diffusivity (m^2/s), e = kappa/sqrt(alpha) effusivity.

* constant flux (eq. 7.27-7.33):
  theta(z, t) - Theta_0 = 2 q sqrt(alpha t)/kappa * ierfc(z / (2 sqrt(alpha t)))
  theta(0, t) - Theta_0 = 2 q sqrt(t/pi) / e
* piecewise-constant flux q_k on (t_{k-1}, t_k], any steps (Duhamel, eq. 7.54-7.56, digest §2.5):
  theta(0, t_n) - Theta_0 = C sum_k q_k dt_k / (sqrt(t_n - t_{k-1}) + sqrt(t_n - t_k)),  C = 2/(e sqrt(pi))
  (the rationalised form of sqrt(t_n - t_{k-1}) - sqrt(t_n - t_k); the thesis's sign and
  off-by-one typos, digest §9 item 19, are corrected).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import erfc


def ierfc(x):
    """First integral of erfc: exp(-x^2)/sqrt(pi) - x erfc(x) (eq. 7.30); ierfc(0) = 1/sqrt(pi)."""
    x = np.asarray(x, float)
    return np.exp(-x * x) / math.sqrt(math.pi) - x * erfc(x)


def surface_rise_constant_flux(q, t, conductivity, diffusivity):
    """theta(0, t) - Theta_0 = 2 q sqrt(t/pi)/e for a constant flux q from t = 0 (eq. 7.33)."""
    e = conductivity / math.sqrt(diffusivity)
    return 2.0 * q * np.sqrt(np.asarray(t, float) / math.pi) / e


def profile_constant_flux(q, z, t, conductivity, diffusivity):
    """theta(z, t) - Theta_0 = 2 q sqrt(alpha t)/kappa ierfc(z/(2 sqrt(alpha t))) (eq. 7.27-7.28); 0 at t <= 0."""
    z = np.asarray(z, float)
    if t <= 0.0:
        return np.zeros_like(z)
    s = math.sqrt(diffusivity * t)
    return 2.0 * q * s / conductivity * ierfc(z / (2.0 * s))


def profile_piecewise_flux(fluxes, times, z, t, conductivity, diffusivity):
    """Depth profile at time t for flux fluxes[k] on (times[k], times[k+1]] (superposition of eq. 7.55).

    ``times`` has one more entry than ``fluxes`` (times[0] is the start, usually 0).
    """
    fluxes = np.asarray(fluxes, float)
    times = np.asarray(times, float)
    out = np.zeros_like(np.asarray(z, float))
    for k, qk in enumerate(fluxes):
        start, end = times[k], times[k + 1]
        if t <= start:
            break
        out += profile_constant_flux(qk, z, t - start, conductivity, diffusivity)
        if t > end:
            out -= profile_constant_flux(qk, z, t - end, conductivity, diffusivity)
    return out


def duhamel_surface(fluxes, steps, conductivity, diffusivity):
    """Interface temperature rises theta(0, t_n) - Theta_0, n = 1..N, for a piecewise-constant flux.

    ``fluxes[k]`` acts during the step ``steps[k]`` (variable steps allowed).  Incremental
    Duhamel sum (eq. 7.56) in the conjugate form C q_k dt_k/(sqrt(t_n - t_{k-1}) + sqrt(t_n - t_k)),
    the lower-triangular matrix A of §7.2.2 applied row by row (O(N^2)).
    """
    q = np.asarray(fluxes, float)
    dt = np.asarray(steps, float)
    if q.shape != dt.shape:
        raise ValueError("fluxes and steps must have the same length")
    e = conductivity / math.sqrt(diffusivity)
    C = 2.0 / (e * math.sqrt(math.pi))
    t = np.concatenate(([0.0], np.cumsum(dt)))
    out = np.empty(q.size)
    for n in range(1, q.size + 1):
        older = t[n] - t[: n]          # t_n - t_{k-1}, k = 1..n
        newer = t[n] - t[1: n + 1]     # t_n - t_k
        out[n - 1] = C * np.sum(q[:n] * dt[:n] / (np.sqrt(older) + np.sqrt(np.maximum(newer, 0.0))))
    return out


def duhamel_surface_uniform(fluxes, dt, conductivity, diffusivity):
    """Constant-step form: C sqrt(dt) T q with the Toeplitz T_{nk} = 1/(sqrt(n-k+1) + sqrt(n-k)) (FFT convolution)."""
    q = np.asarray(fluxes, float)
    n = q.size
    e = conductivity / math.sqrt(diffusivity)
    C = 2.0 / (e * math.sqrt(math.pi))
    j = np.arange(n, dtype=float)
    kernel = 1.0 / (np.sqrt(j + 1.0) + np.sqrt(j))
    size = 1 << (2 * n - 1).bit_length()
    conv = np.fft.irfft(np.fft.rfft(kernel, size) * np.fft.rfft(q, size), size)[:n]
    return C * math.sqrt(dt) * conv
