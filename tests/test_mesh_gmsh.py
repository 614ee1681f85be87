"""gmsh meshes: the reader (counts, areas, orientation, side paths, points), the deck's mesh-file
bodies (named sides as boundaries, ties, slide lines, probes; errors exit 2), and a run on a
gmsh mesh that reproduces the same run on block meshes."""

import numpy as np
import pytest

from shockfriction.deck.base import validate
from shockfriction.deck.run import RunDeck
from shockfriction.errors import DeckError
from shockfriction.hydro.api import run
from shockfriction.hydro.setup import build_problem
from shockfriction.mesh.gmsh import FileBlock, MeshFileError, read_mesh_file

# left: [0,2]x[0,1] mapped 4x2; right: [2,3]x[0,1] shares the curve x = 2 (coincident nodes);
# free: a recombined unstructured (frontal) quad mesh of a pentagon (area 3); tri: triangles.
GEO = """
Geometry.AutoCoherence = 0;
If (!Exists(n)) n = 2; EndIf
Point(1) = {0,0,0}; Point(2) = {2,0,0}; Point(3) = {2,1,0}; Point(4) = {0,1,0};
Point(6) = {3,0,0}; Point(7) = {3,1,0};
Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,1};
Line(5) = {2,6}; Line(6) = {6,7}; Line(7) = {7,3};
Curve Loop(1) = {1,2,3,4}; Plane Surface(1) = {1};
Curve Loop(2) = {5,6,7,-2}; Plane Surface(2) = {2};
Transfinite Curve{1,3} = 2*n+1; Transfinite Curve{2,4,6} = n+1; Transfinite Curve{5,7} = 3;
Transfinite Surface{1}; Transfinite Surface{2}; Recombine Surface{1,2};
Point(11) = {5,0,0,0.3}; Point(12) = {7,0,0,0.3}; Point(13) = {7,1,0,0.3}; Point(14) = {6,2,0,0.3};
Point(15) = {5,1,0,0.3};
Line(11) = {11,12}; Line(12) = {12,13}; Line(13) = {13,14}; Line(14) = {14,15}; Line(15) = {15,11};
Curve Loop(3) = {11,12,13,14,15}; Plane Surface(3) = {3}; Recombine Surface{3};
Point(21) = {10,0,0,0.5}; Point(22) = {11,0,0,0.5}; Point(23) = {10,1,0,0.5};
Line(21) = {21,22}; Line(22) = {22,23}; Line(23) = {23,21};
Curve Loop(4) = {21,22,23}; Plane Surface(4) = {4};
Physical Surface("left") = {1}; Physical Surface("right") = {2}; Physical Surface("free") = {3};
Physical Surface("tri") = {4};
Physical Curve("mid") = {2}; Physical Curve("bottom") = {1,5}; Physical Curve("top") = {3,7};
Physical Curve("roof") = {13,14}; Physical Curve("base") = {11}; Physical Curve("outline") = {1,2,3,4};
Physical Point("corner") = {3};
"""


@pytest.fixture(scope="module")
def geo(tmp_path_factory):
    path = tmp_path_factory.mktemp("gmsh") / "parts.geo"
    path.write_text(GEO)
    return path


@pytest.fixture(scope="module")
def data(geo):
    return read_mesh_file(geo, scale=1e-3)


def _areas(blk):
    c = blk.connectivity()
    x, y = blk.x[c], blk.y[c]
    return 0.5 * ((x[:, 0] - x[:, 2]) * (y[:, 1] - y[:, 3]) - (x[:, 1] - x[:, 3]) * (y[:, 0] - y[:, 2]))


def test_counts_areas_and_orientation(data):
    left, right, free = FileBlock(data, "left"), FileBlock(data, "right"), FileBlock(data, "free")
    assert (left.n_cells, left.n_nodes) == (8, 15)
    assert (right.n_cells, right.n_nodes) == (4, 9)
    for blk, area in ((left, 2e-6), (right, 1e-6), (free, 3e-6)):  # mm^2 -> m^2 (scale 1 mm)
        a = _areas(blk)
        assert np.all(a > 0.0)  # counter-clockwise cells
        assert a.sum() == pytest.approx(area, rel=1e-12)
    assert free.n_cells > 10 and free.nx is None


