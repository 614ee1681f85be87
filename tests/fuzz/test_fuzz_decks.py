"""Property: whatever is done to an example deck, the command exits 0, 2 or 3; on 2 or 3 with a
one-line message; never a traceback, never a hang (tests/fuzz/deckfuzz.py; a larger campaign:
tests/fuzz/campaign.py)."""

from __future__ import annotations

import sys
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parent))
from deckfuzz import DECKS, MUTATIONS, mutate, run_case


@settings(max_examples=40, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(deck=st.sampled_from(DECKS), kind=st.sampled_from(MUTATIONS), rnd=st.randoms(use_true_random=False))
def test_mutated_example_decks_fail_cleanly(tmp_path_factory, deck, kind, rnd):
    cmd, name = deck
    text = mutate(cmd, name, kind, rnd)
    out = run_case(cmd, text, tmp_path_factory.mktemp("fuzz"), timeout_s=20.0, name=name)
    assert not out.hang, f"{name} {kind}: still running after 20 s"
    assert not out.traceback, f"{name} {kind}: traceback\n{out.stderr[-2000:]}"
    assert out.code in (0, 2, 3), f"{name} {kind}: exit {out.code}\n{out.stderr[-2000:]}"
    if out.code:
        assert out.message, f"{name} {kind}: exit {out.code} without a message"
        assert "internal error" not in out.stderr, f"{name} {kind}: reached the catch-all: {out.message}"
        assert "np.float64(" not in out.stderr, out.message
