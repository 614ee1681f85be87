"""Reading TOML and the deck base: strict models, readable errors (the lowest deck layer).

Every file the package reads as TOML (run, sub-grid, sweep and fit decks, the material
library's data files) goes through :func:`read_toml`; every deck section derives from
:class:`DeckModel` and is validated by :func:`validate`.  A bad deck becomes one
:class:`~shockfriction.errors.DeckError` whose message names each offending field by its path,
the value given and what was expected.

This module imports neither :mod:`shockfriction.deck` nor :mod:`shockfriction.materials`, so
both can use it: the deck layer (``deck/``) validates material names against the library
(``materials/``), and the library reads its data files with :func:`read_toml`; materials never
import the deck layer (tests/test_layering.py).
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ConfigDict, ValidationError

from shockfriction.errors import DeckError

M = TypeVar("M", bound=BaseModel)


class DeckModel(BaseModel):
    """Base of every deck section: unknown keys are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


def _field_path(loc: tuple) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out


_EXPECT = {
    "missing": "a value (this field is required)",
    "extra_forbidden": "no such key (check the spelling against the documented deck fields)",
}


def format_validation_error(err: ValidationError, source: str = "deck", raw: dict | None = None) -> str:
    """One line per error: ``source: field.path = <given>: expected <what>``."""
    lines = []
    for e in err.errors(include_url=False):
        loc = tuple(p for p in e["loc"] if not (isinstance(p, str) and p.startswith(("function-", "kind:"))))
        path = _field_path(loc)
        given = _lookup(raw, loc) if raw is not None else e.get("input")
        expected = _EXPECT.get(e["type"]) or e["msg"].removeprefix("Value error, ")
        if not path:  # a check of the whole deck: its message names the fields
            lines.append(f"{source}: {expected}")
        elif e["type"] == "missing":
            lines.append(f"{source}: {path} is missing: expected {expected}")
        elif isinstance(given, (dict, list)):  # a table-level check: name the table, not its contents
            lines.append(f"{source}: {path}: {'' if 'expected' in expected else 'expected '}{expected}")
        elif e["type"] == "value_error" and "expected" in expected:
            lines.append(f"{source}: {path} = {given!r}: {expected}")  # the message states the expectation
        else:
            lines.append(f"{source}: {path} = {given!r}: expected {expected}")
    return "\n".join(lines)


def _lookup(raw: Any, loc: tuple) -> Any:
    cur = raw
    for part in loc:
        try:
            cur = cur[part]
        except (KeyError, IndexError, TypeError):
            return "<missing>" if cur is raw else cur
    return cur


def read_toml(path: str | Path) -> dict:
    """Read a TOML file; a missing file or a syntax error becomes a DeckError."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise DeckError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise DeckError(f"{path}: is a folder: expected a TOML deck file") from None
    except UnicodeDecodeError as exc:
        raise DeckError(f"{path}: not valid TOML: expected UTF-8 text (undecodable byte at offset "
                        f"{exc.start})") from None
    except tomllib.TOMLDecodeError as exc:
        raise DeckError(f"{path}: not valid TOML: {exc}") from None
    except OSError as exc:
        raise DeckError(f"{path}: cannot be read ({exc.strerror or type(exc).__name__})") from None


def validate(model: type[M], data: dict, source: str = "deck", folder: str | Path | None = None) -> M:
    """Validate ``data`` against ``model``; errors become one readable DeckError.  ``folder``:
    the deck's folder, against which relative file paths in the deck (mesh files) are resolved."""
    try:
        return model.model_validate(data, context={"deck_dir": folder} if folder is not None else None)
    except ValidationError as err:
        raise DeckError(format_validation_error(err, source, data)) from None


def load_deck(path: str | Path, model: type[M]) -> M:
    """Read and validate a TOML deck."""
    return validate(model, read_toml(path), str(path), Path(path).parent)
