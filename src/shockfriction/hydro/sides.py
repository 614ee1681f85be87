"""Current geometry of a body side, for interfaces (slide lines) and boundary loads.

For the ordered nodes of a side (``Mesh.side_nodes``: counter-clockwise around the body, so
the outward normal of segment a -> b is (y_b - y_a, -(x_b - x_a))/length):

* segment lengths, unit outward normals and unit tangents (a -> b);
* nodal areas consistent with the Galerkin forces: int N_i w ds over the adjacent
  segments, w = 1 (plane strain: m^2 per metre of depth) or w = r (axisymmetric: m^2 per
  radian; times 2 pi for the whole ring).  Per segment (a, b) of length l:
  plane strain l/2 to each node; axisymmetric l (2 r_a + r_b)/6 to a and l (r_a + 2 r_b)/6 to b;
* nodal unit normals: the area-weighted mean of the adjacent segments' normals.

The nodal areas sum exactly to the side's area (length, or int r ds).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class SideGeometry:
    """Geometry of one side at the current positions (arrays along the side)."""

    length: np.ndarray  # (n-1,) segment lengths
    normal: np.ndarray  # (n-1, 2) outward unit normals of the segments
    tangent: np.ndarray  # (n-1, 2) unit tangents a -> b
    node_area: np.ndarray  # (n,) nodal areas (per unit depth or per radian)
    node_normal: np.ndarray  # (n, 2) outward unit normals at the nodes


def side_geometry(x: np.ndarray, y: np.ndarray, nodes: np.ndarray, axisymmetric: bool) -> SideGeometry:
    """Segments and nodal areas/normals of the side through ``nodes`` (global indices, in order)."""
    px, py = x[nodes], y[nodes]
    dx, dy = np.diff(px), np.diff(py)
    length = np.hypot(dx, dy)
    tangent = np.column_stack([dx, dy]) / length[:, None]
    normal = np.column_stack([tangent[:, 1], -tangent[:, 0]])
    area = np.zeros(len(nodes))
    if axisymmetric:
        ra, rb = px[:-1], px[1:]
        wa = length * (2 * ra + rb) / 6.0
        wb = length * (ra + 2 * rb) / 6.0
    else:
        wa = wb = 0.5 * length
    area[:-1] += wa
    area[1:] += wb
    nn = np.zeros((len(nodes), 2))
    nn[:-1] += wa[:, None] * normal
    nn[1:] += wb[:, None] * normal
    norm = np.hypot(nn[:, 0], nn[:, 1])
    # a node on the axis has no area in r-z: give it its segment's normal
    bad = norm <= 0.0
    if np.any(bad):
        seg = np.minimum(np.arange(len(nodes)), len(nodes) - 2)
        nn[bad] = normal[seg[bad]]
        norm[bad] = 1.0
    return SideGeometry(length, normal, tangent, area, nn / norm[:, None])
