"""The sweep file (TOML): base deck, parameters to vary, sampling and outputs to keep.

Example::

    base = "ball.toml"            # relative to the sweep file
    [set]                         # fixed overrides for every run (dotted paths)
    "time.duration" = "50 ns"
    [sample]
    method = "grid"               # or "lhs" (Latin hypercube, scipy.stats.qmc) with n and seed
    [[parameter]]
    path = "friction.mu0"
    values = [0.1, 0.2, 0.3]
    [[parameter]]
    path = "loading.velocity"
    range = ["100 m/s", "300 m/s"]
    n = 3
    [keep]
    records = ["interface"]       # or "all" / []
    scalars = "all"
    [[keep.derived]]
    name = "peak_temperature"
    record = "interface"
    column = "temperature"
    op = "max"
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from shockfriction.deck.base import DeckModel, read_toml, validate
from shockfriction.errors import DeckError
from shockfriction.safety import MAX_RUNS, TRUSTED, Trust, resolve_inside
from shockfriction.sweep.paths import parse_path
from shockfriction.sweep.quantities import in_unit, split_value

Value = int | float | str
DERIVED_OPS = ("max", "min", "mean", "initial", "final", "integral", "time_of_max", "time_of_min", "arrival")


def _check_value(v: Any) -> Any:
    split_value(v)
    return v


def _check_path(p: str) -> str:
    parse_path(p)
    return p


class Parameter(DeckModel):
    """One deck field to vary: explicit ``values``, or a ``range`` (with ``n`` for a grid)."""

    path: str
    name: str | None = None
    values: list[Value] | None = Field(default=None, min_length=1)
    range: tuple[Value, Value] | None = None
    n: int | None = Field(default=None, ge=1)
    scale: Literal["linear", "log"] = "linear"

    @field_validator("path")
    @classmethod
    def _path_readable(cls, p):
        return _check_path(p)

    @field_validator("values")
    @classmethod
    def _values_readable(cls, vs):
        for v in vs or []:
            _check_value(v)
        return vs

    @field_validator("range")
    @classmethod
    def _range_readable(cls, r):
        if r is None:
            return r
        lo, unit = split_value(r[0])
        hi = in_unit(r[1], unit)
        if not hi > lo:
            raise ValueError(f"a range (low, high) with high > low, both in one dimension, got {list(r)}")
        return r

    @model_validator(mode="after")
    def _one_source(self):
        if (self.values is None) == (self.range is None):
            raise ValueError("either values (a list) or range (low and high), exactly one of them")
        if self.values is not None and self.n is not None:
            raise ValueError("'n' goes with 'range', not with 'values'")
        if self.scale == "log" and self.range is not None and split_value(self.range[0])[0] <= 0.0:
            raise ValueError("a positive range for scale = 'log'")
        return self

    @property
    def column(self) -> str:
        return self.name or self.path


class Sample(DeckModel):
    """How parameter values combine: the full grid, or ``n`` Latin-hypercube points."""

    method: Literal["grid", "lhs"] = "grid"
    n: int | None = Field(default=None, ge=1)
    seed: int = 0

    @model_validator(mode="after")
    def _n_for_lhs(self):
        if self.method == "lhs" and self.n is None:
            raise ValueError("n (the number of Latin-hypercube samples) for method = 'lhs'")
        if self.method == "grid" and self.n is not None:
            raise ValueError("no 'n' for method = 'grid' (give each parameter its values or range and n)")
        return self


class Derived(DeckModel):
    """A scalar computed from a record: ``op`` of ``column`` against ``time`` (``arrival``: first
    time ``|column| >= threshold``)."""

    name: str = Field(min_length=1)
    record: str
    column: str
    op: Literal[DERIVED_OPS]  # type: ignore[valid-type]
    time: str = "time"
    threshold: float | None = None

    @model_validator(mode="after")
    def _threshold_for_arrival(self):
        if (self.op == "arrival") != (self.threshold is not None):
            raise ValueError("a threshold with op = 'arrival', and only with it")
        return self


class Keep(DeckModel):
    """What each run keeps: record names (or "all"), summary scalars (or "all"), derived scalars."""

    records: Literal["all"] | list[str] = "all"
    scalars: Literal["all"] | list[str] = "all"
    derived: list[Derived] = []

    @model_validator(mode="after")
    def _unique_names(self):
        names = [d.name for d in self.derived]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"distinct names for derived scalars; repeated: {sorted(dup)}")
        return self


class SweepSpec(DeckModel):
    """A whole sweep file."""

    base: str | None = None
    kind: Literal["run", "subgrid", "python"] | None = None
    model: str | None = None
    set: dict[str, Any] = {}
    sample: Sample = Sample()
    parameter: list[Parameter] = Field(min_length=1)
    keep: Keep = Keep()
    max_runs: int = Field(default=MAX_RUNS, ge=1, description="largest number of runs (grid product or "
                          "sample.n), checked before any run is planned; raise it for a larger sweep")

    @field_validator("set")
    @classmethod
    def _flatten_set(cls, table):
        flat = flatten(table)
        for p in flat:
            _check_path(p)
        return flat

    def check(self, source: str) -> None:
        """Cross-field checks, as DeckErrors naming the fields involved."""
        def fail(msg: str):
            raise DeckError(f"{source}: {msg}")

        if self.kind == "python" and not self.model:
            fail("kind = 'python' needs model = 'package.module:function'")
        if self.model and self.kind not in ("python", None):
            fail(f"model = {self.model!r}: expected no model with kind = {self.kind!r} (model is for kind = 'python')")
        if self.kind != "python" and not self.model and not self.base:
            fail("base is missing: expected base = 'deck.toml' (the deck to vary, relative to the sweep file)")
        n_runs = self.count_runs()
        if n_runs > self.max_runs:
            how = ("sample.n" if self.sample.method == "lhs" else
                   "the grid: " + " x ".join(str(len(p.values) if p.values is not None else p.n or 1)
                                            for p in self.parameter))
            fail(f"{n_runs:.3g} runs ({how}): expected at most max_runs = {self.max_runs:,} (raise max_runs in "
                 "the sweep file for a larger sweep)")
        cols = [p.column for p in self.parameter]
        dup = sorted({c for c in cols if cols.count(c) > 1})
        if dup:
            fail(f"parameter: {dup} repeated: expected each path (or name) once")
        for i, p in enumerate(self.parameter):
            if self.sample.method == "lhs" and p.range is None:
                fail(f"parameter[{i}] ({p.column}): expected a range (low and high values) with sample.method = 'lhs'")
            if self.sample.method == "lhs" and p.n is not None:
                fail(f"parameter[{i}].n = {p.n}: expected no per-parameter n with sample.method = 'lhs' "
                     "(give sample.n)")
            if self.sample.method == "grid" and p.range is not None and p.n is None:
                fail(f"parameter[{i}] ({p.column}): expected n (the number of grid values) with its range")

    @property
    def effective_kind(self) -> str | None:
        return "python" if self.model else self.kind

    def count_runs(self) -> int:
        """The number of runs, computed from the counts (nothing allocated)."""
        if self.sample.method == "lhs":
            return int(self.sample.n or 0)
        return math.prod(len(p.values) if p.values is not None else (p.n or 1) for p in self.parameter)


def flatten(table: dict, prefix: str = "") -> dict[str, Any]:
    """Nested TOML tables -> ``{"a.b.c": value}``; quoted dotted keys pass through."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        path = f"{prefix}.{key}" if prefix else str(key)
        if isinstance(value, dict) and value:
            out.update(flatten(value, path))
        else:
            out[path] = value
    return out


def load_sweep(path: str | Path, trust: Trust = TRUSTED) -> tuple[SweepSpec, Path]:
    """Read and validate a sweep file; returns the spec and the folder it lives in."""
    path = Path(path)
    spec = validate(SweepSpec, read_toml(path), str(path))
    spec.check(str(path))
    if spec.base is not None:
        resolve_inside(path.parent, spec.base, "base", str(path), trust)
    if spec.base is not None and not (path.parent / spec.base).is_file():
        raise DeckError(f"{path}: base = {spec.base!r}: expected a deck file relative to the sweep file "
                        f"(looked for {path.parent / spec.base})")
    return spec, path.parent
