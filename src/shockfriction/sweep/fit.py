"""Least-squares fit of deck parameters (and a time shift) to a measured record.

Residuals, one per measured sample t_i inside the window, for each dataset k:

    r_i(p, s_k) = (y_c(t_i - s_k; p) - y_m(t_i)) / sigma_k      (sigma_k = 1 SI unit if not given)

with y_c the computed record linearly interpolated (held constant outside the
computed time span) and s_k the dataset's time shift (measured time = computed
time + s_k).
scipy.optimize.least_squares (trust-region reflective) works on variables
scaled to their bounds, z = (x - lo) / (hi - lo) in [0, 1].  The Jacobian is
made by central (or forward) differences of step h in z; the model runs of one
Jacobian go to the executor together, so they run in parallel.  The shift
column needs no run: it is differenced on the interpolated record.

Uncertainty (Gauss-Newton, at the optimum): s^2 = sum r_i^2 / (m - n),
Cov = s^2 (J^T J)^-1 with J = dr/dx, sigma(p_j) = sqrt(Cov_jj).  A direction
along which J^T J is singular (a parameter the record does not determine, e.g.
f when the Coulomb branch of the friction law is everywhere active) gets
sigma = inf and is reported as not identifiable.
"""

from __future__ import annotations

import csv
from concurrent.futures import Executor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import qmc

from shockfriction.deck.base import read_toml
from shockfriction.io.atomic import atomic_write_json
from shockfriction.errors import DeckError, SimulationError
from shockfriction.safety import TRUSTED, Trust
from shockfriction.sweep.design import run_key
from shockfriction.sweep.executors import open_executor
from shockfriction.sweep.fitspec import FitSpec, load_fit
from shockfriction.sweep.measured import read_measured
from shockfriction.sweep.paths import get_path, set_paths
from shockfriction.sweep.quantities import in_unit, join_value, si_factor, split_value
from shockfriction.sweep.runners import anchor_files, check_deck, detect_kind
from shockfriction.sweep.worker import execute


@dataclass
class Curve:
    """One dataset at the optimum: measured samples and the computed record (shifted)."""

    name: str
    label: str
    t_measured: np.ndarray
    y_measured: np.ndarray
    t_computed: np.ndarray
    y_computed: np.ndarray
    rms: float
    column: str = "value"   # the computed record's column (computed.record.value)
    unit: str = ""          # measured.value_unit: computed.csv writes the computed values in it


@dataclass
class FitResult:
    """Best values, uncertainties and residual of a fit, and the records to plot."""

    names: list[str]
    units: list[str]
    values: np.ndarray
    sigma: np.ndarray
    covariance: np.ndarray
    identifiable: list[bool]
    at_bound: list[bool]
    rms: float
    sum_squares: float
    dof: int
    samples: int
    success: bool
    message: str
    evaluations: int
    runs: int
    curves: list[Curve]
    weighted: bool
    history: list[dict] = field(default_factory=list)

    def as_dict(self) -> dict:
        sd = np.sqrt(np.diag(self.covariance))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = self.covariance / np.outer(sd, sd)
        params = {n: {"value": float(v), "sigma": float(s), "unit": u, "identifiable": i, "at_bound": b}
                  for n, u, v, s, i, b in zip(self.names, self.units, self.values, self.sigma,
                                              self.identifiable, self.at_bound)}
        clean = lambda a: [[None if not np.isfinite(x) else float(x) for x in row] for row in a]  # noqa: E731
        return {"parameters": params,
                "residual": {"rms": self.rms, "sum_squares": self.sum_squares, "dof": self.dof,
                             "samples": self.samples, "weighted": self.weighted,
                             "per_dataset_rms_SI": {c.name or "record": c.rms for c in self.curves}},
                "covariance": clean(self.covariance), "correlation": clean(corr),
                "success": self.success, "message": self.message,
                "evaluations": self.evaluations, "model_runs": self.runs}


