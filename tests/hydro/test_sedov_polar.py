"""A cylindrical Sedov blast on a polar quarter-annulus mesh (a 2D robustness check with a
known answer): E = 0.311357 J/m in a gas of rho = 1, gamma = 1.4 puts the shock at
R = xi0 (E t^2/rho)^(1/4) = 0.750 m at t = 1 s (xi0 = 1.004; the classic test, e.g. Kamm &
Timmes 2007).  The energy is given to an inner ring (a tied body), the inner wall is fixed."""

import numpy as np
import pytest

from shockfriction.hydro.api import run_dict

E_TOTAL = 0.311357  # J per metre of depth, the full circle


def _sedov_deck(na=30, nr=100, r0=0.005, r1=0.03, radius=1.2):
    th = np.linspace(0.0, np.pi / 2, na + 1)

    def arc(r, reverse=False):
        pts = [[f"{float(r * np.cos(t))!r} m", f"{float(r * np.sin(t))!r} m"] for t in th]
        return pts[::-1] if reverse else pts

    def ring(name, a, b, n, e):
        return {"name": name, "eos": "ideal-gas", "gamma": 1.4, "density": "1 kg/m^3", "specific_energy": f"{float(e)!r} J/kg",
                "mesh": {"corners": [[f"{a} m", "0 m"], [f"{b} m", "0 m"], ["0 m", f"{b} m"], ["0 m", f"{a} m"]],
                         "nx": n, "ny": na, "sides": {"right": arc(b), "left": arc(a, reverse=True)}},
                "boundary": {"bottom": "symmetry", "top": "symmetry", "left": "fixed" if a == r0 else "free"}}

    core_mass = np.pi / 4 * (r1**2 - r0**2)
    return {"time": {"end": "1 s"}, "viscosity": {"hourglass": 1.0},
            "bodies": [ring("core", r0, r1, 2, E_TOTAL / 4 / core_mass), ring("gas", r1, radius, nr, 1e-8)],
            "ties": [{"sides": ["core.right", "gas.left"]}]}


def test_cylindrical_sedov_shock_radius():
    res = run_dict(_sedov_deck())
    s = res.state
    gas = res.mesh.cell_body == 1
    r = np.hypot(s.x[s.conn].mean(axis=1), s.y[s.conn].mean(axis=1))[gas]
    rho = s.rho[gas]
    exact = 1.004 * E_TOTAL ** 0.25
    # the shock front: the outermost radius where the density exceeds half the peak jump (6 - 1)/2
    front = r[rho > 3.5].max()
    print(f"shock front {front:.4f} m (exact {exact:.4f}), peak density {rho.max():.3f} (exact 6), "
          f"{res.summary['cycles']} cycles, relative energy error {res.summary['relative_energy_error']:.1e}")
    assert front == pytest.approx(exact, rel=0.02)
    assert 4.5 < rho.max() < 6.2
    assert res.summary["relative_energy_error"] < 2e-3
    # cylindrical symmetry: the front radius along each angular row of cells agrees to ~2 cells
    theta = np.arctan2(s.y[s.conn].mean(axis=1), s.x[s.conn].mean(axis=1))[gas]
    fronts = [r[(rho > 3.5) & (np.abs(theta - t) < np.pi / 120)].max() for t in np.linspace(0.1, 1.47, 8)]
    print("front along the angle", np.round(fronts, 4))
    assert np.ptp(fronts) < 2 * 1.17 / 100
