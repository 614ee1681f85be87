"""The slide line's local search (seeded by the previous cycle's segment, certified by chunk boxes)
returns exactly the pairs and hat coordinates of the all-segment search, on moving configurations:
random walks of slave nodes along straight, curved, kinked and folded guides (a guide that turns
back on itself puts index-far segments next to each other), with separations, jumps, nodes on
grid points (exact ties) and zero-length guide segments."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from shockfriction.contact.pairing import (closest_guide_coordinate, closest_guide_coordinate_local,
                                           guide_chunk_boxes, pair_slave_nodes, pair_slave_nodes_local,
                                           slave_hat_coordinates)


def _guide(kind: str, n: int, rng) -> tuple[np.ndarray, np.ndarray]:
    s = np.linspace(0.0, 1.0, n)
    if kind == "straight":
        return s.copy(), np.zeros(n)
    if kind == "arc":            # convex and (with the other normal sign) concave
        a = np.pi * s
        return np.cos(a), np.sin(a)
    if kind == "kinked":         # the cone shot's bore and barrel: one corner
        return np.where(s < 0.6, s, 0.6 + 0.3 * (s - 0.6)), np.where(s < 0.6, 0.0, -(s - 0.6))
    if kind == "folded":         # a hairpin: out along y = 0, back along y = 0.05
        half = n // 2
        x = np.concatenate((np.linspace(0.0, 1.0, half), np.linspace(1.0, 0.0, n - half)))
        y = np.concatenate((np.zeros(half), np.full(n - half, 0.05)))
        return x, y
    if kind == "zigzag":         # many kinks, both convex and concave
        return s.copy(), 0.02 * (np.arange(n) % 2)
    if kind == "grid":           # quantised points, duplicated ones (zero-length segments): exact ties
        x = np.round(s * 8) / 8
        y = np.round(0.1 * np.sin(6 * s) * 16) / 16
        return x, y
    if kind == "noisy":
        return s + rng.uniform(-0.2, 0.2, n) / n, rng.uniform(-0.01, 0.01, n)
    raise ValueError(kind)


KINDS = ["straight", "arc", "kinked", "folded", "zigzag", "grid", "noisy"]


def _both(xs, ys, gx, gy, sign, max_gap, max_pen, seed_seg, chunk):
    ns = xs.size
    idx = np.arange(ns)
    ref = [np.full(ns, -1, np.int64)] + [np.zeros(ns) for _ in range(6)] + [np.zeros(ns, np.bool_)]
    pair_slave_nodes(xs, ys, idx, gx, gy, sign, max_gap, max_pen, *ref)
    box = np.zeros((-(-(gx.size - 1) // chunk), 4))
    pad = guide_chunk_boxes(gx, gy, chunk, box)
    loc = [seed_seg.copy()] + [np.zeros(ns) for _ in range(6)] + [np.zeros(ns, np.bool_)]
    pair_slave_nodes_local(xs, ys, idx, gx, gy, sign, max_gap, max_pen, chunk, box, pad, *loc)
    return ref, loc, box, pad


def _assert_same(ref, loc):
    for a, b in zip(ref, loc):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_local_pairing_equals_global_on_random_walks(kind, sign):
    rng = np.random.default_rng(2 * KINDS.index(kind) + (sign > 0))
    ng = 41
    gx, gy = _guide(kind, ng, rng)
    seg_len = np.hypot(np.diff(gx), np.diff(gy))
    h = 0.5 * seg_len[seg_len > 0].min() if (seg_len > 0).any() else 0.1
    ns = 60
    # slave nodes start near the guide (on random guide points, offset along the normal)
    k = rng.integers(0, ng - 1, ns)
    u = rng.uniform(0, 1, ns)
    xs = gx[k] + u * (gx[k + 1] - gx[k]) + rng.normal(0, 0.3 * h, ns)
    ys = gy[k] + u * (gy[k + 1] - gy[k]) + rng.normal(0, 0.3 * h, ns)
    seg = np.full(ns, -1, np.int64)      # first cycle: no seed
    compared = paired = 0
    for cycle in range(60):
        for chunk in (1, 4, 7):
            ref, loc, _, _ = _both(xs, ys, gx, gy, sign, h, h, seg, chunk)
            _assert_same(ref, loc)
        compared += ns
        paired += int(ref[-1].sum())
        seg = loc[0]                     # the next cycle's seeds
        # random walk (a fraction of a segment), occasional jumps across the guide and separations
        xs = xs + rng.normal(0, 0.2 * h, ns)
        ys = ys + rng.normal(0, 0.2 * h, ns)
        jump = rng.random(ns) < 0.05
        xs[jump] = rng.uniform(gx.min(), gx.max(), jump.sum())
        ys[jump] = rng.uniform(gy.min() - h, gy.max() + h, jump.sum())
        if kind == "grid":               # back onto a grid: exact ties between segments and corners
            xs = np.round(xs * 64) / 64
            ys = np.round(ys * 64) / 64
    assert paired > 0.2 * compared      # the walk keeps many nodes in contact


@pytest.mark.parametrize("kind", KINDS)
def test_local_hat_coordinates_equal_global(kind):
    rng = np.random.default_rng(len(kind))
    gx, gy = _guide(kind, 33, rng)
    for chunk in (1, 3, 6, 32):
        box = np.zeros((-(-(gx.size - 1) // chunk), 4))
        pad = guide_chunk_boxes(gx, gy, chunk, box)
        for _ in range(300):
            px = rng.uniform(gx.min() - 0.1, gx.max() + 0.1)
            py = rng.uniform(gy.min() - 0.1, gy.max() + 0.1)
            if kind == "grid":
                px, py = np.round(px * 32) / 32, np.round(py * 32) / 32
            seed = int(rng.integers(-1, gx.size + 1))     # including no seed and out-of-range ones
            assert closest_guide_coordinate_local(px, py, gx, gy, seed, chunk, box, pad) == \
                closest_guide_coordinate(px, py, gx, gy)


@pytest.mark.parametrize("periodic", [False, True])
def test_slave_hat_coordinates_local_equal_global(periodic):
    rng = np.random.default_rng(7)
    gx, gy = _guide("noisy", 25, rng)
    if periodic:                         # guide spans one period (1, 0)
        gx = np.linspace(0.0, 1.0, 25)
    ns = 30
    xs = np.sort(rng.uniform(0.0, 1.0, ns))[::-1].copy()
    ys = rng.uniform(-0.005, 0.005, ns)
    d = np.diff(xs)
    prev_dx, next_dx = np.concatenate(([0.0], -d)), np.concatenate((d, [0.0]))
    prev_dy, next_dy = np.zeros(ns), np.zeros(ns)
    has_prev, has_next = np.arange(ns) > 0, np.arange(ns) < ns - 1
    if periodic:
        prev_dx[0], has_prev[0] = 0.5, True
    seg = rng.integers(0, 24, ns).astype(np.int64)      # any seeds: the result may not depend on them
    coef = rng.uniform(0, 1, ns)
    active = rng.random(ns) < 0.9
    ref = [np.zeros(ns) for _ in range(3)]
    loc = [np.zeros(ns) for _ in range(3)]
    args = (xs, ys, prev_dx, prev_dy, next_dx, next_dy, has_prev, has_next, seg, coef, active, gx, gy, periodic)
    slave_hat_coordinates(*args, *ref)
    box = np.zeros((6, 4))
    pad = guide_chunk_boxes(gx, gy, 4, box)
    slave_hat_coordinates(*args, *loc, 4, box, pad)
    for a, b in zip(ref, loc):
        np.testing.assert_array_equal(a, b)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(-8, 8), st.integers(-8, 8)), min_size=2, max_size=12),
       st.tuples(st.integers(-10, 10), st.integers(-10, 10)), st.integers(-1, 12), st.integers(1, 5),
       st.sampled_from([1.0, -1.0]))
def test_local_search_equals_global_on_any_integer_polyline(points, p, seed, chunk, sign):
    """Arbitrary (self-crossing, degenerate) polylines on an integer grid: ties everywhere."""
    gx = np.array([a for a, _ in points], float) / 4
    gy = np.array([b for _, b in points], float) / 4
    xs, ys = np.array([p[0] / 4]), np.array([p[1] / 4])
    ref, loc, box, pad = _both(xs, ys, gx, gy, sign, 0.6, 0.4, np.array([seed]), chunk)
    _assert_same(ref, loc)
    assert closest_guide_coordinate_local(xs[0], ys[0], gx, gy, seed, chunk, box, pad) == \
        closest_guide_coordinate(xs[0], ys[0], gx, gy)


def test_exact_tie_between_two_convex_corners_goes_to_the_first():
    """Two peaks equally far (2.5) from the node: the all-segment search keeps the first corner."""
    gx = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    gy = np.array([0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    xs, ys = np.array([2.5]), np.array([3.0])
    for seed in (-1, 0, 3, 4, 5):
        ref, loc, _, _ = _both(xs, ys, gx, gy, -1.0, 3.0, 1.0, np.array([seed]), 1)
        _assert_same(ref, loc)
        assert loc[0][0] == 0 and loc[1][0] == 1.0 and loc[6][0] == 2.5    # corner 1, i.e. the end of segment 0


def test_search_pad_covers_the_coef_tolerance():
    """A node just before the start of segment A (coef = -5e-10, inside the pairing tolerance) on its
    line (g = 0), while the seed's segment B, far along the guide, is 1e-10 away: A's box is farther
    than B's |g|, and only the pad makes the local search look at it."""
    gx = np.array([-1.0, 1.0, 1.0, 0.5, 0.2, 0.0, 1.0])
    gy = np.array([1e-10, 1e-10, 1.0, 1.0, 0.5, 0.0, 0.0])
    xs, ys = np.array([-5e-10]), np.array([0.0])
    ref, loc, _, _ = _both(xs, ys, gx, gy, 1.0, 0.1, 0.1, np.array([0]), 1)
    _assert_same(ref, loc)
    assert ref[0][0] == 5 and ref[6][0] == 0.0
