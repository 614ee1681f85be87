"""The CEA/DAM-type cone-in-cylinder shot (thesis §3.4, §7.3.4, §8.3.3) as a run-deck generator.

The thesis gives no geometry (digest part 1 §6.1: cone angle, sizes, impactor and probe positions
are all missing); this one is in the spirit of Juanicotena et al. (2006): an aluminium alloy
AA5083-H111 truncated cone fills the matching conical bore of an AISI 321 stainless confinement,
both struck at 250 m/s by an AISI 321 flyer plate.  Axisymmetric, x = r, y = z (the shot along +z):

* cone: base radius R_b at z = 0 (the impact face), length L, half-angle alpha, so the rear
  radius is R_t = R_b - L tan(alpha): the cone is driven into a bore that narrows ahead of it,
  which loads the conical interface in compression and makes it slide;
* confinement: the annulus between the bore and the outer radius R_o, same length;
* flyer: thickness H, radius R_o, in two tied bodies (core r < R_b and ring r > R_b) so that
  frictionless slide lines carry the impact into the cone base and the confinement face
  separately and the cone base can slide past the confinement;
* the cone/confinement slide line (``cone_wall``): slave = the cone's conical side (the finer
  side, one column per node), guide = the bore; the friction law is the study's parameter;
* the cone's base corner (R_b, 0) belongs to the cone_wall line only (the cone_base line stops
  one node short): two slide lines pushing one corner node along two normals jet it out;
* probes: free-surface axial velocity of the cone's rear face on the axis (``cone_fs``) and of
  the confinement's rear face at mid-wall (``confinement_fs``).

Defaults: L = 30 mm, R_b = 10 mm, alpha = 10 deg (R_t = 4.71 mm), R_o = 25 mm, H = 4 mm, about
100 um cells along the interface (300 slide-line nodes), the guide 4/3 coarser, radial grading in
the confinement.  ``cell_um`` scales the whole mesh (400: a coarse test variant).
"""

from __future__ import annotations

import math


def _pt(r_mm: float, z_mm: float) -> list[str]:
    return [f"{r_mm:.6f} mm", f"{z_mm:.6f} mm"]


def _grading(width: float, n: int, first: float, cap: float = 1.03) -> float:
    """Geometric ratio r in [1, cap] whose first of ``n`` cells over ``width`` is ``first`` (1 if uniform is finer)."""
    def first_cell(r):
        return width / n if r == 1.0 else width * (r - 1.0) / (r ** n - 1.0)

    if first_cell(1.0) <= first or n < 10:
        return 1.0
    if first_cell(cap) >= first:
        return cap
    lo, hi = 1.0, cap
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if first_cell(mid) > first else (lo, mid)
    return round(0.5 * (lo + hi), 6)


def friction_table(law: str = "coulomb", mu0: float = 0.3, f: float = 0.7, mu_inf: float = 0.01,
                   gamma: float = 0.05, cells: int = 500, profile_nodes=None, profile_interval: str | None = None):
    """The ``friction`` table of the cone/confinement slide line for ``law``."""
    if law == "coulomb":
        return {"law": "coulomb", "mu0": mu0}
    if law == "modified_coulomb":
        return {"law": "modified_coulomb", "mu0": mu0, "mu_inf": mu_inf, "gamma": f"{gamma} s/m"}
    if law == "frictionless":
        return {"law": "frictionless"}
    table = {"law": law, "mu0": mu0, "f": f, "thickness": "20 um", "cells": cells}
    if profile_nodes is not None:
        table["profile_nodes"] = list(profile_nodes)
    if profile_interval is not None:
        table["profile_interval"] = profile_interval
    return table


