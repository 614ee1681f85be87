"""``shockfriction run DECK.toml --out DIR``: run a hydrocode deck."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from shockfriction.cli_options import ALLOW_GEO, DRY_RUN, FORCE, QUIET, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("run", epilog=EXIT_CODES)
    def run(
        deck: Path = typer.Argument(..., help="run deck (TOML); see docs/deck-run.md"),
        out: Path = typer.Option(Path("out"), "--out", "-o", help="output folder (new or empty; see --force)"),
        threads: Optional[int] = typer.Option(None, "--threads", "-t",
                                              help="numba threads (1 = serial kernels, 0 = all); default: deck"),
        force: bool = FORCE,
        verbose: int = VERBOSE,
        quiet: bool = QUIET,
        restart: bool = typer.Option(False, "--restart",
                                     help="continue from OUT/checkpoint.h5 (same deck), appending to OUT's outputs"),
        dry_run: bool = DRY_RUN,
        allow_outside: bool = typer.Option(False, "--allow-outside",
                                           help="let the deck name mesh files outside its folder"),
        allow_geo: bool = ALLOW_GEO,
    ) -> None:
        """Run a deck: probes.csv, energy.csv, fields.h5/.xmf and summary.json in OUT.

        SIGTERM or Ctrl-C stops at the end of the cycle, writes a checkpoint and finishes every output
        (exit status 143 or 130); continue with --restart."""
        from rich.console import Console

        from shockfriction.deck.base import load_deck
        from shockfriction.deck.run import RunDeck
        from shockfriction.io.outdir import check_out_path, check_threads, out_dir_state, prepare_out_dir
        from shockfriction.log import configure_logging, verbosity
        from shockfriction.safety import Trust

        configure_logging(verbosity(verbose, quiet))
        check_threads(threads)
        check_out_path(out)
        trust = Trust(allow_outside=allow_outside, allow_geo=allow_geo)
        model = load_deck(deck, RunDeck, trust)  # before the hydrocode is imported: a bad deck fails fast
        if dry_run:
            from shockfriction.hydro.setup import build_problem

            problem = build_problem(model, str(deck))
            mesh = problem.mesh
            con = Console()
            con.print(f"{deck}: valid run deck {model.title!r} ({model.geometry}), {mesh.n_cells:,} cells, "
                      f"{mesh.n_nodes:,} nodes, {len(model.bodies)} bodies, {len(model.ties)} ties, "
                      f"{len(model.slide_lines)} slide lines, {len(model.probes)} probes, end time "
                      f"{model.time.end:.4g} s", highlight=False)
            for b, name in enumerate(mesh.names):
                body = model.bodies[b]
                what = f"{Path(body.mesh.file).name}:{body.mesh.group}" if body.from_file else \
                    f"{body.mesh.nx} x {body.mesh.ny} block"
                con.print(f"  body {name}: {mesh.cell_start[b + 1] - mesh.cell_start[b]:,} cells ({what}), "
                          f"material {body.material or 'inline'}", highlight=False)
            con.print(f"output folder {out}: {out_dir_state(out, force=force, restart=restart)}; nothing run",
                      highlight=False)
            return
        from shockfriction.hydro.api import prepare, run_simulation
        from shockfriction.io.session import RunInterrupted

        sim = prepare(model, threads=threads, source=str(deck))
        prepare_out_dir(out, force=force, restart=restart)
        try:
            res = run_simulation(sim, out, progress=not quiet, restart=restart, signals=True, force=force)
        except RunInterrupted as exc:
            Console(stderr=True).print(f"[yellow]{exc}; outputs and checkpoint written in {out} "
                                       "(continue with --restart)[/]", highlight=False)
            raise typer.Exit(exc.exit_code) from None
        s = res.summary  # a run that returns reached time.end (the guards raise otherwise)
        Console().print(
            f"{s['cycles']} cycles to t = {s['final_time_s']:.4e} s in {s['wall_time_s']:.2f} s "
            f"({s['zone_cycles_per_second'] or 0:.3g} zone-cycles/s), relative energy error "
            f"{s['relative_energy_error']:.2e}; results in {out}")
