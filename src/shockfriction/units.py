"""Units at the edge: unit strings ("250 m/s", "10 GPa", "20 um") to SI floats.

Everything inside the package is SI (m, kg, s, K, Pa, J, W).  This module is the
only place that parses units; decks use the annotated pydantic types below.
"""

from __future__ import annotations

import dataclasses
import math
from functools import lru_cache
from typing import Annotated, Any

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
    "molar_volume": ("[length] ** 3 / [substance]", "m^3/mol", "2.1e-6 m^3/mol"),
    "dimensionless": ("", "", "0.3"),
}


# Largest magnitude (SI) accepted for a kind: far beyond any shock/friction problem, so that a
# typo (a missing exponent sign, a wrong unit prefix) is refused at the deck instead of making a run
# that never ends or a 1e300-sized allocation.  Kinds not listed are only required to be finite.
MAGNITUDE_LIMITS: dict[str, float] = {
    "length": 1e3,            # 1 km
    "time": 1e3,              # 1000 s
    "velocity": 1e6,          # 1000 km/s
    "pressure": 1e14,         # 100 TPa
    "temperature": 1e7,       # 10 MK
    "density": 1e6,           # kg/m^3
    "specific_energy": 1e13,  # J/kg
    "heat_flux": 1e16,        # W/m^2
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
            return _checked(float(value), value, kind)
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
    try:
        si = float(q.to(si_unit).magnitude) if si_unit else float(q.to("").magnitude)
    except (TypeError, ValueError, OverflowError, ArithmeticError) as exc:
        raise UnitError(f"cannot read {value!r} as a number ({exc}); expected a {kind} such as '{example}'") from None
    return _checked(si, value, kind)


def _checked(si: float, given, kind: str) -> float:
    """``si`` if finite and within MAGNITUDE_LIMITS[kind]; else UnitError."""
    if not math.isfinite(si):
        raise UnitError(f"{given!r} is not a finite number; expected a finite {kind}")
    limit = MAGNITUDE_LIMITS.get(kind)
    if limit is not None and abs(si) > limit:
        unit = DIMENSIONS[kind][1]
        raise UnitError(f"{given!r} is {si:.3g} {unit}: expected a {kind} of magnitude at most {limit:g} {unit} "
                        "(outside any problem this code solves; check the exponent and the unit prefix)")
    return si


_BOUNDS = {"gt": ">", "ge": ">=", "lt": "<", "le": "<=", "exclusiveMinimum": ">", "minimum": ">=",
           "exclusiveMaximum": "<", "maximum": "<="}


@dataclasses.dataclass(frozen=True)
class QuantityValidator(BeforeValidator):
    """The unit-string validator of one dimension, with its JSON schema.

    A deck gives a string with a unit (``"1 ns"``), so the JSON schema of a deck
    (``shockfriction schema run``) says ``{"type": "string", "x-dimension": "[time]",
    "x-si-unit": "s", ...}``; a bound on the SI value (``Field(gt=0)``) becomes
    ``"x-bound": "> 0 s"``.  Dimensionless values also take bare numbers.
    """

    kind: str = "dimensionless"

    def __get_pydantic_json_schema__(self, core_schema: Any, handler: Any) -> dict:
        inner = handler(core_schema)
        if handler.mode == "serialization":  # a validated deck holds SI floats
            return {**inner, "x-si-unit": DIMENSIONS[self.kind][1]}
        return quantity_schema(self.kind, inner)


def quantity_schema(kind: str, number_schema: dict | None = None) -> dict:
    """JSON schema of a value of dimension ``kind``; bounds of ``number_schema`` (SI) kept as text."""
    dim, si_unit, example = DIMENSIONS[kind]
    name = kind.replace("_", " ")
    if kind == "dimensionless":
        out: dict = {"type": ["number", "string"], "description": f"a number (or a string such as '{example}')"}
    else:
        out = {"type": "string", "description": f"a {name} with its unit, such as '{example}'"}
    out.update({"x-quantity": kind, "x-dimension": dim or "dimensionless", "x-si-unit": si_unit,
                "examples": [example]})
    bounds = [f"{_BOUNDS[k]} {v:g}{(' ' + si_unit) if si_unit else ''}"
              for k, v in (number_schema or {}).items() if k in _BOUNDS]
    if bounds:
        out["x-bound"] = " and ".join(bounds)
    return out


def pressure_power_time_to_si(value: str, power: float) -> float:
    """A quantity of dimension pressure^power x time (the Tuler-Butcher K, e.g. '2.5 GPa^2*us')
    to SI (Pa^power s)."""
    if not isinstance(value, str):
        raise UnitError(f"expected a pressure^{power:g} x time with its unit, such as '1 GPa^{power:g}*us', "
                        f"got {value!r}")
    try:
        q = _parse(value.strip())
    except Exception as exc:
        raise UnitError(f"cannot read {value!r} as a quantity ({exc})") from None
    target = ureg.Quantity(1.0, "Pa") ** power * ureg.Quantity(1.0, "s")
    if not isinstance(q, pint.Quantity) or q.dimensionality != target.dimensionality:
        raise UnitError(f"{value!r} is not a pressure^{power:g} x time (lambda = {power:g}), "
                        f"such as '1 GPa^{power:g}*us'")
    return float((q / target).to("").magnitude)


def quantity(kind: str) -> BeforeValidator:
    """Pydantic validator turning a unit string of ``kind`` (a key of DIMENSIONS) into SI."""

    def check(value):
        try:
            return to_si(value, kind)
        except UnitError as exc:
            raise ValueError(str(exc)) from None

    return QuantityValidator(check, kind=kind)


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
#: the viscoplastic column's Picard tolerance, a temperature change in kelvin ("1e-6 K")
PicardTolerance = Annotated[Temperature, Field(gt=0.0, le=1.0)]
