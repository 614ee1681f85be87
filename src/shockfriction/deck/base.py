"""Shared deck machinery: the deck base of :mod:`shockfriction.tomlio` and the deck-level validators.

:class:`DeckModel`, :func:`read_toml`, :func:`validate`, :func:`load_deck` and
:func:`format_validation_error` live in the low module :mod:`shockfriction.tomlio` (which the
material library uses too) and are re-exported here; :func:`known_material` checks a name against
the library (the deck layer uses the materials, never the other way round).
"""

from __future__ import annotations

from shockfriction.errors import DeckError
from shockfriction.materials.library import get_material, material_names
from shockfriction.tomlio import DeckModel, format_validation_error, load_deck, read_toml, validate

__all__ = ["DeckModel", "format_validation_error", "known_material", "load_deck", "read_toml", "validate"]


def known_material(name: str | None) -> str | None:
    """Field validator of a library material name (None passes): ValueError listing the library otherwise."""
    if name is None:
        return name
    try:
        get_material(name)
    except DeckError:
        raise ValueError(f"unknown material: expected one of the library's {', '.join(material_names())}") from None
    return name
