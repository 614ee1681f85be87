"""Strong scaling of the hydro cycle and the cone shot on 1, 2, 4, ... threads; and two threads against one under load.

    PYTHONPATH=src python benchmarks/threads.py [--sizes 200 800] [--threads 1 2 4 8 16] [--repeat 3]
                                                [--cone-end-time 8] [--cone-laws coulomb subgrid-thermoelastoplastic]
                                                [--zone-cycles 1e7] [--governor]
    PYTHONPATH=src python benchmarks/threads.py --policies policy[,spin+governor,...] [--n 200] [--cycles 60]
    PYTHONPATH=src python benchmarks/threads.py --size-sweep

**Scaling** (the default): in one process, for each mesh n x n of benchmarks/hydro.py's block (SCG Al on a wall,
a history row every cycle) a simulation per thread count (threads = 1: the serial kernels; n > 1: the partitioned
parallel kernels, ``numba.set_num_threads(n)``), stepped ``--zone-cycles`` / n^2 cycles per timing, the counts
interleaved (1, 2, 4, ..., 1, 2, 4, ...) so that a change of the machine's load hits them alike; then the cone shot
of examples' cone_in_cylinder (100 um cells, examples/cone_shot.py, Coulomb and thermoelastoplastic
sub-grid columns) to ``--cone-end-time`` microseconds with ``run_simulation``, each count in turn, the laws
interleaved within each repeat.  The thread
governor is off (the kernels' own scaling) unless ``--governor``.  For each case it prints the median rate (or
wall time), the speed-up over one thread (of the medians), the parallel efficiency (speed-up / threads), the
*paired* speed-up (the median over repeats of each repeat's ratio to its own one-thread timing: the counts of a
repeat run back to back, so a change of this shared machine's speed between repeats cancels) and the serial fraction
``s`` of an Amdahl fit, speed-up(p) = 1 / (s + (1 - s) / p) (least squares on 1 / speed-up).  Default thread counts:
1, 2, 4, ... up to the cores this process may use, and that count.

**Policies** (``--policies``): for each waiting policy and each load (none / one busy-loop process pinned to core
0), a fresh Python process (numba reads the waiting policy when its threading layer starts) times the hydro cycle
of the ``--n`` block on 1 thread (serial kernels) and on 2 threads (parallel kernels), interleaved, and prints the
median 2-thread/1-thread throughput ratio (target: never below 0.9).  Policies:

* ``policy``: shockfriction.threading_policy as it stands (a short spin, ``GOMP_SPINCOUNT`` 10000 rounds, and the
  thread governor);
* ``spin+governor``: libgomp's default waiting (spin 300000 rounds, then sleep) with the governor;
* ``passive+governor``: no spin (``OMP_WAIT_POLICY=PASSIVE``: the policy before 0.4) with the governor;
* ``spin100k+governor``: a spin ten times the policy's (``GOMP_SPINCOUNT`` 100000 rounds) with the governor;
* ``spin-only``: the policy's short spin without the governor (what ``--size-sweep`` runs unless
  ``--sweep-policy`` names another);
* ``passive-only``: passive waiting without the governor;
* ``libgomp-default``: libgomp's own default (spin 300000 rounds, then sleep), no governor: before the policy;
* ``spin``: ``OMP_WAIT_POLICY=ACTIVE`` (workers never sleep), no governor;
* ``workqueue``: numba's workqueue layer instead of OpenMP, no governor.

``--size-sweep`` prints the 2/1 ratio against the mesh size on the unloaded machine, the measurement behind
threading_policy.MIN_PARALLEL_CELLS.  Quote the machine's load (printed) with the numbers: on a shared machine
the "idle" case is only as idle as the other jobs allow.
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
    "passive+governor": {"OMP_WAIT_POLICY": "PASSIVE"},
    "spin100k+governor": {"GOMP_SPINCOUNT": "100000"},
    "spin-only": {"_GOVERNOR": "0"},
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
    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "KMP_BLOCKTIME")}
    env.update(env_extra)
    governor = env.pop("_GOVERNOR", "1")
    env.setdefault("PYTHONPATH", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src"))
    out = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", "--n", str(n), "--cycles",
                          str(cycles), "--repeat", str(repeats), "--governor-child", governor], env=env, capture_output=True, text=True,
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


def _cpu_name() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "?"


def amdahl_serial_fraction(threads: list[int], speedups: list[float]) -> float:
    """s of speed-up(p) = 1 / (s + (1 - s) / p), least squares on 1 / speed-up - 1 / p = s (1 - 1 / p)."""
    num = den = 0.0
    for p, sp in zip(threads, speedups):
        if p > 1:
            a = 1.0 - 1.0 / p
            num += (1.0 / sp - 1.0 / p) * a
            den += a * a
    return num / den if den else float("nan")


def paired_speedup(values: dict, t: int, base: int, higher_is_faster: bool) -> float:
    """The median over rounds of the speed-up of ``t`` threads against ``base`` threads in the same round (the
    counts run one after the other in each round, so a change of the machine's speed between rounds cancels)."""
    pairs = [(a / b if higher_is_faster else b / a) for a, b in zip(values[t], values[base])]
    return statistics.median(pairs)


def _table(title: str, threads: list[int], values: dict, unit: str, higher_is_faster: bool) -> None:
    one = 1 if 1 in values else threads[0]
    base = statistics.median(values[one])
    print(title)
    print(f"  {'threads':>7}  {unit:>14}  {'speed-up':>8}  {'efficiency':>10}  {'paired':>6}  (min-max)")
    sps = []
    for t in threads:
        med = statistics.median(values[t])
        sp = med / base if higher_is_faster else base / med
        sps.append(sp)
        paired = paired_speedup(values, t, one, higher_is_faster)
        print(f"  {t:7d}  {med:14.4g}  {sp:8.2f}  {sp / t:10.2f}  {paired:6.2f}  "
              f"({min(values[t]):.4g}-{max(values[t]):.4g})")
    print(f"  Amdahl fit: serial fraction s = {amdahl_serial_fraction(threads, sps):.3f}", flush=True)


def scaling(args) -> None:
    import numba

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from hydro import deck  # benchmarks/hydro.py

    from shockfriction.hydro.api import prepare, run_simulation
    from shockfriction.threading_policy import ThreadGovernor, available_cores

    cap = int(numba.config.NUMBA_NUM_THREADS)
    if args.threads:
        counts = sorted({t for t in args.threads if 1 <= t <= cap} | {1})
    else:
        top = min(available_cores(), cap)
        counts = sorted({1 << k for k in range(top.bit_length()) if 1 << k <= top} | {top})
    print(f"{_cpu_name()}; {os.cpu_count()} CPUs, {available_cores()} usable, NUMBA_NUM_THREADS {cap}; "
          f"threading layer after the first run below; load average {os.getloadavg()[0]:.2f}", flush=True)

    def plain(sim):
        if not args.governor:
            sim.between_cycles[:] = [h for h in sim.between_cycles if not isinstance(h, ThreadGovernor)]
        return sim

    def use(t):
        numba.set_num_threads(max(t, 1))

    for t in counts:  # compile (or load the caches) outside the timings
        use(t)
        sim = plain(prepare(deck(8, 5, t)))
        for _ in range(5):
            sim.step()
    print(f"threading layer: {numba.threading_layer()}", flush=True)
    for n in args.sizes:
        cycles = max(5, int(args.zone_cycles / (n * n)))
        sims = {}
        for t in counts:
            use(t)
            sims[t] = plain(prepare(deck(n, cycles, t)))
            for _ in range(3):  # first touches
                sims[t].step()
        rates = {t: [] for t in counts}
        for _ in range(args.repeat):
            for t in counts:
                use(t)
                sim = sims[t]
                start = time.perf_counter()
                for _ in range(cycles):
                    sim.step()
                    for hook in sim.between_cycles:
                        hook(sim)
                rates[t].append(n * n * cycles / (time.perf_counter() - start))
        del sims
        _table(f"hydro block {n} x {n} ({n * n} cells), {cycles} cycles per timing, {args.repeat} repeat(s), "
               f"load average {os.getloadavg()[0]:.2f}:", counts, rates, "zone-cycles/s", True)
    if args.cone_end_time > 0:
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples"))
        from cone_shot import cone_deck  # examples/cone_shot.py

        from shockfriction.contact import slideline
        from shockfriction.hydro import cycle

        sizes = (getattr(slideline, "PARALLEL_MIN_NODES", 0), getattr(cycle, "STAGED_PARALLEL_NODES", 0),
                 getattr(cycle, "STAGED_PARALLEL_THREADS", 1))
        # compile outside the timings (the parallel slide-line geometry and node passes too: the coarse shot is
        # smaller than the sizes from which a run takes them)
        slideline.PARALLEL_MIN_NODES, cycle.STAGED_PARALLEL_NODES, cycle.STAGED_PARALLEL_THREADS = 1, 0, 1
        for law in args.cone_laws:
            for t in counts:
                use(t)
                run_simulation(plain(prepare(cone_deck(law, 0.3, 0.7, cell_um=400.0, threads=t, end_us=0.3))))
        slideline.PARALLEL_MIN_NODES, cycle.STAGED_PARALLEL_NODES, cycle.STAGED_PARALLEL_THREADS = sizes
        walls = {law: {t: [] for t in counts} for law in args.cone_laws}
        info = {}
        for _ in range(args.repeat):  # the laws interleaved too: a change of the machine's speed hits them alike
            for law in args.cone_laws:
                for t in counts:
                    use(t)
                    sim = plain(prepare(cone_deck(law, 0.3, 0.7, cell_um=args.cone_cell_um, threads=t,
                                                  end_us=args.cone_end_time)))
                    start = time.perf_counter()
                    res = run_simulation(sim)
                    walls[law][t].append(time.perf_counter() - start)
                    info[law] = f"{res.summary['zones']} zones, {res.summary['cycles']} cycles"
        for law in args.cone_laws:
            _table(f"cone shot, {law}, {args.cone_cell_um:g} um cells, {args.cone_end_time:g} us ({info[law]}), "
                   f"{args.repeat} repeat(s), load average {os.getloadavg()[0]:.2f}:", counts, walls[law],
                   "wall time s", False)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="*", default=[200, 800], help="hydro blocks n x n")
    ap.add_argument("--threads", type=int, nargs="*", default=None, help="thread counts (default 1, 2, 4 ... cores)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--zone-cycles", type=float, default=1e7, help="zone-cycles per hydro timing")
    ap.add_argument("--cone-end-time", type=float, default=8.0, help="cone shot end time, us (0: no cone shot)")
    ap.add_argument("--cone-cell-um", type=float, default=100.0)
    ap.add_argument("--cone-laws", nargs="*", default=["coulomb", "subgrid-thermoelastoplastic"])
    ap.add_argument("--governor", action="store_true", help="keep the thread governor in the scaling runs")
    ap.add_argument("--n", type=int, default=200, help="--policies: the block")
    ap.add_argument("--cycles", type=int, default=60, help="--policies: cycles per timing")
    ap.add_argument("--policies", default=None, help="compare waiting policies, 2 threads against 1, idle and busy")
    ap.add_argument("--size-sweep", action="store_true", help="2/1 ratio against the mesh size, no busy process")
    ap.add_argument("--sweep-policy", default="spin-only", choices=sorted(POLICIES),
                    help="--size-sweep: the waiting policy (default: the policy's short spin, no governor)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--governor-child", default="1", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(child(args.n, args.cycles, args.repeat, args.governor_child == "1")))
        return
    if not (args.policies or args.size_sweep):
        scaling(args)
        return
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    if args.size_sweep:
        for n in (20, 40, 60, 80, 100, 140, 200):
            r = run_child(POLICIES[args.sweep_policy], n, max(args.cycles, int(args.cycles * (200 / n) ** 2 / 4)),
                          args.repeat)
            print(f"{n:4d} x {n:<4d} ({n * n:6d} cells): 2/1 threads = {r['ratio']:.2f} "
                  f"(min {r['min_ratio']:.2f}; 1 thread {r['one']:.3e} zone-cycles/s)", flush=True)
        return
    for name in args.policies.split(","):
        for busy in (False, True):
            r = with_load(busy, lambda: run_child(POLICIES[name], args.n, args.cycles, args.repeat))
            load = "busy process on core 0" if busy else "no busy process      "
            print(f"{name:<16} {load}: 2/1 threads = {r['ratio']:.2f} (min {r['min_ratio']:.2f}; "
                  f"{r['one']:.3e} -> {r['two']:.3e} zone-cycles/s; layer {r['layer']}, "
                  f"OMP_WAIT_POLICY {r['wait']}; load average {os.getloadavg()[0]:.2f})", flush=True)


if __name__ == "__main__":
    main()
