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
        restart: bool = typer.Option(False, "--restart",
                                     help="continue from OUT/checkpoint.h5 (same deck), appending to OUT's outputs"),
    ) -> None:
        """Run a deck: probes.csv, energy.csv, fields.h5/.xmf and summary.json in OUT.

        SIGTERM or Ctrl-C stops at the end of the cycle, writes a checkpoint and finishes every output
        (exit status 143 or 130); continue with --restart."""
        from rich.console import Console

        from shockfriction.hydro.api import prepare, run_simulation
        from shockfriction.io.session import RunInterrupted

        sim = prepare(deck, threads=threads)
        try:
            res = run_simulation(sim, out, progress=not quiet, restart=restart, signals=True)
        except RunInterrupted as exc:
            Console(stderr=True).print(f"[yellow]{exc}; outputs and checkpoint written in {out} "
                                       "(continue with --restart)[/]", highlight=False)
            raise typer.Exit(exc.exit_code) from None
        except KeyboardInterrupt:
            Console(stderr=True).print(f"[yellow]interrupted; outputs written in {out}[/]", highlight=False)
            raise typer.Exit(130) from None
        s = res.summary
        if not s["completed"]:
            Console(stderr=True).print(f"[yellow]stopped at max_cycles = {s['cycles']} before the end time[/]")
        Console().print(
            f"{s['cycles']} cycles to t = {s['final_time_s']:.4e} s in {s['wall_time_s']:.2f} s "
            f"({s['zone_cycles_per_second'] or 0:.3g} zone-cycles/s), relative energy error "
            f"{s['relative_energy_error']:.2e}; results in {out}")
