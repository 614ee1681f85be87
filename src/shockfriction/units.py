"""Units at the edge: unit strings ("250 m/s", "10 GPa", "20 um") to SI floats.

Everything inside the package is SI (m, kg, s, K, Pa, J, W).  This module is the
only place that parses units; decks use the annotated pydantic types below.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Annotated

import pint
from pydantic import BeforeValidator, Field

ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
ureg.define("percent_ = 0.01 = pct")

# name -> (pint dimensionality, SI unit, example shown in error messages)
DIMENSIONS: dict[str, tuple[str, str, str]] = {
    "length": ("[length]", "m", "20 um"),
    "time": ("[time]", "s", "1 ns"),
    "velocity": ("[length] / [time]", "m/s", "250 m/s"),
    "pressure": ("[pressure]", "Pa", "10 GPa"),
    "temperature": ("[temperature]", "K", "300 K"),
    "density": ("[mass] / [length] ** 3", "kg/m^3", "2703 kg/m^3"),
    "mass": ("[mass]", "kg", "1 g"),
    "conductivity": ("[power] / [length] / [temperature]", "W/(m*K)", "117 W/(m*K)"),
    "diffusivity": ("[length] ** 2 / [time]", "m^2/s", "48.9e-6 m^2/s"),
    "specific_heat": ("[energy] / [mass] / [temperature]", "J/(kg*K)", "885 J/(kg*K)"),
    "specific_energy": ("[energy] / [mass]", "J/kg", "1 kJ/kg"),
    "heat_flux": ("[power] / [length] ** 2", "W/m^2", "6.12e9 W/m^2"),
    "inverse_pressure": ("1 / [pressure]", "1/Pa", "6.52e-11 1/Pa"),
    "inverse_temperature": ("1 / [temperature]", "1/K", "6.16e-4 1/K"),
    "slowness": ("[time] / [length]", "s/m", "0.05 s/m"),
    "viscosity": ("[pressure] * [time]", "Pa*s", "1.3 mPa*s"),
    "dimensionless": ("", "", "0.3"),
}


class UnitError(ValueError):
    """A value does not carry a unit of the expected dimension."""


@lru_cache(maxsize=4096)
def _parse(text: str) -> pint.Quantity:
    return ureg.Quantity(text)


def to_si(value: str | float | int, kind: str) -> float:
    """Convert ``value`` (a string with units) to the SI float of dimension ``kind``.

    Bare numbers are accepted only for dimensionless quantities: a dimensional
    input without a unit is ambiguous and refused.
    """
    dim, si_unit, example = DIMENSIONS[kind]
    if isinstance(value, bool):
        raise UnitError(f"expected a {kind} such as '{example}', got a boolean")
    if isinstance(value, (int, float)):
        if kind == "dimensionless":
            return float(value)
        raise UnitError(f"expected a {kind} with its unit, such as '{example}', got the bare number {value!r}")
    if not isinstance(value, str):
        raise UnitError(f"expected a {kind} such as '{example}', got {type(value).__name__}")
    try:
        q = _parse(value.strip())
    except Exception as exc:  # pint raises several unrelated types on bad text
        raise UnitError(f"cannot read {value!r} as a quantity ({exc}); expected a {kind} such as '{example}'") from None
    if not isinstance(q, pint.Quantity):  # a plain number inside a string
        q = ureg.Quantity(float(q), "")
    target = ureg.Quantity(1.0, si_unit) if si_unit else ureg.Quantity(1.0, "")
    if q.dimensionality != target.dimensionality:
        raise UnitError(
            f"{value!r} has dimension {q.dimensionality or 'dimensionless'}; expected a {kind} such as '{example}'"
        )
    return float(q.to(si_unit).magnitude) if si_unit else float(q.to("").magnitude)


def quantity(kind: str) -> BeforeValidator:
    """Pydantic validator turning a unit string of ``kind`` (a key of DIMENSIONS) into SI."""

    def check(value):
        try:
            return to_si(value, kind)
        except UnitError as exc:
            raise ValueError(str(exc)) from None

    return BeforeValidator(check)


Length = Annotated[float, quantity("length")]
Time = Annotated[float, quantity("time")]
Velocity = Annotated[float, quantity("velocity")]
Pressure = Annotated[float, quantity("pressure")]
Temperature = Annotated[float, quantity("temperature")]
Density = Annotated[float, quantity("density")]
HeatFlux = Annotated[float, quantity("heat_flux")]
Slowness = Annotated[float, quantity("slowness")]
Dimensionless = Annotated[float, quantity("dimensionless")]
SpecificEnergy = Annotated[float, quantity("specific_energy")]
SpecificHeat = Annotated[float, quantity("specific_heat")]
Viscosity = Annotated[float, quantity("viscosity")]

PositiveLength = Annotated[Length, Field(gt=0.0)]
PositiveTime = Annotated[Time, Field(gt=0.0)]
NonNegativeTime = Annotated[Time, Field(ge=0.0)]
NonNegativePressure = Annotated[Pressure, Field(ge=0.0)]
PositiveTemperature = Annotated[Temperature, Field(gt=0.0)]