@dataclass
class _Data:
    """A dataset ready to evaluate: deck with the fixed overrides, measured samples in SI, weight."""

    name: str
    kind: str
    model: str | None
    deck0: dict
    record: str
    time: str
    value: str
    t_m: np.ndarray
    y_m: np.ndarray
    weight: float
    shift: int | None  # index of its time shift in the variable vector
    unit: str = ""     # measured.value_unit (computed.csv is written in it)

    @property
    def keep(self) -> dict:
        # every record: datasets comparing two probes of one deck share its run
        return {"records": "all", "scalars": [], "derived": []}


class FitProblem:
    """The residual vector of a fit file as a function of the scaled variables z.

    Variables: the deck parameters (shared by every dataset), then one time shift per
    dataset that asks for one.  Residuals: the datasets' blocks one after the other,
    each divided by its sigma when given.
    """

    def __init__(self, spec: FitSpec, here: Path, executor: Executor, source: str = "fit",
                 on_evaluation: Callable[[int, dict], None] | None = None, trust: Trust = TRUSTED):
        self.spec, self.ex, self.source = spec, executor, source
        self.on_evaluation = on_evaluation
        self.params = spec.parameter
        self.n_deck = len(self.params)
        self.units = [split_value(p.bounds[0])[1] for p in self.params]
        lo = [split_value(p.bounds[0])[0] for p in self.params]
        hi = [in_unit(p.bounds[1], u) for p, u in zip(self.params, self.units)]
        x0 = [in_unit(p.initial, u) if p.initial is not None else 0.5 * (a + b)
              for p, u, a, b in zip(self.params, self.units, lo, hi)]
        self.shift_names: list[str] = []
        self.data: list[_Data] = []
        for k, d in enumerate(spec.datasets()):
            where = f"{source}: dataset[{k}]" if d.name else source
            base = anchor_files(read_toml(here / d.base), (here / d.base).parent, f"{where}: base = {d.base!r}",
                                trust) if d.base else {}
            deck0 = set_paths(base, d.set, where) if d.set else base
            kind = d.effective_kind or detect_kind(base, f"{where}: base = {d.base!r}")
            t_m, y_m = read_measured(d.measured, here, where)
            shift = None
            if d.time_shift is not None:
                shift = self.n_deck + len(self.shift_names)
                self.shift_names.append(f"time_shift.{d.name}" if d.name else "time_shift")
                lo.append(in_unit(d.time_shift.bounds[0], "s"))
                hi.append(in_unit(d.time_shift.bounds[1], "s"))
                x0.append(in_unit(d.time_shift.initial, "s"))
            weight = 1.0 / (d.sigma * si_factor(d.measured.value_unit)) if d.sigma else 1.0
            self.data.append(_Data(d.name, kind, d.model, deck0, d.computed.record, d.computed.time,
                                   d.computed.value, t_m, y_m, weight, shift, d.measured.value_unit))
        self.lo, self.hi, self.x0 = np.array(lo), np.array(hi), np.array(x0)
        self.weighted = any(d.sigma for d in spec.datasets())
        self.cache: dict[str, dict] = {}  # run key -> records of the run
        self.history: list[dict] = []
        self.runs = 0
        for ds in self.data:
            for what, x in (("the initial values", self.x0), ("the lower bounds", self.lo),
                            ("the upper bounds", self.hi)):
                check_deck(ds.kind, self.deck_for(ds, x), f"{source}: {ds.name or 'deck'} at {what}", ds.model,
                           trust)

    # --- model runs -------------------------------------------------------------
    def x_of(self, z: np.ndarray) -> np.ndarray:
        return self.lo + np.asarray(z) * (self.hi - self.lo)

    def deck_for(self, ds: _Data, x: np.ndarray) -> dict:
        values = {p.path: join_value(v, u) for p, v, u in zip(self.params, x[: self.n_deck], self.units)}
        return set_paths(ds.deck0, values, self.source)

    def records(self, xs: list[np.ndarray]) -> list[list[tuple[np.ndarray, np.ndarray]]]:
        """The computed (t, y) of every dataset at each parameter vector; new runs go out together."""
        jobs = [[(ds, self.deck_for(ds, x)) for ds in self.data] for x in xs]
        keys = [[run_key(ds.kind, ds.model, deck, ds.keep) for ds, deck in row] for row in jobs]
        todo: dict[str, tuple] = {}
        for row, krow in zip(jobs, keys):
            for (ds, deck), k in zip(row, krow):
                if k not in self.cache and k not in todo:
                    task = {"key": k, "kind": ds.kind, "model": ds.model, "deck": deck, "keep": ds.keep}
                    todo[k] = (deck, self.ex.submit(execute, task))
        wait([fut for _, fut in todo.values()])
        for k, (deck, fut) in todo.items():
            res = fut.result()
            self.runs += 1
            if res["status"] != "ok":
                raise SimulationError(f"{self.source}: model run failed at {self._describe(deck)}: {res['error']}")
            self.cache[k] = res["records"]
        return [[self._pick(ds, self.cache[k]) for (ds, _), k in zip(row, krow)] for row, krow in zip(jobs, keys)]

    def _pick(self, ds: _Data, records: dict) -> tuple[np.ndarray, np.ndarray]:
        where = f"{self.source}: {ds.name + ': ' if ds.name else ''}"
        if ds.record not in records:
            raise DeckError(f"{where}computed.record = {ds.record!r}: expected a record the run produces, "
                            f"one of {sorted(records)}")
        rec = records[ds.record]
        for col in (ds.time, ds.value):
            if col not in rec:
                raise DeckError(f"{where}computed: column {col!r} not in record {ds.record!r}; "
                                f"expected one of {sorted(rec)}")
        return rec[ds.time], rec[ds.value]

    def _describe(self, deck: dict) -> str:
        return ", ".join(f"{p.column} = {get_path(deck, p.path, self.source)!r}" for p in self.params)

    # --- residuals and Jacobian ---------------------------------------------------
    def block(self, ds: _Data, rec: tuple[np.ndarray, np.ndarray], x: np.ndarray, ds_shift: float = 0.0) -> np.ndarray:
        """Weighted residuals of one dataset: w (y_c(t_i - s) - y_m(t_i))."""
        shift = (x[ds.shift] if ds.shift is not None else 0.0) + ds_shift
        t_c, y_c = rec
        return ds.weight * (np.interp(ds.t_m - shift, t_c, y_c) - ds.y_m)

    def beyond(self, ds: _Data, rec: tuple[np.ndarray, np.ndarray], x: np.ndarray) -> int:
        """How many measured samples, at the time shift of x, fall outside the computed record's span by more than
        one record interval: np.interp holds the record's end values there, values the run never computed."""
        shift = x[ds.shift] if ds.shift is not None else 0.0
        t_c = rec[0]
        if t_c.size == 0:
            return int(ds.t_m.size)
        gap = float(np.max(np.diff(t_c))) if t_c.size > 1 else 0.0
        t = ds.t_m - shift
        return int(np.count_nonzero((t < t_c[0] - gap) | (t > t_c[-1] + gap)))

    def residual(self, recs: list, x: np.ndarray) -> np.ndarray:
        return np.concatenate([self.block(ds, rec, x) for ds, rec in zip(self.data, recs)])

    def fun(self, z: np.ndarray) -> np.ndarray:
        x = self.x_of(z)
        r = self.residual(self.records([x])[0], x)
        self.history.append({**{n: float(v) for n, v in zip(self.names, x)}, "rms": float(np.sqrt(np.mean(r**2)))})
        if self.on_evaluation is not None:
            self.on_evaluation(len(self.history), self.history[-1])
        return r

    def jac(self, z: np.ndarray) -> np.ndarray:
        h = self.spec.solver.step
        central = self.spec.solver.difference == "central"
        x = self.x_of(z)
        points, plan = [x], []
        for j in range(self.n_deck):
            up, down = z[j] + h <= 1.0, z[j] - h >= 0.0
            if central:
                a, b = (z[j] + h if up else z[j]), (z[j] - h if down else z[j])
            else:
                a, b = (z[j] + h, z[j]) if up else (z[j], z[j] - h)
            za, zb = z.copy(), z.copy()
            za[j], zb[j] = a, b
            plan.append((len(points), len(points) + 1, a - b))
            points += [self.x_of(za), self.x_of(zb)]
        recs = self.records(points)
        J = np.zeros((sum(len(ds.t_m) for ds in self.data), len(z)))
        for j, (ia, ib, dz) in enumerate(plan):
            J[:, j] = (self.residual(recs[ia], x) - self.residual(recs[ib], x)) / dz
        row = 0
        for ds, rec in zip(self.data, recs[0]):  # the shifts: no run, difference the interpolated record
            m = len(ds.t_m)
            if ds.shift is not None:
                width = self.hi[ds.shift] - self.lo[ds.shift]
                ds_ = h * width
                J[row:row + m, ds.shift] = (self.block(ds, rec, x, ds_) - self.block(ds, rec, x, -ds_)) / (2 * h)
            row += m
        return J

    @property
    def names(self) -> list[str]:
        return [p.column for p in self.params] + self.shift_names

    @property
    def all_units(self) -> list[str]:
        return self.units + ["s"] * len(self.shift_names)


