"""Cylindrical Noh implosion on a polar quarter-annulus mesh with the edge viscosity (a 2D
robustness check with a known answer): gas of rho = 1, gamma = 5/3, cold, flowing in at 1 m/s;
the stagnation shock moves out at 1/3 m/s with rho = 16 behind it (exact).  The origin is
replaced by a fixed wall at r0 = 1 cm (wall heating spoils the first cells, as usual).  The
edge viscosity has no limiter: it also acts, weakly, in the smooth converging inflow."""

import numpy as np
import pytest

from shockfriction.hydro.api import run_dict


def test_cylindrical_noh_on_a_polar_mesh():
    na, nr, r0, radius = 30, 120, 0.01, 1.2
    th = np.linspace(0.0, np.pi / 2, na + 1)

    def arc(r, reverse=False):
        pts = [[f"{float(r * np.cos(t))!r} m", f"{float(r * np.sin(t))!r} m"] for t in th]
        return pts[::-1] if reverse else pts

    deck = {"time": {"end": "0.6 s"}, "viscosity": {"kind": "edge", "quadratic": 1.0, "linear": 0.0},
            "bodies": [{"name": "gas", "eos": "ideal-gas", "gamma": 5 / 3, "density": "1 kg/m^3",
                        "specific_energy": "1e-9 J/kg", "radial_velocity": "-1 m/s",
                        "mesh": {"corners": [[f"{r0} m", "0 m"], [f"{radius} m", "0 m"], ["0 m", f"{radius} m"],
                                             ["0 m", f"{r0} m"]],
                                 "nx": nr, "ny": na, "sides": {"right": arc(radius), "left": arc(r0, True)}},
                        "boundary": {"bottom": "symmetry", "top": "symmetry", "left": "fixed"}}]}
    res = run_dict(deck)
    s = res.state
    r = np.hypot(s.x[s.conn].mean(axis=1), s.y[s.conn].mean(axis=1))
    plateau = s.rho[(r > 0.05) & (r < 0.15)]
    front = r[s.rho > 8.0].max()
    # the pre-shock flow, away from the outer free surface (now at r ~ 0.6)
    outside = s.rho[(r > 0.25) & (r < 0.4)]
    r_out = r[(r > 0.25) & (r < 0.4)]
    print(f"plateau {plateau.mean():.3f} (exact 16), front {front:.4f} m (exact 0.2), "
          f"pre-shock error {np.abs(outside / (1 + 0.6 / r_out) - 1).max():.2e}, "
          f"energy error {res.summary['relative_energy_error']:.1e}")
    assert plateau.mean() == pytest.approx(16.0, rel=0.05)
    assert front == pytest.approx(0.2, abs=0.02)
    np.testing.assert_allclose(outside, 1 + 0.6 / r_out, rtol=0.02)  # the converging inflow, 1 + t/r
    assert res.summary["relative_energy_error"] < 1e-3
