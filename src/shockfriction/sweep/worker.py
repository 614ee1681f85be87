"""The task a worker executes: run one deck in its own scratch folder, keep what is asked.

``execute`` is a plain top-level function of plain data, so that it pickles to a
local process pool and to Dask workers alike.  Any exception of the run becomes
a ``failed`` result carrying the error text: one bad run never stops a sweep.
The scratch folder is a fresh temporary directory on the worker's machine (a
remote worker need not see the sweep's output folder); it is removed afterwards.
"""

from __future__ import annotations

import tempfile
import time
import traceback
from pathlib import Path

from shockfriction.errors import ShockfrictionError
from shockfriction.sweep.keep import select
from shockfriction.sweep.runners import run_deck


def execute(task: dict) -> dict:
    """Run ``task`` = {key, kind, model, deck, keep}; return {key, status, error, seconds, records, scalars}."""
    t0 = time.perf_counter()
    out = {"key": task["key"], "status": "ok", "error": "", "records": {}, "scalars": {}}
    try:
        with tempfile.TemporaryDirectory(prefix=f"sf-{task['key'][:8]}-") as tmp:
            result = run_deck(task["kind"], task["deck"], Path(tmp), task.get("model"))
            kept = select(result, task["keep"])
        out["records"], out["scalars"] = kept.records, kept.summary
    except Exception as exc:  # a failed run is data, not the end of the sweep
        tb = traceback.extract_tb(exc.__traceback__)
        plain = isinstance(exc, ShockfrictionError) or not tb  # our errors already say where
        where = "" if plain else f" (at {Path(tb[-1].filename).name}:{tb[-1].lineno})"
        out.update(status="failed", error=f"{type(exc).__name__}: {exc}{where}")
    out["seconds"] = time.perf_counter() - t0
    return out
