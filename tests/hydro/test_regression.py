"""Pinned regression numbers of the example decks (after Laghos: any build must reproduce them).

They are not verification (see the other tests for exact solutions): they catch any change of
the discrete scheme.  Tolerance 1e-9 relative (1e-7 for the 4788-cycle plastic Taylor run:
round-off across platforms); change the numbers only with a reason stated in the commit.
"""

from pathlib import Path

import pytest

from shockfriction.hydro.api import run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_plate_impact_example_is_unchanged():
    r = run(EXAMPLES / "plate_impact_al_250ms.toml")
    assert r.summary["cycles"] == 391
    assert r.energy["kinetic"][-1] == pytest.approx(31.949552547747267, rel=1e-9)
    assert r.energy["internal"][-1] == pytest.approx(1.6297122584285058, rel=1e-9)
    assert r.probes["fs.vy"][-1] == pytest.approx(250.00675487328476, rel=1e-9)
    assert r.probes["mid.p"][200] == pytest.approx(1829458014.8485522, rel=1e-9)
    assert r.state.y.sum() == pytest.approx(0.8987421375008751, rel=1e-12)


def test_taylor_anvil_example_is_unchanged():
    r = run(EXAMPLES / "taylor_anvil_cu.toml")
    # shear viscosity on by default (viscosity.shear = "elastic"); with shear = "off" the former pins
    # hold: 4794 cycles, top.y 0.016968661770002322, foot.x 0.006519944950118737
    assert r.summary["cycles"] == 4792
    assert r.probes["top.y"][-1] == pytest.approx(0.016964169909007624, rel=1e-7)
    assert r.probes["foot.x"][-1] == pytest.approx(0.0065095693671599, rel=1e-7)
    assert r.probes["core.eps_p"][-1] == pytest.approx(1.4962488111469106, rel=1e-7)
    assert r.energy["total"][-1] == pytest.approx(185.27809432681468, rel=1e-7)
