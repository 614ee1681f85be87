"""Shared helpers of the hydrocode tests: small decks as dicts."""

import pytest


def strip_deck(ny_flyer=40, ny_target=100, velocity="250 m/s", material="Al6061-T6", strength="none",
               end="2.6 us", geometry="planar", x0_mm=0.0, width_mm=0.1, extra_body=None):
    """A 1D uniaxial-strain strip (symmetry on left/right): flyer tied to target."""
    x1 = x0_mm + width_mm

    def body(name, y0, y1, ny, v):
        b = {"name": name, "material": material, "strength": strength, "velocity": ["0 m/s", v],
             "mesh": {"corners": [[f"{x0_mm} mm", f"{y0} mm"], [f"{x1} mm", f"{y0} mm"],
                                  [f"{x1} mm", f"{y1} mm"], [f"{x0_mm} mm", f"{y1} mm"]], "nx": 1, "ny": ny},
             "boundary": {"left": "symmetry", "right": "symmetry"}}
        if extra_body:
            b.update(extra_body)
        return b

    return {
        "title": "strip", "geometry": geometry, "time": {"end": end},
        "bodies": [body("flyer", -0.1 * ny_flyer, 0.0, ny_flyer, velocity),
                   body("target", 0.0, 0.1 * ny_target, ny_target, "0 m/s")],
        "ties": [{"sides": ["flyer.top", "target.bottom"]}],
        "probes": [{"name": "fs", "body": "target", "node": [0, -1], "quantities": ["vy"]},
                   {"name": "mid", "body": "target", "cell": [0, ny_target // 2],
                    "quantities": ["p", "q", "sigma_yy", "rho", "T", "sxx", "syy"]}],
    }


@pytest.fixture(scope="session")
def make_strip():
    """The :func:`strip_deck` factory (tests import nothing from conftest: importlib mode)."""
    return strip_deck
