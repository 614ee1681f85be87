"""Run a sweep: plan the runs, skip the finished ones, dispatch the rest, keep every result.

Each finished run is written to the journal as soon as it comes back (see
:mod:`shockfriction.sweep.journal`); ``sweep.csv`` is refreshed every
``TABLE_REFRESH_S`` seconds while the sweep runs, and ``sweep.csv`` and
``records.h5`` are rebuilt from the journal when the sweep ends, also when it is
interrupted (Ctrl-C).  A run that raises is recorded as ``failed`` with its error; a run
lost with its worker (process killed, cluster gone) is left pending and is run
again by the next invocation.
"""

from __future__ import annotations

import json
import time
from concurrent.futures import FIRST_COMPLETED, Executor, wait
from dataclasses import dataclass, field
from pathlib import Path

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from shockfriction.deck.base import read_toml
from shockfriction.io.atomic import atomic_write_text
from shockfriction.safety import TRUSTED, Trust
from shockfriction.sweep.design import RunPoint, build_runs, column_unit
from shockfriction.sweep.executors import open_executor
from shockfriction.sweep.journal import finished, read_summary, result_path, write_result
from shockfriction.sweep.runners import anchor_files, check_deck, detect_kind, load_function
from shockfriction.sweep.spec import SweepSpec, load_sweep
from shockfriction.sweep.store import gather, write_records, write_table
from shockfriction.sweep.worker import execute


TABLE_REFRESH_S = 30.0


@dataclass
class SweepOutcome:
    """Counts of a sweep invocation and where its files are."""

    total: int
    ok: int = 0
    failed: int = 0
    pending: int = 0
    reused: int = 0
    computed: int = 0
    lost: list[str] = field(default_factory=list)
    interrupted: bool = False
    table: Path | None = None
    records: Path | None = None


def plan(sweep_file: str | Path, trust: Trust = TRUSTED,
         import_model: bool = True) -> tuple[SweepSpec, str, list[RunPoint]]:
    """Read the sweep file and the base deck, and validate every run's deck before any run starts.

    ``import_model``: import a Python model (kind = "python", allowed by ``trust``) to check that it
    exists; ``--dry-run`` passes False and so runs no user code."""
    sweep_file = Path(sweep_file)
    spec, here = load_sweep(sweep_file, trust)
    base = anchor_files(read_toml(here / spec.base), (here / spec.base).parent,
                        f"{sweep_file}: base = {spec.base!r}", trust) if spec.base else {}
    kind = spec.effective_kind
    if kind is None:
        build_runs(spec, base, None, str(sweep_file))  # report a bad path before an unknown kind
        kind = detect_kind(base, f"{sweep_file}: base = {spec.base!r}")
    runs = build_runs(spec, base, kind, str(sweep_file))
    checked: set[str] = set()
    for run in runs:
        if run.key not in checked:
            check_deck(kind, run.deck, f"{sweep_file}: run {run.run_id} {run.values}", spec.model, trust)
            checked.add(run.key)
    if kind == "python" and import_model:
        load_function(spec.model or "", str(sweep_file))
    return spec, kind, runs


