"""``shockfriction subgrid DECK.toml [--out DIR]``: sub-grid interface columns under imposed loading."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np
import typer

from shockfriction.cli_options import DRY_RUN, FORCE, QUIET, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("subgrid", epilog=EXIT_CODES)
    def subgrid(
        deck: Path = typer.Argument(..., help="TOML deck (see examples/subgrid/)"),
        out: Optional[Path] = typer.Option(None, "--out", help="output folder (default: out/<deck stem>)"),
        plots: bool = typer.Option(True, "--plots/--no-plots", help="write the PNG figures"),
        threads: Optional[int] = typer.Option(None, "--threads", "-t",
                                              help="numba threads for the columns (1 = one, 0 = all cores); "
                                                   "default: all cores from 1600 cells in all"),
        force: bool = FORCE,
        verbose: int = VERBOSE,
        quiet: bool = QUIET,
        dry_run: bool = DRY_RUN,
    ) -> None:
        """Run a sub-grid interface model (model = thermoelastic, thesis ch. 7; thermoelastoplastic, ch. 8;
        or viscoplastic, docs/theory/viscoplastic.md) under imposed slip velocity and normal stress, or a
        heat flux alone.

        Writes history.csv (t [s], theta_interface [K], tau [Pa], slip_macro [m/s], slip_local [m/s],
        flux [W/m^2] = flux entering the column, iterations), profiles.csv (t [s], z [m], theta [K],
        eps_p [-]) and interface.png / profiles.png.
        """
        from rich.console import Console

        from shockfriction.deck.base import load_deck
        from shockfriction.deck.subgrid import SubgridDeck
        from shockfriction.friction.subgrid.driver import run_subgrid
        from shockfriction.io.outdir import check_out_path, check_threads, out_dir_state, prepare_out_dir
        from shockfriction.log import configure_logging, verbosity
        from shockfriction.plot.subgrid import plot_interface, plot_profiles

        configure_logging(verbosity(verbose, quiet))
        check_threads(threads)
        out_dir = check_out_path(out if out is not None else Path("out") / deck.stem)
        model = load_deck(deck, SubgridDeck)
        if dry_run:
            Console().print(f"{deck}: valid sub-grid deck, model {model.model!r}, material {model.material}, "
                            f"{len(model.loading)} column(s) of {model.column.cells} cells, "
                            f"duration {model.duration:.4g} s in steps of {model.dt:.4g} s\n"
                            f"output folder {out_dir}: {out_dir_state(out_dir, force=force)}; nothing run",
                            highlight=False)
            return
        from shockfriction.threading_policy import effective_threads, use_threads

        # the columns run in parallel blocks (the same bytes on any count); 0 / default: the available cores, one
        # below threading_policy.MIN_PARALLEL_CELLS cells in all
        use_threads(effective_threads(0 if threads is None else threads, len(model.loading) * model.column.cells))
        prepare_out_dir(out_dir, force=force, restart=False)
        res = run_subgrid(model, out_dir, source=str(deck), force=force)
        files = list(res.files)
        if plots:
            title = model.title or deck.stem
            files.append(plot_interface(res.t, res.theta_interface, res.tau, res.names, res.melting_temperature,
                                        out_dir / "interface.png", title, film=res.film))
            files.append(plot_profiles(res.z, res.profile_times, res.profiles, res.eps_profiles,
                                       out_dir / "profiles.png", title=title))
        con = Console()
        k = res.theta_interface.shape[1]
        for j, name in enumerate(res.names):
            tau = res.tau[-1, j]
            tau_txt = f", tau = {tau / 1e6:.4g} MPa" if tau == tau else ""
            its = res.iterations[:, j]
            limit = int(np.count_nonzero(its < 0))
            limit_txt = f" ({limit} steps at the Picard sweep limit, kept: energy exact)" if limit else ""
            if res.substeps is not None and (res.substeps[:, j] > 1).any():
                limit_txt += f" ({int(np.count_nonzero(res.substeps[:, j] > 1))} steps split into sub-steps)"
            con.print(f"{name}: t = {res.t[-1] * 1e6:.4g} us, interface {res.theta_interface[-1, j]:.6g} K"
                      f"{tau_txt}, max iterations {int(np.abs(its).max())}{limit_txt}", highlight=False)
        con.print(f"{res.t.size} steps x {k} column(s); wrote " + ", ".join(str(f) for f in files), highlight=False)