def test_sides_run_counter_clockwise_with_their_cells(data):
    left, right = FileBlock(data, "left"), FileBlock(data, "right")
    # the shared curve x = 2: up along the left body (its right side), down along the right body
    m_l, m_r = left.side_nodes("mid"), right.side_nodes("mid")
    np.testing.assert_allclose(left.x[m_l], 2e-3)
    np.testing.assert_allclose(left.y[m_l], [0.0, 0.5e-3, 1e-3])
    np.testing.assert_allclose(right.y[m_r], [1e-3, 0.5e-3, 0.0])
    # a group over two bodies: each body sees its own piece; along +x on the bottom
    b = left.side_nodes("bottom")
    np.testing.assert_allclose(left.x[b], np.linspace(0, 2e-3, 5))
    np.testing.assert_allclose(right.x[right.side_nodes("bottom")], [2e-3, 2.5e-3, 3e-3])
    np.testing.assert_allclose(left.x[left.side_nodes("top")], np.linspace(2e-3, 0, 5))
    # segment k lies on cell k: both its nodes belong to the cell
    for blk, side in ((left, "mid"), (left, "bottom"), (right, "top")):
        nodes, cells = blk.side_nodes(side), blk.side_cells(side)
        assert cells.size == nodes.size - 1
        conn = blk.connectivity()
        for k, c in enumerate(cells):
            assert {nodes[k], nodes[k + 1]} <= set(conn[c].tolist())
    # a closed side repeats its first node; a side spanning two curves is one path
    loop = left.side_nodes("outline")
    assert loop[0] == loop[-1] and loop.size == 13
    free = FileBlock(data, "free")
    roof = free.side_nodes("roof")
    assert (free.x[roof[0]], free.y[roof[0]]) == pytest.approx((7e-3, 1e-3))
    assert (free.x[roof[-1]], free.y[roof[-1]]) == pytest.approx((5e-3, 1e-3))
    assert left.point("corner") == pytest.approx((2e-3, 1e-3))
    assert sorted(left.side_names) == ["bottom", "mid", "outline", "top"]


def test_reader_refuses_triangles_and_unknown_groups(data, geo):
    with pytest.raises(MeshFileError, match="triangle"):
        FileBlock(data, "tri")
    with pytest.raises(MeshFileError, match="no physical surface named 'nope'"):
        FileBlock(data, "nope")
    with pytest.raises(KeyError, match="does not touch body 'left'"):
        FileBlock(data, "left").side_nodes("roof")
    assert read_mesh_file(geo, 1.0, {"n": 4}).quads["left"].shape == (32, 4)  # .geo parameters


def _deck(geo, **over):
    body = {"name": "a", "material": "Al6061-T6", "velocity": ["100 m/s", "0 m/s"],
            "mesh": {"file": geo.name, "group": "left", "scale": "1 mm"}, "boundary": {"bottom": "symmetry"}}
    body.update(over)
    return {"time": {"end": "0.1 us"}, "bodies": [body]}


def test_deck_resolves_the_file_against_the_deck_folder_and_names_errors(geo):
    deck = validate(RunDeck, _deck(geo), "d", geo.parent)
    assert deck.bodies[0].from_file and deck.bodies[0].mesh.file == str(geo.resolve())
    problem = build_problem(deck)
    assert problem.mesh.n_cells == 8
    with pytest.raises(DeckError, match=r"mesh.file = 'parts.geo': expected an existing mesh file"):
        validate(RunDeck, _deck(geo), "d", geo.parent / "elsewhere")
    bad = {
        "triangle": _deck(geo, mesh={"file": geo.name, "group": "tri"}),
        "no physical curve named 'wall'": _deck(geo, boundary={"wall": "fixed"}),
        "its nodes and cells have no": dict(_deck(geo), probes=[{"name": "p", "body": "a", "node": [0, 0],
                                                                 "quantities": ["vx"]}]),
        "no physical point named 'tip'": dict(_deck(geo), probes=[{"name": "p", "body": "a", "point": "tip",
                                                                   "quantities": ["vx"]}]),
    }
    for message, d in bad.items():
        with pytest.raises(DeckError, match=message):
            build_problem(validate(RunDeck, d, "d", geo.parent), "d")
    block = {"name": "b", "material": "Al6061-T6",
             "mesh": {"corners": [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]],
                      "nx": 1, "ny": 1}, "boundary": {"wall": "fixed"}}
    with pytest.raises(DeckError, match="a block body has only the sides"):
        validate(RunDeck, dict(_deck(geo), bodies=[block]), "d", geo.parent)


