"""Sub-grid interface throughput: interface node-steps per second (one column per node).

    PYTHONPATH=src python benchmarks/subgrid.py [--columns 1000] [--cells 500] [--repeats 3]

Compares the batched numba path (SubgridInterface.step: the columns stored (n_nodes, n_columns),
one fused factored Thomas sweep per step vectorised across the columns, Brent in numba) with

* the ceiling: a bare factored Thomas solve (forward + backward sweep, nothing else) on an array
  of the same size laid out the same way (column index innermost), in the same process;
* a plain baseline: one scipy.linalg.solve_banded per column per step and scipy.optimize.brentq
  on the same residual in Python (numpy for the plastic layer).

The viscoplastic model (inertia on, eta_vp from the material or 50 Pa s) has neither; it is timed
over ``--vp-steps`` steps after 5 warm-up steps at f = 0.3 (a thin plastic layer) and f = 0.7 (every cell
plastic), with its default Picard tolerance (1e-6 K), with 1e-3 K, and on a column cut to its active layer (25 cells
of the same size: the floor of any scheme that would solve only the cells that yield and heat), and in a run that
melts (``--melt-columns`` columns under the YLP loading of examples/subgrid/ylp_7075_toolsteel.toml: Al 7075-T6 on
steel, 5 GPa, 250 m/s, mu0 = 0.05, no Tresca branch, 2 um / 200 cells continued to the shear-wave reach, two-sided
heat, timed from the start to ``--melt-time``: the surface melts at 0.17 us), each in column-steps/s and as a
ratio to the thermoelastoplastic column of the same run (docs/theory/viscoplastic.md, "Speed" and "Cost").
Loading: the thesis's Ball case (Al 5083-H111, 10 GPa, 150-250 m/s spread over the columns,
f = 0.3, dt = 1 ns), after 20 warm-up steps.  Each repeat times the model and then the bare
Thomas solve (interleaved, so that both see the same load); prints the medians.  Times are the
CPU time of this (single-threaded) process, i.e. node-steps per second on one core, which other
processes sharing the machine do not inflate (``--wall`` for wall-clock time); the load average
is printed with them.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numba
import numpy as np
from numba import njit
from scipy.linalg import solve_banded
from scipy.optimize import brentq

from shockfriction.friction.subgrid.column import heat_matrix, thomas_factor
from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.materials.library import get_material, heat_share
from shockfriction.materials.strength import scg_shear_ratio, shear_ratio

AL, ST = get_material("Al5083-H111"), get_material("AISI321")
SIGMA, DT, F = 10e9, 1e-9, 0.3
clock = time.process_time  # CPU time of this process (main() switches to wall-clock time with --wall)


def fast(model, ncol, cells, steps, warmup=20, thickness=20e-6, picard_tol=None, f=F):
    opts = {"picard_tol": picard_tol} if model == "viscoplastic" else None
    sg = SubgridInterface(ncol, AL, ST, thickness=thickness, n_cells=cells, model=model, mu0=0.3, f=f,
                          viscoplastic=opts)
    v = np.linspace(150.0, 250.0, ncol)
    for _ in range(warmup):
        sg.step(SIGMA, v, v, np.inf, np.inf, 1.0, DT)
    t0 = clock()
    for _ in range(steps):
        sg.step(SIGMA, v, v, np.inf, np.inf, 1.0, DT)
    return ncol * steps / (clock() - t0)


def melting(ncol, duration, dt=DT):
    """Column-steps/s of viscoplastic columns under the YLP loading (examples/subgrid/ylp_7075_toolsteel.toml, the
    film regime: the surface melts at 0.17 us), timed from t = 0 to ``duration`` (the slip spread over 245-255 m/s
    so that the columns differ), and the run's Picard sweeps: whether the melt onset's slow steps occur is decided
    at round-off, so they say why one melting timing differs from another (docs/theory/viscoplastic.md, "The
    mechanics Newton's last iteration")."""
    al, steel = get_material("Al7075-T6"), get_material("Steel4340")
    r = scg_shear_ratio(5e9, 300.0, al.scg_g, al.scg_h, al.scg_xi, al.melting_temperature)
    depth = 1.2 * math.sqrt(al.G0 * max(r, 1.0) / al.rho0) * 1e-6  # the deck's depth = "auto" for a 1 us run
    sg = SubgridInterface(ncol, al, steel, thickness=2e-6, n_cells=200, model="viscoplastic", mu0=0.05, f=0.3,
                          viscoplastic={"eta_vp": 50.0, "inertia": True, "tresca": False, "depth": depth})
    v = np.linspace(245.0, 255.0, ncol) if ncol > 1 else np.full(1, 250.0)
    steps = int(round(duration / dt))
    sweeps = 0
    t0 = clock()
    for _ in range(steps):
        sg.step(5e9, v, v, np.inf, np.inf, 1.0, dt)
        sweeps += int(np.abs(sg.iterations).sum())
    return ncol * steps / (clock() - t0), sweeps


@njit(cache=True)
def bare_thomas(X, mult, inv_bp, c):
    """The ceiling: factored Thomas solve (eq. A.6-A.12) of every column of X (n_nodes, n_columns), in place."""
    nn, ncol = X.shape
    for i in range(1, nn):
        m = mult[i]
        cur = X[i]
        prev = X[i - 1]
        for j in range(ncol):
            cur[j] = cur[j] - m * prev[j]
    last = X[nn - 1]
    ib = inv_bp[nn - 1]
    for j in range(ncol):
        last[j] = last[j] * ib
    for i in range(nn - 2, -1, -1):
        ci = c[i]
        ib = inv_bp[i]
        cur = X[i]
        nxt = X[i + 1]
        for j in range(ncol):
            cur[j] = (cur[j] - ci * nxt[j]) * ib


def ceiling(ncol, cells, steps):
    """Node-steps/s of the bare Thomas solve on (cells + 1, ncol), the same matrix as the columns."""
    m = AL
    a, b, c = heat_matrix(np.linspace(0.0, 20e-6, cells + 1), m.conductivity / (m.rho0 * m.heat_capacity), DT)
    mult, inv_bp = thomas_factor(a, b, c)
    X = np.full((cells + 1, ncol), 300.0)
    bare_thomas(X, mult, inv_bp, c)
    t0 = clock()
    for _ in range(steps):
        bare_thomas(X, mult, inv_bp, c)
    return ncol * steps / (clock() - t0)


class Baseline:
    """The same equations, column by column in Python with scipy."""

    def __init__(self, model, ncol, cells):
        self.model = model
        m = AL
        self.z = np.linspace(0.0, 20e-6, cells + 1)
        dz = np.diff(self.z)
        self.w = np.zeros(cells + 1)
        self.w[:-1] += dz / 2
        self.w[1:] += dz / 2
        self.rho_c = m.rho0 * m.heat_capacity
        a, b, c = heat_matrix(self.z, m.conductivity / self.rho_c, DT)
        self.ab = np.zeros((3, cells + 1))
        self.ab[0, 1:] = c[:-1]
        self.ab[1] = b
        self.ab[2, :-1] = a[1:]
        e0 = np.zeros(cells + 1)
        e0[0] = DT / (self.rho_c * self.w[0])
        self.unit = solve_banded((1, 1), self.ab, e0)
        self.theta = np.full((ncol, cells + 1), 300.0)
        self.eps = np.zeros_like(self.theta)
        self.pending = np.zeros_like(self.theta)
        self.beta = heat_share(AL, ST)
        self.v = np.linspace(150.0, 250.0, ncol)

    def tau(self, T):
        m = AL
        return F * m.Ymax / math.sqrt(3) * float(shear_ratio(SIGMA, T, m.scg_g, m.scg_h, m.scg_xi, m.melting_temperature))

    def deps(self, tau, T_ad, q, eps):
        m = AL
        r = shear_ratio(SIGMA, T_ad + q * self.unit, m.scg_g, m.scg_h, m.scg_xi, m.melting_temperature)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = math.sqrt(3) * tau / (m.Y0 * r)
        target = np.where(x > 1.0, (np.maximum(x, 1.0) ** (1 / m.scg_n) - 1) / m.scg_beta, 0.0)
        return np.maximum(target - eps, 0.0)

    def step(self):
        TF, a0 = AL.melting_temperature, self.unit[0]
        for j in range(self.theta.shape[0]):
            T_ad = solve_banded((1, 1), self.ab, self.theta[j] + self.pending[j] / self.rho_c)
            v = self.v[j]
            if self.model == "thermoelastic":
                def R(T):
                    return T - T_ad[0] - a0 * self.beta * self.tau(T) * v
            else:
                def R(T):
                    t = self.tau(T)
                    d = self.deps(t, T_ad, (T - T_ad[0]) / a0, self.eps[j])
                    vl = max(v - math.sqrt(3) * (self.w @ d) / DT, 0.0)
                    return T - T_ad[0] - a0 * self.beta * t * vl
            T = brentq(R, T_ad[0], TF, xtol=1e-9)
            t = self.tau(T)
            q = (T - T_ad[0]) / a0
            if self.model == "thermoelastoplastic":
                d = self.deps(t, T_ad, q, self.eps[j])
                self.eps[j] += d
                self.pending[j] = 0.9 * math.sqrt(3) * t * d
            self.theta[j] = T_ad + q * self.unit


def slow(model, ncol, cells, steps):
    b = Baseline(model, ncol, cells)
    b.step()
    t0 = clock()
    for _ in range(steps):
        b.step()
    return ncol * steps / (clock() - t0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--columns", type=int, default=1000)
    ap.add_argument("--cells", type=int, default=500)
    ap.add_argument("--steps", type=int, default=50)
    ap.add_argument("--baseline-steps", type=int, default=2)
    ap.add_argument("--vp-steps", type=int, default=5, help="timed steps of the viscoplastic model (after 5)")
    ap.add_argument("--melt-columns", type=int, default=4, help="columns of the melting run (0: none)")
    ap.add_argument("--melt-time", type=float, default=1e-6, help="duration of the melting run (s)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--wall", action="store_true", help="time with the wall clock instead of CPU time")
    args = ap.parse_args()
    # one thread: the CPU time of a parallel kernel counts its idle workers' spinning (without this the chapter 8
    # column measured 2.7e5-8.2e5 column-steps/s from one process to the next on the 2-core machine, 2026-11-28)
    numba.set_num_threads(1)
    global clock
    clock = time.perf_counter if args.wall else time.process_time
    fast("thermoelastic", 2, 10, 1)  # compile
    fast("thermoelastoplastic", 2, 10, 1)
    fast("viscoplastic", 2, 10, 1)
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"{args.columns} columns x {args.cells} cells, dt = 1 ns, median of {args.repeats} repeats, "
          f"{'wall-clock' if args.wall else 'CPU'} time, load average {load}")
    print(f"{'model':20s} {'numba node-steps/s':>19s} {'bare Thomas':>12s} {'of ceiling':>10s} "
          f"{'baseline':>10s} {'speed-up':>9s}")
    for model in ("thermoelastic", "thermoelastoplastic"):
        pairs = [(fast(model, args.columns, args.cells, args.steps), ceiling(args.columns, args.cells, args.steps))
                 for _ in range(args.repeats)]
        f = statistics.median(p[0] for p in pairs)
        c = statistics.median(p[1] for p in pairs)
        s = statistics.median(slow(model, args.columns, args.cells, args.baseline_steps) for _ in range(args.repeats))
        print(f"{model:20s} {f:19.4g} {c:12.4g} {f / c:10.2f} {s:10.4g} {f / s:9.1f}")
        tep = f
    # viscoplastic columns (inertia, overstress flow, enthalpy melting): no scipy baseline.  At f = 0.3 (beside the
    # full column: a looser Picard tolerance, and the column cut to its active layer: the plastic cells and the first
    # ~1 um of heating at these times, 25 cells of the same 40 nm, the floor of any scheme that would solve only the
    # active layer), at f = 0.7 (every cell plastic) and in a run that melts; the ratios are to the
    # thermoelastoplastic column of this run (the targets: >= 0.5 at f = 0.3, >= 0.25 at f = 0.7 and melting)
    dz = 20e-6 / args.cells
    runs = {"viscoplastic f=0.3": {}, "  picard_tol 1e-3 K": {"picard_tol": 1e-3},
            "  25-cell layer only": {"cells": 25, "thickness": 25 * dz},
            "viscoplastic f=0.7": {"f": 0.7}}
    rows = {name: [] for name in runs}
    rows["melting (YLP)"] = []
    for _ in range(args.repeats):
        for name, kw in runs.items():
            rows[name].append(fast("viscoplastic", args.columns, kw.get("cells", args.cells), args.vp_steps, warmup=5,
                                   thickness=kw.get("thickness", 20e-6), picard_tol=kw.get("picard_tol"),
                                   f=kw.get("f", F)))
        if args.melt_columns > 0:
            rate, melt_sweeps = melting(args.melt_columns, args.melt_time)
            rows["melting (YLP)"].append(rate)
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"{'':20s} {'column-steps/s':>19s} {'of thermoelastoplastic':>23s}   (load average {load})")
    for name, r in rows.items():
        if r:
            f = statistics.median(r)
            print(f"{name:20s} {f:19.4g} {f / tep:23.3g}")
    if rows["melting (YLP)"]:
        print(f"melting run: {melt_sweeps} Picard sweeps over {args.melt_columns} column(s)")

if __name__ == "__main__":
    main()
