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


@njit(cache=True)
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


@njit(cache=True)
def _hardening(eps, p, off):
    """min(Ymax, Y0 (1 + beta eps)^n) and its derivative in eps."""
    y0 = p[off + I_Y0]
    beta = p[off + I_BETA]
    n = p[off + I_N]
    base = 1.0 + beta * eps
    y = y0 * base ** n
    if y >= p[off + I_YMAX]:
        return p[off + I_YMAX], 0.0
    return y, y0 * n * beta * base ** (n - 1.0)


@njit(cache=True)
def shear_modulus_and_ratio(pressure, temp, props, m):
    """(G used in the elastic predictor, SCG ratio G(P,T)/G0) for body m."""
    kind = props[m, P_STRENGTH]
    if kind == STRENGTH_NONE:
        return 0.0, 0.0
    if kind == STRENGTH_EPP:
        return props[m, P_G0], 1.0
    off = P_SCG
    ratio = scg_shear_ratio(pressure, temp, props[m, off + I_G], props[m, off + I_H], props[m, off + I_XI],
                            props[m, off + I_TF])
    if props[m, P_G_CONST] != 0.0 and ratio > 0.0:
        return props[m, P_G0], ratio
    return props[m, P_G0] * ratio, ratio


@njit(cache=True)
def yield_stress(eps_p, ratio, props, m):
    """Current flow stress: Y0 (EPP) or min(Ymax, Y0 (1+beta eps)^n) G/G0 (SCG)."""
    kind = props[m, P_STRENGTH]
    if kind == STRENGTH_NONE:
        return 0.0
    if kind == STRENGTH_EPP:
        return props[m, P_Y0]
    y, _ = _hardening(eps_p, props[m], P_SCG)
    return y * ratio


@njit(cache=True)
def radial_return(sxx, syy, sxy, eps_p, G, ratio, props, m):
    """Return (sxx, syy, sxy, d_eps, Y) after the yield check and radial return.

    ``sxx, syy, sxy`` is the elastic predictor (szz = -(sxx+syy)).  With ratio = 0
    (melted, or G(P,T) clamped at 0) the deviator is set to zero.
    """
    kind = props[m, P_STRENGTH]
    szz = -(sxx + syy)
    seq = math.sqrt(1.5 * (sxx * sxx + syy * syy + szz * szz + 2.0 * sxy * sxy))
    if kind == STRENGTH_EPP:
        y = props[m, P_Y0]
        if seq <= y:
            return sxx, syy, sxy, 0.0, y
        f = y / seq
        return sxx * f, syy * f, sxy * f, (seq - y) / (3.0 * G), y
    if ratio <= 0.0 or G <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    p = props[m]
    h0, _ = _hardening(eps_p, p, P_SCG)
    y = h0 * ratio
    if seq <= y:
        return sxx, syy, sxy, 0.0, y
    # f(d) = seq - 3 G d - ratio*h(eps+d), decreasing; root in [0, (seq - y)/(3G)]
    lo = 0.0
    hi = (seq - y) / (3.0 * G)
    d = hi
    for _ in range(NEWTON_MAXIT):
        h, dh = _hardening(eps_p + d, p, P_SCG)
        f = seq - 3.0 * G * d - ratio * h
        if abs(f) <= NEWTON_RTOL * seq:
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
    h, _ = _hardening(eps_p + d, p, P_SCG)
    y = ratio * h
    fac = y / seq
    return sxx * fac, syy * fac, sxy * fac, d, y
