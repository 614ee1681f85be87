"""Dissimilar elastic pressure-shear impact: steel flyer on aluminium, 150 m/s at 20 deg, Coulomb
mu = 0.15, against the exact 1D solution (shockfriction.analysis.pressure_shear):
sigma_n = 1.75766 GPa, tau = 0.26365 GPa, slip 9.610 m/s, target rear transverse free-surface
velocity 62.39 m/s, rear normal 206.01 m/s.

Without a shear viscosity the transverse wave rings: the rear transverse velocity overshoots the
plateau by +27 % on every mesh and the slip oscillates (std 1.9 m/s at 50 um).  The default shear
viscosity (viscosity.shear = "elastic", C_L = 0.15) removes it.  Measured at 50 um cells
(60 + 60 cells): sigma_n +0.07 %, tau +0.07 %, slip -0.28 %, rear transverse +0.11 %, rear normal
+0.02 %, overshoot +0.41 %, slip std 0.13 m/s; with shear = "off" the overshoot is +26.6 %.
"""

import math
import tempfile
from pathlib import Path

import numpy as np
import pytest

from shockfriction.analysis.pressure_shear import pressure_shear
from shockfriction.hydro.api import prepare, run_simulation
from shockfriction.io.interface import read_interface

STEEL = (7850.0, 5900.0, 3200.0)
AL = (2700.0, 6320.0, 3130.0)
SPEED, ANGLE, MU = 150.0, 20.0, 0.15
EXACT = pressure_shear(SPEED, math.radians(ANGLE), MU, *STEEL, *AL)


def _elastic(rho, cl, cs, material):
    c0 = math.sqrt(cl ** 2 - 4.0 * cs ** 2 / 3.0)
    return {"material": material, "density": f"{rho} kg/m^3", "c0": f"{c0} m/s", "s": 0.0, "gamma0": 0.0,
            "strength": "elastic-perfectly-plastic", "shear_modulus": f"{rho * cs ** 2} Pa",
            "yield_stress": "100 GPa", "elastic_modulus": "constant"}


def deck(cells_per_mm=20, shear="elastic", thickness_mm=3.0):
    vn, vt = SPEED * math.cos(math.radians(ANGLE)), SPEED * math.sin(math.radians(ANGLE))
    per = {"left": "periodic", "right": "periodic"}

    def block(name, y0, y1, v, mat):
        return {"name": name, "velocity": [f"{v[0]} m/s", f"{v[1]} m/s"], "boundary": per, **mat,
                "mesh": {"corners": [["0 mm", f"{y0} mm"], ["0.1 mm", f"{y0} mm"], ["0.1 mm", f"{y1} mm"],
                                     ["0 mm", f"{y1} mm"]], "nx": 2, "ny": round(cells_per_mm * (y1 - y0))}}

    return {"title": "dissimilar pressure-shear", "geometry": "planar", "time": {"end": "1.5 us", "cfl": 0.5},
            "viscosity": {"shear": shear},
            "bodies": [block("flyer", -thickness_mm, 0.0, (vt, vn), _elastic(*STEEL, "SS304")),
                       block("target", 0.0, thickness_mm, (0.0, 0.0), _elastic(*AL, "Al6061-T6"))],
            "slide_lines": [{"name": "interface", "guide": {"body": "target", "side": "bottom"},
                             "slave": {"body": "flyer", "side": "top"}, "record_interval": "10 ns",
                             "friction": {"law": "coulomb", "mu0": MU}}],
            "probes": [{"name": "rear", "body": "target", "node": [0, -1], "quantities": ["vx", "vy"]}]}


def _measure(shear):
    sim = prepare(deck(shear=shear))
    with tempfile.TemporaryDirectory() as tmp:
        res = run_simulation(sim, tmp)
        d = read_interface(Path(tmp) / "interface.h5")["interface"]
    sel = (d["t_s"] > 0.15e-6) & (d["t_s"] < 0.9e-6)     # before the reflections return
    t, vx, vy = res.probes["t_s"], res.probes["rear.vx"], res.probes["rear.vy"]
    return {"sigma_n": (float(np.mean(d["sigma_n_Pa"][sel])), EXACT.sigma_n),
            "tau": (float(-np.mean(d["tau_Pa"][sel])), EXACT.tau),
            "slip": (float(np.mean(d["slip_mps"][sel])), EXACT.slip_rate),
            "rear transverse": (float(vx[(t > 1.05e-6) & (t < 1.45e-6)].mean()), EXACT.rear_transverse_fs_velocity),
            "rear normal": (float(vy[(t > 0.6e-6) & (t < 0.9e-6)].mean()), EXACT.rear_normal_fs_velocity),
            "overshoot": float(vx[t > 0.9e-6].max() / EXACT.rear_transverse_fs_velocity - 1.0),
            "slip std": float(np.std(d["slip_mps"][sel].mean(axis=1))),
            "energy error": sim.relative_energy_error()}


@pytest.fixture(scope="module")
def damped():
    return _measure("elastic")


def test_exact_solution_values():
    assert EXACT.sigma_n == pytest.approx(1.75766e9, rel=1e-5)
    assert EXACT.tau == pytest.approx(0.26365e9, rel=1e-4)
    assert EXACT.slip_rate == pytest.approx(9.610, rel=1e-3)
    assert EXACT.rear_transverse_fs_velocity == pytest.approx(62.39, rel=1e-3)
    assert EXACT.rear_normal_fs_velocity == pytest.approx(206.01, rel=1e-4)


def test_against_exact_without_ringing(damped):
    m = damped
    print()
    for k, v in m.items():
        if isinstance(v, tuple):
            print(f"  {k:16s} {v[0]:.6g} exact {v[1]:.6g} ({v[0] / v[1] - 1:+.2e})")
        else:
            print(f"  {k:16s} {v:.3e}")
    for k in ("sigma_n", "tau", "slip", "rear transverse", "rear normal"):
        got, ref = m[k]
        assert got == pytest.approx(ref, rel=0.01), k
    assert m["overshoot"] < 0.05
    assert m["slip std"] < 0.3                # 1.9 m/s without the shear viscosity
    assert m["energy error"] < 2e-4


def test_without_shear_viscosity_the_shear_wave_rings():
    m = _measure("off")
    print(f"\nshear = off: overshoot {m['overshoot']:+.3f}, slip std {m['slip std']:.2f} m/s")
    assert m["overshoot"] > 0.2 and m["slip std"] > 1.0
