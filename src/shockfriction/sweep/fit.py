"""Least-squares fit of deck parameters (and a time shift) to a measured record.

Residuals, one per measured sample t_i inside the window:

    r_i(p, s) = y_c(t_i - s; p) - y_m(t_i)

with y_c the computed record linearly interpolated (held constant outside the
computed time span) and s the time shift (measured time = computed time + s).
scipy.optimize.least_squares (trust-region reflective) works on variables
scaled to their bounds, z = (x - lo) / (hi - lo) in [0, 1].  The Jacobian is
made by central (or forward) differences of step h in z; the model runs of one
Jacobian go to the executor together, so they run in parallel.  The shift
column needs no run: it is differenced on the interpolated record.

Uncertainty (Gauss-Newton, at the optimum): s^2 = sum r_i^2 / (m - n),
Cov = s^2 (J^T J)^-1 with J = dr/dx, sigma_k = sqrt(Cov_kk).  A direction
along which J^T J is singular (a parameter the record does not determine, e.g.
f when the Coulomb branch of the friction law is everywhere active) gets
sigma = inf and is reported as not identifiable.
"""

from __future__ import annotations

import csv
import json
from concurrent.futures import Executor, wait
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from shockfriction.deck.base import read_toml
from shockfriction.errors import DeckError, SimulationError
from shockfriction.sweep.design import run_key
from shockfriction.sweep.executors import open_executor
from shockfriction.sweep.fitspec import FitSpec, load_fit
from shockfriction.sweep.measured import read_measured
from shockfriction.sweep.paths import get_path, set_paths
from shockfriction.sweep.quantities import in_unit, join_value, split_value
from shockfriction.sweep.runners import check_deck, detect_kind
from shockfriction.sweep.worker import execute


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
    success: bool
    message: str
    evaluations: int
    runs: int
    t_measured: np.ndarray
    y_measured: np.ndarray
    t_computed: np.ndarray
    y_computed: np.ndarray
    history: list[dict] = field(default_factory=list)
    label: str = "value (SI)"

    def as_dict(self) -> dict:
        sd = np.sqrt(np.diag(self.covariance))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = self.covariance / np.outer(sd, sd)
        params = {n: {"value": float(v), "sigma": float(s), "unit": u, "identifiable": i, "at_bound": b}
                  for n, u, v, s, i, b in zip(self.names, self.units, self.values, self.sigma,
                                              self.identifiable, self.at_bound)}
        clean = lambda a: [[None if not np.isfinite(x) else float(x) for x in row] for row in a]  # noqa: E731
        return {"parameters": params, "residual": {"rms": self.rms, "sum_squares": self.sum_squares,
                                                   "dof": self.dof, "samples": len(self.t_measured)},
                "covariance": clean(self.covariance), "correlation": clean(corr),
                "success": self.success, "message": self.message,
                "evaluations": self.evaluations, "model_runs": self.runs}


