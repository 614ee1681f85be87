"""Per-cell deviatoric stress update: Jaumann rotation, elastic predictor, radial return.

Thesis sec. 3.2.2 (eqs. 3.20-3.27, 3.40-3.49) with the errata resolved:

* rotation (explicit Jaumann, eq. before 3.21) done as the Hughes-Winget rotation
  S~ = R S R^T, R = (1 - W dt/2)^-1 (1 + W dt/2), which is exactly orthogonal
  (invariants of S are kept to round-off) and first-order equal to the thesis's
  S + (W S - S W) dt;
* predictor S* = S~ + 2 G dt (D - tr(D)/3 1) (eq. 3.41);
* yield check sqrt(3/2 S*:S*) <= Y (eq. 3.43 without the spurious 1/sqrt(3));
* return S = Y/S*_eq S*, with the hardening solved inside the return:
  S*_eq - 3 G d_eps - Y(eps_p + d_eps) = 0 (safeguarded Newton), so that
  S:D_p dt = Y d_eps >= 0 exactly (plastic work).

Deviators are carried as (sxx, syy, sxy), with szz = -(sxx + syy) the out-of-plane
(plane strain) or hoop (axisymmetric) component.
"""

from __future__ import annotations

import math

from numba import njit

from shockfriction.hydro.matprops import P_G0, P_G_CONST, P_SCG, P_STRENGTH, P_Y0, STRENGTH_EPP, STRENGTH_NONE
from shockfriction.materials.strength import I_BETA, I_G, I_H, I_N, I_TF, I_XI, I_Y0, I_YMAX, scg_shear_ratio

NEWTON_RTOL = 1e-12
NEWTON_MAXIT = 100


@njit(cache=True, inline="always")
def rotate_deviator(sxx, syy, sxy, spin, dt):
    """Hughes-Winget rotation of the in-plane deviator by the spin W_xy = spin (= (du/dy - dv/dx)/2)."""
    beta = 0.5 * spin * dt
    d = 1.0 / (1.0 + beta * beta)
    c = (1.0 - beta * beta) * d
    s = 2.0 * beta * d
    cc = c * c
    ss = s * s
    cs = c * s
    nxx = cc * sxx + 2.0 * cs * sxy + ss * syy
    nyy = ss * sxx - 2.0 * cs * sxy + cc * syy
    nxy = cs * (syy - sxx) + (cc - ss) * sxy
    return nxx, nyy, nxy


@njit(cache=True, inline="always")
def hardening(eps, y0, beta, n, ymax):
    """min(Ymax, Y0 (1 + beta eps)^n) and its derivative in eps."""
    base = 1.0 + beta * eps
    y = y0 * base ** n
    if y >= ymax:
        return ymax, 0.0
    return y, y * n * beta / base


@njit(cache=True)
def shear_modulus_and_ratio_s(pressure, temp, kind, g0, gconst, g, h, xi, tmelt):
    """(G of the elastic predictor, SCG ratio G(P,T)/G0)."""
    if kind == STRENGTH_NONE:
        return 0.0, 0.0
    if kind == STRENGTH_EPP:
        return g0, 1.0
    ratio = scg_shear_ratio(pressure, temp, g, h, xi, tmelt)
    if gconst != 0.0 and ratio > 0.0:
        return g0, ratio
    return g0 * ratio, ratio


@njit(cache=True)
def yield_stress_s(eps_p, ratio, kind, y_epp, y0, beta, n, ymax):
    """Flow stress: Y0 (EPP) or min(Ymax, Y0 (1+beta eps)^n) G/G0 (SCG)."""
    if kind == STRENGTH_NONE:
        return 0.0
    if kind == STRENGTH_EPP:
        return y_epp
    y, _ = hardening(eps_p, y0, beta, n, ymax)
    return y * ratio


