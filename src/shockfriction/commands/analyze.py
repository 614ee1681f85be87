"""``shockfriction analyze``: the thesis's chapter-5/6 analyses for a friction pair."""

from __future__ import annotations

import json
import math
from typing import Optional

import typer

from shockfriction.cli_options import QUIET, VERBOSE

UNITS = {
    "velocity": "m/s", "pressure": "Pa", "time": "s", "temperature": "K",
    "scales.time": "s", "scales.stress": "Pa", "scales.temperature": "K", "scales.density": "kg/m^3",
    "scales.conductivity": "W/(m K)", "scales.velocity": "m/s", "scales.length": "m", "scales.thickness": "m",
    "scales.specific_energy": "J/kg", "scales.transverse_velocity": "m/s", "scales.plastic_rate": "1/s",
    "scales.plastic_strain": "-", "scales.diffusivity": "m^2/s", "scales.heat_capacity": "J/(kg K)",
    "thesis_thickness": "m", "thermal_depth": "m", "column_depth": "m", "shear_band_thickness": "m",
    "flow_stress": "Pa", "heat_share": "-", "max_stable_strain": "-", "saturation_strain": "-",
}


def _parse(text: str, kind: str, option: str) -> float:
    from shockfriction.errors import DeckError
    from shockfriction.units import UnitError, to_si

    try:
        return to_si(text, kind)
    except UnitError as exc:
        raise DeckError(f"{option} = {text!r}: {exc}") from None


def _materials(pair: str):
    from shockfriction.errors import DeckError
    from shockfriction.materials.library import get_material

    parts = pair.split(":")
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise DeckError(f"--pair = {pair!r}: expected two library materials as 'FIRST:SECOND', "
                        "such as 'Al5083-H111:AISI321'")
    try:
        return tuple(get_material(p.strip()) for p in parts)
    except DeckError as exc:
        raise DeckError(f"--pair = {pair!r}: {exc}") from None


