"""The threading policy: a short OpenMP spin, the thread count of a request, the governor that
switches between 1 and n threads (results unchanged, bit for bit), and ``threads`` end to end
through the deck and the command line."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
import pytest

from shockfriction import threading_policy as tp
from shockfriction.hydro.api import prepare


def _block(n: int, threads: int, end: str = "0.3 us") -> dict:
    return {"time": {"end": end}, "threads": threads,
            "bodies": [{"name": "b", "material": "Al6061-T6", "strength": "scg", "velocity": ["0 m/s", "-400 m/s"],
                        "mesh": {"corners": [["0 mm", "0 mm"], ["3 mm", "0 mm"], ["3 mm", "3 mm"], ["0 mm", "3.5 mm"]],
                                 "nx": n, "ny": n},
                        "boundary": {"bottom": "fixed", "left": "symmetry"}}]}


def test_short_spin_is_in_the_environment_unless_the_user_chose():
    assert "GOMP_SPINCOUNT" in os.environ or "OMP_WAIT_POLICY" in os.environ
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "KMP_BLOCKTIME", "GOMP_SPINCOUNT")}
    show = "print(os.environ.get('OMP_WAIT_POLICY', '-'), os.environ.get('GOMP_SPINCOUNT', '-'), os.environ['KMP_BLOCKTIME'])"
    cases = {"": ["-", str(tp.SPIN_ROUNDS), "0"],                       # nothing set: the short spin
             "os.environ['OMP_WAIT_POLICY'] = 'ACTIVE'; ": ["ACTIVE", "-", "0"],  # the user's policy is kept
             "os.environ['GOMP_SPINCOUNT'] = '300000'; ": ["-", "300000", "0"]}  # and the user's spin
    for pre, expected in cases.items():
        code = f"import os; {pre}import shockfriction.threading_policy; {show}"
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        assert out.stdout.split() == expected, pre


def test_thread_count_of_a_request():
    cap = numba.config.NUMBA_NUM_THREADS
    assert tp.effective_threads(1, 10**6) == 1
    assert tp.effective_threads(2, 10) == min(2, cap)             # an explicit count is obeyed on any size
    assert tp.effective_threads(10**6, 10**6) == cap
    assert tp.effective_threads(0, tp.MIN_PARALLEL_CELLS - 1) == 1
    assert tp.effective_threads(0, tp.MIN_PARALLEL_CELLS) == min(tp.available_cores(), cap)
    assert prepare(_block(4, 0)).threads == 1 and not prepare(_block(4, 0)).parallel


class _Clock:
    """A fake perf_counter: each cycle lasts ``cost[threads]`` seconds."""

    def __init__(self, gov, cost):
        self.t, self.gov, self.cost = 0.0, gov, cost

    def __call__(self):
        return self.t

    def cycle(self):
        self.t += self.cost[self.gov.current]


@pytest.mark.parametrize("cost, winner", [({2: 1.0, 1: 1.7}, 2), ({2: 1.5, 1: 1.0}, 1)])
def test_governor_keeps_the_faster_count(monkeypatch, cost, winner):
    gov = tp.ThreadGovernor(2, period=20, probe=3)
    clock = _Clock(gov, cost)
    monkeypatch.setattr(tp.time, "perf_counter", clock)
    counts = []
    monkeypatch.setattr(numba, "set_num_threads", counts.append)
    used = []
    for _ in range(60):
        clock.cycle()
        gov()
        used.append(gov.current)
    assert gov.chosen[winner] == 3 and gov.chosen[3 - winner] == 0
    # without a simulation to switch, each change of count goes to numba, one thread included
    changes = [u for prev, u in zip([2] + used, used) if u != prev]
    assert counts == changes and 1 in counts
    # probes alternate 2, 1, 2, 1, 2, 1; then the winner for the rest of each period
    assert used[:7] == [2, 1, 2, 1, 2, 1, winner] and set(used[6:20]) == {winner}


def test_governor_switching_threads_changes_no_result():
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one core")
    deck = _block(16, 2)
    a = prepare(deck)
    a.between_cycles.clear()   # two threads throughout
    a.run()
    b = prepare(deck)
    gov = next(h for h in b.between_cycles if isinstance(h, tp.ThreadGovernor))
    gov.period, gov.probe = 5, 1   # switch often: 2, 1, best, best, best, 2, 1, ...
    seen = set()
    b.between_cycles.append(lambda sim: seen.add((gov.current, sim.parallel)))
    b.run()
    assert seen == {(1, False), (2, True)}  # one thread = the serial kernels
    assert a.state.cycle == b.state.cycle > 20
    for name in ("x", "y", "vx", "vy", "e", "sxx", "sxy", "eps_p", "pressure"):
        assert np.array_equal(getattr(a.state, name), getattr(b.state, name)), name
    # the energy history too (its sums are taken in cell order whatever the count: a restarted run, whose
    # governor picks afresh, writes the same energy.csv), and the serial kernels give the same rows
    assert a.energy_rows == b.energy_rows
    c = prepare(_block(16, 1))
    assert not c.parallel
    c.run()
    assert c.energy_rows == a.energy_rows
    assert np.array_equal(c.state.e, a.state.e)


@pytest.mark.parametrize("deck_threads, option, expected", [(2, None, 2), (1, "2", 2), (2, "0", 1)])
def test_threads_from_the_deck_and_the_command_line(tmp_path, deck_threads, option, expected):
    """``threads`` in the deck, overridden by ``--threads``; 0 on this small mesh = serial kernels."""
    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one core")
    from cone_shot import to_toml

    deck = tmp_path / "deck.toml"
    deck.write_text(to_toml(_block(6, deck_threads, "0.1 us")))
    argv = [sys.executable, "-m", "shockfriction", "run", str(deck), "--out", str(tmp_path / "out")]
    if option is not None:
        argv += ["--threads", option]
    env = dict(os.environ, PYTHONPATH=str(Path(tp.__file__).parents[1]))
    out = subprocess.run(argv, env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["threads"] == expected
