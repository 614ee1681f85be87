"""Run one deck, whatever its kind, and return its records and summary scalars.

A run is a pure function of its deck: ``run_deck(kind, deck, workdir, model)``
returns a :class:`RunResult` holding

* ``records``: ``{name: {column: 1D float array}}``, e.g. a probe's
  ``{"time": ..., "velocity": ...}`` (SI units, equal-length columns);
* ``summary``: ``{name: float}``, scalars the run reports.

Kinds: ``"run"`` (hydrocode deck), ``"subgrid"`` (uncoupled sub-grid deck), and
``"python"``: a user function ``module:function`` called as ``fn(deck, workdir)``
returning ``{"records": ..., "summary": ...}``, for models outside the package
(an analytic formula, a wrapper around another code).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from shockfriction.errors import DeckError
from shockfriction.safety import TRUSTED, Trust, check_python

# kind -> module exposing ``check(deck, source)`` and ``run(deck, workdir) -> RunResult``
ADAPTERS: dict[str, str] = {
    "run": "shockfriction.sweep.adapter_hydro",
    "subgrid": "shockfriction.sweep.adapter_subgrid",
}


@dataclass
class RunResult:
    """What a run produced: named records (tables of columns) and summary scalars."""

    records: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    summary: dict[str, float] = field(default_factory=dict)


def normalise(out: Mapping[str, Any], origin: str) -> RunResult:
    """Check and convert a run's output to float64 columns and float scalars."""
    if isinstance(out, RunResult):
        out = {"records": out.records, "summary": out.summary}
    if not isinstance(out, Mapping):
        raise TypeError(f"{origin} returned {type(out).__name__}; expected a mapping with 'records' and 'summary'")
    records: dict[str, dict[str, np.ndarray]] = {}
    for name, cols in dict(out.get("records") or {}).items():
        arrays = {str(c): np.asarray(v, dtype=np.float64).reshape(-1) for c, v in dict(cols).items()}
        lengths = {len(a) for a in arrays.values()}
        if len(lengths) > 1:
            raise ValueError(f"{origin}: record {name!r} has columns of unequal lengths {sorted(lengths)}")
        records[str(name)] = arrays
    summary = {str(k): float(v) for k, v in dict(out.get("summary") or {}).items()}
    return RunResult(records, summary)


def load_function(model: str, source: str = "sweep") -> Callable:
    """Import ``package.module:function``; DeckError naming the field if it cannot be found."""
    mod_name, sep, fn_name = model.partition(":")
    if not sep or not mod_name or not fn_name:
        raise DeckError(f"{source}: model = {model!r}: expected 'package.module:function'")
    try:
        fn = getattr(importlib.import_module(mod_name), fn_name)
    except (ImportError, AttributeError) as exc:
        raise DeckError(f"{source}: model = {model!r}: expected an importable function ({exc})") from None
    if not callable(fn):
        raise DeckError(f"{source}: model = {model!r}: expected a function, found {type(fn).__name__}")
    return fn


def known_kinds() -> list[str]:
    return sorted([*ADAPTERS, "python"])


def _adapter(kind: str, source: str):
    if kind not in ADAPTERS:
        raise DeckError(f"{source}: kind = {kind!r}: expected one of {known_kinds()}")
    return importlib.import_module(ADAPTERS[kind])


def detect_kind(deck: dict, source: str) -> str:
    """The kind of a deck, asked of each adapter (``looks_like(deck)``)."""
    matches = [k for k in ADAPTERS if importlib.import_module(ADAPTERS[k]).looks_like(deck)]
    if len(matches) == 1:
        return matches[0]
    raise DeckError(f"{source}: cannot tell the kind of the base deck (matches: {matches or 'none'}); "
                    f"expected kind = one of {known_kinds()} in the sweep file")


def anchor_files(deck: dict, folder: Path, source: str, trust: Trust = TRUSTED) -> dict:
    """``deck`` (a run deck read from ``folder``) with each relative ``bodies[k].mesh.file`` made absolute
    against ``folder``, so that the deck runs from any working directory and on any worker; each file is
    checked by the command line's rules (inside ``folder`` unless ``trust.allow_outside``; a ``.geo``
    only with ``trust.allow_geo``).  Other decks are returned as they are."""
    from shockfriction.safety import check_geo, resolve_inside

    bodies = deck.get("bodies") if isinstance(deck, dict) else None
    if not isinstance(bodies, list):
        return deck
    out = dict(deck)
    out["bodies"] = []
    for k, body in enumerate(bodies):
        mesh = body.get("mesh") if isinstance(body, dict) else None
        if isinstance(mesh, dict) and isinstance(mesh.get("file"), str) and mesh["file"]:
            field = f"bodies[{k}].mesh.file"
            path = resolve_inside(folder, mesh["file"], field, source, trust)
            check_geo(mesh["file"], field, source, trust)
            body = {**body, "mesh": {**mesh, "file": str(Path(path).absolute())}}
        out["bodies"].append(body)
    return out


def check_deck(kind: str, deck: dict, source: str, model: str | None = None, trust: Trust = TRUSTED) -> None:
    """Validate a deck before any run (DeckError naming field, value and expectation).

    A Python model is checked for its ``module:function`` form and for ``trust.allow_python``;
    it is not imported here (validation, ``--dry-run``, runs no user code)."""
    if kind == "python":
        check_python(model, "model", source, trust)
        return
    _adapter(kind, source).check(deck, source)


def run_deck(kind: str, deck: dict, workdir: Path, model: str | None = None) -> RunResult:
    """Run one deck in ``workdir`` and return its records and summary."""
    if kind == "python":
        fn = load_function(model or "", "model")
        return normalise(fn(deck, workdir), model or "model")
    return normalise(_adapter(kind, "deck").run(deck, workdir), f"{kind} run")