def _finite(obj):
    """nan/inf -> None so that the output is strict JSON."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def _or_melted(x: float) -> str:
    """A number of the table, or "none (melted)" where it is undefined (nan: no strength at Theta0; JSON: null)."""
    return "none (melted)" if math.isnan(x) else f"{x:.4g}"


def _print_tables(result) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console(width=150)
    a, b = result.materials
    head = (f"V0 = {result.velocity:g} m/s, |F_N| = {result.pressure / 1e9:g} GPa, "
            f"T^ = {result.time:g} s, Theta0 = {result.temperature:g} K")

    t = Table(title=f"Characteristic values (thesis 5.2.1)  [{head}]")
    for col in ("quantity", a.material, b.material):
        t.add_column(col)
    rows = [
        ("zeta_L = sqrt(G0/rho0) (m/s)", "velocity", 1.0), ("L^ = zeta_L T^ (um)", "length", 1e6),
        ("h^ = kappa0 T_F/(Y0 zeta_L) (um)", "thickness", 1e6), ("V^_Z = h^/T^ (m/s)", "transverse_velocity", 1.0),
        ("plastic rate V^_X/h^ (1/s)", "plastic_rate", 1.0), ("plastic strain L^/h^", "plastic_strain", 1.0),
        ("e^ (J/kg)", "specific_energy", 1.0), ("alpha^ = h^^2/T^ (m2/s)", "diffusivity", 1.0),
        ("c = kappa0/(rho0 alpha0) (J/(kg K))", "heat_capacity", 1.0),
    ]
    for label, key, f in rows:
        t.add_row(label, f"{getattr(a.scales, key) * f:.4g}", f"{getattr(b.scales, key) * f:.4g}")
    console.print(t)

    t = Table(title="Dimensionless numbers (eq. 5.144)")
    for col in ("number", a.material, b.material):
        t.add_column(col)
    for key in a.numbers:
        t.add_row(key, f"{a.numbers[key]:.4g}", f"{b.numbers[key]:.4g}")
    console.print(t)

    t = Table(title=f"Terms of the layer problem (negligible when the number <= {result.threshold:g})")
    for col in ("terms", "eq.", "number", a.material, b.material, "when negligible"):
        t.add_column(col, overflow="fold")
    for ta, tb in zip(a.terms, b.terms):
        cells = [f"[green]drop[/] {x.value:.3g}" if x.negligible else f"[red]keep[/] {x.value:.3g}" for x in (ta, tb)]
        t.add_row(ta.description, ta.equations, ta.number, *cells, ta.consequence)
    console.print(t)

    t = Table(title="Layer thicknesses and stability")
    for col in ("quantity", a.material, b.material):
        t.add_column(col)
    um = 1e6
    t.add_row("thesis thickness h^ (um)", f"{a.thesis_thickness * um:.4g}", f"{b.thesis_thickness * um:.4g}")
    t.add_row("thermal depth sqrt(alpha T^) (um)", f"{a.thermal_depth * um:.4g}", f"{b.thermal_depth * um:.4g}")
    t.add_row(f"column depth, {result.column_fraction:.0%} of surface rise (um)",
              f"{a.column_depth * um:.4g}", f"{b.column_depth * um:.4g}")
    t.add_row("flow stress Y(0, |F_N|, Theta0) (MPa)", f"{a.flow_stress / 1e6:.4g}", f"{b.flow_stress / 1e6:.4g}")
    t.add_row("shear band kappa0 T_F/(Y V0) (um)",
              f"{a.shear_band_thickness * um:.4g}", f"{b.shear_band_thickness * um:.4g}")
    t.add_row("heat share beta_T (effusivities)", f"{a.heat_share:.4g}", f"{b.heat_share:.4g}")
    t.add_row("largest stable plastic strain (eq. 6.72)", *(_or_melted(m.max_stable_strain) for m in (a, b)))
    t.add_row("saturation strain eps_sat", f"{a.saturation_strain:.4g}", f"{b.saturation_strain:.4g}")
    console.print(t)


def register(app: typer.Typer) -> None:
    from shockfriction.errors import EXIT_CODES

    @app.command("analyze", epilog=EXIT_CODES)
    def analyze(
        pair: str = typer.Option(..., "--pair", help="two library materials, 'FIRST:SECOND'"),
        velocity: str = typer.Option(..., "--velocity", help="impact/sliding velocity V0, e.g. '250 m/s'"),
        pressure: str = typer.Option(..., "--pressure", help="contact pressure |F_N|, e.g. '10 GPa'"),
        time: str = typer.Option(..., "--time", help="time scale T^, e.g. '10 us'"),
        temperature: str = typer.Option("300 K", "--temperature", help="initial temperature Theta0"),
        threshold: float = typer.Option(0.01, "--threshold", help="a term drops when its number is <= this"),
        as_json: bool = typer.Option(False, "--json", help="print JSON (SI values) instead of tables"),
        plot: Optional[str] = typer.Option(None, "--plot", help="write the stability-limit figure to this PNG "
                                           "(an explicit path, e.g. out/stability.png; an existing file needs "
                                           "--force)"),
        force: bool = typer.Option(False, "--force", "-f", help="replace an existing --plot file"),
        verbose: int = VERBOSE,
        quiet: bool = QUIET,
    ) -> None:
        """Dimensionless numbers, droppable terms, layer thicknesses and the stability limit (thesis ch. 5-6).

        Tables (or --json) go to stdout; the figure goes only where --plot says, and its path is printed."""
        from pathlib import Path

        from shockfriction.analysis.dimensionless import analyze_pair
        from shockfriction.errors import DeckError, UsageError
        from shockfriction.log import configure_logging, verbosity

        configure_logging(verbosity(verbose, quiet))

        first, second = _materials(pair)
        v = _parse(velocity, "velocity", "--velocity")
        p = _parse(pressure, "pressure", "--pressure")
        t = _parse(time, "time", "--time")
        theta = _parse(temperature, "temperature", "--temperature")
        if not t >= 1e-15:  # below a femtosecond the numbers overflow (1/T^ in every group)
            raise DeckError(f"--time = {time!r}: expected a positive time of at least 1 fs, such as '10 us'")
        if not theta > 0.0:
            raise DeckError(f"--temperature = {temperature!r}: expected a positive absolute temperature")
        if not threshold > 0.0:
            raise DeckError(f"--threshold = {threshold!r}: expected a positive number such as 0.01")
        if plot is not None and not plot.lower().endswith(".png"):
            raise DeckError(f"--plot = {plot!r}: expected a file name ending in .png")
        if plot is not None:
            target = Path(plot).expanduser()
            if target.is_dir():
                raise UsageError(f"--plot = {plot!r} is a folder: expected a file name ending in .png")
            if target.exists() and not force:
                raise UsageError(f"--plot = {plot!r} exists: use --force to replace it, or choose a new file")

        result = analyze_pair(first, second, v, p, t, theta, threshold)
        if plot is not None:
            from shockfriction.plot.stability import plot_stability_limit

            target.parent.mkdir(parents=True, exist_ok=True)
            plot_stability_limit((first, second), str(target), marker=(theta, abs(p)))
        if as_json:
            out = _finite(result.to_dict())
            out["units"] = UNITS
            typer.echo(json.dumps(out, indent=2))
        else:
            _print_tables(result)
        if plot is not None:  # stdout holds the JSON with --json: the path then goes to stderr
            typer.echo(f"stability figure written to {target.resolve()}", err=as_json)
