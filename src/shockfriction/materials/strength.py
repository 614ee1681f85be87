"""Steinberg-Cochran-Guinan (SCG) strength, shared by the hydrocode and the sub-grid models.

Thesis form (eq. 2.53-2.54 with the Ball & Winter melt factor, eq. 4.57)::

    G(P, T) = G0 (1 + g P - h (T - 300)) exp(-xi T / (T_F - T))     (0 for T >= T_F, never < 0)
    Y(eps, P, T) = min(Ymax, Y0 (1 + beta eps)^n) G(P, T) / G0

P is the pressure (compression positive) or, at the interface, the normal
stress |F_N|.  The kernels take the parameter array of
:meth:`shockfriction.materials.Material.scg_params`:
``[G0, Y0, Ymax, beta, n, g, h, xi, T_F]``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize

from shockfriction.jit_bits import f64_bits, f64_from_bits

T_REF = 300.0  #: SCG reference temperature (K)

I_G0, I_Y0, I_YMAX, I_BETA, I_N, I_G, I_H, I_XI, I_TF = range(9)


@njit(cache=True, inline="always", error_model="numpy")
def exp_inline(x):
    """exp(x) without a libm call, so that a loop calling it can be vectorised (SVML is absent):
    fdlibm's e_exp.c, x = k ln2 + r (|r| <= ln2/2, ln2 in two parts), exp(r) = 1 + r + r c/(2 - c),
    c = r - r^2 (P1 + ... + P5 r^8); exp(x) = exp(r) 2^(k1) 2^(k - k1), k1 = k/2, the powers of two
    from their bits.  Within 1 ulp of libm (tests/test_exp_inline.py); x is clamped to [-746, 710]
    (0 and inf outside), NaN stays NaN."""
    x = max(min(x, 710.0), -746.0)
    kf = math.floor(x * 1.44269504088896338700e+00 + 0.5)
    hi = x - kf * 6.93147180369123816490e-01  # exact: ln2's high part has 32 bits
    lo = kf * 1.90821492927058770002e-10
    r = hi - lo
    t = r * r
    c = r - t * (1.66666666666666019037e-01 + t * (-2.77777777770155933842e-03 + t * (
        6.61375632143793436117e-05 + t * (-1.65339022054652515390e-06 + t * 4.13813679705723846039e-08))))
    y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi)
    k = int(kf)
    k1 = k >> 1
    return y * f64_from_bits((k1 + 1023) << 52) * f64_from_bits((k - k1 + 1023) << 52)


@njit(cache=True, inline="always", error_model="numpy")
def log_inline(x):
    """ln(x) of a finite x > 0 (normal numbers) without a libm call, so that a loop calling it can be vectorised:
    fdlibm's e_log.c, x = 2^k (1 + f) with sqrt(2)/2 <= 1 + f < sqrt(2), s = f/(2 + f),
    ln(1 + f) = f - s (f - R(s^2)) (Lg1 ... Lg7), k ln2 in two parts; both of fdlibm's final forms, chosen by
    a select.  Within 1 ulp of libm (tests/test_exp_inline.py)."""
    b = f64_bits(x)
    hx = np.int64(b >> np.uint64(32)) & 0x7FFFFFFF
    k = (hx >> 20) - 1023
    hx &= 0x000FFFFF
    i = (hx + 0x95F64) & 0x100000  # the mantissa at or above sqrt(2)'s: halve it (k + 1)
    k += i >> 20
    lo = b & np.uint64(0xFFFFFFFF)
    f = f64_from_bits((np.uint64(hx | (i ^ 0x3FF00000)) << np.uint64(32)) | lo) - 1.0
    dk = float(k)
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * (3.999999999940941908e-01 + w * (2.222219843214978396e-01 + w * 1.531383769920937332e-01))
    t2 = z * (6.666666666666735130e-01 + w * (2.857142874366239149e-01 + w * (
        1.818357216161805012e-01 + w * 1.479819860511658591e-01)))
    R = t2 + t1
    hfsq = 0.5 * f * f
    ln2_hi = 6.93147180369123816490e-01
    ln2_lo = 1.90821492927058770002e-10
    a = dk * ln2_hi - ((hfsq - (s * (hfsq + R) + dk * ln2_lo)) - f)
    c = dk * ln2_hi - ((s * (f - R) - dk * ln2_lo) - f)
    return a if ((hx - 0x6147A) | (0x6B851 - hx)) > 0 else c


@njit(cache=True, inline="always", error_model="numpy")
def scg_hardening_power(eps_p, Y0, beta, n):
    """Y0 (1 + beta eps_p)^n, the hardening of :func:`scg_hardening` before its cap Ymax (eps_p >= 0), by
    :func:`exp_inline` and :func:`log_inline`, so that a loop over cells vectorises (within a few ulp of the libm
    power)."""
    return Y0 * exp_inline(n * log_inline(1.0 + beta * eps_p))


@njit(cache=True, inline="always", error_model="numpy")
def scg_hardening_simd(eps_p, Y0, beta, n, Ymax):
    """min(Ymax, Y0 (1 + beta eps_p)^n) (:func:`scg_hardening`) by :func:`scg_hardening_power`."""
    y = scg_hardening_power(eps_p, Y0, beta, n)
    return y if y < Ymax else Ymax


@njit(cache=True, inline="always", error_model="numpy")  # T_F - T > 0 where it divides: no zero check needed
def _shear_ratio(P, T, g, h, xi, T_melt, vector):
    """G(P, T)/G0: (1 + g P - h (T - 300)) exp(-xi T/(T_F - T)); 0 at or above T_F, never negative.
    ``vector`` (a constant): the exponential by :func:`exp_inline` (no call: a loop can be
    vectorised), else by libm (faster in scalar code)."""
    if T >= T_melt:
        return 0.0
    a = -xi * T / (T_melt - T)
    r = (1.0 + g * P - h * (T - T_REF)) * (exp_inline(a) if vector else math.exp(a))
    return r if r > 0.0 else 0.0


@njit(cache=True, error_model="numpy")
def scg_shear_ratio(P, T, g, h, xi, T_melt):
    """G(P, T)/G0 (:func:`_shear_ratio`, libm's exp): scalar code (the sub-grid models' friction law, the
    initial cell state)."""
    return _shear_ratio(P, T, g, h, xi, T_melt, False)


@njit(cache=True, inline="always", error_model="numpy")
def scg_shear_ratio_simd(P, T, g, h, xi, T_melt):
    """G(P, T)/G0 (:func:`_shear_ratio`, :func:`exp_inline`): in loops to be vectorised (the hydro
    update's moduli loop, across cells; the thermoelastoplastic layer's first pass, across nodes)."""
    return _shear_ratio(P, T, g, h, xi, T_melt, True)


@njit(cache=True)
def scg_shear_modulus(P, T, p):
    """G(P, T) in Pa for the parameter array ``p``."""
    return p[I_G0] * scg_shear_ratio(P, T, p[I_G], p[I_H], p[I_XI], p[I_TF])


@njit(cache=True)
def scg_hardening(eps_p, p):
    """Work-hardened yield at reference state: min(Ymax, Y0 (1 + beta eps_p)^n)."""
    y = p[I_Y0] * (1.0 + p[I_BETA] * max(eps_p, 0.0)) ** p[I_N]
    return y if y < p[I_YMAX] else p[I_YMAX]


@njit(cache=True)
def scg_yield(eps_p, P, T, p):
    """Y(eps_p, P, T) = min(Ymax, Y0 (1 + beta eps_p)^n) G(P, T)/G0, in Pa."""
    return scg_hardening(eps_p, p) * scg_shear_ratio(P, T, p[I_G], p[I_H], p[I_XI], p[I_TF])


@njit(cache=True)
def hugoniot_compression(P, K0, s):
    """eta = rho/rho0 on the principal Hugoniot of the linear Us = c0 + s up law at the pressure P:
    P = K0 mu/(1 - s mu)^2, mu = 1 - 1/eta, K0 = rho0 c0^2, solved for mu in the form without cancellation
    mu = 2 P/(K0 + 2 s P + sqrt(K0^2 + 4 s P K0)); P <= 0 gives eta = 1."""
    if not P > 0.0:
        return 1.0
    mu = 2.0 * P / (K0 + 2.0 * s * P + math.sqrt(K0 * K0 + 4.0 * s * P * K0))
    return 1.0 / (1.0 - mu)


@njit(cache=True)
def scg_melt_temperature(P, T_m0, K0, s, gamma0, a):
    """SCG melt law (Steinberg, Cochran & Guinan 1980, eq. 5; a Lindemann law with gamma = gamma0 - a (1 - 1/eta)):
    T_m = T_m0 exp(2 a (1 - 1/eta)) eta^(2 (gamma0 - a - 1/3)), eta = rho/rho0 at the pressure P on the principal
    Hugoniot (:func:`hugoniot_compression`); K0 <= 0: the constant T_m0."""
    if not K0 > 0.0:
        return T_m0
    eta = hugoniot_compression(P, K0, s)
    return T_m0 * math.exp(2.0 * a * (1.0 - 1.0 / eta)) * eta ** (2.0 * (gamma0 - a - 1.0 / 3.0))


@vectorize(["float64(float64, float64, float64, float64, float64, float64)"], cache=True)
def shear_ratio(P, T, g, h, xi, T_melt):
    """Element-wise G/G0 (numpy ufunc over P and T): :func:`scg_shear_ratio`."""
    return scg_shear_ratio(P, T, g, h, xi, T_melt)


def shear_modulus(material, P, T) -> np.ndarray:
    """G(P, T) for a :class:`~shockfriction.materials.Material` (numpy arrays or floats)."""
    m = material
    return m.G0 * shear_ratio(np.asarray(P, float), np.asarray(T, float), m.scg_g, m.scg_h, m.scg_xi,
                              m.melting_temperature)


def yield_stress(material, eps_p, P, T) -> np.ndarray:
    """Y(eps_p, P, T) for a material (numpy arrays or floats)."""
    m = material
    hard = np.minimum(m.Ymax, m.Y0 * (1.0 + m.scg_beta * np.maximum(np.asarray(eps_p, float), 0.0)) ** m.scg_n)
    return hard * shear_modulus(m, P, T) / m.G0