def covariance(J: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, list[bool], int]:
    """Cov = s^2 (J^T J)^-1, s^2 = |r|^2 / (m - n); inf where J^T J is singular. Returns (Cov, identifiable, dof)."""
    m, n = J.shape
    dof = max(m - n, 1)
    s2 = float(r @ r) / dof
    U, S, Vt = np.linalg.svd(J, full_matrices=False)
    tol = S.max(initial=0.0) * max(m, n) * np.finfo(float).eps * 1e3
    good = S > tol
    cov = (Vt[good].T / S[good] ** 2) @ Vt[good] * s2
    null = Vt[~good]
    identifiable = [bool(np.all(np.abs(null[:, k]) < 1e-6)) for k in range(n)]
    for k in range(n):
        if not identifiable[k]:
            cov[k, :] = cov[:, k] = np.inf
    return cov, identifiable, dof


def fit(fit_file: str | Path, scheduler: str | None = None, workers: int | None = None,
        executor: Executor | None = None, on_evaluation: Callable[[int, dict], None] | None = None,
        trust: Trust = TRUSTED) -> FitResult:
    """Run the fit described by ``fit_file`` and return its result (see the module docstring).

    ``on_evaluation(k, point)`` is called after each residual evaluation with the
    parameter values and the residual rms (for progress reports).
    """
    spec, here = load_fit(fit_file, trust)
    if executor is None:
        with open_executor(scheduler, workers) as ex:
            return _solve(spec, here, ex, str(fit_file), on_evaluation, trust)
    return _solve(spec, here, executor, str(fit_file), on_evaluation, trust)


