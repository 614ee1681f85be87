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


def test_side_geometry_areas_and_normals():
    """Nodal areas of a side sum to its length (plane strain) or to int r ds (r-z: the lateral
    area of a cylinder / the disc of a face per radian); normals point outwards."""
    from shockfriction.hydro.sides import side_geometry

    blk = Block.from_outline([[0, 0], [2, 0], [2, 3], [0, 3]], 4, 6)
    mesh = Mesh(["a"], [blk])
    right = side_geometry(mesh.x, mesh.y, mesh.side_nodes("a", "right"), False)
    assert right.node_area.sum() == pytest.approx(3.0, rel=1e-14)
    np.testing.assert_allclose(right.node_normal, [[1.0, 0.0]] * 7, atol=1e-14)
    top = side_geometry(mesh.x, mesh.y, mesh.side_nodes("a", "top"), True)
    assert top.node_area.sum() == pytest.approx(2.0**2 / 2, rel=1e-14)  # int_0^2 r dr
    np.testing.assert_allclose(top.node_normal, [[0.0, 1.0]] * 5, atol=1e-14)
    assert top.node_area[-1] == pytest.approx(0.5 * 0.5 / 6, rel=1e-14)  # axis node: int N r ds
    side = side_geometry(mesh.x, mesh.y, mesh.side_nodes("a", "right"), True)
    assert side.node_area.sum() == pytest.approx(2.0 * 3.0, rel=1e-14)  # r L
    np.testing.assert_allclose(side.tangent, [[0.0, 1.0]] * 6, atol=1e-14)


@pytest.mark.parametrize("modulus", ["constant", "pressure-temperature"])
def test_scg_elastic_modulus_choice(modulus):
    """Elastic uniaxial strain of one cell: syy = -(4/3) int G d(ln V) with G = G0 (thesis eq. 3.41,
    elastic_modulus = "constant") or G(P, T) = G0 (1 + g P - h (T - 300)) exp(-xi T/(T_F - T))."""
    from shockfriction.materials.library import get_material
    al = get_material("Al5083-H111")
    deck = {"time": {"end": "1 us", "dt_max": "1 ns"}, "viscosity": {"quadratic": 0.0, "linear": 0.0},
            "bodies": [{"name": "c", "material": "Al5083-H111", "strength": "scg", "elastic_modulus": modulus,
                        "mesh": {"corners": [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]],
                                 "nx": 1, "ny": 1},
                        "boundary": {"left": "symmetry", "right": "symmetry", "bottom": "fixed",
                                     "top": {"type": "velocity", "vy": "-1 m/s"}}}],
            "probes": [{"name": "c", "body": "c", "cell": [0, 0], "quantities": ["syy", "p", "T", "rho"]}]}
    res = run_dict(deck)
    p = res.probes
    strain = np.log(p["c.rho"] / al.rho0)  # = -ln(V/V0) > 0 in compression
    assert res.state.eps_p[0] == 0.0 and strain[-1] > 9e-4
    if modulus == "constant":
        g = np.full_like(strain, al.G0)
    else:
        t = p["c.T"]
        g = al.G0 * (1 + al.scg_g * p["c.p"] - al.scg_h * (t - 300.0)) * np.exp(
            -al.scg_xi * t / (al.melting_temperature - t))
    # the predictor uses G(P^n, T^n) over the step n -> n+1 (explicit): a left Riemann sum
    expected = -(4.0 / 3.0) * np.concatenate([[0.0], np.cumsum(g[:-1] * np.diff(strain))])
    print(f"{modulus}: syy {p['c.syy'][-1]:.6e}, expected {expected[-1]:.6e}")
    assert p["c.syy"][-1] == pytest.approx(expected[-1], rel=1e-5)
    if modulus != "constant":  # the pressure stiffening is visible
        assert g[-1] > 1.003 * al.G0


def test_closed_form_axisymmetric_integrals_equal_gauss_quadrature():
    from shockfriction.hydro.geometry import bvec_axi, bvec_axi_gauss

    rng = np.random.default_rng(7)
    for _ in range(50):
        x = np.array([1.0, 2.0, 2.2, 0.9]) + 0.3 * rng.random(4)
        y = np.array([0.0, 0.1, 1.0, 1.1]) + 0.3 * rng.random(4)
        a = np.array(bvec_axi(*x, *y))
        b = np.array(bvec_axi_gauss(*x, *y))
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-13 * np.abs(b).max())
