"""Python API of the hydrocode.

>>> from shockfriction.hydro.api import run
>>> res = run("examples/plate_impact_al_250ms.toml")          # doctest: +SKIP
>>> res.probes["t_s"], res.probes["fs.vy"], res.energy["total"], res.summary
>>> res.probes_df["fs.vy [m/s]"], res.energy_df["total [J/m]"], res.interface_df   # pandas

Histories come as dicts of arrays (``probes``, ``energy``) and as pandas DataFrames with the
units in the column names (``probes_df``, ``energy_df``, ``interface_df``, ``columns_df``;
see :mod:`shockfriction.io.tables`).

``run_dict(deck_dict, out_dir)`` runs a deck given as a dict (as read from TOML,
with unit strings), for sweeps.  ``prepare(deck)`` returns the
:class:`~shockfriction.hydro.cycle.Simulation` without running it (to register
interfaces, change the initial state, or step by hand).
"""

from __future__ import annotations

import json
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from shockfriction.deck.base import load_deck, validate
from shockfriction.deck.run import PROBE_QUANTITIES, RunDeck
from shockfriction.hydro.cycle import ENERGY_COLUMNS, Simulation
from shockfriction.hydro.setup import build_problem, build_slide_lines
from shockfriction.hydro.state import State
from shockfriction.mesh.assembly import Mesh

log = logging.getLogger(__name__)
if TYPE_CHECKING:
    import pandas as pd


@dataclass
class Result:
    """Histories (arrays keyed by column name, time in ``t_s``), final state and summary;
    the same histories as DataFrames with units in the column names (``*_df``)."""

    probes: dict[str, np.ndarray]
    energy: dict[str, np.ndarray]
    state: State
    mesh: Mesh
    summary: dict[str, Any]
    out_dir: Path | None = None
    simulation: Simulation | None = field(default=None, repr=False)

    @property
    def probes_df(self) -> pd.DataFrame:
        """Probe histories: ``t [s]``, then ``<probe>.<quantity> [unit]``."""
        from shockfriction.io.tables import history_frame

        header = probe_header(self.simulation) if self.simulation is not None else list(self.probes)
        return history_frame(self.probes, header)

    @property
    def energy_df(self) -> pd.DataFrame:
        """Energy history: ``t [s]``, ``kinetic [J]``, ... (``[J/m]`` in plane strain)."""
        from shockfriction.io.tables import history_frame

        return history_frame(self.energy, energy_header(self.state.axisymmetric))

    def _h5(self, name: str, reader):
        if self.out_dir is not None and (Path(self.out_dir) / name).is_file():
            return reader(Path(self.out_dir) / name)
        return None

    @property
    def interface_df(self) -> pd.DataFrame:
        """Slide-line records, one row per (line, record time, slave node) (empty without slide lines)."""
        from shockfriction.io.interface import DATASETS, read_interface
        from shockfriction.io.tables import interface_frame

        records = self._h5("interface.h5", read_interface)
        if records is None:  # no output folder: the records kept in memory
            records = {}
            for obj in (self.simulation.interfaces if self.simulation is not None else []):
                rec = getattr(getattr(obj, "line", None), "record", None)
                if rec is None:
                    continue
                arrays = rec.arrays()
                records[obj.name] = {DATASETS[k]: v for k, v in arrays.items() if k in DATASETS}
                records[obj.name]["node_index"] = rec.slave_nodes
        return interface_frame(records)

    @property
    def columns_df(self) -> pd.DataFrame:
        """Sub-grid column profiles, one row per (line, time, node, depth); needs ``out_dir``."""
        from shockfriction.io.columns import read_columns
        from shockfriction.io.tables import columns_frame

        return columns_frame(self._h5("columns.h5", read_columns) or {})


def load(deck_or_path: RunDeck | str | Path | dict, source: str | None = None,
         folder: str | Path | None = None) -> RunDeck:
    """A validated RunDeck from a model, a TOML path or a dict (``folder``: where a dict's
    relative mesh-file paths are resolved; default the current directory)."""
    if isinstance(deck_or_path, RunDeck):
        return deck_or_path
    if isinstance(deck_or_path, dict):
        return validate(RunDeck, deck_or_path, source or "deck", folder)
    return load_deck(deck_or_path, RunDeck)


def prepare(deck_or_path, threads: int | None = None, interfaces=None) -> Simulation:
    """Build the problem and the simulation (slide lines of the deck registered)."""
    source = str(deck_or_path) if isinstance(deck_or_path, (str, Path)) else "deck"
    deck = load(deck_or_path)
    problem = build_problem(deck, source)
    sim = Simulation(problem, interfaces=interfaces, threads=threads)
    for obj in build_slide_lines(problem, sim):
        sim.register_interface(obj)
    return sim


