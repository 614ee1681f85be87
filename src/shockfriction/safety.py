"""What a deck may reach outside itself: files beside it, and user Python code.

A sweep or fit file names other files (``base``, ``measured.file``) and may name a
Python function (``kind = "python"``, ``model = "module:function"``).  A deck received
from someone else must not read files elsewhere on the machine nor run code, so the
command line refuses both unless asked (``--allow-outside``, ``--allow-python``):

* a file reference is resolved against the deck's folder (symbolic links followed) and
  must stay inside it;
* a Python model is imported only when a run executes, never while validating
  (``--dry-run`` imports nothing).

The Python API (``run_sweep``, ``fit``, ...) is called by code that can already run
code and read files; its default is :data:`TRUSTED`.  Pass ``Trust()`` to apply the
command line's rules to decks from elsewhere (docs/theory/reliability.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from shockfriction.errors import DeckError


@dataclass(frozen=True)
class Trust:
    """What decks may do beyond their folder: read files outside it, run Python models."""

    allow_outside: bool = False
    allow_python: bool = False


STRICT = Trust()
TRUSTED = Trust(allow_outside=True, allow_python=True)


def resolve_inside(here: Path, ref: str, field: str, source: str, trust: Trust = STRICT) -> Path:
    """``here / ref``, refused (DeckError naming ``field``) if it leaves ``here`` without ``allow_outside``."""
    path = Path(here) / ref
    if trust.allow_outside:
        return path
    root = Path(here).resolve()
    try:
        path.resolve().relative_to(root)
    except ValueError:
        raise DeckError(f"{source}: {field} = {ref!r}: expected a file inside the deck's folder {root} "
                        "(a file elsewhere needs --allow-outside)") from None
    return path


def check_python(model: str | None, field: str, source: str, trust: Trust = STRICT) -> None:
    """DeckError unless Python models are allowed; checks the ``module:function`` form without importing."""
    if not trust.allow_python:
        raise DeckError(f"{source}: {field} = {model!r}: a Python model runs arbitrary code: expected "
                        "--allow-python on the command line to allow it")
    mod, sep, fn = (model or "").partition(":")
    if not sep or not mod or not fn or not all(p.isidentifier() for p in mod.split(".")) or not fn.isidentifier():
        raise DeckError(f"{source}: {field} = {model!r}: expected 'package.module:function'")
