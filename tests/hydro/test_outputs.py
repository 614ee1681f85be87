"""Outputs: the XDMF index is valid XML pointing at datasets that exist; point probes;
the example decks run."""

import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

from shockfriction.hydro.api import run, run_dict

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_xdmf_points_at_existing_datasets(tmp_path, make_strip):
    deck = make_strip(ny_flyer=4, ny_target=10, end="0.5 us")
    deck["output"] = {"field_times": ["0.2 us", "0.5 us"]}
    run_dict(deck, tmp_path)
    root = ET.parse(tmp_path / "fields.xmf").getroot()
    grids = root.findall(".//Grid[@GridType='Uniform']")
    assert len(grids) == 2
    times = [float(g.find("Time").get("Value")) for g in grids]
    assert times[0] == pytest.approx(0.2e-6, rel=0.05) and times[1] == pytest.approx(0.5e-6, rel=1e-9)
    with h5py.File(tmp_path / "fields.h5") as f:
        for item in root.iter("DataItem"):
            path = item.text.split(":", 1)[1]
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            assert f[path].shape == dims, path


def test_point_probe_follows_the_nearest_node_and_cell(make_strip):
    deck = make_strip(ny_flyer=4, ny_target=10, end="0.3 us")
    deck["probes"] = [{"name": "pt", "body": "target", "at": ["0.01 mm", "0.52 mm"], "quantities": ["y", "p"]},
                      {"name": "nd", "body": "target", "node": [0, 5], "quantities": ["y"]},
                      {"name": "cl", "body": "target", "cell": [0, 5], "quantities": ["p"]}]
    res = run_dict(deck)
    np.testing.assert_array_equal(res.probes["pt.y"], res.probes["nd.y"])
    np.testing.assert_array_equal(res.probes["pt.p"], res.probes["cl.p"])


@pytest.mark.parametrize("name, check", [
    ("pressure_shear_strip.toml", lambda r: r.probes["fs.vx"].max() > 40.0),
    ("taylor_anvil_cu.toml", lambda r: 0.6 < r.probes["top.y"][-1] / 25.4e-3 < 0.75),
    ("cone_impact_axi.toml", lambda r: r.probes["tip.vy"].max() > 40.0),
])
def test_examples_run(name, check, tmp_path):
    res = run(EXAMPLES / name, tmp_path)
    assert res.summary["completed"]
    assert check(res)
    assert res.summary["relative_energy_error"] < 5e-3


def test_max_cycles_stops_and_says_so(make_strip, tmp_path):
    deck = make_strip(ny_flyer=4, ny_target=10)
    deck["time"]["max_cycles"] = 7
    import pytest

    from shockfriction.errors import SimulationError
    with pytest.raises(SimulationError, match="max_cycles"):  # a run cut short is a failure (exit 3)
        run_dict(deck, tmp_path)
    import json
    assert json.loads((tmp_path / "summary.json").read_text())["completed"] is False
