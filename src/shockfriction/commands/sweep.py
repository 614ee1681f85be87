"""``shockfriction sweep SWEEP.toml --out DIR``: run a parameter sweep (resumable)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("sweep", epilog=EXIT_CODES)
    def sweep(
        sweep_file: Path = typer.Argument(..., help="sweep file (TOML): base deck, parameters, keep"),
        out: Path = typer.Option(..., "--out", help="output folder: sweep.csv, records.h5, runs/ (the journal)"),
        scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address, e.g. tcp://host:8786"),
        workers: Optional[int] = typer.Option(None, "--workers", help="local pool size (default: all cores); "
                                              "with --scheduler, wait for this many Dask workers"),
        retry_failed: bool = typer.Option(False, "--retry-failed", help="run again the runs recorded as failed"),
        verbose: int = typer.Option(0, "--verbose", "-v", count=True, help="more log messages (-vv: debug)"),
        quiet: bool = typer.Option(False, "--quiet", "-q", help="no progress bar; log errors only"),
        dry_run: bool = typer.Option(False, "--dry-run", help="validate every deck and list the runs; run nothing"),
    ) -> None:
        """Run every deck of a sweep; rerunning the same command resumes an interrupted sweep."""
        from rich.console import Console

        from shockfriction.io.outdir import check_out_path, check_workers
        from shockfriction.log import configure_logging, verbosity
        from shockfriction.sweep.engine import run_sweep

        configure_logging(verbosity(verbose, quiet))
        check_workers(workers)
        check_out_path(out)  # an existing folder is resumed into
        console = Console(stderr=True)
        if dry_run:
            _show_plan(sweep_file, out, retry_failed)
            return
        res = run_sweep(sweep_file, out, scheduler, workers, retry_failed, progress=not quiet)
        console.print(f"{res.total} runs: {res.ok} ok, {res.failed} failed, {res.pending} pending "
                      f"({res.computed} computed now, {res.reused} already finished)")
        for line in res.lost[:5]:
            console.print(f"[yellow]lost with its worker, left pending[/]: {line}", highlight=False)
        if len(res.lost) > 5:
            console.print(f"... and {len(res.lost) - 5} more runs lost with their workers", highlight=False)
        console.print(f"table: {res.table}\nrecords: {res.records}")
        if res.interrupted:
            console.print("[yellow]interrupted[/]: rerun the same command to resume")
            raise typer.Exit(130)
        if res.pending:
            raise typer.Exit(1)


def _show_plan(sweep_file: Path, out: Path, retry_failed: bool, shown: int = 40) -> None:
    """Print the runs of a sweep (validated) and which of them ``out`` already holds."""
    from rich.console import Console
    from rich.table import Table

    from shockfriction.sweep.engine import plan
    from shockfriction.sweep.journal import finished

    spec, kind, runs = plan(sweep_file)
    done = finished(out, retry_failed)
    table = Table(title=f"{sweep_file.name}: {len(runs)} runs of kind {kind!r}, every deck valid")
    table.add_column("run")
    for p in spec.parameter:
        table.add_column(p.column)
    table.add_column("in " + str(out))
    for r in runs[:shown]:
        table.add_row(r.run_id, *(str(r.values[p.column]) for p in spec.parameter),
                      done.get(r.key, "to run"))
    console = Console()
    console.print(table)
    if len(runs) > shown:
        console.print(f"... and {len(runs) - shown} more")
    console.print(f"{sum(1 for r in runs if r.key in done)} finished, "
                  f"{sum(1 for r in runs if r.key not in done)} to run")
