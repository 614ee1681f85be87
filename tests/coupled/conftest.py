"""Deck factories of the coupled (sub-grid friction) tests: dicts as read from TOML."""

import pytest


def strip_deck(flyer="Steel4340", target="Ti-6Al-4V", vt=55.0, vn=85.0, model="thermoelastic", mu0=0.15, f=0.15,
               end="1.2 us", cell_um=100.0, flyer_mm=5.0, target_mm=6.0, cells=200, gap_mm=0.0, record="20 ns",
               **friction):
    """Pressure-shear 1D strip (periodic left/right): ``flyer`` below at (vt, vn), ``target`` above,
    slide line slave = target bottom (the columns model the target), guide = flyer top."""
    per = {"left": "periodic", "right": "periodic"}
    ny_f = max(2, round(flyer_mm * 1e3 / cell_um))
    ny_t = max(2, round(target_mm * 1e3 / cell_um))
    fr = {"law": f"subgrid-{model}", "mu0": mu0, "f": f, "thickness": "20 um", "cells": cells}
    fr.update(friction)
    y0 = -gap_mm
    return {
        "title": "coupled strip", "geometry": "planar", "time": {"end": end, "cfl": 0.5},
        "bodies": [
            {"name": "flyer", "material": flyer, "strength": "scg", "velocity": [f"{vt} m/s", f"{vn} m/s"],
             "mesh": {"corners": [["0 mm", f"{y0 - flyer_mm} mm"], ["0.1 mm", f"{y0 - flyer_mm} mm"],
                                  ["0.1 mm", f"{y0} mm"], ["0 mm", f"{y0} mm"]], "nx": 2, "ny": ny_f},
             "boundary": per},
            {"name": "target", "material": target, "strength": "scg",
             "mesh": {"corners": [["0 mm", "0 mm"], ["0.1 mm", "0 mm"], ["0.1 mm", f"{target_mm} mm"],
                                  ["0 mm", f"{target_mm} mm"]], "nx": 3, "ny": ny_t},
             "boundary": per},
        ],
        "slide_lines": [{"name": "interface", "guide": {"body": "flyer", "side": "top"},
                         "slave": {"body": "target", "side": "bottom"}, "record_interval": record,
                         "friction": fr}],
        "probes": [{"name": "rear", "body": "target", "node": [0, -1], "quantities": ["vx", "vy"]}],
    }


@pytest.fixture(scope="session")
def coupled_decks():
    """Deck factories (tests import nothing from conftest: importlib mode)."""
    return {"strip": strip_deck}
