"""Deck factories of the slide-line tests (dicts, as read from TOML)."""

import math

import pytest

# linear-elastic steel of materials-data.md section 4: rho 7850, c_L 5900, c_S 3200
RHO, CL, CS = 7850.0, 5900.0, 3200.0
G_STEEL = RHO * CS ** 2
C0_STEEL = math.sqrt(CL ** 2 - 4.0 * CS ** 2 / 3.0)


def elastic_steel(**extra):
    body = {"material": "SS304", "density": f"{RHO} kg/m^3", "c0": f"{C0_STEEL} m/s", "s": 0.0, "gamma0": 0.0,
            "strength": "elastic-perfectly-plastic", "shear_modulus": f"{G_STEEL} Pa", "yield_stress": "100 GPa",
            "elastic_modulus": "constant"}
    body.update(extra)
    return body


def block(name, x0, x1, y0, y1, nx, ny, boundary, velocity=("0 m/s", "0 m/s"), **material):
    b = elastic_steel(**material)
    b.update({"name": name, "velocity": list(velocity),
              "mesh": {"corners": [[f"{x0} mm", f"{y0} mm"], [f"{x1} mm", f"{y0} mm"], [f"{x1} mm", f"{y1} mm"],
                                   [f"{x0} mm", f"{y1} mm"]], "nx": nx, "ny": ny},
              "boundary": boundary})
    return b


def pressure_shear_deck(mu=0.1, speed=100.0, angle_deg=30.0, thickness_mm=3.0, ny=60, nx_flyer=2, nx_target=3,
                        end="1.5 us", law="coulomb", record="10 ns", heat="none", flyer_material="SS304",
                        target_material="SS304", friction_extra=None, yield_stress="100 GPa"):
    """Pressure-shear impact of two identical elastic steel plates, 1D periodic strip.

    The library materials only lend their thermal data (heat share, temperature); the
    mechanical data are those of the linear-elastic steel."""
    vn = speed * math.cos(math.radians(angle_deg))
    vt = speed * math.sin(math.radians(angle_deg))
    per = {"left": "periodic", "right": "periodic"}
    return {
        "title": "pressure-shear", "geometry": "planar", "time": {"end": end, "cfl": 0.5},
        "bodies": [block("flyer", 0.0, 0.1, -thickness_mm, 0.0, nx_flyer, ny, per, (f"{vt} m/s", f"{vn} m/s"),
                         material=flyer_material, yield_stress=yield_stress),
                   block("target", 0.0, 0.1, 0.0, thickness_mm, nx_target, ny, per, material=target_material,
                         yield_stress=yield_stress)],
        "slide_lines": [{"name": "interface", "guide": {"body": "target", "side": "bottom"},
                         "slave": {"body": "flyer", "side": "top"}, "record_interval": record, "heat": heat,
                         "friction": {"law": law, "mu0": mu, **(friction_extra or {})}}],
        "probes": [{"name": "rear", "body": "target", "node": [0, -1], "quantities": ["vx", "vy"]}],
    }


@pytest.fixture(scope="session")
def contact_decks():
    """Deck factories (tests import nothing from conftest: importlib mode)."""
    return {"pressure_shear": pressure_shear_deck, "block": block, "elastic_steel": elastic_steel,
            "steel": (RHO, CL, CS, G_STEEL, C0_STEEL)}
