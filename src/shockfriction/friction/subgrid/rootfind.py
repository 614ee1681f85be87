"""Brent's bracketed root finder in reverse-communication form (numba), for the interface temperature.

The thesis solves its scalar interface equation by an unsafeguarded secant
(eq. 7.92, 7.103, 8.78; digest §9 item 9).  Here a root is always bracketed,
R(lo) <= 0 < R(hi), and Brent's method (inverse quadratic interpolation, secant,
bisection fallback) keeps it bracketed, so it cannot leave [T_ad(0), T_F).

Use (inside an njit kernel)::

    st = np.empty(BRENT_STATE)
    brent_start(lo, f_lo, hi, f_hi, xtol, st)
    while True:
        done, x = brent_next(st)
        if done: break
        brent_feed(st, residual(x))
    # bracket: (st[B], st[FB]) and (st[C], st[FC]) with opposite signs (or a zero)

Convergence: the bracket is narrower than 2 (2 eps |x| + xtol/2), i.e. about ``xtol``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

A, FA, B, FB, C, FC, D, E, XTOL = range(9)
BRENT_STATE = 9
_EPS = 2.220446049250313e-16


@njit(cache=True)
def brent_start(a, fa, b, fb, xtol, st):
    """Start from a bracket [a, b] with fa * fb <= 0."""
    st[A] = a
    st[FA] = fa
    st[B] = b
    st[FB] = fb
    st[C] = a
    st[FC] = fa
    st[D] = b - a
    st[E] = b - a
    st[XTOL] = xtol


@njit(cache=True)
def brent_next(st):
    """Return (converged, x): the root estimate st[B] if converged, else the next point to evaluate."""
    a, fa, b, fb, c, fc, d, e, xtol = st[A], st[FA], st[B], st[FB], st[C], st[FC], st[D], st[E], st[XTOL]
    if (fb > 0.0 and fc > 0.0) or (fb < 0.0 and fc < 0.0):
        c = a
        fc = fa
        d = b - a
        e = d
    if abs(fc) < abs(fb):  # keep b the best estimate
        a = b
        b = c
        c = a
        fa = fb
        fb = fc
        fc = fa
    tol = 2.0 * _EPS * abs(b) + 0.5 * xtol
    m = 0.5 * (c - b)
    if abs(m) <= tol or fb == 0.0:
        st[A], st[FA], st[B], st[FB], st[C], st[FC], st[D], st[E] = a, fa, b, fb, c, fc, d, e
        return True, b
    if abs(e) < tol or abs(fa) <= abs(fb):
        d = m
        e = m
    else:
        s = fb / fa
        if a == c:  # secant
            p = 2.0 * m * s
            q = 1.0 - s
        else:  # inverse quadratic interpolation
            qq = fa / fc
            r = fb / fc
            p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0))
            q = (qq - 1.0) * (r - 1.0) * (s - 1.0)
        if p > 0.0:
            q = -q
        else:
            p = -p
        if 2.0 * p < 3.0 * m * q - abs(tol * q) and p < abs(0.5 * e * q):
            e = d
            d = p / q
        else:
            d = m
            e = m
    a = b
    fa = fb
    if abs(d) > tol:
        b = b + d
    elif m > 0.0:
        b = b + tol
    else:
        b = b - tol
    st[A], st[FA], st[B], st[FB], st[C], st[FC], st[D], st[E] = a, fa, b, np.nan, c, fc, d, e
    return False, b


@njit(cache=True)
def brent_feed(st, fx):
    """Give the residual at the point returned by :func:`brent_next`."""
    st[FB] = fx
