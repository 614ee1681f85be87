"""Periodic sides: a pressure-shear strip (oblique symmetric impact) stays 1D, and the
transverse (shear) wave carries half the transverse velocity jump at c_s = sqrt(G/rho)."""

import numpy as np
import pytest

from shockfriction.hydro.api import run_dict


def _shear_strip(vx="50 m/s"):
    def body(name, y0, y1, ny, v):
        return {"name": name, "material": "Al6061-T6", "strength": "elastic-perfectly-plastic",
                "yield_stress": "5 GPa", "velocity": v,
                "mesh": {"corners": [["0 mm", f"{y0} mm"], ["0.2 mm", f"{y0} mm"], ["0.2 mm", f"{y1} mm"],
                                     ["0 mm", f"{y1} mm"]], "nx": 2, "ny": ny},
                "boundary": {"left": "periodic", "right": "periodic"}}

    return {"time": {"end": "3.6 us"},
            "bodies": [body("flyer", -6.0, 0.0, 60, [vx, "250 m/s"]), body("target", 0.0, 8.0, 80, ["0 m/s", "0 m/s"])],
            "ties": [{"sides": ["flyer.top", "target.bottom"]}],
            "probes": [{"name": "fs0", "body": "target", "node": [0, -1], "quantities": ["vx", "vy"]},
                       {"name": "fs1", "body": "target", "node": [1, -1], "quantities": ["vx", "vy"]},
                       {"name": "mid", "body": "target", "cell": [0, 40], "quantities": ["sigma_xy"]}]}


def test_pressure_shear_strip():
    res = run_dict(_shear_strip())
    pr = res.probes
    t = pr["t_s"]
    rho0, g = 2703.0, 27.6e9
    cs = np.sqrt(g / rho0)
    t_arrival = 8e-3 / cs
    # 1D: every node of a row moves alike (periodic pairs and the middle node)
    np.testing.assert_allclose(pr["fs0.vx"], pr["fs1.vx"], atol=1e-9)
    np.testing.assert_allclose(pr["fs0.vy"], pr["fs1.vy"], atol=1e-9)
    late = t > t_arrival + 0.25e-6
    vx = pr["fs0.vx"][late].mean()
    print(f"transverse free-surface velocity {vx:.2f} m/s (exact 50), shear wave at {t_arrival * 1e6:.3f} us")
    assert vx == pytest.approx(50.0, rel=0.02)
    assert np.abs(pr["fs0.vx"][t < t_arrival - 0.25e-6]).max() < 1.0
    # elastic shear stress behind the shear wave: rho c_s (vx/2)
    sel = (t > 4e-3 / cs + 0.3e-6) & (t < 3.0e-6)
    tau = pr["mid.sigma_xy"][sel].mean()
    print(f"shear stress {tau / 1e6:.2f} MPa (exact {rho0 * cs * 25 / 1e6:.2f})")
    assert abs(tau) == pytest.approx(rho0 * cs * 25.0, rel=0.02)
    px, _ = res.simulation.momentum()
    flyer = res.mesh.cell_body == 0
    assert px == pytest.approx(res.state.cell_mass[flyer].sum() * 50.0, rel=1e-12)
