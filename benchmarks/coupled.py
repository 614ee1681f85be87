"""Cost of the sub-grid friction on the cone-in-cylinder shot, and of the alternative (refining the mesh).

    python benchmarks/coupled.py [--cell-um 100] [--repeat 3] [--threads 1] [--laws coulomb subgrid-...]

Prints, for the cone shot of :func:`examples/cone_shot.py's cone_deck` on one mesh:

* the median wall time of the Coulomb run and of the thermoelastic, thermoelastoplastic and
  viscoplastic runs (mu0 = 0.3, f = 0.7; 500-cell columns under the ~300 slide-line nodes), the
  overhead of the sub-grid runs over the Coulomb run (targets: thermoelastic within 1.1x,
  thermoelastoplastic within 1.2x) and the time spent inside the sub-grid friction step;
* what resolving the 20 um layer in the hydrocode instead would cost: the zones and the cycles of
  the same shot meshed with 20 um cells (one cell per layer thickness, which still resolves none
  of its gradients) and 2 um cells (ten per layer), from the meshes and their stable time steps
  (the runs themselves are out of reach), and the time this predicts at the Coulomb run's
  zone-cycle rate: the thesis's argument (Part II, §3.4.3) for a sub-grid model.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))  # examples/cone_shot.py

from cone_shot import cone_deck  # noqa: E402
from shockfriction.hydro.api import prepare, run_simulation  # noqa: E402

LAWS = ("coulomb", "subgrid-thermoelastic", "subgrid-thermoelastoplastic")  # add subgrid-viscoplastic with --laws (slow)


def timed_run(law: str, cell_um: float, threads: int, end_us: float) -> dict:
    sim = prepare(cone_deck(law, 0.3, 0.7, cell_um=cell_um, threads=threads, end_us=end_us))
    line = next(obj.line for obj in sim.interfaces if obj.name == "cone_wall")
    inside = [0.0]
    fm = line.friction_model
    if fm is not None:
        step = fm.tangential

        def wrapped(*a, **k):
            t0 = time.perf_counter()
            try:
                return step(*a, **k)
            finally:
                inside[0] += time.perf_counter() - t0

        fm.tangential = wrapped
    t0 = time.perf_counter()
    res = run_simulation(sim)
    wall = time.perf_counter() - t0
    return {"wall": wall, "cycles": res.summary["cycles"], "zones": res.summary["zones"], "subgrid": inside[0],
            "nodes": line.slave.size}


def mesh_cost(cell_um: float, end_us: float) -> tuple[int, int, float]:
    """Zones, estimated cycles (end time / stable step at t = 0) and the step of the cone shot meshed at ``cell_um``."""
    sim = prepare(cone_deck("coulomb", 0.3, cell_um=cell_um, end_us=end_us))
    dt = sim.state.dt
    return sim.state.n_cells, int(round(end_us * 1e-6 / dt)), dt


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description="sub-grid friction cost on the cone shot")
    ap.add_argument("--cell-um", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--end-us", type=float, default=8.0)
    ap.add_argument("--rate", type=float, default=None,
                    help="zone-cycles/s of the Coulomb run: skip the runs, only count the refined meshes")
    ap.add_argument("--laws", nargs="+", default=list(LAWS), help="friction laws (the first is the baseline)")
    args = ap.parse_args(argv)
    if args.rate is not None:
        refined(args, args.rate)
        return
    laws = tuple(args.laws)
    for law in laws:  # compile (numba caches) outside the timings
        timed_run(law, 400.0, args.threads, 0.5)
    times = {law: [] for law in laws}
    info = {}
    for _ in range(args.repeat):
        for law in laws:  # interleaved, so that a busy machine slows all three alike
            r = timed_run(law, args.cell_um, args.threads, args.end_us)
            times[law].append(r)
            info = r
    print(f"cone shot, {args.cell_um:g} um cells: {info['zones']} zones, {info['nodes']} slide-line nodes, "
          f"{args.threads} thread(s), {args.repeat} run(s) each, medians:")
    base = statistics.median(r["wall"] for r in times[laws[0]])
    base_cycles = times[laws[0]][0]["cycles"]
    zc_rate = times[laws[0]][0]["zones"] * base_cycles / base
    for law in laws:
        wall = statistics.median(r["wall"] for r in times[law])
        sub = statistics.median(r["subgrid"] for r in times[law])
        cyc = times[law][0]["cycles"]
        # the ratio of each repeat's pair of runs (taken a minute apart): the host's speed drifts between repeats
        pairs = sorted(r["wall"] / b["wall"] for r, b in zip(times[law], times[laws[0]]))
        extra = "" if law == laws[0] else (f"  x{wall / base:.2f} of {laws[0]} (per repeat x{pairs[0]:.2f}-"
                                             f"x{pairs[-1]:.2f}, median x{statistics.median(pairs):.2f}); "
                                             f"sub-grid step {sub:.1f} s ({sub / cyc * 1e3:.2f} ms per cycle)")
        print(f"  {law:<28} {wall:7.1f} s  {cyc} cycles, {wall / cyc * 1e3:.2f} ms per cycle{extra}")
    refined(args, zc_rate)


def refined(args, zc_rate: float) -> None:
    print("resolving the 20 um layer with the hydrocode's own cells instead:")
    z0, c0, dt0 = mesh_cost(args.cell_um, args.end_us)
    print(f"  {args.cell_um:5.0f} um cells: {z0:>9} zones x {c0:>7} cycles (dt {dt0 * 1e9:.2f} ns) = "
          f"{z0 * c0:.3e} zone-cycles")
    z20 = c20 = 0
    for cell in (20.0, 2.0):
        if cell == 2.0:  # too many zones to build: scale from the 20 um mesh (zones ~ 1/h^2, cycles ~ 1/h)
            z, c = int(z20 * (20.0 / cell) ** 2), int(c20 * 20.0 / cell)
            how = "scaled from 20 um"
        else:
            z, c, _ = mesh_cost(cell, args.end_us)
            z20, c20 = z, c
            how = "meshed"
        print(f"  {cell:5.0f} um cells: {z:>9} zones x {c:>7} cycles = {z * c:.3e} zone-cycles "
              f"({z * c / (z0 * c0):.0f}x; about {z * c / zc_rate / 3600:.1f} h at {zc_rate:.2e} zone-cycles/s, {how})")


if __name__ == "__main__":
    main()
