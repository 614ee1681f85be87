"""Reference histories of the viscoplastic column (tau, Theta(0) per step) for comparing kernels.

    PYTHONPATH=src python benchmarks/vp_reference.py save ref.npz      # the current kernel's answers
    PYTHONPATH=src python benchmarks/vp_reference.py compare ref.npz   # max relative differences against them

Cases: Ball loading (Al 5083-H111 on AISI 321, 10 GPa, 150-250 m/s over 4 columns, dt = 1 ns, 20 um / 500 cells,
inertia, two-sided heat as SubgridInterface sets it) at f = 0.3 / 0.7 / 0.9 to 0.3 us, and the YLP film
(examples/subgrid/ylp_7075_toolsteel.toml) to 1 us.  Prints the CPU time of each case.
"""

from __future__ import annotations

import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.materials.library import get_material

ROOT = Path(__file__).resolve().parents[1]


def ball(f, ncol=4, steps=300):
    sg = SubgridInterface(ncol, get_material("Al5083-H111"), get_material("AISI321"), thickness=20e-6, n_cells=500,
                          model="viscoplastic", mu0=0.3, f=f)
    v = np.linspace(150.0, 250.0, ncol)
    tau, th = np.empty((steps, ncol)), np.empty((steps, ncol))
    for i in range(steps):
        t, _ = sg.step(10e9, v, v, np.inf, np.inf, 1.0, 1e-9)
        tau[i], th[i] = t, sg.theta_interface
    return tau, th, sg.vp.energy_residual()


def ylp(duration="1 us"):
    from shockfriction.deck.base import validate
    from shockfriction.deck.subgrid import SubgridDeck
    from shockfriction.friction.subgrid.driver import run_subgrid
    deck = tomllib.loads((ROOT / "examples/subgrid/ylp_7075_toolsteel.toml").read_text())
    deck["duration"] = duration
    deck["output_times"] = [duration]
    with tempfile.TemporaryDirectory() as d:
        res = run_subgrid(validate(SubgridDeck, deck, "deck"), Path(d) / "out")
    return res.tau, res.theta_interface, np.zeros(1)


def run_all():
    out = {}
    for name, fn in (("ball03", lambda: ball(0.3)), ("ball07", lambda: ball(0.7)), ("ball09", lambda: ball(0.9)),
                     ("ylp", ylp)):
        t0 = time.process_time()
        tau, th, res = fn()
        print(f"{name}: {time.process_time() - t0:.2f} s CPU, energy residual {np.max(np.abs(res)):.2e}", flush=True)
        out[name + "_tau"], out[name + "_theta"] = tau, th
    return out


def main():
    mode, path = sys.argv[1], sys.argv[2]
    ball(0.3, 2, 2)  # compile
    out = run_all()
    if mode == "save":
        np.savez(path, **out)
        return
    ref = np.load(path)
    for key, a in out.items():
        b = ref[key]
        scale = np.max(np.abs(b), axis=0)
        print(f"{key:14s} max |new - old| / max|old| = {np.max(np.abs(a - b) / scale):.3e}   "
              f"pointwise rel {np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300 + 1e-3 * scale)):.3e}")


if __name__ == "__main__":
    main()
