"""Zone-cycles per second of the hydrocode, and its fixed cost per cycle.

Al 6061-T6, Mie-Grueneisen EOS and SCG strength (elastic-plastic), hitting a rigid
frictionless wall at 500 m/s (the bottom side is a symmetry plane), so that every kernel
path (viscosity, shear viscosity, return mapping with hardening, hourglass) is exercised;
default output settings (a history row every cycle).  For each mesh (default 25 x 25,
200 x 200, 800 x 800) it prints the median over repeats of zone-cycles/s on one thread
(serial kernels) and on all threads (prange kernels), and the fixed cost of a cycle on one
thread: the intercept of a least-squares line through the time per cycle of small meshes
(2 x 2 ... 25 x 25) against their zone count.

    PYTHONPATH=src python benchmarks/hydro.py [--sizes 25 200 800] [--zone-cycles 2e6] [--repeats 3]
                                              [--threads 0] [--probe-every 1] [--cpu-time]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba
import numpy as np


def deck(n: int, cycles: int, threads: int, probe_every: int = 1) -> dict:
    return {
        "title": "benchmark", "threads": threads,
        "time": {"end": "1 ms"},  # never reached: measure() steps exactly ``cycles`` cycles
        "output": {"probe_every": probe_every},
        "bodies": [{"name": "block", "material": "Al6061-T6", "strength": "scg", "velocity": ["0 m/s", "-500 m/s"],
                    "mesh": {"corners": [["0 mm", "0 mm"], ["20 mm", "0 mm"], ["20 mm", "20 mm"], ["0 mm", "20 mm"]],
                             "nx": n, "ny": n},
                    "boundary": {"bottom": "symmetry", "left": "symmetry"}}],
    }


def seconds_per_cycle(n: int, cycles: int, threads: int, probe_every: int = 1, warm: int = 3,
                      cpu: bool = False) -> float:
    """Wall time of one cycle (``cpu``: this thread's CPU time, robust on a loaded machine for the
    serial kernels), stepping exactly ``cycles`` cycles after ``warm`` untimed ones."""
    from shockfriction.hydro.api import prepare

    sim = prepare(deck(n, cycles, threads, probe_every))
    for _ in range(warm):  # first touches of the arrays, lazy set-up
        sim.step()
    clock = time.thread_time if cpu else time.perf_counter
    start = clock()
    for _ in range(cycles):  # step() directly: the run guards would (rightly) refuse a 1 ms end at max_cycles
        sim.step()
    return (clock() - start) / cycles


def fixed_cost(threads: int, probe_every: int, repeats: int, cpu: bool) -> tuple[float, float]:
    """(fixed cost s/cycle, cost per zone s) from a line through the small meshes' time per cycle."""
    sizes = [2, 4, 8, 16, 25]
    zones, secs = [], []
    for n in sizes:
        zones.append(n * n)
        secs.append(min(seconds_per_cycle(n, 200, threads, probe_every, cpu=cpu) for _ in range(repeats)))
    slope, intercept = np.polyfit(np.array(zones, float), np.array(secs), 1)
    return float(intercept), float(slope)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[25, 200, 800], help="meshes n x n")
    ap.add_argument("--zone-cycles", type=float, default=2e6, help="zone-cycles per timing (at least 10 cycles)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0, help="threads of the parallel run (0 = all)")
    ap.add_argument("--probe-every", type=int, default=1, help="history row every N cycles (deck default 1)")
    ap.add_argument("--cpu-time", action="store_true",
                    help="time the one-thread runs and the fit by this thread's CPU time (shared machines)")
    args = ap.parse_args()
    all_threads = args.threads or numba.config.NUMBA_NUM_THREADS
    thread_counts = [1, all_threads] if all_threads > 1 else [1]
    for threads in thread_counts:  # compile (or load the cache) outside the timing
        seconds_per_cycle(8, 5, threads, args.probe_every)
    print(f"hydro cycle, SCG Al block on a wall, history every {args.probe_every} cycle(s); "
          f"zone-cycles/s, median of {args.repeats} (min-max)")
    for n in args.sizes:
        cycles = max(10, int(args.zone_cycles / (n * n)))
        for threads in thread_counts:
            cpu = args.cpu_time and threads == 1
            rates = [n * n / seconds_per_cycle(n, cycles, threads, args.probe_every, cpu=cpu)
                     for _ in range(args.repeats)]
            print(f"  {n:4d} x {n:<4d} {cycles:5d} cycles  threads = {threads:2d}: {statistics.median(rates):.3e} "
                  f"({min(rates):.3e} - {max(rates):.3e}){' CPU time' if cpu else ''}", flush=True)
    fixed, per_zone = fixed_cost(1, args.probe_every, args.repeats, args.cpu_time)
    print(f"  one thread, fit of time per cycle on 4 ... 625 zones: fixed cost {fixed * 1e6:.1f} us/cycle, "
          f"{per_zone * 1e9:.1f} ns per zone-cycle{' (CPU time)' if args.cpu_time else ''}")


if __name__ == "__main__":
    main()
