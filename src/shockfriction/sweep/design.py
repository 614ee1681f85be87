"""The runs of a sweep: parameter values (full grid or Latin hypercube) applied to the base deck.

Every run is identified by the content hash of what determines it (kind,
model, deck after overrides, outputs kept, package version and a hash of the package's
source files): a finished run
is found again by that key when a sweep resumes, whatever its position.
"""

from __future__ import annotations

import hashlib
import itertools
import json
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from scipy.stats import qmc

import shockfriction
from shockfriction.sweep.paths import set_paths
from shockfriction.sweep.quantities import in_unit, join_value, split_value
from shockfriction.sweep.spec import Parameter, SweepSpec


@dataclass(frozen=True)
class RunPoint:
    """One run: its position, the parameter values (as given to the deck and as numbers), the deck."""

    index: int
    values: dict[str, Any]
    numbers: dict[str, float]
    deck: dict
    key: str

    @property
    def run_id(self) -> str:
        return f"r{self.index:05d}"


def column_unit(p: Parameter) -> str:
    """The unit of a parameter's column: that of its first value or of its range's low end."""
    return split_value(p.values[0] if p.values is not None else p.range[0])[1]


def grid_values(p: Parameter) -> list:
    """The deck values of one parameter of a grid: its list, or ``n`` points over its range."""
    if p.values is not None:
        return list(p.values)
    lo, unit = split_value(p.range[0])
    hi = in_unit(p.range[1], unit)
    pts = np.geomspace(lo, hi, p.n) if p.scale == "log" else np.linspace(lo, hi, p.n)
    return [join_value(x, unit) for x in pts]


def lhs_values(params: list[Parameter], n: int, seed: int) -> list[list]:
    """``n`` Latin-hypercube points (scipy.stats.qmc) over the parameters' ranges, log-uniform where asked."""
    u = qmc.LatinHypercube(d=len(params), seed=seed).random(n)
    rows = []
    for row in u:
        out = []
        for p, x in zip(params, row):
            lo, unit = split_value(p.range[0])
            hi = in_unit(p.range[1], unit)
            v = np.exp(np.log(lo) + x * (np.log(hi) - np.log(lo))) if p.scale == "log" else lo + x * (hi - lo)
            out.append(join_value(v, unit))
        rows.append(out)
    return rows


@lru_cache(maxsize=1)
def code_hash() -> str:
    """SHA-256 of the package's source and data files (path and bytes), so that a result computed
    by other code is never reused, whatever the version number says."""
    root = Path(shockfriction.__file__).parent
    h = hashlib.sha256()
    for f in sorted(root.rglob("*")):
        if f.is_file() and f.suffix in (".py", ".toml") and "__pycache__" not in f.parts:
            h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:16]


def run_key(kind: str | None, model: str | None, deck: dict, keep: dict) -> str:
    """Content hash of everything a run's result depends on (the package's code included)."""
    blob = json.dumps({"kind": kind, "model": model, "deck": deck, "keep": keep,
                       "version": shockfriction.__version__, "code": code_hash()}, sort_keys=True, default=repr)
    return hashlib.sha256(blob.encode()).hexdigest()[:24]


def build_runs(spec: SweepSpec, base_deck: dict, kind: str | None, source: str = "sweep") -> list[RunPoint]:
    """All runs of the sweep, in order (grid: the first parameter varies slowest)."""
    if spec.sample.method == "grid":
        combos = list(itertools.product(*(grid_values(p) for p in spec.parameter)))
    else:
        combos = lhs_values(spec.parameter, spec.sample.n, spec.sample.seed)
    fixed = set_paths(base_deck, spec.set, source) if spec.set else base_deck
    keep = spec.keep.model_dump()
    units = [column_unit(p) for p in spec.parameter]
    runs = []
    for i, combo in enumerate(combos):
        values = {p.column: v for p, v in zip(spec.parameter, combo)}
        deck = set_paths(fixed, {p.path: v for p, v in zip(spec.parameter, combo)}, source)
        numbers = {p.column: in_unit(v, u) for p, v, u in zip(spec.parameter, combo, units)}
        runs.append(RunPoint(i, values, numbers, deck, run_key(kind, spec.model, deck, keep)))
    return runs
