"""One structured block of quadrilaterals: a mapped quad (transfinite interpolation).

A block has ``nx x ny`` cells and ``(nx+1) x (ny+1)`` nodes.  Node (i, j) has the
local index ``j*(nx+1) + i``; cell (i, j) has the local index ``j*nx + i`` and the
nodes (i, j), (i+1, j), (i+1, j+1), (i, j+1), counter-clockwise when the corners
are given counter-clockwise.

Sides: ``bottom`` (j = 0), ``right`` (i = nx), ``top`` (j = ny), ``left`` (i = 0).
Side node lists run counter-clockwise around the block (bottom i = 0..nx, right
j = 0..ny, top i = nx..0, left j = ny..0), so the outward normal of the segment
a -> b is (dy, -dx)/|ab|, and segment k of a side joins nodes k and k+1 and
belongs to the k-th entry of the side's cell list.

The outline is four corners (straight sides) or, per side, a polyline from corner
to corner; the interior follows by Coons (transfinite) interpolation, sides
parametrised by normalised arc length, optionally graded by a geometric ratio.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SIDES = ("bottom", "right", "top", "left")


def _polyline_param(points: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points at normalised arc length ``s`` (0..1) along a polyline."""
    seg = np.hypot(*np.diff(points, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    cum /= cum[-1]
    return np.column_stack([np.interp(s, cum, points[:, 0]), np.interp(s, cum, points[:, 1])])


def graded(n: int, ratio: float = 1.0) -> np.ndarray:
    """n+1 parameters in [0, 1], each interval ``ratio`` times the previous one."""
    if abs(ratio - 1.0) < 1e-14:
        return np.linspace(0.0, 1.0, n + 1)
    widths = ratio ** np.arange(n)
    return np.concatenate([[0.0], np.cumsum(widths)]) / widths.sum()


@dataclass
class Block:
    """A structured block: its node coordinates ``x, y`` of shape (ny+1, nx+1)."""

    nx: int
    ny: int
    x: np.ndarray
    y: np.ndarray

    @classmethod
    def from_outline(cls, corners, nx: int, ny: int, sides: dict | None = None,
                     ratio_x: float = 1.0, ratio_y: float = 1.0) -> "Block":
        """Mesh the outline: four corners (i,j) = (0,0), (nx,0), (nx,ny), (0,ny) and
        optional polylines per side (each from its first to its second corner,
        in the counter-clockwise sense of :data:`SIDES`)."""
        c = np.asarray(corners, dtype=float)
        sides = dict(sides or {})
        outline = {
            "bottom": np.array([c[0], c[1]]),
            "right": np.array([c[1], c[2]]),
            "top": np.array([c[3], c[2]]),  # stored left to right (i increasing)
            "left": np.array([c[0], c[3]]),  # stored bottom to top (j increasing)
        }
        for name, pts in sides.items():
            pts = np.asarray(pts, dtype=float)
            if name in ("top", "left"):  # given counter-clockwise: reverse to i/j increasing
                pts = pts[::-1]
            outline[name] = pts
        s = graded(nx, ratio_x)
        t = graded(ny, ratio_y)
        bottom = _polyline_param(outline["bottom"], s)
        top = _polyline_param(outline["top"], s)
        left = _polyline_param(outline["left"], t)
        right = _polyline_param(outline["right"], t)
        S, T = np.meshgrid(s, t)  # (ny+1, nx+1)
        xy = np.empty((ny + 1, nx + 1, 2))
        for k in range(2):
            xy[..., k] = ((1 - T) * bottom[None, :, k] + T * top[None, :, k]
                          + (1 - S) * left[:, None, k] + S * right[:, None, k]
                          - ((1 - S) * (1 - T) * c[0, k] + S * (1 - T) * c[1, k]
                             + S * T * c[2, k] + (1 - S) * T * c[3, k]))
        return cls(nx, ny, xy[..., 0].copy(), xy[..., 1].copy())

    @property
    def n_nodes(self) -> int:
        return (self.nx + 1) * (self.ny + 1)

    @property
    def n_cells(self) -> int:
        return self.nx * self.ny

    def connectivity(self) -> np.ndarray:
        """Local node indices of each cell, shape (nx*ny, 4), counter-clockwise."""
        nx, ny = self.nx, self.ny
        j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
        n0 = j * (nx + 1) + i
        return np.stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1], axis=-1).reshape(-1, 4)

    def side_nodes(self, side: str) -> np.ndarray:
        """Local node indices of a side, counter-clockwise around the block."""
        nx, ny = self.nx, self.ny
        idx = np.arange(self.n_nodes).reshape(ny + 1, nx + 1)
        if side == "bottom":
            return idx[0, :].copy()
        if side == "right":
            return idx[:, nx].copy()
        if side == "top":
            return idx[ny, ::-1].copy()
        if side == "left":
            return idx[::-1, 0].copy()
        raise ValueError(f"unknown side {side!r}: expected one of {SIDES}")

    def side_cells(self, side: str) -> np.ndarray:
        """Local indices of the cells along a side, aligned with the side's segments."""
        nx, ny = self.nx, self.ny
        idx = np.arange(self.n_cells).reshape(ny, nx)
        if side == "bottom":
            return idx[0, :].copy()
        if side == "right":
            return idx[:, nx - 1].copy()
        if side == "top":
            return idx[ny - 1, ::-1].copy()
        if side == "left":
            return idx[::-1, 0].copy()
        raise ValueError(f"unknown side {side!r}: expected one of {SIDES}")