def best_start(prob: FitProblem, z0: np.ndarray, starts: int, seed: int) -> tuple[np.ndarray, list[float]]:
    """The best of z0 and ``starts - 1`` Latin-hypercube points of the deck parameters (shifts at z0)."""
    zs = [z0]
    if starts > 1:
        u = qmc.LatinHypercube(d=prob.n_deck, seed=seed).random(starts - 1)
        for row in u:
            z = z0.copy()
            z[: prob.n_deck] = row
            zs.append(z)
    xs = [prob.x_of(z) for z in zs]
    recs = prob.records(xs)  # one parallel batch
    costs = [float(np.sum(prob.residual(r, x) ** 2)) for r, x in zip(recs, xs)]
    return zs[int(np.argmin(costs))], costs


def _solve(spec: FitSpec, here: Path, ex: Executor, source: str, on_evaluation=None,
           trust: Trust = TRUSTED) -> FitResult:
    prob = FitProblem(spec, here, ex, source, on_evaluation, trust)
    for ds, rec in zip(prob.data, prob.records([prob.x0])[0]):  # (the first evaluation's runs: cached)
        n = prob.beyond(ds, rec, prob.x0)
        if n:
            t_c = rec[0]
            span = f"{t_c[0]:.4g}-{t_c[-1]:.4g} s" if t_c.size else "empty"
            raise DeckError(f"{source}: {ds.name + ': ' if ds.name else ''}{n} of {ds.t_m.size} measured samples "
                            f"(at the initial time shift) fall beyond the computed record {ds.record}.{ds.time}, "
                            f"{span}: expected the run to cover the samples (a longer duration or time.end, or "
                            "a measured.window)")
    z0 = (prob.x0 - prob.lo) / (prob.hi - prob.lo)
    s = spec.solver
    if s.starts > 1:
        z0, _ = best_start(prob, z0, s.starts, s.seed)
    sol = least_squares(prob.fun, z0, jac=prob.jac, bounds=(0.0, 1.0), method="trf", x_scale=1.0,
                        max_nfev=s.max_evaluations, xtol=s.xtol, ftol=s.ftol, gtol=s.gtol)
    x = prob.x_of(sol.x)
    J = sol.jac / (prob.hi - prob.lo)  # dr/dx from dr/dz
    cov, ident, dof = covariance(J, sol.fun)
    curves = []
    outside = 0
    for ds, (t_c, y_c) in zip(prob.data, prob.records([x])[0]):
        outside += prob.beyond(ds, (t_c, y_c), x)
        shift = x[ds.shift] if ds.shift is not None else 0.0
        r = np.interp(ds.t_m - shift, t_c, y_c) - ds.y_m
        curves.append(Curve(ds.name, f"{ds.record}.{ds.value} (SI)", ds.t_m, ds.y_m, t_c + shift, y_c,
                            float(np.sqrt(np.mean(r**2))), f"{ds.record}.{ds.value}", ds.unit))
    tol = 1e-9
    return FitResult(
        names=prob.names, units=prob.all_units, values=x, sigma=np.sqrt(np.diag(cov)), covariance=cov,
        identifiable=ident, at_bound=[bool(z <= tol or z >= 1 - tol) for z in sol.x],
        rms=float(np.sqrt(np.mean(sol.fun**2))), sum_squares=float(sol.fun @ sol.fun), dof=dof,
        samples=len(sol.fun), success=bool(sol.success),
        message=str(sol.message) + (f" ({outside} measured samples fall beyond the computed record at the fitted "
                                    "time shift: compared with its end values)" if outside else ""),
        evaluations=int(sol.nfev),
        runs=prob.runs, curves=curves, weighted=prob.weighted, history=prob.history)


