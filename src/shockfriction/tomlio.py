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
import typing
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ConfigDict, ValidationError, ValidationInfo, field_validator

from shockfriction.errors import DeckError

M = TypeVar("M", bound=BaseModel)


class DeckModel(BaseModel):
    """Base of every deck section: unknown keys are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    @field_validator("*", mode="before")
    @classmethod
    def _no_boolean_numbers(cls, value: Any, info: ValidationInfo) -> Any:
        """A boolean where the field takes no boolean (``bounds = [0.2, true]``, ``cfl = true``) is an
        error: pydantic's lax mode would read it as 1 or 0."""
        field = cls.model_fields.get(info.field_name or "")
        if field is None or _admits_bool(field.annotation):
            return value
        in_table = isinstance(value, dict) and _is_table(field.annotation) and any(map(_holds_bool, value.values()))
        if not (_holds_bool(value) or in_table):
            return value
        raise ValueError("expected a number (or a string with its unit), not a boolean (true/false)")


def _admits_bool(annotation: Any, depth: int = 0) -> bool:
    """True if ``annotation`` takes a boolean anywhere (bool, Any, or an unconstrained object)."""
    if annotation is bool or annotation is Any or annotation is object or depth > 8:
        return True
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return False  # a nested model checks its own fields
    origin = typing.get_origin(annotation)
    if origin is typing.Literal:
        return any(isinstance(a, bool) for a in typing.get_args(annotation))
    args = typing.get_args(annotation)
    if origin is typing.Annotated:
        return _admits_bool(args[0], depth + 1)
    if origin in (dict,) and len(args) == 2:
        return _admits_bool(args[1], depth + 1)
    return any(_admits_bool(a, depth + 1) for a in args if a is not type(None) and a is not Ellipsis)


def _is_table(annotation: Any, depth: int = 0) -> bool:
    """True if ``annotation`` is a ``dict[...]`` (possibly optional or annotated), not a model."""
    origin = typing.get_origin(annotation)
    if origin is dict:
        return True
    return depth < 4 and any(_is_table(a, depth + 1) for a in typing.get_args(annotation))


def _holds_bool(value: Any, depth: int = 0) -> bool:
    """A boolean at the top of ``value`` or inside its lists (not inside nested tables)."""
    if isinstance(value, bool):
        return True
    if isinstance(value, (list, tuple)) and depth < 4:
        return any(_holds_bool(v, depth + 1) for v in value)
    return False


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


#: largest deck file read (bytes); a deck is a few kB, a sweep's or fit's a few more
MAX_DECK_BYTES = 1 << 20
#: deepest nesting of arrays and inline tables in a deck (tomllib recurses once per level)
MAX_DECK_DEPTH = 50


def _nesting_depth(text: str) -> int:
    """Deepest nesting of ``[`` / ``{`` outside strings and comments (a cheap scan before tomllib,
    whose parser recurses once per level); table headers ``[a.b]`` count one level."""
    depth = deepest = 0
    quote = ""
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if quote:
            if c == "\\" and quote[0] == '"':
                i += 2
                continue
            if c == quote[0] and text.startswith(quote, i):
                i += len(quote)
                quote = ""
                continue
            if c == "\n" and len(quote) == 1:
                quote = ""
        elif c in "\"'":
            quote = c * 3 if text.startswith(c * 3, i) else c
            i += len(quote)
            continue
        elif c == "#":
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        elif c in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif c in "]}":
            depth = max(depth - 1, 0)
        i += 1
    return deepest


def read_toml(path: str | Path, max_bytes: int = MAX_DECK_BYTES, max_depth: int = MAX_DECK_DEPTH) -> dict:
    """Read a TOML file; a missing file, a non-regular file (FIFO, device), a file over ``max_bytes``,
    nesting deeper than ``max_depth`` or a syntax error becomes a DeckError (before it is read whole)."""
    import os
    import stat

    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise DeckError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise DeckError(f"{path}: is a folder: expected a TOML deck file") from None
    except OSError as exc:
        raise DeckError(f"{path}: cannot be read ({exc.strerror or type(exc).__name__})") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise DeckError(f"{path}: is a folder: expected a TOML deck file")
        if not stat.S_ISREG(info.st_mode):
            raise DeckError(f"{path}: not a regular file (a device, FIFO or socket): expected a TOML deck file")
        if info.st_size > max_bytes:
            raise DeckError(f"{path}: {info.st_size:,} bytes: expected a deck of at most {max_bytes:,} bytes")
        with os.fdopen(fd, "rb", closefd=True) as fh:
            fd = -1
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise DeckError(f"{path}: cannot be read ({exc.strerror or type(exc).__name__})") from None
    finally:
        if fd >= 0:
            os.close(fd)
    if len(data) > max_bytes:
        raise DeckError(f"{path}: more than {max_bytes:,} bytes: expected a deck of at most {max_bytes:,} bytes")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise DeckError(f"{path}: not valid TOML: expected UTF-8 text (undecodable byte at offset "
                        f"{exc.start})") from None
    depth = _nesting_depth(text)
    if depth > max_depth:
        raise DeckError(f"{path}: arrays or inline tables nested {depth} deep: expected at most {max_depth} levels")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DeckError(f"{path}: not valid TOML: {exc}") from None
    except RecursionError:
        raise DeckError(f"{path}: nested too deeply for the TOML reader: expected at most {max_depth} levels") from None


def validate(model: type[M], data: dict, source: str = "deck", folder: str | Path | None = None,
             trust=None) -> M:
    """Validate ``data`` against ``model``; errors become one readable DeckError.  ``folder``:
    the deck's folder, against which relative file paths in the deck (mesh files) are resolved;
    ``trust`` (:class:`shockfriction.safety.Trust`, default: trusted): what those files may be."""
    context = {}
    if folder is not None:
        context["deck_dir"] = folder
    if trust is not None:
        context["trust"] = trust
    try:
        return model.model_validate(data, context=context or None)
    except ValidationError as err:
        raise DeckError(format_validation_error(err, source, data)) from None
    except RecursionError:
        raise DeckError(f"{source}: nested too deeply to validate") from None


def load_deck(path: str | Path, model: type[M], trust=None) -> M:
    """Read and validate a TOML deck (``trust``: see :func:`validate`)."""
    return validate(model, read_toml(path), str(path), Path(path).parent, trust)
