"""Cost of one slide-line cycle (pairing, mortar weights, contact and Coulomb friction sweeps), and of its
pairing and hat-coordinate searches: local (seeded by the previous cycle's segment) against global.

Run: PYTHONPATH=src python benchmarks/contact_slideline.py [N_SLAVE] [N_GUIDE]
     PYTHONPATH=src python benchmarks/contact_slideline.py --search [--cone-cycles 300]

The first form prints milliseconds per cycle and slave node-steps per second (after numba compilation).
``--search`` prints the time per cycle of the searches alone, global (every segment for every node, the
former code) and local (the code now), timed interleaved at the same positions: on the cone shot of
``examples/cone_shot.py`` (100 um cells, both slide lines, at every cycle of its first
``--cone-cycles`` cycles) and on flat rows of growing size (the scaling).  Both searches must give the
same pairs; the script checks it at every timed call.
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from shockfriction.contact.pairing import (guide_chunk_boxes, guide_normal_sign, pair_slave_nodes,
                                           pair_slave_nodes_local, slave_hat_coordinates)
from shockfriction.contact.slideline import SlideLine
from shockfriction.friction.laws import COULOMB, law_parameters


def main(ns: int = 301, ng: int = 201, cycles: int = 200) -> None:
    gx = np.linspace(0.0, 1e-2, ng)
    sx = np.linspace(1e-2, 0.0, ns)
    x = np.concatenate((gx, sx))
    y = np.zeros(x.size)
    guide, slave = np.arange(ng), np.arange(ng, ng + ns)
    mass = np.random.default_rng(0).uniform(1.0, 2.0, x.size) * 1e-4
    vx = np.concatenate((np.zeros(ng), np.full(ns, 100.0)))
    vy = np.concatenate((np.zeros(ng), np.full(ns, -10.0)))
    line = SlideLine("bench", slave, guide, np.arange(ns - 1), np.arange(ng - 1),
                     guide_normal_sign(x, y, guide, 0.5e-2, -1.0), law=COULOMB, law_params=law_parameters(mu0=0.3),
                     x0=x, y0=y)
    line.apply(x, y, vx.copy(), vy.copy(), mass, 1e-9, 0.0)      # compile
    start = time.perf_counter()
    for _ in range(cycles):
        line.apply(x, y, vx.copy(), vy.copy(), mass, 1e-9, 0.0)
    per = (time.perf_counter() - start) / cycles
    print(f"{ns} slave / {ng} guide nodes: {per * 1e3:.3f} ms per cycle, {ns / per:.3g} slave node-steps/s "
          f"(sweeps: normal {line.sweeps_normal}, tangential {line.sweeps_tangential})")


def time_searches(line: SlideLine, x, y) -> tuple[float, float]:
    """Wall time of the global and of the local search (pairing + hat coordinates) of ``line`` at ``x, y``."""
    line.geometry(x, y)        # this cycle's positions into the line's scratch arrays (xs, ys, gx, gy)
    gx, gy, xs, ys, box = (a.copy() for a in line._scratch[:5])
    ns = line.slave.size
    idx = np.arange(ns)
    seed = line.seg.copy()
    nb = [np.zeros(ns) for _ in range(4)]
    nb[0][1:], nb[2][:-1] = np.diff(xs), np.diff(xs)     # neighbour offsets: any will do for timing
    has = np.ones(ns, np.bool_)
    out = {}
    for mode in ("global", "local"):
        res = [seed.copy()] + [np.zeros(ns) for _ in range(6)] + [np.zeros(ns, np.bool_)]
        xi = [np.zeros(ns) for _ in range(3)]
        t0 = time.perf_counter()
        if mode == "global":
            pair_slave_nodes(xs, ys, idx, gx, gy, line.normal_sign, line.max_gap, line.max_penetration, *res)
            slave_hat_coordinates(xs, ys, *nb, has, has, res[0], res[1], res[-1], gx, gy, line.periodic, *xi)
        else:
            pad = guide_chunk_boxes(gx, gy, line.search_chunk, box)
            pair_slave_nodes_local(xs, ys, idx, gx, gy, line.normal_sign, line.max_gap, line.max_penetration,
                                   line.search_chunk, box, pad, *res)
            slave_hat_coordinates(xs, ys, *nb, has, has, res[0], res[1], res[-1], gx, gy, line.periodic, *xi,
                                  line.search_chunk, box, pad)
        out[mode] = (time.perf_counter() - t0, res, xi)
    for a, b in zip(out["global"][1] + out["global"][2], out["local"][1] + out["local"][2]):
        if not np.array_equal(a, b):
            raise SystemExit("local and global searches differ")
    return out["global"][0], out["local"][0]


def search(cone_cycles: int) -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))  # examples/cone_shot.py
    from cone_shot import cone_deck
    from shockfriction.hydro.api import prepare

    sim = prepare(cone_deck("coulomb", 0.3, cell_um=100.0, end_us=8.0))
    lines = [obj.line for obj in sim.interfaces]
    g_all, l_all = [], []
    for cycle in range(cone_cycles):
        sim.step()
        if cycle < 3:
            for line in lines:
                time_searches(line, sim.state.x, sim.state.y)      # compile
            continue
        g = l_ = 0.0
        for line in lines:
            a, b = time_searches(line, sim.state.x, sim.state.y)
            g, l_ = g + a, l_ + b
        g_all.append(g)
        l_all.append(l_)
    sizes = ", ".join(f"{line.name} {line.slave.size} slave / {line.guide.size} guide nodes" for line in lines)
    gm, lm = statistics.median(g_all), statistics.median(l_all)
    print(f"cone shot, 100 um cells ({sizes}), cycles 3-{cone_cycles}: search per cycle (median) "
          f"global {gm * 1e3:.3f} ms, local {lm * 1e3:.3f} ms (x{gm / lm:.1f}); identical pairs and coordinates")
    for n in (300, 1000, 3000, 10000):
        ng = (3 * n) // 4
        gx = np.linspace(0.0, 1e-2, ng)
        rng = np.random.default_rng(1)
        sx = np.linspace(1e-2, 0.0, n) + rng.uniform(-1e-3, 1e-3, n) / n
        x = np.concatenate((gx, sx))
        y = np.concatenate((np.zeros(ng), rng.uniform(-1e-3, 1e-3, n) / n))
        guide, slave = np.arange(ng), np.arange(ng, ng + n)
        line = SlideLine("rows", slave, guide, np.arange(n - 1), np.arange(ng - 1),
                         guide_normal_sign(x, y, guide, 0.5e-2, -1.0), x0=x, y0=y)
        line.geometry(x, y)
        times = [time_searches(line, x, y) for _ in range(5)]
        gm = statistics.median(t[0] for t in times)
        lm = statistics.median(t[1] for t in times)
        print(f"flat rows, {n:5d} slave / {ng:5d} guide nodes: global {gm * 1e3:8.3f} ms, local {lm * 1e3:6.3f} ms "
              f"(x{gm / lm:.0f})")


if __name__ == "__main__":
    if "--search" in sys.argv:
        ap = argparse.ArgumentParser()
        ap.add_argument("--search", action="store_true")
        ap.add_argument("--cone-cycles", type=int, default=300)
        search(ap.parse_args().cone_cycles)
    else:
        main(*(int(a) for a in sys.argv[1:3]))
