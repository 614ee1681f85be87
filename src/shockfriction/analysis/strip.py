"""Profiles of a 1D strip computed by the hydrocode (post-processing for verification).

A strip is one cell wide (symmetry sides) and carries a plane or radial wave along one
axis.  Cell centres are the means of the four nodes; the longitudinal compressive stress
along the axis is Sigma = P + q - S_aa (compression positive).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np


def read_deck(path: str | Path) -> dict:
    """A TOML deck as a plain dict (to change resolution or times before a run)."""
    with open(path, "rb") as handle:
        return tomllib.load(handle)


def cell_centres(state) -> tuple[np.ndarray, np.ndarray]:
    """Cell-centre coordinates (mean of the four nodes)."""
    return state.x[state.conn].mean(axis=1), state.y[state.conn].mean(axis=1)


def strip_profile(state, axis: str = "y") -> dict[str, np.ndarray]:
    """Cell fields sorted along `axis` ("x" or "y"): coordinate, size, rho, p, q, e, stress, velocity."""
    if axis not in ("x", "y"):
        raise ValueError(f"axis must be 'x' or 'y', got {axis!r}")
    xc, yc = cell_centres(state)
    coord = yc if axis == "y" else xc
    order = np.argsort(coord)
    nodes = state.y if axis == "y" else state.x
    size = nodes[state.conn].max(axis=1) - nodes[state.conn].min(axis=1)
    deviator = state.syy if axis == "y" else state.sxx
    velocity = (state.vy if axis == "y" else state.vx)[state.conn].mean(axis=1)
    fields = {
        "coord": coord, "size": size, "rho": state.rho, "p": state.pressure, "q": state.q, "e": state.e,
        "stress": state.pressure + state.q - deviator, "deviator": deviator, "velocity": velocity,
        "eps_p": state.eps_p,
    }
    return {key: np.asarray(value)[order] for key, value in fields.items()}
