"""Any thread count gives the same bytes (docs/theory/threads.md): the example and verification decks, and a short
cone shot with its slide line and sub-grid columns, stepped on 1 thread (the serial kernels) and on 2, 3 and 4 (the
partitioned parallel kernels: 3 and 4 are more threads than a 2-core machine has, numba runs them all the same, and
give uneven partitions), every state array and every history row equal.  Run in a child process with
``NUMBA_NUM_THREADS=4`` (numba reads it when it starts).  On 2, 3 and 4 threads the slide lines take their
parallel path too (the geometry over the slave nodes), and the staged cycle its parallel node passes (free
velocities, jumps' works, position shifts, positions), whatever the sizes."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

CHILD = r'''
import json, sys
import numba
import numpy as np
import shockfriction.contact.slideline as slideline
import shockfriction.hydro.cycle as cycle
from shockfriction.hydro.api import prepare

# the slide lines' parallel geometry on every line and the staged cycle's parallel node passes on every mesh and
# thread count (the size defaults now; kept here should the sizes from which a run takes them rise above the coarse
# cone shot's lines of 21 and 76 slave nodes and its 2 k nodes)
slideline.PARALLEL_MIN_NODES = 1
cycle.STAGED_PARALLEL_NODES = 0
cycle.STAGED_PARALLEL_THREADS = 2  # and on every thread count above one (as a run does since the short spin)

def state_arrays(sim):
    out = {k: v for k, v in vars(sim.state).items() if isinstance(v, np.ndarray)}
    out["energy_rows"] = np.array(sim.energy_rows)
    out["probe_rows"] = np.array(sim.probe_rows)
    for i, obj in enumerate(sim.interfaces):
        line = getattr(obj, "line", None)
        for k, v in (vars(line).items() if line is not None else ()):
            if isinstance(v, np.ndarray):
                out[f"line{i}.{k}"] = v
    return out

def run(spec, threads, cycles):
    if spec.startswith("cone:"):
        from cone_shot import cone_deck  # examples/cone_shot.py (examples/ is on the child's PYTHONPATH)
        law = spec[5:]
        deck = cone_deck(law, 0.3, 0.7, cell_um=400.0, end_us=1.0, cells=100, threads=threads)
    else:
        deck = spec
    sim = prepare(deck, threads=threads)
    n = 0
    while n < cycles and sim.state.t < sim.t_end * (1 - 1e-12):
        sim.step()
        for hook in sim.between_cycles:  # the governor among them: it may switch kernels, results stay
            hook(sim)
        n += 1
    return sim, state_arrays(sim)

specs, counts, cycles = json.loads(sys.argv[1])
report = {}
for spec in specs:
    base = None
    for t in counts:
        sim, arrays = run(spec, t, cycles)
        if base is None:
            base = arrays
            report[spec] = {"cycles": int(sim.state.cycle), "cells": int(sim.state.n_cells), "diff": [],
                            "parallel": []}
            continue
        report[spec]["parallel"].append(bool(sim.threads > 1))
        for k, v in base.items():
            if not np.array_equal(v, arrays[k], equal_nan=True):
                report[spec]["diff"].append(f"{t} threads: {k}")
print(json.dumps(report))
'''


def _compare(specs: list[str], counts=(1, 2, 3, 4), cycles: int = 60) -> dict:
    env = dict(os.environ, NUMBA_NUM_THREADS="4")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), str(ROOT / "examples")]
                                        + [p for p in [env.get("PYTHONPATH")] if p])
    out = subprocess.run([sys.executable, "-c", CHILD, json.dumps([specs, list(counts), cycles])], env=env,
                         capture_output=True, text=True, timeout=1800)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def _check(report: dict) -> None:
    for spec, r in report.items():
        assert r["cycles"] > 0, spec
        assert all(r["parallel"]), spec  # the parallel kernels ran on 2, 3 and 4 threads
        assert r["diff"] == [], (spec, r["diff"])


def test_thread_counts_give_the_same_bytes():
    decks = [EXAMPLES / "plate_impact_al_250ms.toml", EXAMPLES / "verification" / "sedov_cylindrical.toml",
             EXAMPLES / "pressure_shear_strip.toml"]
    _check(_compare([str(d) for d in decks] + ["cone:coulomb", "cone:subgrid-thermoelastoplastic"], cycles=40))


@pytest.mark.slow
def test_thread_counts_give_the_same_bytes_on_every_deck():
    decks = sorted(EXAMPLES.glob("*.toml")) + sorted((EXAMPLES / "verification").glob("*.toml"))
    decks = [d for d in decks if "gmsh" not in d.name and "sweep" not in d.name]
    _check(_compare([str(d) for d in decks] + ["cone:coulomb", "cone:subgrid-thermoelastic",
                                              "cone:subgrid-thermoelastoplastic"], cycles=120))
