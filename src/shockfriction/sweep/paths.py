"""Dotted paths into a deck held as a nested dict: ``friction.mu0``, ``bodies[1].velocity``.

A sweep or a fit names any deck field by such a path.  Setting a value copies
the deck; the base deck is never changed.  The parent tables must exist in the
base deck; the last key may be new (a field the base deck leaves at its default)
and is then checked by the deck's own validation.
"""

from __future__ import annotations

import copy
import re
from typing import Any

from shockfriction.errors import DeckError

_SEGMENT = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def parse_path(path: str) -> list[str | int]:
    """``"bodies[1].velocity"`` or ``"bodies.1.velocity"`` -> ``["bodies", 1, "velocity"]``."""
    if not isinstance(path, str) or not path.strip():
        raise ValueError("a dotted path such as 'friction.mu0'")
    parts: list[str | int] = []
    pos = 0
    text = path.strip()
    while pos < len(text):
        if text[pos] == "." and parts:
            pos += 1
        m = _SEGMENT.match(text, pos)
        if m is None:
            raise ValueError("a dotted path such as 'friction.mu0' or 'bodies[1].velocity'")
        if m.group(2) is not None:
            parts.append(int(m.group(2)))
        else:
            key = m.group(1)
            parts.append(int(key) if key.isdigit() else key)
        pos = m.end()
    return parts


def _describe(node: Any) -> str:
    if isinstance(node, dict):
        return "keys there: " + (", ".join(map(str, node)) or "none")
    if isinstance(node, list):
        return f"a list of {len(node)} items"
    return f"a value {node!r}, not a table"


def _walk(deck: dict, parts: list[str | int], path: str, source: str):
    node: Any = deck
    for depth, key in enumerate(parts[:-1]):
        here = ".".join(map(str, parts[:depth])) or "(top level)"
        if isinstance(node, dict) and isinstance(key, str) and key in node:
            node = node[key]
        elif isinstance(node, list) and isinstance(key, int) and key < len(node):
            node = node[key]
        else:
            raise DeckError(f"{source}: path = {path!r}: expected an existing table at {here}, "
                            f"but {key!r} is not there ({_describe(node)})")
    last = parts[-1]
    if isinstance(node, dict) and isinstance(last, str):
        return node, last
    if isinstance(node, list) and isinstance(last, int) and last < len(node):
        return node, last
    raise DeckError(f"{source}: path = {path!r}: cannot set {last!r} in {_describe(node)}")


def get_path(deck: dict, path: str, source: str = "sweep") -> Any:
    """The value at ``path`` (DeckError if absent)."""
    parts = _parse(path, source)
    node, last = _walk(deck, parts, path, source)
    try:
        return node[last]
    except (KeyError, IndexError):
        raise DeckError(f"{source}: path = {path!r}: no value there in the base deck ({_describe(node)})") from None


def set_paths(deck: dict, values: dict[str, Any], source: str = "sweep") -> dict:
    """A copy of ``deck`` with each ``path: value`` of ``values`` set."""
    out = copy.deepcopy(deck)
    for path, value in values.items():
        node, last = _walk(out, _parse(path, source), path, source)
        node[last] = value
    return out


def _parse(path: str, source: str) -> list[str | int]:
    try:
        return parse_path(path)
    except ValueError as exc:
        raise DeckError(f"{source}: path = {path!r}: expected {exc}") from None
