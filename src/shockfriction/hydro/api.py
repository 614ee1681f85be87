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

import logging
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
         folder: str | Path | None = None, trust=None) -> RunDeck:
    """A validated RunDeck from a model, a TOML path or a dict (``folder``: where a dict's
    relative mesh-file paths are resolved; default the current directory; ``trust``: what the
    deck's files may be, :class:`shockfriction.safety.Trust`, default trusted)."""
    if isinstance(deck_or_path, RunDeck):
        return deck_or_path
    if isinstance(deck_or_path, dict):
        return validate(RunDeck, deck_or_path, source or "deck", folder, trust)
    return load_deck(deck_or_path, RunDeck, trust)


def prepare(deck_or_path, threads: int | None = None, interfaces=None, trust=None,
            source: str | None = None) -> Simulation:
    """Build the problem and the simulation (slide lines of the deck registered); ``source``: the
    deck's name in messages (default: its path, or "deck")."""
    source = source or (str(deck_or_path) if isinstance(deck_or_path, (str, Path)) else "deck")
    deck = load(deck_or_path, trust=trust)
    problem = build_problem(deck, source)
    sim = Simulation(problem, interfaces=interfaces, threads=threads)
    for obj in build_slide_lines(problem, sim):
        sim.register_interface(obj)
    return sim


def energy_header(axisymmetric: bool) -> list[str]:
    """Header of ``energy.csv``: ``t [s]``, then ``<term> [J]`` (per radian, axisymmetric) or ``[J/m]``."""
    unit = "J" if axisymmetric else "J/m"
    return ["t [s]"] + [f"{c} [{unit}]" for c in ENERGY_COLUMNS[1:]]


def probe_header(sim: Simulation) -> list[str]:
    """Header of ``probes.csv``: ``t [s]``, then ``<probe>.<quantity> [unit]`` (``[-]``: dimensionless)."""
    out = ["t [s]"]
    for p in sim.problem.probes:
        out += [f"{p.name}.{q} [{csv_unit(PROBE_QUANTITIES[q])}]" for q in p.quantities]
    return out


def csv_unit(unit: str) -> str:
    """A unit as the CSV headers write it (docs/cli.md): ``1`` -> ``-``, ``kg/m3`` -> ``kg/m^3``."""
    return {"1": "-", "kg/m3": "kg/m^3"}.get(unit, unit)


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
        "warnings": list(sim.guards.warnings),
    }


def run_simulation(sim: Simulation, out_dir: str | Path | None = None, progress: bool = False,
                   on_progress: Callable[[float], None] | None = None, restart: bool = False,
                   signals: bool = False, force: bool = False) -> Result:
    """Run a prepared simulation, writing ``probes.csv``, ``energy.csv``, fields, slide-line records
    and ``summary.json`` into ``out_dir`` when given, complete at every output time
    (:class:`~shockfriction.io.session.RunOutputs`); ``restart``: continue from ``out_dir``'s checkpoint;
    ``signals``: SIGTERM/SIGINT stop at the end of a cycle with a checkpoint (raises
    :class:`~shockfriction.io.session.RunInterrupted`).  A non-empty ``out_dir`` is refused
    (:class:`~shockfriction.errors.UsageError`) unless ``force`` (its previous outputs are deleted)
    or ``restart``, as on the command line (:func:`shockfriction.io.outdir.prepare_out_dir`)."""
    outputs = None
    if out_dir is not None:
        from shockfriction.io.outdir import prepare_out_dir
        from shockfriction.io.session import RunOutputs

        prepare_out_dir(out_dir, force=force, restart=restart, option="out_dir")

        outputs = RunOutputs(sim, out_dir, restart=restart, summarize=summarize,
                             headers=(energy_header(sim.state.axisymmetric), probe_header(sim)), signals=signals)
    elif restart:
        raise ValueError("restart needs the output folder that holds the checkpoint")
    log.info("%d zones, %d nodes, end time %.4g s, %d thread(s), outputs in %s%s",
             sim.state.n_cells, sim.state.n_nodes, sim.t_end, sim.threads, out_dir or "(none)",
             f" (restart from t = {sim.state.t:.4g} s)" if restart else "")
    bar = None
    if progress:
        from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

        bar = Progress(TextColumn("[bold]run[/]"), BarColumn(), TextColumn("{task.percentage:>5.1f}%"),
                       TextColumn("t = {task.fields[t]:.3e} s"), TimeRemainingColumn())
        task = bar.add_task("run", total=sim.t_end, t=sim.state.t)
        bar.start()

        def on_progress(t, _prev=on_progress):  # noqa: F811
            bar.update(task, completed=t, t=t)
            if _prev is not None:
                _prev(t)
    error = None
    try:
        sim.run(progress=on_progress)
    except BaseException as exc:
        error = exc
        raise
    finally:
        if bar is not None:
            bar.stop()
        if outputs is not None:
            outputs.finish(error)
    summary = summarize(sim)
    summary["completed"] = sim.state.t >= sim.t_end * (1 - 1e-12)
    return Result(sim.probe_history(), sim.energy_history(), sim.state, sim.mesh, summary,
                  Path(out_dir) if out_dir is not None else None, sim)


def run(deck_or_path, out_dir: str | Path | None = None, progress: bool = False,
        threads: int | None = None, restart: bool = False, force: bool = False) -> Result:
    """Load, build and run a deck (TOML path, dict or RunDeck); ``restart``: continue from the
    checkpoint in ``out_dir`` (docs/theory/outputs-and-restart.md); ``force``: replace the
    previous outputs of a non-empty ``out_dir`` (refused otherwise)."""
    return run_simulation(prepare(deck_or_path, threads=threads), out_dir, progress, restart=restart, force=force)


def run_dict(deck_dict: dict, out_dir: str | Path | None = None, progress: bool = False,
             threads: int | None = None, restart: bool = False, force: bool = False) -> Result:
    """Run a deck given as a dict (unit strings as in TOML), e.g. from a sweep."""
    return run(load(deck_dict, "deck"), out_dir, progress, threads, restart, force)