def energy_header(axisymmetric: bool) -> list[str]:
    unit = "J" if axisymmetric else "J/m"
    return ["t_s"] + [f"{c}_{unit}" for c in ENERGY_COLUMNS[1:]]


def probe_header(sim: Simulation) -> list[str]:
    out = ["t_s"]
    for p in sim.problem.probes:
        out += [f"{p.name}.{q}_{PROBE_QUANTITIES[q]}" for q in p.quantities]
    return out


def summarize(sim: Simulation) -> dict[str, Any]:
    s = sim.state
    deck = sim.problem.deck
    px, py = sim.momentum()
    zc = s.n_cells * s.cycle
    return {
        "title": deck.title,
        "geometry": deck.geometry,
        "cycles": s.cycle,
        "final_time_s": s.t,
        "wall_time_s": sim.wall_time,
        "zones": s.n_cells,
        "nodes": s.n_nodes,
        "threads": sim.threads,
        "zone_cycles_per_second": zc / sim.wall_time if sim.wall_time > 0 else None,
        "relative_energy_error": sim.relative_energy_error(),
        "momentum_kg_m_s": [px * (2 * np.pi if s.axisymmetric else 1.0), py * s.geometry_factor],
        "mass_kg": float(s.cell_mass.sum() * s.geometry_factor),
        "energy_unit": "J" if s.axisymmetric else "J/m",
    }


def run_simulation(sim: Simulation, out_dir: str | Path | None = None, progress: bool = False,
                   on_progress: Callable[[float], None] | None = None) -> Result:
    """Run a prepared simulation, writing ``probes.csv``, ``energy.csv``, fields and
    ``summary.json`` into ``out_dir`` when given (files stay readable on failure)."""
    from shockfriction.io.fields import FieldWriter
    from shockfriction.io.histories import CsvHistory

    out = Path(out_dir) if out_dir is not None else None
    sim.out_dir = out
    log.info("%d zones, %d nodes, end time %.4g s, %d thread(s), outputs in %s",
             sim.state.n_cells, sim.state.n_nodes, sim.t_end, sim.threads, out or "(none)")
    writers = []
    fields = None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        energy_csv = CsvHistory(out / "energy.csv", energy_header(sim.state.axisymmetric))
        probes_csv = CsvHistory(out / "probes.csv", probe_header(sim))
        writers = [energy_csv, probes_csv]

        def stream(s: Simulation) -> None:
            energy_csv.write(s.energy_rows[-1])
            if s.probe_rows:
                probes_csv.write(s.probe_rows[-1])

        sim.observers.append(stream)
        fields = FieldWriter.from_output(out, sim)
        if fields is not None:
            sim.observers.append(fields.maybe_write)
    bar = None
    if progress:
        from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

        bar = Progress(TextColumn("[bold]run[/]"), BarColumn(), TextColumn("{task.percentage:>5.1f}%"),
                       TextColumn("t = {task.fields[t]:.3e} s"), TimeRemainingColumn())
        task = bar.add_task("run", total=sim.t_end, t=0.0)
        bar.start()

        def on_progress(t, _prev=on_progress):  # noqa: F811
            bar.update(task, completed=t, t=t)
            if _prev is not None:
                _prev(t)
    started = time.perf_counter()
    try:
        sim.run(progress=on_progress)
    finally:
        if bar is not None:
            bar.stop()
        for w in writers:
            w.close()
        if fields is not None:
            fields.close(sim)
        if out is not None:
            from shockfriction.contact.build import write_interface_outputs

            write_interface_outputs(sim, out)  # slide-line records: interface.h5 + maps
            from shockfriction.io.tables import write_record_tables

            write_record_tables(out)  # interface.csv, columns.csv
            summary = summarize(sim)
            summary["completed"] = sim.state.t >= sim.t_end * (1 - 1e-12)
            summary["total_wall_time_s"] = time.perf_counter() - started
            (out / "summary.json").write_text(json.dumps(summary, indent=2))
    summary = summarize(sim)
    summary["completed"] = sim.state.t >= sim.t_end * (1 - 1e-12)
    return Result(sim.probe_history(), sim.energy_history(), sim.state, sim.mesh, summary, out, sim)


def run(deck_or_path, out_dir: str | Path | None = None, progress: bool = False,
        threads: int | None = None) -> Result:
    """Load, build and run a deck (TOML path, dict or RunDeck)."""
    return run_simulation(prepare(deck_or_path, threads=threads), out_dir, progress)


def run_dict(deck_dict: dict, out_dir: str | Path | None = None, progress: bool = False,
             threads: int | None = None) -> Result:
    """Run a deck given as a dict (unit strings as in TOML), e.g. from a sweep."""
    return run(load(deck_dict, "deck"), out_dir, progress, threads)
