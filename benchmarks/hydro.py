"""Zone-cycles per second of the hydrocode on a 200 x 200 plane-strain block.

Al 6061-T6, Mie-Grueneisen EOS and SCG strength (elastic-plastic), hitting a rigid
frictionless wall at 500 m/s (the bottom side is a symmetry plane), so that every kernel
path (viscosity, return mapping with hardening, hourglass) is exercised.  Prints the median
over repeats of zone-cycles/s on one thread (serial kernels) and on all threads (prange
kernels), with min and max.

    PYTHONPATH=src python benchmarks/hydro.py [--n 200] [--cycles 200] [--repeats 5] [--threads 0]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numba


def deck(n: int, cycles: int, threads: int) -> dict:
    return {
        "title": "benchmark", "threads": threads,
        "time": {"end": "1 ms"},  # never reached: measure() steps exactly ``cycles`` cycles
        "bodies": [{"name": "block", "material": "Al6061-T6", "strength": "scg", "velocity": ["0 m/s", "-500 m/s"],
                    "mesh": {"corners": [["0 mm", "0 mm"], ["20 mm", "0 mm"], ["20 mm", "20 mm"], ["0 mm", "20 mm"]],
                             "nx": n, "ny": n},
                    "boundary": {"bottom": "symmetry", "left": "symmetry"}}],
    }


def measure(n: int, cycles: int, threads: int) -> float:
    from shockfriction.hydro.api import prepare

    sim = prepare(deck(n, cycles, threads))
    start = time.perf_counter()
    for _ in range(cycles):  # step() directly: the run guards would (rightly) refuse a 1 ms end at max_cycles
        sim.step()
    wall = time.perf_counter() - start
    return sim.state.n_cells * sim.state.cycle / wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--cycles", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--threads", type=int, default=0, help="threads of the parallel run (0 = all)")
    args = ap.parse_args()
    measure(8, 5, 1)  # compile (or load the cache) outside the timing
    all_threads = args.threads or numba.config.NUMBA_NUM_THREADS
    if all_threads > 1:
        measure(8, 5, all_threads)
    for threads in ([1, all_threads] if all_threads > 1 else [1]):
        rates = [measure(args.n, args.cycles, threads) for _ in range(args.repeats)]
        print(f"{args.n} x {args.n} zones, {args.cycles} cycles, threads = {threads}: "
              f"median {statistics.median(rates):.3e} zone-cycles/s "
              f"(min {min(rates):.3e}, max {max(rates):.3e}, {args.repeats} repeats)")


if __name__ == "__main__":
    main()
