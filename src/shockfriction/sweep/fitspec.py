"""The fit file (TOML): model deck, measured record, parameters with bounds, optional time shift.

Example::

    base = "ball.toml"                 # relative to the fit file (or kind = "python" + model)
    [set]
    "time.duration" = "100 ns"
    [measured]
    file = "measured.csv"              # CSV with a header row (or an HDF5 record, see below)
    time = "time"                      # column names
    value = "velocity"
    time_unit = "us"                   # units of those columns
    value_unit = "m/s"
    window = ["0.1 us", "2 us"]        # optional: measured samples used
    [computed]
    record = "free_surface"            # record of the run to compare with
    time = "time"
    value = "velocity"
    [[parameter]]
    path = "friction.f"
    bounds = [0.2, 1.2]
    initial = 0.5
    [time_shift]                       # optional: measured time = computed time + shift
    bounds = ["-50 ns", "50 ns"]
    initial = "0 ns"
    sigma = 5.0                        # optional: noise of the record, in measured.value_unit
    [solver]
    max_evaluations = 40               # least_squares max_nfev
    difference = "central"             # Jacobian by central or forward differences
    step = 0.01                        # difference step, as a fraction of each bound interval
    starts = 1                         # > 1: start from the best of this many points (LHS, seed)

Several records at once (shots at several velocities, several probes): the fitted
parameters are shared, each ``[[dataset]]`` has its own ``name``, ``base``, ``set``,
``measured``, ``computed``, optional ``time_shift`` and ``sigma``.  With ``sigma``
the residuals are divided by it (records in different units can be combined);
without, they are in SI units of the measured value.

An HDF5 measured record (e.g. one kept by a sweep): ``file = "records.h5"``,
``group = "r00003/free_surface"``; its columns are SI (no units to give).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from shockfriction.deck.base import DeckModel, read_toml, validate
from shockfriction.errors import DeckError
from shockfriction.safety import TRUSTED, Trust, resolve_inside
from shockfriction.sweep.paths import parse_path
from shockfriction.sweep.quantities import in_unit, si_factor, split_value
from shockfriction.sweep.spec import flatten

Value = int | float | str


def _bounds_ok(b: tuple[Value, Value], initial: Value | None) -> None:
    lo, unit = split_value(b[0])
    hi = in_unit(b[1], unit)
    if not hi > lo:
        raise ValueError(f"bounds (low, high) with high > low, both in one dimension, got {list(b)}")
    if initial is not None:
        x0 = in_unit(initial, unit)
        if not lo <= x0 <= hi:
            raise ValueError(f"an initial value inside the bounds {list(b)}, got {initial!r}")


class FitParameter(DeckModel):
    """A deck field to fit, between finite bounds, from an initial guess (default: mid-interval)."""

    path: str
    name: str | None = None
    bounds: tuple[Value, Value]
    initial: Value | None = None

    @field_validator("path")
    @classmethod
    def _path(cls, p):
        parse_path(p)
        return p

    @model_validator(mode="after")
    def _inside(self):
        _bounds_ok(self.bounds, self.initial)
        return self

    @property
    def column(self) -> str:
        return self.name or self.path


class TimeShift(DeckModel):
    """A shift s fitted along with the parameters: measured time = computed time + s."""

    bounds: tuple[Value, Value]
    initial: Value = "0 s"

    @model_validator(mode="after")
    def _inside(self):
        for v in (*self.bounds, self.initial):
            try:
                in_unit(v, "s")
            except ValueError:
                raise ValueError(f"times with their unit, such as '-50 ns' and '50 ns', got {v!r}") from None
        _bounds_ok(self.bounds, self.initial)
        return self


class Measured(DeckModel):
    """The measured record: CSV columns with their units, or an HDF5 group of SI columns."""

    file: str
    group: str | None = None
    time: str = "time"
    value: str = "velocity"
    time_unit: str = "s"
    value_unit: str = ""
    window: tuple[Value, Value] | None = None

    @field_validator("time_unit")
    @classmethod
    def _time_unit(cls, u):
        try:
            in_unit(f"1 {u}", "s")
        except ValueError:
            raise ValueError("a time unit such as 'us' or 'ns'") from None
        return u

    @field_validator("value_unit")
    @classmethod
    def _value_unit(cls, u):
        si_factor(u)
        return u

    @field_validator("window")
    @classmethod
    def _window(cls, w):
        if w is not None:
            lo, hi = in_unit(w[0], "s"), in_unit(w[1], "s")
            if not hi > lo:
                raise ValueError(f"a time window (start, end) with end > start, got {list(w)}")
        return w


class Computed(DeckModel):
    """Which record of a run, and which of its columns, to compare with the measurement."""

    record: str
    time: str = "time"
    value: str = "velocity"


class Solver(DeckModel):
    """scipy.optimize.least_squares settings (method 'trf', variables scaled to their bounds).

    ``starts`` > 1: the residual is first evaluated at the initial point and at
    ``starts - 1`` Latin-hypercube points of the parameter box (one parallel batch),
    and the solver starts from the best of them (against local minima).
    """

    max_evaluations: int = Field(default=50, ge=1)
    starts: int = Field(default=1, ge=1, le=10000)
    seed: int = 0
    difference: Literal["central", "forward"] = "central"
    step: float = Field(default=0.01, gt=0.0, lt=0.5)
    xtol: float = Field(default=1e-6, gt=0.0)
    ftol: float = Field(default=1e-8, gt=0.0)
    gtol: float = Field(default=1e-8, gt=0.0)


class Dataset(DeckModel):
    """One measured record and the run it is compared with (its own deck, window, shift, noise)."""

    name: str = Field(default="", pattern=r"^[A-Za-z0-9_\-]*$")
    base: str | None = None
    kind: Literal["run", "subgrid", "python"] | None = None
    model: str | None = None
    set: dict[str, Any] = {}
    measured: Measured
    computed: Computed
    time_shift: TimeShift | None = None
    sigma: float | None = Field(default=None, gt=0.0)

    @field_validator("set")
    @classmethod
    def _flatten_set(cls, table):
        flat = flatten(table)
        for p in flat:
            parse_path(p)
        return flat

    @property
    def effective_kind(self) -> str | None:
        return "python" if self.model else self.kind


class FitSpec(DeckModel):
    """A whole fit file: one record (top-level fields) or several (``[[dataset]]``)."""

    base: str | None = None
    kind: Literal["run", "subgrid", "python"] | None = None
    model: str | None = None
    set: dict[str, Any] = {}
    measured: Measured | None = None
    computed: Computed | None = None
    time_shift: TimeShift | None = None
    sigma: float | None = Field(default=None, gt=0.0)
    dataset: list[Dataset] = []
    parameter: list[FitParameter] = Field(min_length=1)
    solver: Solver = Solver()

    def datasets(self) -> list[Dataset]:
        """The records to fit, the single top-level one included."""
        if self.dataset:
            return [d if d.name else d.model_copy(update={"name": f"dataset{k}"}) for k, d in enumerate(self.dataset)]
        return [Dataset.model_construct(name="", base=self.base, kind=self.kind, model=self.model, set=self.set,
                                        measured=self.measured, computed=self.computed,
                                        time_shift=self.time_shift, sigma=self.sigma)]


def _check_dataset(d: Dataset, where: str, here: Path, path: Path, trust: Trust = TRUSTED) -> None:
    if d.kind == "python" and not d.model:
        raise DeckError(f"{path}: {where}kind = 'python' needs model = 'package.module:function'")
    if not d.model and not d.base:
        raise DeckError(f"{path}: {where}base is missing: expected base = 'deck.toml' (relative to the fit file)")
    if d.base is not None:
        resolve_inside(here, d.base, f"{where}base", str(path), trust)
    resolve_inside(here, d.measured.file, f"{where}measured.file", str(path), trust)
    if d.base is not None and not (here / d.base).is_file():
        raise DeckError(f"{path}: {where}base = {d.base!r}: expected a deck file relative to the fit file "
                        f"(looked for {here / d.base})")
    if not (here / d.measured.file).is_file():
        raise DeckError(f"{path}: {where}measured.file = {d.measured.file!r}: expected a file relative to the fit "
                        f"file (looked for {here / d.measured.file})")


def load_fit(path: str | Path, trust: Trust = TRUSTED) -> tuple[FitSpec, Path]:
    """Read and validate a fit file; returns the spec and the folder it lives in."""
    path = Path(path)
    spec = validate(FitSpec, read_toml(path), str(path))
    here = path.parent
    single = [k for k in ("base", "kind", "model", "measured", "computed", "time_shift", "sigma")
              if getattr(spec, k) is not None] + (["set"] if spec.set else [])
    if spec.dataset and single:
        raise DeckError(f"{path}: {', '.join(single)} at the top level with dataset tables: expected either "
                        "one record at the top level or every record in its own dataset table")
    if not spec.dataset:
        for k in ("measured", "computed"):
            if getattr(spec, k) is None:
                raise DeckError(f"{path}: {k} is missing: expected a {k!r} table (or dataset tables)")
    names = [d.name for d in spec.datasets()]
    if len(set(names)) != len(names):
        raise DeckError(f"{path}: dataset names {names}: expected distinct names")
    for k, d in enumerate(spec.datasets()):
        _check_dataset(d, f"dataset[{k}]." if spec.dataset else "", here, path, trust)
    cols = [p.column for p in spec.parameter]
    dup = sorted({c for c in cols if cols.count(c) > 1})
    if dup:
        raise DeckError(f"{path}: parameter: {dup} repeated: expected each path (or name) once")
    return spec, here
