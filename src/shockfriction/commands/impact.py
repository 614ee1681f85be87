"""``shockfriction impact FLYER TARGET --velocity "250 m/s"``: exact plate-impact states.

Hydrodynamic impedance match on the two Mie-Grueneisen Hugoniots and, with strength, the
elastic-plastic two-wave solution in each plate (analysis/hugoniot.py; theory in
docs/theory/exact-solutions.md).
"""

from __future__ import annotations

import typer

from shockfriction.cli_options import QUIET, VERBOSE


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("impact", epilog=EXIT_CODES)
    def impact(
        flyer: str = typer.Argument(..., help="flyer material (library name, see `shockfriction materials`)"),
        target: str = typer.Argument(..., help="target material"),
        velocity: str = typer.Option(..., "--velocity", help="impact velocity with its unit, e.g. '250 m/s' "
                                     "(no short form: -v is --verbose, as in every command)"),
        strength: str = typer.Option("epp", "--strength", "-s",
                                     help="'none', 'epp' (perfect plasticity at the material's Y0, G0) or "
                                          "'scg' (the library's SCG yield at the shocked state, 300 K)"),
        verbose: int = VERBOSE,
        quiet: bool = QUIET,
    ) -> None:
        """Print the interface state of a plate impact and the HEL / plastic waves of both plates."""
        from shockfriction.log import configure_logging, verbosity

        configure_logging(verbosity(verbose, quiet))
        from rich.console import Console
        from rich.table import Table

        from shockfriction.analysis import hugoniot as H
        from shockfriction.errors import DeckError
        from shockfriction.materials.library import get_material
        from shockfriction.units import UnitError, to_si

        try:
            v = to_si(velocity, "velocity")
        except UnitError as exc:
            raise DeckError(f"--velocity = {velocity!r}: {exc}") from None
        if v <= 0.0:
            raise DeckError(f"--velocity = {velocity!r}: expected a positive impact velocity")
        if strength not in ("none", "epp", "scg"):
            raise DeckError(f"--strength = {strength!r}: expected 'none', 'epp' or 'scg'")
        mats = {"flyer": get_material(flyer), "target": get_material(target)}
        for role, m in mats.items():
            if not m.has("eos_c0"):
                raise DeckError(f"{role} = {m.name!r}: the material has no Mie-Grueneisen data")
        eos = {role: H.LinearHugoniotEOS.from_material(m) for role, m in mats.items()}
        console = Console()
        hydro = H.impedance_match(eos["flyer"], eos["target"], v)
        table = Table(title=f"{mats['flyer'].name} on {mats['target'].name} at {v:g} m/s, no strength")
        for col in ("quantity", "value"):
            table.add_column(col)
        table.add_row("interface particle velocity", f"{hydro.particle_velocity:.4f} m/s")
        table.add_row("interface pressure", f"{hydro.pressure / 1e9:.5f} GPa")
        table.add_row("shock speed in target / flyer",
                      f"{hydro.target_shock_speed:.2f} / {hydro.flyer_shock_speed:.2f} m/s")
        table.add_row("shocked density target / flyer",
                      f"{hydro.target_density:.2f} / {hydro.flyer_density:.2f} kg/m3")
        console.print(table)
        if strength == "none":
            return

        def yield_of(m):
            return H.scg_yield_function(m) if strength == "scg" else m.Y0
        from shockfriction.errors import SimulationError

        try:
            ep = H.impedance_match_elastic_plastic(eos["flyer"], mats["flyer"].G0, yield_of(mats["flyer"]),
                                                   eos["target"], mats["target"].G0, yield_of(mats["target"]), v)
        except ValueError as exc:  # the root finders say which state they could not find
            raise SimulationError(f"--velocity = {velocity!r}, --strength = {strength!r}: no elastic-plastic "
                                  f"solution ({exc}); the hydrodynamic table above holds") from None
        table = Table(title=f"with strength ({strength}, G0 of the library): uniaxial-strain two-wave solution")
        for col in ("quantity", "target", "flyer (its rest frame)"):
            table.add_column(col)
        sols = (ep.target, ep.flyer)
        table.add_row("HEL (longitudinal stress)", *(f"{s.hel / 1e9:.5f} GPa" for s in sols))
        table.add_row("precursor speed", *(f"{s.precursor_speed:.2f} m/s" for s in sols))
        table.add_row("HEL particle velocity", *(f"{s.precursor.u:.4f} m/s" for s in sols))
        table.add_row("plastic shock speed", *(f"{s.plastic_speed:.2f} m/s" if s.two_waves else "(elastic)"
                                               for s in sols))
        table.add_row("final longitudinal stress", *(f"{s.final.stress / 1e9:.5f} GPa" for s in sols))
        table.add_row("final pressure", *(f"{s.final.pressure / 1e9:.5f} GPa" for s in sols))
        table.add_row("final density", *(f"{s.final.rho:.2f} kg/m3" for s in sols))
        table.add_row("particle velocity jump", *(f"{s.final.u:.4f} m/s" for s in sols))
        console.print(table)
        console.print(f"interface velocity {ep.particle_velocity:.4f} m/s (lab frame); target free-surface "
                      f"velocity estimate (up + release + strength correction): "
                      f"{H.free_surface_velocity_estimate(eos['target'], mats['target'].G0, ep.target):.3f} m/s")