@njit(cache=True, inline="always")
def radial_return_s(sxx, syy, sxy, eps_p, G, ratio, kind, y_epp, y0, beta, n, ymax, y_now):
    """Return (sxx, syy, sxy, d_eps, Y, h) after the yield check and radial return.

    ``sxx, syy, sxy`` is the elastic predictor (szz = -(sxx+syy)); h is the SCG work
    hardening min(Ymax, Y0 (1+beta eps)^n) at the new plastic strain (Y0 for EPP).
    With ratio = 0 (melted, or G(P,T) clamped at 0) the deviator is set to zero.
    ``y_now`` is the SCG flow stress Y(eps_p, P^n, T^n) if known (the cycle keeps it
    per cell), or a negative number to compute it here.
    """
    szz = -(sxx + syy)
    seq2 = 1.5 * (sxx * sxx + syy * syy + szz * szz + 2.0 * sxy * sxy)  # S*_eq^2 (the root only past yield)
    if kind == STRENGTH_EPP:
        if seq2 <= y_epp * y_epp:
            return sxx, syy, sxy, 0.0, y_epp, y_epp
        seq = math.sqrt(seq2)
        f = y_epp / seq
        return sxx * f, syy * f, sxy * f, (seq - y_epp) / (3.0 * G), y_epp, y_epp
    if ratio <= 0.0 or G <= 0.0:
        h0, _ = hardening(eps_p, y0, beta, n, ymax)
        return 0.0, 0.0, 0.0, 0.0, 0.0, h0
    if y_now >= 0.0:
        y = y_now
    else:
        h0, _ = hardening(eps_p, y0, beta, n, ymax)
        y = h0 * ratio
    if seq2 <= y * y:
        return sxx, syy, sxy, 0.0, y, y / ratio
    seq = math.sqrt(seq2)
    # f(d) = seq - 3 G d - ratio*h(eps+d), decreasing; root in [0, (seq - y)/(3G)]
    hi = (seq - y) / (3.0 * G)
    # start from the root of the linearised equation: the hardening is concave, so f(d0) >= 0
    # and d0 is a lower bound from which Newton converges monotonically
    base = 1.0 + beta * eps_p
    slope = y * n * beta / base if y < ratio * ymax else 0.0
    d = (seq - y) / (3.0 * G + slope)
    lo = d
    h = 0.0
    h_at_d = False  # h = hardening at the current d (the converged iterate): no second evaluation
    for _ in range(NEWTON_MAXIT):
        h, dh = hardening(eps_p + d, y0, beta, n, ymax)
        f = seq - 3.0 * G * d - ratio * h
        if abs(f) <= NEWTON_RTOL * seq:
            h_at_d = True
            break
        if f > 0.0:
            lo = d
        else:
            hi = d
        dn = d + f / (3.0 * G + ratio * dh)
        if dn <= lo or dn >= hi:
            dn = 0.5 * (lo + hi)
        d = dn
        if hi - lo <= 1e-15 * (1.0 + hi):
            break
    if not h_at_d:
        h, _ = hardening(eps_p + d, y0, beta, n, ymax)
    y = ratio * h
    fac = y / seq
    return sxx * fac, syy * fac, sxy * fac, d, y, h


@njit(cache=True)
def _params(props, m):
    """(kind, G0, G-constant flag, Y_epp, Y0, beta, n, Ymax, g, h, xi, T_F) of body m."""
    o = P_SCG
    return (props[m, P_STRENGTH], props[m, P_G0], props[m, P_G_CONST], props[m, P_Y0], props[m, o + I_Y0],
            props[m, o + I_BETA], props[m, o + I_N], props[m, o + I_YMAX], props[m, o + I_G], props[m, o + I_H],
            props[m, o + I_XI], props[m, o + I_TF])


@njit(cache=True)
def shear_modulus_and_ratio(pressure, temp, props, m):
    """(G used in the elastic predictor, SCG ratio G(P,T)/G0) for body m."""
    kind, g0, gc, ye, y0, beta, n, ymax, g, h, xi, tf = _params(props, m)
    return shear_modulus_and_ratio_s(pressure, temp, kind, g0, gc, g, h, xi, tf)


@njit(cache=True)
def yield_stress(eps_p, ratio, props, m):
    """Current flow stress of body m."""
    kind, g0, gc, ye, y0, beta, n, ymax, g, h, xi, tf = _params(props, m)
    return yield_stress_s(eps_p, ratio, kind, ye, y0, beta, n, ymax)


@njit(cache=True)
def radial_return(sxx, syy, sxy, eps_p, G, ratio, props, m):
    """:func:`radial_return_s` with the parameters of body m: (sxx, syy, sxy, d_eps, Y)."""
    kind, g0, gc, ye, y0, beta, n, ymax, g, h, xi, tf = _params(props, m)
    r = radial_return_s(sxx, syy, sxy, eps_p, G, ratio, kind, ye, y0, beta, n, ymax, -1.0)
    return r[0], r[1], r[2], r[3], r[4]