IMPACT_GEO = """
Geometry.AutoCoherence = 0;
Point(1) = {0,0,0}; Point(2) = {1,0,0}; Point(3) = {1,2,0}; Point(4) = {0,2,0};
Point(5) = {0,2,0}; Point(6) = {1,2,0}; Point(7) = {1,2.5,0}; Point(8) = {0,2.5,0};
Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,1};
Line(5) = {5,6}; Line(6) = {6,7}; Line(7) = {7,8}; Line(8) = {8,5};
Curve Loop(1) = {1,2,3,4}; Plane Surface(1) = {1}; Curve Loop(2) = {5,6,7,8}; Plane Surface(2) = {2};
Transfinite Curve{1,3} = 5; Transfinite Curve{2,4} = 11; Transfinite Curve{5,7} = 4; Transfinite Curve{6,8} = 4;
Transfinite Surface{1}; Transfinite Surface{2}; Recombine Surface{1,2};
Physical Surface("target") = {1}; Physical Surface("flyer") = {2};
Physical Curve("target_top") = {3}; Physical Curve("flyer_bottom") = {5};
Physical Curve("target_axis") = {4}; Physical Curve("flyer_axis") = {8};
Physical Point("back") = {1};
"""


def test_run_on_a_gmsh_mesh_reproduces_the_block_mesh(tmp_path):
    """Axisymmetric flyer (3x3) on a target (4x10), non-matching, frictionless slide line:
    the same nodes as mapped blocks, numbered differently -> the same histories to round-off."""
    (tmp_path / "impact.geo").write_text(IMPACT_GEO)

    def body(name, group, corners, nx, ny, v, side):
        b = {"name": name, "material": "Al6061-T6", "strength": "elastic-perfectly-plastic",
             "velocity": ["0 m/s", v]}
        if corners is None:
            b["mesh"] = {"file": "impact.geo", "group": group, "scale": "1 mm"}
            b["boundary"] = {side: "symmetry"}
        else:
            b["mesh"] = {"corners": [[f"{x} mm", f"{y} mm"] for x, y in corners], "nx": nx, "ny": ny}
            b["boundary"] = {"left": "symmetry"}
        return b

    decks = {}
    for kind in ("block", "gmsh"):
        file = kind == "gmsh"
        decks[kind] = {
            "geometry": "axisymmetric", "time": {"end": "0.4 us"},
            "bodies": [body("target", "target", None if file else [(0, 0), (1, 0), (1, 2), (0, 2)], 4, 10,
                            "0 m/s", "target_axis"),
                       body("flyer", "flyer", None if file else [(0, 2), (1, 2), (1, 2.5), (0, 2.5)], 3, 3,
                            "-300 m/s", "flyer_axis")],
            "slide_lines": [{"name": "impact", "guide": {"body": "target", "side": "target_top" if file else "top"},
                             "slave": {"body": "flyer", "side": "flyer_bottom" if file else "bottom"}}],
            "probes": [{"name": "back", "body": "target", **({"point": "back"} if file else {"node": [0, 0]}),
                        "quantities": ["vy"]},
                       {"name": "mid", "body": "target", "at": ["0.3 mm", "1.1 mm"], "quantities": ["p", "vx"]}],
        }
    res = {k: run(validate(RunDeck, d, k, tmp_path)) for k, d in decks.items()}
    a, b = res["block"].probes, res["gmsh"].probes
    assert res["block"].summary["cycles"] == res["gmsh"].summary["cycles"]
    for key in ("back.vy", "mid.p", "mid.vx"):
        scale = np.abs(a[key]).max()
        assert scale > 0.0
        np.testing.assert_allclose(b[key], a[key], rtol=0, atol=1e-9 * scale)


def test_unstructured_recombined_mesh_runs(geo):
    """The pentagon's frontal/recombined quads (no (i, j) structure): a free body in uniform motion
    stays in uniform motion (patch test), and an impact on its fixed base conserves energy."""
    free = {"name": "p", "material": "Al6061-T6", "strength": "elastic-perfectly-plastic",
            "velocity": ["30 m/s", "-200 m/s"], "mesh": {"file": geo.name, "group": "free", "scale": "1 mm"}}
    res = run(validate(RunDeck, {"time": {"end": "0.3 us"}, "bodies": [free]}, "d", geo.parent))
    np.testing.assert_allclose(res.state.vx, 30.0, rtol=1e-12)
    np.testing.assert_allclose(res.state.vy, -200.0, rtol=1e-12)
    assert np.abs(res.state.pressure).max() < 1e-3
    hit = dict(free, boundary={"base": "fixed"})
    res = run(validate(RunDeck, {"time": {"end": "0.12 us"}, "bodies": [hit]}, "d", geo.parent))
    assert res.state.pressure.max() > 1e9  # the impact shock (rho c v ~ 3 GPa), not yet reflected
    # measured 3.1e-3; a 6x5 (12x10) block of the same size and impact gives 6.8e-3 (4.0e-3)
    assert res.summary["relative_energy_error"] < 5e-3
