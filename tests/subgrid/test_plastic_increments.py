"""The closed-form plastic strain increments (eq. 8.42) of the thermoelastoplastic solve, whose first two passes
are vectorised across the nodes (G/G0 by an inlined exp, x^(1/n) by products), against the formula written
plainly (numpy: libm's exp, pow).  Cases: every node of a 501-node column yields (the columns at the kinematic
limit that dominate the cone shot at f = 0.7), about half of them yield, and the same with stale (lazy) hardening
entries; each by the vectorised first pass (a plastic-front bound of SIMD_MIN_NODES or more, reading the
contiguous copy) and by the scalar one (no bound, reading the column), which must agree bit for bit."""

import math

import numpy as np
import pytest

from shockfriction.friction.subgrid.thermoelastoplastic import SIMD_MIN_NODES, STALE_SHRINK, plastic_increments
from shockfriction.materials.library import get_material
from shockfriction.materials.strength import I_BETA, I_G, I_H, I_N, I_TF, I_XI, I_Y0

AL = get_material("Al5083-H111")
P = AL.scg_params()
NN = 501
F_N = 8e9


def _column():
    z = np.linspace(0.0, 20e-6, NN)
    w = np.full(NN, z[1])
    w[[0, -1]] *= 0.5
    theta = 300.0 + 500.0 * np.exp(-z / 3e-6)  # 800 K at the interface
    eps = np.random.default_rng(3).uniform(0.0, 2e-3, NN)
    return w, theta, eps


def _reference(s, theta, eps):
    n, beta = P[I_N], P[I_BETA]
    ratio = (1.0 + P[I_G] * F_N - P[I_H] * (theta - 300.0)) * np.exp(-P[I_XI] * theta / (P[I_TF] - theta))
    hard = (1.0 + beta * eps) ** n
    x = s / ratio
    return np.where(x > hard, (x ** (1.0 / n) - 1.0) / beta - eps, 0.0), ratio * hard


@pytest.mark.parametrize("stale", [False, True])
@pytest.mark.parametrize("share", ["all", "half"])
def test_increments_match_eq_8_42_written_plainly(share, stale):
    w, theta, eps = _column()
    _, strength = _reference(1.0, theta, eps)
    s = 1.01 * strength.max() if share == "all" else float(np.median(strength))
    ref, _ = _reference(s, theta, eps)
    hard = (1.0 + P[I_BETA] * eps) ** P[I_N]
    if stale:  # what finish_column leaves after a yielded step: lower bounds, formed again where needed
        hard = -hard * (1.0 - STALE_SHRINK)
    tau = s * P[I_Y0] / math.sqrt(3.0)
    runs = []
    for depth in (NN, -1):  # the vectorised first pass (every node), the scalar one
        out = np.zeros(NN)
        h = hard.copy()
        integral = plastic_increments(tau, F_N, theta, theta.copy(), np.zeros(NN), 0.0, eps, h, w, theta.max(), 0.0,
                                      P, out, np.empty((4, NN)), depth, 1.0)
        runs.append((out, h, integral))
    assert NN >= SIMD_MIN_NODES
    np.testing.assert_array_equal(runs[0][0], runs[1][0])
    np.testing.assert_array_equal(runs[0][1], runs[1][1])  # the hardening formed where needed
    assert runs[0][2] == runs[1][2]
    yielded = np.count_nonzero(ref)
    assert yielded == (NN if share == "all" else pytest.approx(NN // 2, abs=1))
    np.testing.assert_array_equal(out > 0.0, ref > 0.0)
    # measured: 1.8e-15 (all) and 2.0e-15 (half) of the largest increment; the integral 1.2e-15 and 7e-16
    assert np.max(np.abs(out - ref)) <= 5e-15 * ref.max()
    assert integral == pytest.approx(w @ ref, rel=5e-15)
