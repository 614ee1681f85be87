"""``shockfriction materials [NAME]``: list the library or show one material with sources."""

from __future__ import annotations

from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from shockfriction.cli_options import QUIET, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("materials", epilog=EXIT_CODES)
    def materials(name: Optional[str] = typer.Argument(None, help="material to show in full"),
                  verbose: int = VERBOSE, quiet: bool = QUIET) -> None:
        """List the material library, or print one material with every parameter, unit and source."""
        from shockfriction.log import configure_logging, verbosity

        configure_logging(verbosity(verbose, quiet))
        from shockfriction.materials.library import get_material, material_names

        console = Console(width=160)
        if name is None:
            table = Table(title="shockfriction material library")
            for col in ("name", "description", "rho0 (kg/m3)", "T_F (K)", "EOS"):
                table.add_column(col)
            for n in material_names():
                m = get_material(n)
                eos = "Mie-Grueneisen" if m.has("eos_c0") else "-"
                table.add_row(n, m.description, f"{m.rho0:g}", f"{m.melting_temperature:g}", eos)
            console.print(table)
            return
        m = get_material(name)
        table = Table(title=f"{m.name}: {m.description}")
        for col in ("parameter", "value (as given)", "SI value", "status", "source"):
            table.add_column(col, overflow="fold")
        for key, p in m.parameters.items():
            table.add_row(key, p.text, f"{p.value:.6g}", p.status, p.source)
        table.add_row("heat capacity (derived)", "", f"{m.heat_capacity:.6g} J/(kg K)", "derived",
                      "c = kappa/(rho0 alpha)")
        table.add_row("diffusivity (derived)", "", f"{m.diffusivity:.6g} m2/s", "derived", "alpha = kappa/(rho0 c)")
        table.add_row("effusivity (derived)", "", f"{m.effusivity:.6g} W s^0.5/(m2 K)", "derived", "kappa/sqrt(alpha)")
        console.print(table)
