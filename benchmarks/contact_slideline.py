"""Cost of one slide-line cycle (pairing, mortar weights, contact and Coulomb friction sweeps).

Run: PYTHONPATH=src python benchmarks/contact_slideline.py [N_SLAVE] [N_GUIDE]
Prints milliseconds per cycle and slave node-steps per second (after numba compilation).
"""

import sys
import time

import numpy as np

from shockfriction.contact.pairing import guide_normal_sign
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


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
