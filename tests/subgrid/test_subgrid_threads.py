"""The chapter 8 columns give the same bytes on any thread count: on more than one numba thread their thermal sweep
and interface solve run in one parallel region over blocks of consecutive columns
(``advance_and_solve_parallel``, blocks of whole cache lines), on one thread the serial sweep and solve.  A regime
where every branch of the step runs: plastic columns whose lagged heat the melt guard clips (melt_energy > 0),
sticking columns (no slip) and columns out of contact (idle, inside the swept span), 77 columns; and a load on the
first 20 columns only (as early in the cone shot: the blocks of equal work, ``balanced_blocks``, crowd there and the
last blocks have no swept column).  Child processes with ``NUMBA_NUM_THREADS=4``: 1, 2, 3 and 4 threads."""

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

CHILD = r'''
import hashlib, json, sys
import numba
import numpy as np
from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.friction.subgrid.thermoelastoplastic import solve_in_parallel
from shockfriction.materials.library import get_material

SCRATCH = {"_out", "_idle_val", "_rise"}  # np.empty work arrays of ThermalColumns, not state
out = {}
for threads, front in [(t, fr) for fr in (False, True) for t in (1, 2, 3, 4)]:
    numba.set_num_threads(threads)
    n = 77
    sg = SubgridInterface(n, get_material("Al5083-H111"), get_material("AISI321"), thickness=20e-6, n_cells=120,
                          model="thermoelastoplastic", mu0=0.5, f=0.7)
    v = np.linspace(100.0, 1500.0, n)
    v[::9] = 0.0
    sig = np.full(n, 10e9)
    sig[5::11] = 0.0
    if front:
        sig[20:] = 0.0
        v[20:] = 0.0
    taus = []
    for _ in range(300 if not front else 100):
        tau, _ = sg.step(sig, v, v, np.inf, np.inf, 1.0, 1e-9)
        taus.append(tau)
    h = hashlib.sha256(np.array(taus).tobytes())
    for obj in (sg, sg.columns):
        for k, a in sorted(vars(obj).items()):
            if isinstance(a, np.ndarray) and k not in SCRATCH:
                h.update(k.encode())
                h.update(np.ascontiguousarray(a).tobytes())
    out[f"{threads}{'f' if front else ''}"] = {"hash": h.hexdigest(), "parallel": solve_in_parallel(n),
                    "clipped": int((sg.melt_energy > 0).sum()), "theta_max": float(sg.theta_interface.max())}
print(json.dumps(out))
'''


def test_columns_give_the_same_bytes_on_every_thread_count():
    env = dict(os.environ, NUMBA_NUM_THREADS="4")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src")] + [p for p in [env.get("PYTHONPATH")] if p])
    run = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    print(out)
    assert [out[t]["parallel"] for t in ("1", "2", "3", "4")] == [False, True, True, True]
    assert out["1"]["clipped"] > 0  # the melt guard clipped lagged heat: the sweep's source branch ran
    assert {out[t]["hash"] for t in ("1", "2", "3", "4")} == {out["1"]["hash"]}
    assert {out[t]["hash"] for t in ("1f", "2f", "3f", "4f")} == {out["1f"]["hash"]}


def test_balanced_blocks_share_the_work_on_whole_cache_lines():
    """balanced_blocks: bounds on whole lines of LINE_COLUMNS columns (and the last column), every column in one
    block, each block's work (SWEPT_WEIGHT a swept column, 1 any other) within one line's work of an equal share."""
    import numpy as np

    from shockfriction.friction.subgrid.thermoelastoplastic import LINE_COLUMNS, SWEPT_WEIGHT, balanced_blocks

    for ncol, nblocks, j0, j1 in [(306, 2, 0, 87), (306, 16, 0, 231), (306, 16, 0, 53), (77, 4, 0, 0), (77, 3, 10, 40),
                                  (9, 4, 0, 9), (306, 1, 0, 306)]:
        bounds = np.empty(nblocks + 1, dtype=np.int64)
        balanced_blocks(ncol, j0, j1, bounds)
        assert bounds[0] == 0 and bounds[-1] == ncol and np.all(np.diff(bounds) >= 0)
        assert all(b % LINE_COLUMNS == 0 or b == ncol for b in bounds)
        swept = (np.arange(ncol) >= j0) & (np.arange(ncol) < j1)
        w = np.where(swept, SWEPT_WEIGHT, 1)
        share = w.sum() / nblocks
        work = [w[a:e].sum() for a, e in zip(bounds[:-1], bounds[1:])]
        line = SWEPT_WEIGHT * LINE_COLUMNS
        assert max(work) <= share + line and (nblocks * LINE_COLUMNS > ncol or min(work) >= share - line), work
