"""``shockfriction fit FIT.toml``: least-squares fit of deck parameters to a measured record."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from shockfriction.cli_options import ALLOW_GEO, DRY_RUN, FORCE, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("fit", epilog=EXIT_CODES)
    def fit(
        fit_file: Path = typer.Argument(..., help="fit file (TOML): deck, measured record, parameters and bounds"),
        out: Optional[Path] = typer.Option(None, "--out", help="output folder (default: out/<fit file stem>): "
                                           "fit.json, fit.png, computed.csv, evaluations.csv"),
        scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address, e.g. tcp://host:8786"),
        workers: Optional[int] = typer.Option(None, "--workers", help="local pool size (default: all cores); "
                                              "with --scheduler, wait for this many Dask workers"),
        force: bool = FORCE,
        verbose: int = VERBOSE,
        quiet: bool = typer.Option(False, "--quiet", "-q", help="no evaluation lines on stderr; log errors only"),
        dry_run: bool = DRY_RUN,
        allow_outside: bool = typer.Option(False, "--allow-outside",
                                           help="let base and measured.file name files outside the fit file's folder"),
        allow_python: bool = typer.Option(False, "--allow-python",
                                          help="let kind = 'python' import and call model = 'module:function'"),
        allow_geo: bool = ALLOW_GEO,
    ) -> None:
        """Fit parameters (and a time shift) by least squares; report values, 1-sigma uncertainties, residual."""
        from rich.console import Console
        from rich.table import Table

        from shockfriction.io.outdir import check_out_path, check_workers, out_dir_state, prepare_out_dir
        from shockfriction.log import configure_logging, verbosity
        from shockfriction.sweep.fit import fit as run_fit
        from shockfriction.sweep.fit import write_outputs

        configure_logging(verbosity(verbose, quiet))
        check_workers(workers)
        out_dir = check_out_path(out or Path("out") / fit_file.stem)
        err = Console(stderr=True)

        def report(k: int, point: dict) -> None:
            values = ", ".join(f"{n} = {v:.6g}" for n, v in point.items() if n != "rms")
            err.print(f"evaluation {k}: {values}: rms {point['rms']:.4g}", highlight=False)

        from shockfriction.safety import Trust

        trust = Trust(allow_outside=allow_outside, allow_python=allow_python, allow_geo=allow_geo)
        if dry_run:
            from shockfriction.sweep.fit import FitProblem
            from shockfriction.sweep.fitspec import load_fit

            spec, here = load_fit(fit_file, trust)
            prob = FitProblem(spec, here, None, str(fit_file), None, trust)
            con = Console()
            con.print(f"{fit_file}: valid fit of {len(prob.names)} variable(s) to {len(prob.data)} dataset(s), "
                      "every deck valid", highlight=False)
            for n, u, lo, hi in zip(prob.names, prob.all_units, prob.lo, prob.hi):
                con.print(f"  {n}: [{lo:.6g}, {hi:.6g}] {u}", highlight=False)
            for ds in prob.data:
                con.print(f"  dataset {ds.name or '(one)'}: kind {ds.kind}, {ds.t_m.size} measured samples, "
                          f"computed {ds.record}.{ds.value}", highlight=False)
            con.print(f"output folder {out_dir}: {out_dir_state(out_dir, force=force)}; nothing run",
                      highlight=False)
            return
        from shockfriction.sweep.fitspec import load_fit

        load_fit(fit_file, trust)  # the fit file is validated before the folder is looked at
        prepare_out_dir(out_dir, force=force)
        res = run_fit(fit_file, scheduler, workers, on_evaluation=None if quiet else report, trust=trust)
        paths = write_outputs(res, out_dir, force=True)
        console = Console()
        table = Table(title=f"fit of {fit_file.name}: {res.message}")
        for col in ("parameter", "best value", "1 sigma", "unit", "note"):
            table.add_column(col)
        for n, v, s, u, ident, bound in zip(res.names, res.values, res.sigma, res.units,
                                            res.identifiable, res.at_bound):
            note = ", ".join(x for x, on in (("not identifiable", not ident), ("at a bound", bound)) if on)
            table.add_row(n, f"{v:.6g}", f"{s:.3g}", u, note)
        console.print(table)
        what = "weighted residual" if res.weighted else "residual"
        console.print(f"{what} rms {res.rms:.4g} over {res.samples} samples "
                      f"({res.evaluations} evaluations, {res.runs} model runs)")
        console.print(f"report: {paths['report']}\nplot: {paths['plot']}")
        if not res.success:
            raise typer.Exit(1)
