"""Sweep/fit adapter for ``shockfriction subgrid`` decks (uncoupled sub-grid columns).

Calls the sub-grid driver's Python API (validated :class:`SubgridDeck` ->
``run_subgrid(deck, out_dir)``) in the run's scratch folder.  Records, one per
loading column (named as the column: ``ball``, or ``column0`` ...), SI units:
``time`` (s), ``theta_interface`` (K), ``tau`` (Pa), ``flux_in`` (W/m^2).
Summary: ``<column>.theta_interface_max`` and ``<column>.tau_final``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shockfriction.deck.base import validate


def looks_like(deck: dict) -> bool:
    """A sub-grid deck has loading tables and a time step (a hydro deck has bodies)."""
    return "loading" in deck and "dt" in deck and "bodies" not in deck


def check(deck: dict, source: str) -> None:
    from shockfriction.deck.subgrid import SubgridDeck

    validate(SubgridDeck, deck, source)


def run(deck: dict, workdir: Path) -> dict:
    from shockfriction.deck.subgrid import SubgridDeck
    from shockfriction.friction.subgrid.driver import run_subgrid

    model = validate(SubgridDeck, deck, "deck")
    res = run_subgrid(model, workdir, source="deck")
    records, summary = {}, {}
    for k, name in enumerate(res.names):
        records[name] = {"time": res.t, "theta_interface": res.theta_interface[:, k],
                         "tau": res.tau[:, k], "flux_in": res.flux_in[:, k]}
        summary[f"{name}.theta_interface_max"] = float(np.max(res.theta_interface[:, k]))
        summary[f"{name}.tau_final"] = float(res.tau[-1, k])
    return {"records": records, "summary": summary}
