"""exp_inline and log_inline (the libm-free exp and log of the SCG melt factor and hardening, so that cell loops vectorise) against libm."""

import math

import numpy as np
from numba import njit

from shockfriction.jit_bits import f64_bits, f64_from_bits
from shockfriction.materials.strength import exp_inline, log_inline, scg_hardening_simd


@njit(cache=True)
def _exp_all(x, out):
    for i in range(x.shape[0]):
        out[i] = exp_inline(x[i])


def _exp(x):
    x = np.asarray(x, float)
    out = np.empty_like(x)
    _exp_all(x, out)
    return out


def test_exp_inline_within_one_ulp_of_libm():
    """fdlibm's algorithm: measured max 1 ulp (in ~10 % of the samples) over the whole range."""
    rng = np.random.default_rng(7)
    for lo, hi in [(-1.0, 1.0), (-60.0, 0.0), (-708.0, 709.7), (-745.0, -708.0)]:
        x = rng.uniform(lo, hi, 200_000)
        ref = np.array([math.exp(v) for v in x])
        ulps = np.abs(_exp(x) - ref) / np.spacing(ref)
        assert ulps.max() <= 1.0, (lo, hi, ulps.max())


def test_exp_inline_special_values():
    x = np.array([0.0, -0.0, 1e-300, -1e-300, -746.0, -1e5, -np.inf, 709.8, 1e5, np.inf, np.nan])
    y = _exp(x)
    assert np.all(y[:4] == 1.0)
    assert np.all(y[4:7] == 0.0)
    assert np.all(np.isposinf(y[7:10]))
    assert np.isnan(y[10])


@njit(cache=True)
def _round_trip(x):
    return f64_from_bits(f64_bits(x)), f64_bits(x)


def test_bit_casts_round_trip_and_order_non_negative_floats():
    vals = [0.0, 5e-324, 2.2e-308, 1e-10, 1.0, 3.5, 1e300, math.inf]
    assert [_round_trip(v)[0] for v in vals] == vals
    bits = [_round_trip(v)[1] for v in vals]
    assert bits == sorted(bits) and len(set(bits)) == len(bits)


@njit(cache=True)
def _log_all(x, out):
    for i in range(x.shape[0]):
        out[i] = log_inline(x[i])


def test_log_inline_within_one_ulp_of_libm():
    """fdlibm's e_log.c on normal numbers: max 1 ulp of math.log (measured: 1 ulp in a few % of the samples)."""
    rng = np.random.default_rng(11)
    for x in (rng.uniform(0.5, 2.0, 200_000), rng.uniform(1.0, 1e3, 200_000), 10.0 ** rng.uniform(-300, 300, 200_000),
              1.0 + rng.uniform(-1e-6, 1e-6, 100_000)):
        ref = np.array([math.log(v) for v in x])
        out = np.empty_like(x)
        _log_all(x, out)
        ulps = np.abs(out - ref) / np.spacing(np.abs(ref) + 1e-300)
        assert ulps.max() <= 1.0, ulps.max()
    out = np.empty(3)
    _log_all(np.array([1.0, 2.0, math.e]), out)
    assert out[0] == 0.0 and out[1] == math.log(2.0) and abs(out[2] - 1.0) <= 2.3e-16


def test_scg_hardening_simd_against_the_power():
    """Y0 (1 + beta eps)^n by exp(n log(.)): the error of the log grows by n ln(1 + beta eps) in the exp (measured
    max 2 ulp at n = 0.1, 6 ulp at n = 0.5, beta = 2000 of the libm power)."""
    rng = np.random.default_rng(3)
    eps = np.concatenate([[0.0], rng.uniform(0.0, 5.0, 20_000), 10.0 ** rng.uniform(-12, 0, 20_000)])
    for Y0, beta, n, Ymax in ((2.9e8, 125.0, 0.1, 6.8e8), (1.0e9, 2000.0, 0.5, 1e12), (4e7, 10.0, 0.3, 4.8e8)):
        ref = np.minimum(Ymax, Y0 * (1.0 + beta * eps) ** n)
        out = np.array([_hardening(x, Y0, beta, n, Ymax) for x in eps])
        assert (np.abs(out - ref) / np.spacing(ref)).max() <= 8.0, (Y0, beta, n)
        assert out[0] == Y0


@njit(cache=True)
def _hardening(eps, Y0, beta, n, Ymax):
    return scg_hardening_simd(eps, Y0, beta, n, Ymax)
