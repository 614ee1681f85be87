"""Parameter values as the deck expects them: bare numbers or unit strings.

A sweep varies a deck field between values written the way the deck wants them
("250 m/s", 0.3).  For sampling and for the results table a value is split
into a magnitude and a unit; a generated value is written back as
``"<magnitude> <unit>"`` (or a bare float when there is no unit).
"""

from __future__ import annotations

import re

import pint

from shockfriction.units import ureg

_NUMBER_THEN_UNIT = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$")


def split_value(value: float | int | str) -> tuple[float, str]:
    """``"250 m/s"`` -> ``(250.0, "m/s")``; ``0.3`` -> ``(0.3, "")``.  ValueError if unreadable."""
    if isinstance(value, bool):
        raise ValueError("a number or a quantity such as '250 m/s', not a boolean")
    if isinstance(value, (int, float)):
        return float(value), ""
    if not isinstance(value, str):
        raise ValueError(f"a number or a quantity such as '250 m/s', not a {type(value).__name__}")
    m = _NUMBER_THEN_UNIT.match(value)
    if m is None:
        raise ValueError(f"a number or a quantity such as '250 m/s' (cannot read {value!r})")
    unit = m.group(2)
    if unit:
        try:
            ureg.Quantity(1.0, unit)
        except Exception as exc:  # pint raises several unrelated types on bad text
            raise ValueError(f"a number or a quantity such as '250 m/s' (unit of {value!r}: {exc})") from None
    return float(m.group(1)), unit


def in_unit(value: float | int | str, unit: str) -> float:
    """Magnitude of ``value`` expressed in ``unit`` (ValueError on a dimension mismatch)."""
    mag, own = split_value(value)
    if own == unit:
        return mag
    if not own or not unit:
        raise ValueError(f"values in one dimension ({value!r} has {'no unit' if not own else 'a unit'}, "
                         f"the first value {'has no unit' if not unit else repr(unit)})")
    q = ureg.Quantity(mag, own)
    try:
        return float(q.to(unit).magnitude)
    except pint.DimensionalityError:
        raise ValueError(f"values in one dimension ({value!r} cannot be expressed in {unit!r})") from None


def join_value(magnitude: float, unit: str) -> float | str:
    """The deck value for ``magnitude`` in ``unit``: a float, or a string ``"<m> <unit>"``."""
    m = float(magnitude)
    return f"{m!r} {unit}" if unit else m


def si_factor(unit: str) -> float:
    """Factor that converts a magnitude in ``unit`` to SI (ValueError if unreadable)."""
    if not unit:
        return 1.0
    try:
        return float(ureg.Quantity(1.0, unit).to_base_units().magnitude)
    except Exception as exc:
        raise ValueError(f"cannot read the unit {unit!r} ({exc})") from None