def cone_deck(law: str = "subgrid-thermoelastic", mu0: float = 0.3, f: float = 0.7, *, half_angle_deg: float = 10.0,
              length_mm: float = 30.0, base_radius_mm: float = 10.0, outer_radius_mm: float = 25.0,
              flyer_mm: float = 4.0, impact_velocity: float = 250.0, cell_um: float = 100.0, end_us: float = 8.0,
              record_ns: float = 50.0, cells: int = 500, threads: int = 1, mu_inf: float = 0.01, gamma: float = 0.05,
              profile_nodes=None, profile_interval: str | None = None, field_interval_us: float | None = None) -> dict:
    """The run deck (a dict, as read from TOML) of the cone-in-cylinder shot."""
    L, Rb, Ro, H = length_mm, base_radius_mm, outer_radius_mm, flyer_mm
    Rt = Rb - L * math.tan(math.radians(half_angle_deg))
    if not 0.0 < Rt < Rb < Ro:
        raise ValueError(f"need 0 < rear radius {Rt:.3f} < base radius {Rb} < outer radius {Ro} mm")
    h = cell_um * 1e-3
    slant = math.hypot(L, Rb - Rt)
    n_iface = max(4, round(slant / h))                           # slave (cone side) segments
    n_guide = max(3, round(0.75 * n_iface))                      # guide (bore) segments, coarser
    g = slant / n_guide
    m_barrel = max(2, math.ceil((H + 1.0) / g))                  # barrel segments, same spacing as the bore
    B = m_barrel * g                                             # barrel length: the flyer starts inside it
    n_cone_r = max(2, round(Rb / (1.5 * h)))                     # cone radial cells (150 um at the base)
    n_conf_r = max(3, round((Ro - Rb) / (4.0 * h)))              # confinement radial cells, graded
    ratio = _grading(Ro - Rb, n_conf_r, 2.0 * h)                  # first confinement cell ~ 2 h, ratio <= 1.03
    n_flyer_z = max(2, round(H / (2.0 * h)))
    scg = {"strength": "scg"}
    axis = {"left": "symmetry"}
    bodies = [
        {"name": "cone", "material": "Al5083-H111", **scg,
         "mesh": {"corners": [_pt(0, 0), _pt(Rb, 0), _pt(Rt, L), _pt(0, L)], "nx": n_cone_r, "ny": n_iface},
         "boundary": axis},
        {"name": "confinement", "material": "AISI321", **scg,
         "mesh": {"corners": [_pt(Rb, -B), _pt(Ro, -B), _pt(Ro, L), _pt(Rt, L)], "nx": n_conf_r,
                  "ny": n_guide + m_barrel, "ratio_x": ratio,
                  "sides": {"left": [_pt(Rt, L), _pt(Rb, 0), _pt(Rb, -B)]}}},
        {"name": "flyer", "material": "AISI321", **scg, "velocity": ["0 m/s", f"{impact_velocity} m/s"],
         "mesh": {"corners": [_pt(0, -H), _pt(Rb, -H), _pt(Rb, 0), _pt(0, 0)], "nx": n_cone_r, "ny": n_flyer_z},
         "boundary": axis},
    ]
    wall = {"name": "cone_wall", "guide": {"body": "confinement", "side": "left"},
            "slave": {"body": "cone", "side": "right"}, "record_interval": f"{record_ns} ns",
            "friction": friction_table(law, mu0, f, mu_inf, gamma, cells, profile_nodes, profile_interval)}
    barrel = {"name": "barrel", "guide": {"body": "confinement", "side": "left"},
              "slave": {"body": "flyer", "side": "right"}, "record_interval": f"{record_ns} ns"}
    deck = {
        "title": (f"Al5083 cone (half-angle {half_angle_deg:g} deg) in an AISI321 confinement, flyer at "
                  f"{impact_velocity:g} m/s, friction {law} mu0 = {mu0:g}" + (f", f = {f:g}" if "subgrid" in law else "")),
        "geometry": "axisymmetric",
        "threads": threads,
        "time": {"end": f"{end_us} us", "cfl": 0.5},
        "bodies": bodies,
        "ties": [{"sides": ["flyer.top", "cone.bottom"]}],
        "slide_lines": [wall, barrel],
        "probes": [
            {"name": "cone_fs", "body": "cone", "node": [0, -1], "quantities": ["vy"]},
            {"name": "confinement_fs", "body": "confinement", "at": _pt(0.5 * (Rt + Ro), L), "quantities": ["vy"]},
        ],
    }
    if field_interval_us is not None:
        deck["output"] = {"field_interval": f"{field_interval_us} us"}
    return deck


def to_toml(deck: dict, header: str = "") -> str:
    """TOML text of a deck dict (the subset of TOML the decks use)."""
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, (int, float)):
            return repr(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        raise TypeError(type(v))

    lines = [header.rstrip()] if header else []
    tables, arrays = [], []
    for k, v in deck.items():
        if isinstance(v, dict):
            tables.append((k, v))
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            arrays.append((k, v))
        else:
            lines.append(f"{k} = {value(v)}")
    for k, v in tables:
        lines += ["", f"[{k}]"] + [f"{kk} = {value(vv)}" for kk, vv in v.items()]
    for k, items in arrays:
        for item in items:
            lines += ["", f"[[{k}]]"]
            subtables = []
            for kk, vv in item.items():
                if isinstance(vv, dict) and kk in ("mesh", "boundary"):
                    subtables.append((kk, vv))
                else:
                    lines.append(f"{kk} = {value(vv)}")
            for kk, vv in subtables:
                lines += [f"[{k}.{kk}]"] + [f"{a} = {value(b)}" for a, b in vv.items()]
    return "\n".join(lines) + "\n"
