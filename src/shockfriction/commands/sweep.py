"""``shockfriction sweep SWEEP.toml --out DIR``: run a parameter sweep (resumable)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from shockfriction.cli_options import ALLOW_GEO, FORCE, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("sweep", epilog=EXIT_CODES)
    def sweep(
        sweep_file: Path = typer.Argument(..., help="sweep file (TOML): base deck, parameters, keep"),
        out: Path = typer.Option(..., "--out", help="output folder: sweep.csv, records.h5, plan.json, runs/ (the "
                                 "journal); new, empty, or holding this sweep (resumed)"),
        scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address, e.g. tcp://host:8786"),
        workers: Optional[int] = typer.Option(None, "--workers", help="local pool size (default: all cores); "
                                              "with --scheduler, wait for this many Dask workers"),
        retry_failed: bool = typer.Option(False, "--retry-failed", help="run again the runs recorded as failed"),
        force: bool = FORCE,
        verbose: int = VERBOSE,
        quiet: bool = typer.Option(False, "--quiet", "-q", help="no progress bar on stderr; log errors only"),
        dry_run: bool = typer.Option(False, "--dry-run", help="validate every deck and list the runs (stdout); "
                                     "run and write nothing"),
        allow_outside: bool = typer.Option(False, "--allow-outside",
                                           help="let base name a deck outside the sweep file's folder"),
        allow_python: bool = typer.Option(False, "--allow-python",
                                          help="let kind = 'python' import and call model = 'module:function'"),
        allow_geo: bool = ALLOW_GEO,
    ) -> None:
        """Run every deck of a sweep; rerunning the same command resumes an interrupted sweep.

        The counts and file names go to stdout, the progress bar and errors to stderr.  Exit status 3
        when runs failed (their errors: column 'error' of sweep.csv), 1 when runs are left pending
        (lost with their worker: rerun to resume)."""
        from rich.console import Console

        from shockfriction.io.outdir import check_out_path, check_workers
        from shockfriction.log import configure_logging, verbosity
        from shockfriction.safety import Trust
        from shockfriction.sweep.spec import load_sweep

        configure_logging(verbosity(verbose, quiet))
        check_workers(workers)
        check_out_path(out)
        console = Console()
        errors = Console(stderr=True)
        trust = Trust(allow_outside=allow_outside, allow_python=allow_python, allow_geo=allow_geo)
        load_sweep(sweep_file, trust)  # the sweep file's own checks (sizes included) before the engine is imported
        from shockfriction.sweep.engine import run_sweep

        if dry_run:
            _show_plan(sweep_file, out, retry_failed, trust, force)
            return
        # a new or empty folder, or one holding a sweep (resumed); another non-empty one needs --force
        res = run_sweep(sweep_file, out, scheduler, workers, retry_failed, progress=not quiet, trust=trust,
                        force=force)
        console.print(f"{res.total} runs: {res.ok} ok, {res.failed} failed, {res.pending} pending "
                      f"({res.computed} computed now, {res.reused} already finished)")
        for line in res.lost[:5]:
            errors.print(f"[yellow]lost with its worker, left pending[/]: {line}", highlight=False)
        if len(res.lost) > 5:
            errors.print(f"... and {len(res.lost) - 5} more runs lost with their workers", highlight=False)
        console.print(f"table: {res.table}\nrecords: {res.records}", highlight=False)
        if res.interrupted:
            errors.print("[yellow]interrupted[/]: rerun the same command to resume")
            raise typer.Exit(130)
        if res.failed:
            errors.print(f"[red]{res.failed} of {res.total} runs failed[/] (their errors: column 'error' of "
                         f"{res.table}; --retry-failed runs them again)", highlight=False)
            raise typer.Exit(3)
        if res.pending:
            raise typer.Exit(1)


def _show_plan(sweep_file: Path, out: Path, retry_failed: bool, trust, force: bool = False, shown: int = 40) -> None:
    """Print the runs of a sweep (validated) and which of them ``out`` already holds."""
    from rich.console import Console
    from rich.table import Table

    from shockfriction.io.outdir import out_dir_state
    from shockfriction.sweep.engine import plan
    from shockfriction.sweep.journal import finished

    spec, kind, runs = plan(sweep_file, trust, import_model=False)
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
                  f"{sum(1 for r in runs if r.key not in done)} to run; output folder {out}: "
                  f"{out_dir_state(out, force=force, resume=True)}", highlight=False)