class FitProblem:
    """The residual vector of a fit file as a function of the scaled variables z."""

    def __init__(self, spec: FitSpec, here: Path, executor: Executor, source: str = "fit"):
        self.spec, self.ex, self.source = spec, executor, source
        base = read_toml(here / spec.base) if spec.base else {}
        self.deck0 = set_paths(base, spec.set, source) if spec.set else base
        self.kind = spec.effective_kind or detect_kind(base, f"{source}: base = {spec.base!r}")
        self.params = spec.parameter
        self.units = [split_value(p.bounds[0])[1] for p in self.params]
        lo = [split_value(p.bounds[0])[0] for p in self.params]
        hi = [in_unit(p.bounds[1], u) for p, u in zip(self.params, self.units)]
        x0 = [in_unit(p.initial, u) if p.initial is not None else 0.5 * (a + b)
              for p, u, a, b in zip(self.params, self.units, lo, hi)]
        if spec.time_shift is not None:
            ts = spec.time_shift
            lo.append(in_unit(ts.bounds[0], "s"))
            hi.append(in_unit(ts.bounds[1], "s"))
            x0.append(in_unit(ts.initial, "s"))
        self.lo, self.hi, self.x0 = np.array(lo), np.array(hi), np.array(x0)
        self.n_deck = len(self.params)
        self.t_m, self.y_m = read_measured(spec.measured, here, source)
        self.keep = {"records": [spec.computed.record], "scalars": [], "derived": []}
        self.cache: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.history: list[dict] = []
        self.runs = 0
        check_deck(self.kind, self.deck_for(self.x0), f"{source}: deck at the initial values", spec.model)
        for corner in (self.lo, self.hi):
            check_deck(self.kind, self.deck_for(corner), f"{source}: deck at the bounds", spec.model)

    # --- model runs -------------------------------------------------------------
    def x_of(self, z: np.ndarray) -> np.ndarray:
        return self.lo + np.asarray(z) * (self.hi - self.lo)

    def deck_for(self, x: np.ndarray) -> dict:
        values = {p.path: join_value(v, u) for p, v, u in zip(self.params, x[: self.n_deck], self.units)}
        return set_paths(self.deck0, values, self.source)

    def records(self, xs: list[np.ndarray]) -> list[tuple[np.ndarray, np.ndarray]]:
        """The computed (t, y) at each deck-parameter vector; new runs go to the executor together."""
        decks = [self.deck_for(x) for x in xs]
        keys = [run_key(self.kind, self.spec.model, d, self.keep) for d in decks]
        todo: dict[str, tuple[dict, object]] = {}
        for k, d in zip(keys, decks):
            if k not in self.cache and k not in todo:
                task = {"key": k, "kind": self.kind, "model": self.spec.model, "deck": d, "keep": self.keep}
                todo[k] = (d, self.ex.submit(execute, task))
        wait([fut for _, fut in todo.values()])
        for k, (d, fut) in todo.items():
            res = fut.result()
            self.runs += 1
            if res["status"] != "ok":
                if res["error"].startswith("KeepError"):
                    raise DeckError(f"{self.source}: computed.record = {self.spec.computed.record!r}: "
                                    f"expected a record the run produces ({res['error']})")
                raise SimulationError(f"{self.source}: model run failed at {self._describe(d)}: {res['error']}")
            rec = res["records"][self.spec.computed.record]
            for col in (self.spec.computed.time, self.spec.computed.value):
                if col not in rec:
                    raise DeckError(f"{self.source}: computed: column {col!r} not in record "
                                    f"{self.spec.computed.record!r}; expected one of {sorted(rec)}")
            self.cache[k] = (rec[self.spec.computed.time], rec[self.spec.computed.value])
        return [self.cache[k] for k in keys]

    def _describe(self, deck: dict) -> str:
        return ", ".join(f"{p.column} = {get_path(deck, p.path, self.source)!r}" for p in self.params)

    # --- residuals and Jacobian ---------------------------------------------------
    def shift_of(self, x: np.ndarray) -> float:
        return float(x[self.n_deck]) if len(x) > self.n_deck else 0.0

    def residual_of(self, rec: tuple[np.ndarray, np.ndarray], shift: float) -> np.ndarray:
        t_c, y_c = rec
        return np.interp(self.t_m - shift, t_c, y_c) - self.y_m

    def fun(self, z: np.ndarray) -> np.ndarray:
        x = self.x_of(z)
        r = self.residual_of(self.records([x])[0], self.shift_of(x))
        self.history.append({**{n: float(v) for n, v in zip(self.names, x)}, "rms": float(np.sqrt(np.mean(r**2)))})
        return r

    def jac(self, z: np.ndarray) -> np.ndarray:
        h = self.spec.solver.step
        central = self.spec.solver.difference == "central"
        points, plan = [self.x_of(z)], []
        for j in range(self.n_deck):
            up, down = z[j] + h <= 1.0, z[j] - h >= 0.0
            a, b = (z[j] + h if up else z[j], z[j] - h if down else z[j]) if central else \
                   ((z[j] + h, z[j]) if up else (z[j], z[j] - h))
            za, zb = z.copy(), z.copy()
            za[j], zb[j] = a, b
            plan.append((len(points), len(points) + 1, a - b))
            points += [self.x_of(za), self.x_of(zb)]
        recs = self.records(points)
        shift = self.shift_of(points[0])
        r = [self.residual_of(rec, shift) for rec in recs]
        J = np.empty((len(self.t_m), len(z)))
        for j, (ia, ib, dz) in enumerate(plan):
            J[:, j] = (r[ia] - r[ib]) / dz
        if len(z) > self.n_deck:  # the shift: no run, difference the interpolated record
            ds = h * (self.hi[-1] - self.lo[-1])
            J[:, -1] = (self.residual_of(recs[0], shift + ds) - self.residual_of(recs[0], shift - ds)) / (
                2 * ds / (self.hi[-1] - self.lo[-1]))
        return J

    @property
    def names(self) -> list[str]:
        return [p.column for p in self.params] + (["time_shift"] if self.spec.time_shift else [])

    @property
    def all_units(self) -> list[str]:
        return self.units + (["s"] if self.spec.time_shift else [])


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
        executor: Executor | None = None) -> FitResult:
    """Run the fit described by ``fit_file`` and return its result (see the module docstring)."""
    spec, here = load_fit(fit_file)
    if executor is None:
        with open_executor(scheduler, workers) as ex:
            return _solve(spec, here, ex, str(fit_file))
    return _solve(spec, here, executor, str(fit_file))


