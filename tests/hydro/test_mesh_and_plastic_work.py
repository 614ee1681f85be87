"""Structured blocks (transfinite interpolation, side ordering) and the plastic strain and
work of a homogeneous uniaxial-strain compression."""

import numpy as np
import pytest

from shockfriction.hydro.api import run_dict
from shockfriction.mesh.assembly import Mesh
from shockfriction.mesh.block import Block


def test_straight_block_is_bilinear_and_sides_run_counter_clockwise():
    blk = Block.from_outline([[0, 0], [4, 1], [5, 4], [-1, 3]], 4, 3)
    s, t = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 4))
    c = np.array([[0, 0], [4, 1], [5, 4], [-1, 3]], float)
    bil = ((1 - s) * (1 - t))[..., None] * c[0] + (s * (1 - t))[..., None] * c[1] + (s * t)[..., None] * c[2] \
        + ((1 - s) * t)[..., None] * c[3]
    np.testing.assert_allclose(blk.x, bil[..., 0], atol=1e-14)
    np.testing.assert_allclose(blk.y, bil[..., 1], atol=1e-14)
    mesh = Mesh(["a"], [blk])
    ring = np.concatenate([mesh.side_nodes("a", side)[:-1] for side in ("bottom", "right", "top", "left")])
    px, py = mesh.x[ring], mesh.y[ring]
    area = 0.5 * np.sum(px * np.roll(py, -1) - np.roll(px, -1) * py)
    assert area > 0  # counter-clockwise
    assert len(set(ring.tolist())) == 2 * (4 + 3)
    # cell k of a side lies on segment k of the side
    for side in ("bottom", "right", "top", "left"):
        nodes, cells = mesh.side_nodes("a", side), mesh.side_cells("a", side)
        assert len(cells) == len(nodes) - 1
        for k, c_ in enumerate(cells):
            assert {nodes[k], nodes[k + 1]} <= set(mesh.conn[c_].tolist())


def test_curved_side_is_followed_and_area_converges():
    """A quarter annulus (bored cylinder section) meshed from its outline: the area tends to
    pi (R^2 - r^2)/4 at second order in the number of segments."""
    r_in, r_out = 1.0, 2.0
    errs = []
    for n in (8, 16, 32):
        th = np.linspace(0, np.pi / 2, n + 1)
        outer = np.column_stack([r_out * np.cos(th), r_out * np.sin(th)])
        inner = np.column_stack([r_in * np.cos(th[::-1]), r_in * np.sin(th[::-1])])
        blk = Block.from_outline([[r_in, 0], [r_out, 0], [0, r_out], [0, r_in]], 4, n,
                                 sides={"right": outer, "left": inner})
        np.testing.assert_allclose(np.hypot(blk.x[:, -1], blk.y[:, -1]), r_out, rtol=1e-12)
        conn = blk.connectivity()
        x, y = blk.x.ravel()[conn], blk.y.ravel()[conn]
        area = 0.5 * np.sum((x[:, 2] - x[:, 0]) * (y[:, 3] - y[:, 1]) - (x[:, 3] - x[:, 1]) * (y[:, 2] - y[:, 0]))
        errs.append(abs(area - np.pi * (r_out**2 - r_in**2) / 4))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    print("area errors", errs, "orders", orders)
    assert np.all(orders > 1.9)


def test_uniaxial_strain_plastic_strain_and_energy_balance():
    """One cell squeezed at constant rate between a fixed bottom and a moving top, rollers on
    its sides: eps_p = (2/3)(|ln V/V0| - Y/(2G)) once yielded, and the piston's work is the
    energy gained."""
    y, g = 0.3e9, 27.6e9
    deck = {"time": {"end": "2 us", "dt_max": "2 ns"}, "viscosity": {"quadratic": 0.0, "linear": 0.0},
            "bodies": [{"name": "c", "material": "Al6061-T6", "strength": "elastic-perfectly-plastic",
                        "yield_stress": "0.3 GPa",
                        "mesh": {"corners": [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]],
                                 "nx": 1, "ny": 1},
                        "boundary": {"left": "symmetry", "right": "symmetry", "bottom": "fixed",
                                     "top": {"type": "velocity", "vy": "-10 m/s"}}}]}
    res = run_dict(deck)
    s = res.state
    strain = abs(np.log(s.volume[0] / (1e-3 * 1e-3)))
    expected = 2.0 / 3.0 * (strain - y / (2 * g))
    print(f"strain {strain:.5f}, eps_p {s.eps_p[0]:.6f} (expected {expected:.6f}), "
          f"energy error {res.summary['relative_energy_error']:.1e}")
    assert strain > 0.015
    assert s.eps_p[0] == pytest.approx(expected, rel=2e-3)
    e = res.energy
    assert e["total"][-1] - e["total"][0] == pytest.approx(e["boundary_work"][-1], rel=1e-3)
    # the plastic work Y eps_p heated the cell: T exceeds the isentropic temperature by about Y eps_p/(rho c)
    assert s.temperature[0] - 300.0 > 0.5 * y * s.eps_p[0] / (s.rho[0] * 885.0)