def write_outputs(result: FitResult, out_dir: Path, force: bool = False) -> dict[str, Path]:
    """fit.json (report), computed[_<dataset>].csv (best computed records, shifted), evaluations.csv, fit.png,
    in ``out_dir`` (new or empty; a non-empty folder is refused unless ``force``: its previous outputs go)."""
    from shockfriction.io.outdir import prepare_out_dir
    from shockfriction.sweep.fitplot import plot_fit

    from shockfriction.sweep.quantities import si_factor

    out_dir = prepare_out_dir(out_dir, force=force, option="out_dir")
    paths = {"report": out_dir / "fit.json", "evaluations": out_dir / "evaluations.csv", "plot": out_dir / "fit.png"}
    atomic_write_json(paths["report"], result.as_dict())
    for c in result.curves:
        key = f"computed_{c.name}" if c.name else "computed"
        paths[key] = out_dir / f"{key}.csv"
        with open(paths[key], "w", newline="") as fh:
            w = csv.writer(fh)
            factor = si_factor(c.unit)
            w.writerow(["t [s]", f"{c.column} [{c.unit or 'SI'}]"])
            w.writerows((f"{a:.12g}", f"{b / factor:.12g}") for a, b in zip(c.t_computed, c.y_computed))
    with open(paths["evaluations"], "w", newline="") as fh:
        if result.history:
            units = dict(zip(result.names, result.units))
            w = csv.writer(fh)
            w.writerow([f"{k} [{units[k]}]" if units.get(k) else k for k in result.history[0]])
            w.writerows([repr(float(v)) for v in row.values()] for row in result.history)
    plot_fit(result, paths["plot"])
    return paths
