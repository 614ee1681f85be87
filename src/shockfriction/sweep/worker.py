"""The task a worker executes: run one deck in its own scratch folder, keep what is asked.

``execute`` is a plain top-level function of plain data, so that it pickles to a
local process pool and to Dask workers alike.  Any exception of the run becomes
a ``failed`` result carrying the error text: one bad run never stops a sweep.
The scratch folder is a fresh temporary directory on the worker's machine (a
remote worker need not see the sweep's output folder); it is removed afterwards,
also when the worker is stopped by SIGTERM (the pool's teardown).

A local pool's workers start with :func:`init_worker`: they die with the sweep that
started them, even when it is killed with SIGKILL and cannot tear its pool down
(Linux: ``prctl(PR_SET_PDEATHSIG)``; everywhere: a thread that polls the parent's
process id), removing their scratch folder first.
"""

from __future__ import annotations

import os
import shutil
import signal
import tempfile
import threading
import time
import traceback
from pathlib import Path

from shockfriction.errors import ShockfrictionError
from shockfriction.sweep.keep import select
from shockfriction.sweep.runners import run_deck


_SCRATCH: dict[str, str | None] = {"path": None, "root": None}
#: seconds between two looks at the parent process
PARENT_POLL_S = 0.5


def _leave(signum: int = signal.SIGTERM, frame=None) -> None:
    """Remove the scratch folder of the current run and end the worker at once."""
    path = _SCRATCH["path"]
    if path:
        shutil.rmtree(path, ignore_errors=True)
    if _SCRATCH["root"]:  # the pool's folder: the last worker out removes it (the parent may be dead)
        try:
            os.rmdir(_SCRATCH["root"])
        except OSError:
            pass
    os._exit(128 + int(signum))


def init_worker(parent_pid: int, root: str | None = None) -> None:
    """Initializer of a local pool worker: SIGTERM removes the scratch folder and ends the worker; the
    worker ends when ``parent_pid`` (the sweep) dies, whatever killed it.  ``root``: the pool's folder,
    where the worker's temporary files and scratch folders go (the pool removes it when it ends)."""
    if root:
        _SCRATCH["root"] = root
        tempfile.tempdir = root
    signal.signal(signal.SIGTERM, _leave)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the sweep, which tears the pool down
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGTERM), 0, 0, 0)  # PR_SET_PDEATHSIG: SIGTERM when the parent dies
    except (OSError, AttributeError):  # not Linux: the watchdog below is enough
        pass
    if os.getppid() != parent_pid:  # the parent died before the signal was armed
        _leave()

    def watch() -> None:
        while True:
            time.sleep(PARENT_POLL_S)
            if os.getppid() != parent_pid:
                _leave()

    threading.Thread(target=watch, name="sf-parent-watchdog", daemon=True).start()


def execute(task: dict) -> dict:
    """Run ``task`` = {key, kind, model, deck, keep}; return {key, status, error, seconds, records, scalars}."""
    t0 = time.perf_counter()
    out = {"key": task["key"], "status": "ok", "error": "", "records": {}, "scalars": {}}
    try:
        with tempfile.TemporaryDirectory(prefix=f"sf-{task['key'][:8]}-") as tmp:
            _SCRATCH["path"] = tmp
            try:
                result = run_deck(task["kind"], task["deck"], Path(tmp), task.get("model"))
                kept = select(result, task["keep"])
            finally:
                _SCRATCH["path"] = None
        out["records"], out["scalars"] = kept.records, kept.summary
    except Exception as exc:  # a failed run is data, not the end of the sweep
        tb = traceback.extract_tb(exc.__traceback__)
        plain = isinstance(exc, ShockfrictionError) or not tb  # our errors already say where
        where = "" if plain else f" (at {Path(tb[-1].filename).name}:{tb[-1].lineno})"
        out.update(status="failed", error=f"{type(exc).__name__}: {exc}{where}")
    out["seconds"] = time.perf_counter() - t0
    return out
