"""The floor of issue 26's design at f = 0.7: a cost prototype, not the model.

    PYTHONPATH=src python benchmarks/vp_layout_floor.py [--columns 200] [--cells 500] [--repeats 3]
                                                       [--sweeps 2] [--newton 2]

What it times: a viscoplastic column-step in the layout the issue's targets ask for (docs/theory/viscoplastic.md,
"What issue 26's targets ask of a pass over the cells"): the columns innermost, so that every loop runs along a
row of columns and vectorises (the chapter 8 kernel's layout), and the closed-form linear overstress return with the
hardening frozen at the start of the step.  Per step, the counts the kernel takes late in the Ball run at f = 0.7
(every cell plastic): two sweeps (``--sweeps``), each with the cells' G(T) (an inlined exponential per cell), Newton
iterations (two, ``--newton``, then one) of a cell pass (trial stress, return, consistent tangent) and a Thomas solve across the columns (reciprocal
pivots), the plastic work as heat and a pre-factored heat solve.  ``--sweeps 1 --newton 1`` is the one-solve step
(one sweep where the predictor is within the Picard tolerance, a piecewise-linear mechanics whose active set did
not change: docs/theory/viscoplastic.md, "The one-sweep design").  What it leaves out, so that a real kernel costs more:
the stick/slip switch and the line search, the enthalpy's melt kink (a solid column's heat is linear), the
hardening's update, the energy books and every convergence test.  The chapter 8 column (thermoelastoplastic,
``SubgridInterface``, Ball loading) is timed in the same process, alternated with it, one thread, CPU time; the
ratio is the issue's measure (target 0.25 at f = 0.7).
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

from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.materials.library import get_material
from shockfriction.materials.strength import exp_inline

INV_SQRT3 = 1.0 / math.sqrt(3.0)


@njit(cache=True, error_model="numpy")
def column_steps(v, vo, ge, T, e, mass_dt, idz, G0, h, T0, Y, eta_dt, dt, rho_c, cap, Tlo, Tdi, Tup, S, Kc, G, kf,
                 snew, dgp, lo, di, up, rhs, src, sweeps, newton):
    """One step of every column (arrays (rows, columns), columns innermost): ``sweeps`` sweeps, ``newton`` Newton
    iterations in the first and one in each later one; see the module docstring."""
    nn, nc = v.shape
    M = nn - 1
    for i in range(nn):
        for j in range(nc):
            vo[i, j] = v[i, j]
    for sweep in range(sweeps):
        for c in range(M):  # the cells' G/G0 at the sweep's temperatures
            for j in range(nc):
                r = exp_inline(-h * (0.5 * (T[c, j] + T[c + 1, j]) - T0))
                G[c, j] = G0 * r
                kf[c, j] = r * INV_SQRT3
        for it in range(newton if sweep == 0 else 1):
            for c in range(M):  # trial stress, closed-form return, consistent tangent
                for j in range(nc):
                    g = G[c, j]
                    s_tr = g * (ge[c, j] + dt * (v[c, j] - v[c + 1, j]) * idz[c])
                    rg = 1.0 / (g + eta_dt)
                    x = (abs(s_tr) - Y * kf[c, j]) * rg
                    pl = x > 0.0
                    x = x if pl else 0.0
                    sg = 1.0 if s_tr >= 0.0 else -1.0
                    sn = s_tr - sg * g * x
                    snew[c, j] = sn
                    dgp[c, j] = sg * x
                    S[c + 1, j] = sn
                    Kc[c, j] = (eta_dt * rg if pl else 1.0) * g * dt * idz[c]
            for j in range(nc):
                S[0, j] = cap
            for i in range(nn):  # rows: m (v - vo)/dt - S_i + S_(i+1) = 0; the far end on a stiff spring
                for j in range(nc):
                    kl = Kc[i - 1, j] if i > 0 else 0.0
                    ku = Kc[i, j] if i < M else 1e9
                    lo[i, j] = -kl
                    up[i, j] = -ku if i < M else 0.0
                    di[i, j] = mass_dt[i] + kl + ku
                    rhs[i, j] = -(mass_dt[i] * (v[i, j] - vo[i, j]) - S[i, j] + (S[i + 1, j] if i < M else 0.0))
            for j in range(nc):  # Thomas across the columns, reciprocal pivots
                di[0, j] = 1.0 / di[0, j]
            for i in range(1, nn):
                for j in range(nc):
                    m = lo[i, j] * di[i - 1, j]
                    di[i, j] = 1.0 / (di[i, j] - m * up[i - 1, j])
                    rhs[i, j] -= m * rhs[i - 1, j]
            for j in range(nc):
                rhs[M, j] *= di[M, j]
            for i in range(M - 1, -1, -1):
                for j in range(nc):
                    rhs[i, j] = (rhs[i, j] - up[i, j] * rhs[i + 1, j]) * di[i, j]
            for i in range(nn):
                for j in range(nc):
                    v[i, j] += rhs[i, j]
        for i in range(nn):  # the plastic work as heat, the pre-factored heat solve (a solid column: linear)
            for j in range(nc):
                src[i, j] = e[i, j]
        for c in range(M):
            for j in range(nc):
                w = 0.5 * snew[c, j] * dgp[c, j] / idz[c]
                src[c, j] += w
                src[c + 1, j] += w
        for i in range(1, nn):
            for j in range(nc):
                src[i, j] -= Tlo[i] * src[i - 1, j]
        for j in range(nc):
            src[M, j] *= Tdi[M]
        for i in range(M - 1, -1, -1):
            for j in range(nc):
                src[i, j] = (src[i, j] - Tup[i] * src[i + 1, j]) * Tdi[i]
        for i in range(nn):
            for j in range(nc):
                T[i, j] = T0 + src[i, j] * (1.0 / rho_c)
    for i in range(nn):
        for j in range(nc):
            e[i, j] = (T[i, j] - T0) * rho_c
    for c in range(M):
        for j in range(nc):
            ge[c, j] = snew[c, j] / G[c, j]


class Floor:
    """The prototype's state: Ball-like loading (Al: rho 2700, G0 27 GPa, 20 um in `cells` cells, dt = 1 ns),
    surface velocities 150-250 m/s across the columns, the surface at the Coulomb cap 0.7 x 10 GPa x 0.01."""

    def __init__(self, ncol: int, cells: int, sweeps: int = 2, newton: int = 2):
        nn = cells + 1
        dz = 20e-6 / cells
        self.v = np.zeros((nn, ncol))
        self.v[0] = np.linspace(150.0, 250.0, ncol)
        self.vo, self.e, self.lo, self.di, self.up, self.rhs, self.src = (np.zeros((nn, ncol)) for _ in range(7))
        self.T = np.full((nn, ncol), 300.0)
        self.S = np.zeros((nn + 1, ncol))  # the stresses on the nodes' faces, S_0 at the surface
        self.Kc, self.G, self.kf, self.snew, self.dgp = (np.zeros((cells, ncol)) for _ in range(5))
        self.ge = np.full((cells, ncol), 1e-3)
        self.counts = (sweeps, newton)
        self.args = (np.full(nn, 2700.0 * dz / 1e-9), np.full(cells, 1.0 / dz), 27e9, 1e-4, 300.0, 3e8, 5e10, 1e-9,
                     2.4e6, 7e7, np.full(nn, -0.1), np.full(nn, 0.8), np.full(nn, -0.1))

    def step(self):
        column_steps(self.v, self.vo, self.ge, self.T, self.e, *self.args, self.S, self.Kc, self.G, self.kf,
                     self.snew, self.dgp, self.lo, self.di, self.up, self.rhs, self.src, *self.counts)


def rate(stepper, ncol: int, steps: int) -> float:
    start = time.process_time()
    for _ in range(steps):
        stepper()
    return ncol * steps / (time.process_time() - start)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--columns", type=int, default=200)
    ap.add_argument("--cells", type=int, default=500)
    ap.add_argument("--steps", type=int, default=20, help="timed steps of the prototype (the chapter 8 column: x2.5)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--sweeps", type=int, default=2, help="sweeps per step (2: the kernel's late count at 1e-6 K)")
    ap.add_argument("--newton", type=int, default=2, help="Newton iterations of the first sweep (later sweeps: 1)")
    args = ap.parse_args()
    numba.set_num_threads(1)
    floor = Floor(args.columns, args.cells, args.sweeps, args.newton)
    floor.step()  # compile
    al, st = get_material("Al5083-H111"), get_material("AISI321")
    ch8 = SubgridInterface(args.columns, al, st, thickness=20e-6, n_cells=args.cells, model="thermoelastoplastic",
                           mu0=0.3, f=0.3)
    v = np.linspace(150.0, 250.0, args.columns)

    def ch8_step():
        ch8.step(10e9, v, v, np.inf, np.inf, 1.0, 1e-9)

    for _ in range(20):
        ch8_step()
    protos, ch8s = [], []
    for _ in range(args.repeats):
        protos.append(rate(floor.step, args.columns, args.steps))
        ch8s.append(rate(ch8_step, args.columns, int(2.5 * args.steps)))
    p, c = statistics.median(protos), statistics.median(ch8s)
    print(f"{args.columns} columns x {args.cells} cells, one thread, CPU time, medians of {args.repeats}, load average "
          f"{os.getloadavg()[0]:.2f}")
    print(f"  prototype (f = 0.7 layout floor, {args.sweeps} sweeps, {args.newton} + {args.sweeps - 1} Newton) "
          f"{p:.3e} column-steps/s")
    print(f"  chapter 8 column                  {c:.3e} column-steps/s")
    print(f"  ratio                             {p / c:.3f}   (issue 26's target at f = 0.7: 0.25)")


if __name__ == "__main__":
    main()
