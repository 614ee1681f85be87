"""Two threads against one, on an idle machine and with a busy-loop process holding one core.

    PYTHONPATH=src python benchmarks/threads.py [--n 200] [--cycles 60] [--repeats 3]
                                                [--policies policy,spin+governor,libgomp-default] [--sizes]

For each waiting policy and each load (none / one busy-loop process pinned to core 0), a fresh
Python process (numba reads the waiting policy when its threading layer starts) times the hydro
cycle of benchmarks/hydro.py's 200 x 200 block on 1 thread (serial kernels) and on 2 threads
(parallel kernels), interleaved (1, 2, 1, 2, ...), and the script prints the median
2-thread/1-thread throughput ratio (target: never below 0.9).  Policies:

* ``policy``: shockfriction.threading_policy as it stands (passive waiting and the thread governor);
* ``spin+governor``: libgomp's default waiting (spin, then sleep) with the governor;
* ``passive-only``: passive waiting without the governor;
* ``libgomp-default``: libgomp's own default (spin 300000 rounds, then sleep), no governor: before the policy;
* ``spin``: ``OMP_WAIT_POLICY=ACTIVE`` (workers never sleep), no governor;
* ``workqueue``: numba's workqueue layer instead of OpenMP, no governor.

``--sizes`` instead prints the ratio against the mesh size on the unloaded machine, the
measurement behind threading_policy.MIN_PARALLEL_CELLS.  Quote the machine's load (printed)
with the numbers: on a shared machine the "idle" case is only as idle as the other jobs allow.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import statistics
import subprocess
import sys
import time

POLICIES = {
    "policy": {},
    "spin+governor": {"GOMP_SPINCOUNT": "300000"},
    "passive-only": {"OMP_WAIT_POLICY": "PASSIVE", "_GOVERNOR": "0"},
    "libgomp-default": {"GOMP_SPINCOUNT": "300000", "_GOVERNOR": "0"},
    "spin": {"OMP_WAIT_POLICY": "ACTIVE", "_GOVERNOR": "0"},
    "workqueue": {"NUMBA_THREADING_LAYER": "workqueue", "_GOVERNOR": "0"},
}


def _busy(core: int) -> None:
    try:
        os.sched_setaffinity(0, {core})
    except (AttributeError, OSError):
        pass
    while True:
        pass


def measure(n: int, cycles: int, threads: int, governor: bool) -> float:
    """Zone-cycles/s of ``cycles`` cycles, with the hooks that run() calls between cycles (the
    thread governor among them, unless ``governor`` is False)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from hydro import deck  # benchmarks/hydro.py

    from shockfriction.hydro.api import prepare
    from shockfriction.threading_policy import ThreadGovernor

    sim = prepare(deck(n, cycles, threads))
    if not governor:
        sim.between_cycles[:] = [h for h in sim.between_cycles if not isinstance(h, ThreadGovernor)]
    start = time.perf_counter()
    for _ in range(cycles):
        sim.step()
        for hook in sim.between_cycles:
            hook(sim)
    return sim.state.n_cells * cycles / (time.perf_counter() - start)


def child(n: int, cycles: int, repeats: int, governor: bool) -> dict:
    """Median zone-cycles/s on 1 and 2 threads, interleaved (runs in its own process)."""
    import numba

    measure(8, 3, 1, governor)  # compile or load the caches outside the timings
    measure(8, 3, 2, governor)
    one, two = [], []
    for _ in range(repeats):
        one.append(measure(n, cycles, 1, governor))
        two.append(measure(n, cycles, 2, governor))
    ratios = [b / a for a, b in zip(one, two)]
    return {"one": statistics.median(one), "two": statistics.median(two), "ratio": statistics.median(ratios),
            "min_ratio": min(ratios), "layer": numba.threading_layer(),
            "wait": os.environ.get("OMP_WAIT_POLICY", "-")}


def run_child(env_extra: dict, n: int, cycles: int, repeats: int) -> dict:
    env = dict(os.environ, **env_extra)
    governor = env.pop("_GOVERNOR", "1")
    env.setdefault("PYTHONPATH", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
    out = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", "--n", str(n), "--cycles",
                          str(cycles), "--repeats", str(repeats), "--governor", governor], env=env, capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def with_load(busy: bool, func):
    proc = None
    if busy:
        proc = mp.Process(target=_busy, args=(0,), daemon=True)
        proc.start()
        time.sleep(0.2)
    try:
        return func()
    finally:
        if proc is not None:
            proc.terminate()
            proc.join()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--cycles", type=int, default=60)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--policies", default="policy,spin+governor,libgomp-default")
    ap.add_argument("--sizes", action="store_true", help="ratio against the mesh size, no busy process")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--governor", default="1", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(child(args.n, args.cycles, args.repeats, args.governor == "1")))
        return
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    if args.sizes:
        for n in (20, 40, 60, 80, 100, 140, 200):
            r = run_child(POLICIES["passive-only"], n, max(args.cycles, int(args.cycles * (200 / n) ** 2 / 4)),
                          args.repeats)
            print(f"{n:4d} x {n:<4d} ({n * n:6d} cells): 2/1 threads = {r['ratio']:.2f} "
                  f"(min {r['min_ratio']:.2f}; 1 thread {r['one']:.3e} zone-cycles/s)", flush=True)
        return
    for name in args.policies.split(","):
        for busy in (False, True):
            r = with_load(busy, lambda: run_child(POLICIES[name], args.n, args.cycles, args.repeats))
            load = "busy process on core 0" if busy else "no busy process      "
            print(f"{name:<16} {load}: 2/1 threads = {r['ratio']:.2f} (min {r['min_ratio']:.2f}; "
                  f"{r['one']:.3e} -> {r['two']:.3e} zone-cycles/s; layer {r['layer']}, "
                  f"OMP_WAIT_POLICY {r['wait']}; load average {os.getloadavg()[0]:.2f})", flush=True)


if __name__ == "__main__":
    main()
