"""The cone-in-cylinder shot rebuilt from examples/cone_in_cylinder.geo (gmsh) against the
block-built deck (examples/cone_in_cylinder.toml, examples/cone_shot.py): the same nodes, and
the same free-surface peak velocities (acceptance: 1%; measured 5e-4 at 400 um cells with
Coulomb friction, 1.1e-5 at 100 um with sub-grid thermoelastic friction)."""

import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from cone_shot import cone_deck
from shockfriction.deck.base import load_deck, validate
from shockfriction.deck.run import RunDeck
from shockfriction.hydro.api import run
from shockfriction.hydro.setup import build_problem

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _gmsh_deck(cell_um: float, law_table: dict, end_us: float) -> RunDeck:
    with open(EXAMPLES / "cone_in_cylinder_gmsh.toml", "rb") as fh:
        d = tomllib.load(fh)
    d["time"]["end"] = f"{end_us} us"
    d.pop("output")
    for b in d["bodies"]:
        b["mesh"]["parameters"] = {"cell_um": cell_um}
    d["slide_lines"][0]["friction"] = law_table
    return validate(RunDeck, d, "gmsh", EXAMPLES)


def test_gmsh_cone_has_the_block_cone_nodes():
    """Full resolution: every body has the block deck's cells and nodes (to the 1e-6 mm of the
    block deck's printed corners), and the slide lines the same node counts."""
    block = build_problem(load_deck(EXAMPLES / "cone_in_cylinder.toml", RunDeck))
    gm = build_problem(load_deck(EXAMPLES / "cone_in_cylinder_gmsh.toml", RunDeck))
    for k in range(3):
        assert block.mesh.names[k] == gm.mesh.names[k]
        s = slice(block.mesh.node_start[k], block.mesh.node_start[k + 1])
        pb = np.column_stack([block.mesh.x[s], block.mesh.y[s]])
        pg = np.column_stack([gm.mesh.x[s], gm.mesh.y[s]])
        assert len(pb) == len(pg)
        assert block.mesh.cell_start[k + 1] == gm.mesh.cell_start[k + 1]
        assert cKDTree(pb).query(pg)[0].max() < 1e-9
    for sl_b, sl_g in zip(block.deck.slide_lines, gm.deck.slide_lines):
        for role in ("guide", "slave"):
            rb, rg = getattr(sl_b, role), getattr(sl_g, role)
            nb = block.mesh.side_nodes(rb.body, rb.side)
            ng = gm.mesh.side_nodes(rg.body, rg.side)
            np.testing.assert_allclose(gm.mesh.x[ng], block.mesh.x[nb], atol=1e-9)
            np.testing.assert_allclose(gm.mesh.y[ng], block.mesh.y[nb], atol=1e-9)
    assert len(gm.constraints.node) == len(block.constraints.node)
    for pb_, pg_ in zip(block.probes, gm.probes):  # the probes sit at the same nodes
        assert (gm.mesh.x[pg_.index], gm.mesh.y[pg_.index]) == pytest.approx(
            (block.mesh.x[pb_.index], block.mesh.y[pb_.index]), abs=1e-9)


def _peaks(res):
    return res.probes["cone_fs.vy"].max(), res.probes["confinement_fs.vy"].max()


def test_coarse_gmsh_cone_matches_the_block_cone():
    """400 um cells, Coulomb mu0 = 0.3, 8 us (566 cycles, about 1 s each once compiled)."""
    table = {"law": "coulomb", "mu0": 0.3}
    block = run(cone_deck(law="coulomb", cell_um=400, end_us=8.0))
    gm = run(_gmsh_deck(400, table, 8.0))
    (cb, fb), (cg, fg) = _peaks(block), _peaks(gm)
    assert cb == pytest.approx(167.0, rel=0.01)
    assert cg == pytest.approx(cb, rel=2e-3)
    assert fg == pytest.approx(fb, rel=2e-3)


@pytest.mark.slow
def test_example_gmsh_cone_matches_the_example_block_cone(tmp_path):
    """The two example decks as shipped (100 um, sub-grid thermoelastic; ~1.5 min each)."""
    block = run(EXAMPLES / "cone_in_cylinder.toml", tmp_path / "block")
    gm = run(EXAMPLES / "cone_in_cylinder_gmsh.toml", tmp_path / "gmsh")
    (cb, fb), (cg, fg) = _peaks(block), _peaks(gm)
    assert cb == pytest.approx(178.1, rel=0.01)
    assert cg == pytest.approx(cb, rel=1e-3)
    assert fg == pytest.approx(fb, rel=1e-3)
