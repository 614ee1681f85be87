"""``shockfriction run DECK.toml --out DIR``: run a hydrocode deck."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer


def register(app: typer.Typer) -> None:
    @app.command("run")
    def run(
        deck: Path = typer.Argument(..., help="run deck (TOML); see docs/deck-run.md"),
        out: Path = typer.Option(Path("out"), "--out", "-o", help="output folder"),
        threads: Optional[int] = typer.Option(None, "--threads", "-t",
                                              help="numba threads (1 = serial kernels, 0 = all); default: deck"),
        quiet: bool = typer.Option(False, "--quiet", "-q", help="no progress bar"),
    ) -> None:
        """Run a deck: probes.csv, energy.csv, fields.h5/.xmf and summary.json in OUT."""
        from rich.console import Console

        from shockfriction.hydro.api import prepare, run_simulation

        sim = prepare(deck, threads=threads)
        res = run_simulation(sim, out, progress=not quiet)
        s = res.summary
        if not s["completed"]:
            Console(stderr=True).print(f"[yellow]stopped at max_cycles = {s['cycles']} before the end time[/]")
        Console().print(
            f"{s['cycles']} cycles to t = {s['final_time_s']:.4e} s in {s['wall_time_s']:.2f} s "
            f"({s['zone_cycles_per_second'] or 0:.3g} zone-cycles/s), relative energy error "
            f"{s['relative_energy_error']:.2e}; results in {out}")
