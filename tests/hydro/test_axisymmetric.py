"""Axisymmetric (r-z) runs against plane strain in the 1D limit, and r-z specifics."""

import numpy as np

from shockfriction.hydro.api import run_dict


def test_axial_strip_matches_plane_strain(make_strip):
    """Uniaxial strain along z (r-rollers on both sides): no hoop strain, so the r-weighted
    scheme must give the planar histories whatever the strip's radius."""
    planar = run_dict(make_strip(x0_mm=10.0))
    axi = run_dict(make_strip(x0_mm=10.0, geometry="axisymmetric"))
    for key in ("fs.vy", "mid.p", "mid.rho"):
        a, b = axi.probes[key], planar.probes[key]
        assert a.shape == b.shape
        scale = np.abs(b).max()
        print(f"{key}: max difference {np.abs(a - b).max() / scale:.2e} of {scale:.4g}")
        np.testing.assert_allclose(a, b, atol=1e-9 * scale)
    assert axi.summary["relative_energy_error"] < 1e-3


def _radial_strip(geometry, r0_mm, thickness_mm=4.0, n=80):
    """A flyer ring hitting a target ring in r (z-rollers on bottom and top): far from the axis
    the hoop strain u/r is small and the response tends to plane strain."""
    h = 0.05

    def ring(name, a, b, ny, v):
        return {"name": name, "material": "Al6061-T6", "velocity": [v, "0 m/s"],
                "mesh": {"corners": [[f"{a} mm", "0 mm"], [f"{b} mm", "0 mm"], [f"{b} mm", f"{h} mm"],
                                     [f"{a} mm", f"{h} mm"]], "nx": ny, "ny": 1},
                "boundary": {"bottom": "symmetry", "top": "symmetry"}}

    return {"geometry": geometry, "time": {"end": "1.4 us"},
            "bodies": [ring("flyer", r0_mm - 2.0, r0_mm, 40, "250 m/s"),
                       ring("target", r0_mm, r0_mm + thickness_mm + 2.0, n + 40, "0 m/s")],
            "ties": [{"sides": ["flyer.right", "target.left"]}],
            "probes": [{"name": "fs", "body": "target", "node": [-1, 0], "quantities": ["vx"]},
                       {"name": "mid", "body": "target", "cell": [40, 0], "quantities": ["p"]}]}


def test_radial_strip_tends_to_plane_strain_as_one_over_radius():
    """The divergence correction of the shocked pressure is first order in d/r0."""
    def plateau(res):  # shocked plateau at 2 mm into the target
        t = res.probes["t_s"]
        return res.probes["mid.p"][(t > 0.5e-6) & (t < 0.7e-6)].mean()

    planar = plateau(run_dict(_radial_strip("planar", 1000.0)))
    diffs = {}
    for r0 in (100.0, 1000.0):
        axi = run_dict(_radial_strip("axisymmetric", r0))
        pa = plateau(axi)
        diffs[r0] = (planar - pa) / planar
        print(f"r0 = {r0} mm: axisymmetric {pa / 1e9:.4f} GPa, planar {planar / 1e9:.4f} GPa, "
              f"relative difference {diffs[r0]:.3e}")
        assert axi.summary["relative_energy_error"] < 2e-3
    order = np.log(diffs[100.0] / diffs[1000.0]) / np.log(10.0)
    print(f"observed order in 1/r0: {order:.3f}")
    assert 0.0 < diffs[1000.0] < 0.004  # a diverging shock weakens, by about d/(2 r0)
    assert 0.9 < order < 1.1


def test_uniform_pressure_in_a_closed_can_stays_at_rest():
    """A pressurised gas cylinder touching the axis, walled in by rollers, is in equilibrium:
    the compatible hoop forces balance the in-plane ones exactly on a distorted mesh."""
    deck = {"geometry": "axisymmetric", "time": {"end": "400 us"},
            "bodies": [{"name": "gas", "eos": "ideal-gas", "gamma": 1.4, "density": "1.2 kg/m^3",
                        "pressure": "1 bar",
                        "mesh": {"corners": [["0 mm", "0 mm"], ["10 mm", "0 mm"], ["10 mm", "8 mm"], ["0 mm", "12 mm"]],
                                 "sides": {"top": [["10 mm", "8 mm"], ["6 mm", "11 mm"], ["0 mm", "12 mm"]]},
                                 "nx": 7, "ny": 9, "ratio_x": 1.2},
                        "boundary": {"left": "symmetry", "right": "symmetry", "bottom": "symmetry",
                                     "top": "fixed"}}]}
    res = run_dict(deck)
    s = res.state
    vmax = max(np.abs(s.vx).max(), np.abs(s.vy).max())
    print(f"{s.cycle} cycles, max velocity {vmax:.2e} m/s, pressure spread {np.ptp(s.pressure):.2e} Pa")
    assert s.cycle > 50
    assert vmax < 1e-9
    np.testing.assert_allclose(s.pressure, 1e5, rtol=1e-12)
