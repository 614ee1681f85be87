"""What a deck may reach outside itself: files beside it, and user Python code.

A sweep or fit file names other files (``base``, ``measured.file``) and may name a
Python function (``kind = "python"``, ``model = "module:function"``).  A deck received
from someone else must not read files elsewhere on the machine nor run code, so the
command line refuses both unless asked (``--allow-outside``, ``--allow-python``):

* a file reference is resolved against the deck's folder (symbolic links followed) and
  must stay inside it;
* a Python model is imported only when a run executes, never while validating
  (``--dry-run`` imports nothing);
* a gmsh ``.geo`` file is a program (``SystemCall``, ``Printf > file``, ``Save``, ``Include``...):
  it is meshed only with ``--allow-geo``, in a child process with a memory cap; a ``.msh`` file is
  data and stays free (``--allow-outside`` still applies to both).

Sizes are checked before anything is read whole or allocated (:mod:`shockfriction.deck.base`
for deck files, ``max_cells`` of a run deck, ``max_runs`` of a sweep file, the gmsh caps here).

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
    allow_geo: bool = False


STRICT = Trust()
TRUSTED = Trust(allow_outside=True, allow_python=True, allow_geo=True)

#: default largest number of cells of a run (``max_cells`` in the run deck raises it): ~300 bytes a
#: cell of state arrays, so 1.5 GB
MAX_CELLS = 5_000_000
#: default largest number of runs of a sweep (``max_runs`` in the sweep file raises it)
MAX_RUNS = 100_000

#: address-space cap (bytes) of the child process that meshes a .geo file
GMSH_MEMORY_BYTES = 2 << 30
#: wall-clock cap (s) of that child process
GMSH_SECONDS = 300.0


def check_geo(ref: str, field: str, source: str, trust: Trust = STRICT) -> None:
    """DeckError unless ``.geo`` scripts may be meshed (``--allow-geo``)."""
    if str(ref).lower().endswith(".geo") and not trust.allow_geo:
        raise DeckError(f"{source}: {field} = {ref!r}: a .geo file is a gmsh script that can run commands and "
                        "write files: expected a .msh mesh, or --allow-geo on the command line to mesh it")


def resolve_inside(here: Path, ref: str, field: str, source: str, trust: Trust = STRICT) -> Path:
    """``here / ref``, refused (DeckError naming ``field``) if it leaves ``here`` without ``allow_outside``."""
    path = Path(here) / Path(ref).expanduser()
    if trust.allow_outside:
        return path
    message = outside_message(here, ref)
    if message:
        raise DeckError(f"{source}: {field} = {ref!r}: {message}")
    return path


def outside_message(here: Path | str, ref: str) -> str | None:
    """None if ``here / ref`` (symbolic links followed) stays inside ``here``, else what was expected."""
    root = Path(here).resolve()
    try:
        (Path(here) / Path(ref).expanduser()).resolve().relative_to(root)
    except ValueError:
        return f"expected a file inside the deck's folder {root} (a file elsewhere needs --allow-outside)"
    return None


def check_python(model: str | None, field: str, source: str, trust: Trust = STRICT) -> None:
    """DeckError unless Python models are allowed; checks the ``module:function`` form without importing."""
    if not trust.allow_python:
        raise DeckError(f"{source}: {field} = {model!r}: a Python model runs arbitrary code: expected "
                        "--allow-python on the command line to allow it")
    mod, sep, fn = (model or "").partition(":")
    if not sep or not mod or not fn or not all(p.isidentifier() for p in mod.split(".")) or not fn.isidentifier():
        raise DeckError(f"{source}: {field} = {model!r}: expected 'package.module:function'")
