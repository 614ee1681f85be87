"""x^(1/n) of the strain target (eq. 8.42) by binary powering where 1/n is an integer (thermoelastoplastic.root_power,
integer_power)."""

import numpy as np
from numba import njit

from shockfriction.friction.subgrid.thermoelastoplastic import ROOT_POWER_MAX, integer_power, root_exponent, root_power


@njit(cache=True)
def _roots(x, n):
    out = np.empty_like(x)
    inv_n = 1.0 / n
    k = root_exponent(n)
    for i in range(x.shape[0]):
        out[i] = root_power(x[i], inv_n, k)
    return out


@njit(cache=True)
def _integer_powers(x, k):
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i] = integer_power(x[i], k)
    return out


def _binary_power(x: float, k: int) -> float:
    """Reference: the binary powering loop that stops at k's top bit (Python floats are IEEE doubles)."""
    r, b = 1.0, x
    while True:
        if k & 1:
            r *= b
        k >>= 1
        if k == 0:
            return r
        b *= b


@njit(cache=True)
def _pows(x, n):
    out = np.empty_like(x)
    for i in range(x.shape[0]):
        out[i] = x[i] ** (1.0 / n)
    return out


def test_root_exponent_takes_the_integer_reciprocals_only():
    assert [root_exponent(n) for n in (0.1, 0.5, 1.0, 0.25, 1.0 / ROOT_POWER_MAX)] == [10, 2, 1, 4, ROOT_POWER_MAX]
    # not an integer, above the cap, or a power above 1: pow
    assert [root_exponent(n) for n in (0.45, 0.3, 1.0 / (ROOT_POWER_MAX + 1), 2.0)] == [0, 0, 0, 0]


def test_root_power_is_within_a_few_ulp_of_pow():
    """n = 0.1 (k = 10, four products) over x up to e^29 (x^10 up to e^290, the capped range of eq. 8.42):
    measured 8.9e-16 relative at most (4 ulp; pow itself is within one); n = 0.45 takes pow, bit for bit (numba's
    pow: numpy's array power may differ from it in the last bit)."""
    x = np.exp(np.random.default_rng(1).uniform(-3.0, 29.0, 20000))
    err = np.max(np.abs(_roots(x, 0.1) / _pows(x, 0.1) - 1.0))
    assert err < 1.0e-15
    assert np.array_equal(_roots(x, 0.45), _pows(x, 0.45))


def test_integer_power_is_binary_powering_bit_for_bit():
    """The fixed-length loop (it vectorises: squarings past k's top bit are formed, may overflow, and are not used)
    makes the products of the loop that stops at the top bit, in the same order: the same doubles for every k up to
    ROOT_POWER_MAX, also where x^k overflows."""
    x = np.exp(np.random.default_rng(2).uniform(-3.0, 29.0, 300))
    for k in range(1, ROOT_POWER_MAX + 1):
        got = _integer_powers(x, k)
        want = np.array([_binary_power(float(v), k) for v in x])
        assert np.array_equal(got, want), k
    assert np.isinf(_integer_powers(np.array([1e300]), 2)[0])
