"""``shockfriction run DECK.toml --out DIR``: run a hydrocode deck."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("run", epilog=EXIT_CODES)
    def run(
        deck: Path = typer.Argument(..., help="run deck (TOML); see docs/deck-run.md"),
        out: Path = typer.Option(Path("out"), "--out", "-o", help="output folder (new or empty; see --force)"),
        threads: Optional[int] = typer.Option(None, "--threads", "-t",
                                              help="numba threads (1 = serial kernels, 0 = all); default: deck"),
        force: bool = typer.Option(False, "--force", "-f",
                                   help="reuse a non-empty OUT: delete its previous shockfriction outputs first"),
        verbose: int = typer.Option(0, "--verbose", "-v", count=True, help="more log messages (-vv: debug)"),
        quiet: bool = typer.Option(False, "--quiet", "-q", help="no progress bar; log errors only"),
        restart: bool = typer.Option(False, "--restart",
                                     help="continue from OUT/checkpoint.h5 (same deck), appending to OUT's outputs"),
    ) -> None:
        """Run a deck: probes.csv, energy.csv, fields.h5/.xmf and summary.json in OUT.

        SIGTERM or Ctrl-C stops at the end of the cycle, writes a checkpoint and finishes every output
        (exit status 143 or 130); continue with --restart."""
        from rich.console import Console

        from shockfriction.hydro.api import prepare, run_simulation
        from shockfriction.io.outdir import check_out_path, check_threads, prepare_out_dir
        from shockfriction.io.session import RunInterrupted
        from shockfriction.log import configure_logging, verbosity

        configure_logging(verbosity(verbose, quiet))
        check_threads(threads)
        check_out_path(out)
        sim = prepare(deck, threads=threads)
        prepare_out_dir(out, force=force, restart=restart)
        try:
            res = run_simulation(sim, out, progress=not quiet, restart=restart, signals=True)
        except RunInterrupted as exc:
            Console(stderr=True).print(f"[yellow]{exc}; outputs and checkpoint written in {out} "
                                       "(continue with --restart)[/]", highlight=False)
            raise typer.Exit(exc.exit_code) from None
        s = res.summary  # a run that returns reached time.end (the guards raise otherwise)
        Console().print(
            f"{s['cycles']} cycles to t = {s['final_time_s']:.4e} s in {s['wall_time_s']:.2f} s "
            f"({s['zone_cycles_per_second'] or 0:.3g} zone-cycles/s), relative energy error "
            f"{s['relative_energy_error']:.2e}; results in {out}")
