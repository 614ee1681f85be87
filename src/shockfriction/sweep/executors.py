"""Where runs execute: a local process pool (default) or a Dask distributed cluster.

Both are used through the ``concurrent.futures`` interface (``submit`` and
``as_completed``), so the sweep and the fit do not care which one they have.

Local default: ``concurrent.futures.ProcessPoolExecutor`` with one worker per
usable core and the ``spawn`` start method.  It starts in well under a second,
opens no network port and needs no scheduler; ``spawn`` gives each worker a
fresh interpreter, as a Dask worker has, so a run sees exactly the same thing
locally and on a cluster (and no lock held by a thread of the parent, e.g. the
progress bar, is inherited by a forked child).  A ``dask.distributed.LocalCluster``
would bring a scheduler, nannies and a dashboard port for no gain on one machine.

``--scheduler ADDRESS``: a ``dask.distributed.Client`` connected to that
scheduler, used through ``Client.get_executor()``; ``--workers N`` then waits
until N workers have joined.  The workers must be able to import
``shockfriction`` (and, for ``kind = "python"``, the model's module).
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager
from typing import Iterator

from shockfriction.errors import DeckError


def _sigterm_interrupts():
    """Make SIGTERM raise KeyboardInterrupt in the main thread (so that the pool is torn down as on
    Ctrl-C); returns the previous handler, or None where no handler can be set (not the main thread)."""
    if threading.current_thread() is not threading.main_thread():
        return None

    def handler(signum, frame):
        raise KeyboardInterrupt(f"signal {signum}")

    return signal.signal(signal.SIGTERM, handler)


def terminate_workers(pool: ProcessPoolExecutor, grace_s: float = 5.0) -> None:
    """Terminate the pool's worker processes now (their runs are lost and stay pending)."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(grace_s)
        if p.is_alive():
            p.kill()


def usable_cores() -> int:
    """Cores this process may run on (affinity-aware)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


@contextmanager
def open_executor(scheduler: str | None = None, workers: int | None = None,
                  connect_timeout: float = 30.0) -> Iterator[Executor]:
    """A concurrent.futures executor: local spawn pool, or a Dask cluster at ``scheduler``."""
    if workers is not None and workers < 1:
        raise DeckError(f"--workers = {workers}: expected a positive number of workers")
    if scheduler is None:
        import shutil
        import tempfile

        from shockfriction.sweep.worker import init_worker

        # the workers' scratch folders live in one folder of the pool's, removed when the pool ends
        # (also the scratch of a worker that crashed); a killed parent leaves it to the workers
        root = tempfile.mkdtemp(prefix="sf-pool-")
        pool = ProcessPoolExecutor(max_workers=workers or usable_cores(),
                                   mp_context=multiprocessing.get_context("spawn"),
                                   initializer=init_worker, initargs=(os.getpid(), root))
        previous = _sigterm_interrupts()
        try:
            yield pool
        except BaseException:  # Ctrl-C, SIGTERM, an error: no worker may outlive the sweep
            terminate_workers(pool)
            raise
        finally:
            try:
                pool.shutdown(wait=True, cancel_futures=True)
            finally:
                shutil.rmtree(root, ignore_errors=True)
                if previous is not None:
                    signal.signal(signal.SIGTERM, previous)
        return
    from dask.distributed import Client

    try:
        client = Client(scheduler, timeout=connect_timeout)
    except (OSError, TimeoutError, ValueError) as exc:
        raise DeckError(f"--scheduler = {scheduler!r}: expected the address of a running Dask scheduler "
                        f"such as 'tcp://host:8786' ({type(exc).__name__}: {exc})") from None
    try:
        if workers:
            client.wait_for_workers(workers, timeout=connect_timeout)
        yield client.get_executor()
    finally:
        client.close()