def run_sweep(sweep_file: str | Path, out_dir: str | Path, scheduler: str | None = None,
              workers: int | None = None, retry_failed: bool = False, progress: bool = True,
              executor: Executor | None = None, trust: Trust = TRUSTED, force: bool = False) -> SweepOutcome:
    """Run (or resume) the sweep of ``sweep_file`` into ``out_dir``; see the module docstring.

    ``out_dir`` is new, empty or holds a sweep (``plan.json``: resumed); another non-empty folder is
    refused (:class:`~shockfriction.errors.UsageError`) unless ``force`` (its previous outputs go)."""
    from shockfriction.io.outdir import prepare_out_dir

    spec, kind, runs = plan(sweep_file, trust)
    out_dir = prepare_out_dir(out_dir, force=force, resume=True)
    units = {p.column: column_unit(p) for p in spec.parameter}
    atomic_write_text(out_dir / "plan.json", json.dumps(
        {"sweep": str(sweep_file), "kind": kind, "parameters": units,
         "runs": [{"run": r.run_id, "key": r.key, "values": r.values} for r in runs]}, indent=1))

    done = finished(out_dir, retry_failed)
    todo: dict[str, RunPoint] = {}
    for run in runs:
        if run.key not in done:
            todo.setdefault(run.key, run)
    outcome = SweepOutcome(total=len(runs), reused=sum(1 for r in runs if r.key in done))
    keep = spec.keep.model_dump()
    console = Console(stderr=True)
    table = _Table(out_dir, runs, units, {k: read_summary(result_path(out_dir, k)) for k in done})
    try:
        if todo:
            ctx = open_executor(scheduler, workers) if executor is None else _borrowed(executor)
            with ctx as ex:
                _dispatch(ex, todo, kind, spec.model, keep, out_dir, outcome, console, progress, table)
    except KeyboardInterrupt:
        outcome.interrupted = True
    finally:
        results = gather(out_dir, runs)
        outcome.ok = sum(1 for r in results.values() if r["status"] == "ok")
        outcome.failed = sum(1 for r in results.values() if r["status"] == "failed")
        outcome.pending = len(runs) - len(results)
        outcome.table = write_table(out_dir, runs, units, results)
        outcome.records = write_records(out_dir, runs, units, results)
    return outcome


class _Table:
    """``sweep.csv`` kept up to date from the runs' summaries, rewritten at most every TABLE_REFRESH_S."""

    def __init__(self, out_dir: Path, runs: list[RunPoint], units: dict[str, str], by_key: dict[str, dict]):
        self.out_dir, self.runs, self.units, self.by_key = out_dir, runs, units, by_key
        self.written = time.monotonic()

    def add(self, res: dict) -> None:
        self.by_key[res["key"]] = {**res, "records": {}}
        if time.monotonic() - self.written >= TABLE_REFRESH_S:
            results = {r.run_id: self.by_key[r.key] for r in self.runs if r.key in self.by_key}
            write_table(self.out_dir, self.runs, self.units, results)
            self.written = time.monotonic()


class _borrowed:
    """Context manager around an executor the caller owns (not shut down here)."""

    def __init__(self, ex: Executor):
        self.ex = ex

    def __enter__(self) -> Executor:
        return self.ex

    def __exit__(self, *exc) -> None:
        return None


def _dispatch(ex: Executor, todo: dict[str, RunPoint], kind: str, model: str | None, keep: dict,
              out_dir: Path, outcome: SweepOutcome, console: Console, show: bool, table: _Table) -> None:
    futures = {ex.submit(execute, {"key": k, "kind": kind, "model": model, "deck": r.deck, "keep": keep}): r
               for k, r in todo.items()}
    columns = (TextColumn("[bold]sweep[/]"), BarColumn(), MofNCompleteColumn(),
               TextColumn("{task.fields[failed]} failed"), TimeElapsedColumn(), TimeRemainingColumn())
    with Progress(*columns, console=console, disable=not show) as bar:
        task = bar.add_task("runs", total=len(futures), failed=0)
        failed = 0
        pending = set(futures)
        try:
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    run = futures.pop(fut)  # drop the future: a Dask worker may then free the result
                    try:
                        res = fut.result()
                    except Exception as exc:  # the worker itself died: the run stays pending
                        outcome.lost.append(f"{run.run_id}: {type(exc).__name__}: {exc}")
                        bar.advance(task)
                        continue
                    write_result(out_dir, res, run.deck)
                    table.add(res)
                    outcome.computed += 1
                    failed += res["status"] == "failed"
                    bar.update(task, advance=1, failed=failed)
        except KeyboardInterrupt:
            for fut in futures:
                fut.cancel()
            raise
