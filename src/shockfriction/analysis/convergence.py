"""Error norms, observed orders of convergence and wave locating for verification runs.

- discrete L1 error  ||q_h - q||_1 = sum_i w_i |q_i - q(x_i)| / sum_i w_i  (w_i = cell size or volume)
- observed order from errors E_k on meshes h_k: the least-squares slope of ln E vs ln h
  (two meshes: p = ln(E_1/E_2) / ln(h_1/h_2))
- wave position: where a monotone front crosses the level halfway between its two plateaus,
  interpolated linearly between the bracketing samples.
"""

from __future__ import annotations

import numpy as np


def l1_error(computed: np.ndarray, exact: np.ndarray, weights: np.ndarray | None = None) -> float:
    """Weighted mean absolute error; weights default to uniform."""
    computed = np.asarray(computed, dtype=float)
    exact = np.asarray(exact, dtype=float)
    w = np.ones_like(computed) if weights is None else np.asarray(weights, dtype=float)
    return float(np.sum(w * np.abs(computed - exact)) / np.sum(w))


def observed_order(sizes, errors) -> float:
    """Least-squares slope of ln(error) against ln(size)."""
    sizes = np.log(np.asarray(sizes, dtype=float))
    errors = np.log(np.asarray(errors, dtype=float))
    if sizes.size < 2:
        raise ValueError("need at least two meshes for an observed order")
    slope, _ = np.polyfit(sizes, errors, 1)
    return float(slope)


def front_position(x: np.ndarray, q: np.ndarray, level: float, from_right: bool = True) -> float:
    """Position where q crosses `level`, scanning from the right end (or the left) to the first crossing.

    x must be increasing.  Raises ValueError when q never crosses the level.
    """
    x = np.asarray(x, dtype=float)
    q = np.asarray(q, dtype=float) - level
    idx = range(len(x) - 1, 0, -1) if from_right else range(len(x) - 1)
    for i in idx:
        a, b = (i - 1, i) if from_right else (i, i + 1)
        if q[a] == 0.0:
            return float(x[a])
        if q[a] * q[b] < 0.0:
            return float(x[a] + (x[b] - x[a]) * q[a] / (q[a] - q[b]))
    raise ValueError(f"the profile never crosses the level {level + 0.0}")
