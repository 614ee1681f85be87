"""Sweep/fit adapter for ``shockfriction run`` decks (the hydrocode).

Calls the hydrocode's ``run_dict(deck, out_dir=None)`` (no files: a sweep
keeps what it needs in memory; fields are not written).  The deck's own
``threads`` (default 1) is left as it is: the parallelism of a sweep is its
worker processes.  Records, SI units: one per probe, named as the probe, with
``time`` (s) and its quantities (``fs`` -> ``{"time", "vy"}``), and ``energy``
(``time`` and the energy-budget columns).  Summary: the run summary's numbers
(``cycles``, ``final_time_s``, ``relative_energy_error``, ``mass_kg`` ...),
except the timings: a run's results are a pure function of its deck, and the
sweep table has its own ``seconds`` column.
"""

from __future__ import annotations

from pathlib import Path

from shockfriction.deck.base import validate


TIMING = {"wall_time_s", "total_wall_time_s", "zone_cycles_per_second", "threads"}


def looks_like(deck: dict) -> bool:
    """A hydrocode deck has bodies."""
    return "bodies" in deck


def check(deck: dict, source: str) -> None:
    from shockfriction.deck.run import RunDeck

    validate(RunDeck, deck, source)


def run(deck: dict, workdir: Path) -> dict:
    from shockfriction.hydro.api import run_dict

    res = run_dict(deck, out_dir=None)
    t = res.probes["t_s"]
    records: dict[str, dict] = {}
    for column, values in res.probes.items():
        if column == "t_s":
            continue
        probe, _, quantity = column.partition(".")
        records.setdefault(probe, {"time": t})[quantity] = values
    records["energy"] = {("time" if k == "t_s" else k): v for k, v in res.energy.items()}
    summary = {k: float(v) for k, v in res.summary.items()
               if isinstance(v, (int, float)) and not isinstance(v, bool) and k not in TIMING}
    return {"records": records, "summary": summary}
