"""Every example sweep and fit file of examples/calibration reads and validates against the current decks."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from shockfriction.deck.base import read_toml
from shockfriction.sweep.engine import plan
from shockfriction.sweep.fit import FitProblem
from shockfriction.sweep.fitspec import load_fit

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples" / "calibration").glob("*.toml"))


def test_there_are_sweep_and_fit_examples():
    names = [p.name for p in EXAMPLES]
    assert any("sweep" in n or "grid" in n or "lhs" in n for n in names) and any("fit" in n for n in names)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_validates(path):
    raw = read_toml(path)
    if "dataset" in raw or "measured" in raw:
        spec, here = load_fit(path)
        with ThreadPoolExecutor(1) as ex:
            prob = FitProblem(spec, here, ex, str(path))  # reads the records, validates the decks, runs nothing
        assert prob.runs == 0 and all(len(d.t_m) > 10 for d in prob.data)
    else:
        spec, kind, runs = plan(path)
        assert kind in ("run", "subgrid") and len(runs) >= 4
