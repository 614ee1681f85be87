"""Bad decks exit with status 2; a tangled mesh stops with a SimulationError that
says where (body, cell) and when (cycle, time), and the histories stay readable."""

import numpy as np
import pytest

from shockfriction.cli import main
from shockfriction.errors import DeckError, SimulationError
from shockfriction.hydro.api import prepare, run_simulation


BAD_DECK = """
[time]
end = "1 us"
[[bodies]]
name = "plate"
material = "Al6061-T6"
velocity = ["0 m/s", "250"]
[bodies.mesh]
corners = [["0 mm", "0 mm"], ["1 mm", "0 mm"], ["1 mm", "1 mm"], ["0 mm", "1 mm"]]
nx = 2
ny = 2
"""


def test_bad_deck_exits_2_naming_the_field(tmp_path, capsys):
    deck = tmp_path / "bad.toml"
    deck.write_text(BAD_DECK)
    with pytest.raises(SystemExit) as exc:
        main(["run", str(deck), "--out", str(tmp_path / "out"), "-q"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "bodies[0].velocity" in err and "'250'" in err and "velocity" in err


def test_clockwise_corners_are_a_deck_error(make_strip):
    d = make_strip()
    c = d["bodies"][0]["mesh"]["corners"]
    d["bodies"][0]["mesh"]["corners"] = c[::-1]
    with pytest.raises(DeckError, match="counter-clockwise"):
        prepare(d)


def test_tangled_mesh_raises_simulation_error_with_place_and_time(make_strip, tmp_path):
    d = make_strip(ny_flyer=4, ny_target=10, end="1 us")
    sim = prepare(d)
    s = sim.state
    # throw one interior target node across its neighbour within the first step
    node = sim.mesh.node_index("target", 0, 5)
    s.vy[node] = -0.3e-3 / s.dt
    with pytest.raises(SimulationError) as exc:
        run_simulation(sim, tmp_path / "out")
    msg = str(exc.value)
    print(msg)
    assert "body 'target'" in msg and "cell (0, 4)" in msg and "cycle 0" in msg and "t = 0.0" in msg
    # what was written is readable
    header = (tmp_path / "out" / "energy.csv").read_text().splitlines()[0]
    assert header.startswith("t [s],kinetic [J/m]")
    assert (tmp_path / "out" / "summary.json").exists()
    rows = np.genfromtxt(tmp_path / "out" / "probes.csv", delimiter=",", skip_header=1)
    assert np.all(np.isfinite(rows))


def test_cli_run_writes_every_output(tmp_path):
    from pathlib import Path
    deck = Path(__file__).resolve().parents[2] / "examples" / "plate_impact_al_250ms.toml"
    with pytest.raises(SystemExit) as exc:
        main(["run", str(deck), "--out", str(tmp_path), "-q"])
    assert exc.value.code == 0
    for name in ("probes.csv", "energy.csv", "summary.json", "fields.h5", "fields.xmf"):
        assert (tmp_path / name).exists(), name
    import json
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["completed"] and s["cycles"] > 100 and s["relative_energy_error"] < 1e-3
    import h5py
    with h5py.File(tmp_path / "fields.h5") as f:
        steps = sorted(k for k in f if k.startswith("step_"))
        assert len(steps) == 6  # 0, 0.5, ..., 2.5 us
        assert f[steps[-1]]["p"].shape == f["connectivity"].shape[:1]


@pytest.mark.parametrize("edit, fragment", [
    (lambda d: d["bodies"][1]["boundary"].update(left="periodic", right="free"),
     "periodic must be given on both left and right"),
    (lambda d: d["bodies"][1]["mesh"].update(nx=2), "the sides have 2 and 3 nodes"),
    (lambda d: d["ties"][0].update(sides=["flyer.top", "target.top"]), "do not coincide"),
    (lambda d: d["bodies"][1].update(material="Unobtainium"), "unknown material"),
    (lambda d: d["probes"][0].update(node=[5, 0]), "probes[0].node"),
    (lambda d: d["bodies"][1].update(eos="ideal-gas", material=None), "needs density and gamma"),
    (lambda d: d["bodies"][1]["mesh"].update(sides={"right": [["0.1 mm", "0 mm"], ["0.2 mm", "0.5 mm"],
                                                              ["0.1 mm", "1 mm"]]}),
     "'symmetry' needs a straight side"),
    (lambda d: d["time"].update(end="-1 us"), "time.end"),
    (lambda d: d.update(geometry="spherical"), "geometry"),
])
def test_bad_decks_name_field_and_expectation(make_strip, edit, fragment):
    d = make_strip(ny_flyer=4, ny_target=10)
    edit(d)
    with pytest.raises(DeckError) as exc:
        prepare(d)
    print(exc.value)
    assert fragment in str(exc.value)