def _solve(spec: FitSpec, here: Path, ex: Executor, source: str) -> FitResult:
    prob = FitProblem(spec, here, ex, source)
    z0 = (prob.x0 - prob.lo) / (prob.hi - prob.lo)
    s = spec.solver
    sol = least_squares(prob.fun, z0, jac=prob.jac, bounds=(0.0, 1.0), method="trf", x_scale=1.0,
                        max_nfev=s.max_evaluations, xtol=s.xtol, ftol=s.ftol, gtol=s.gtol)
    x = prob.x_of(sol.x)
    scale = prob.hi - prob.lo
    J = sol.jac / scale  # dr/dx from dr/dz
    cov, ident, dof = covariance(J, sol.fun)
    t_c, y_c = prob.records([x])[0]
    shift = prob.shift_of(x)
    tol = 1e-9
    return FitResult(
        names=prob.names, units=prob.all_units, values=x, sigma=np.sqrt(np.diag(cov)), covariance=cov,
        identifiable=ident, at_bound=[bool(z <= tol or z >= 1 - tol) for z in sol.x],
        rms=float(np.sqrt(np.mean(sol.fun**2))), sum_squares=float(sol.fun @ sol.fun), dof=dof,
        success=bool(sol.success), message=str(sol.message), evaluations=int(sol.nfev), runs=prob.runs,
        t_measured=prob.t_m, y_measured=prob.y_m, t_computed=t_c + shift, y_computed=y_c, history=prob.history,
        label=f"{spec.computed.record}.{spec.computed.value} (SI)")


def write_outputs(result: FitResult, out_dir: Path) -> dict[str, Path]:
    """fit.json (report), computed.csv (best computed record, shifted), evaluations.csv, fit.png."""
    from shockfriction.sweep.fitplot import plot_fit

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = {"report": out_dir / "fit.json", "computed": out_dir / "computed.csv",
             "evaluations": out_dir / "evaluations.csv", "plot": out_dir / "fit.png"}
    paths["report"].write_text(json.dumps(result.as_dict(), indent=2))
    with open(paths["computed"], "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time [s]", "value [SI]"])
        w.writerows((f"{a:.12g}", f"{b:.12g}") for a, b in zip(result.t_computed, result.y_computed))
    with open(paths["evaluations"], "w", newline="") as fh:
        if result.history:
            w = csv.DictWriter(fh, fieldnames=list(result.history[0]))
            w.writeheader()
            w.writerows(result.history)
    plot_fit(result, paths["plot"])
    return paths
