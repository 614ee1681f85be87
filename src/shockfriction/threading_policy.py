"""How the hydrocode's parallel kernels use threads (docs/theory/threads.md).

The deck's ``threads`` (or ``run --threads``) asks for a count: 1 = serial kernels, n > 1 = the
parallel (prange) kernels on n threads, 0 = automatic.  This module decides how a request is used:

* **Waiting.** numba's OpenMP layer (GNU libgomp here) lets an idle worker spin for a while
  before it sleeps (300 000 rounds by default, a few milliseconds).  When another process holds a
  core, the spinning workers steal the time the working ones need, and two threads ran at
  0.03-0.8 times the speed of one; with no spin at all (passive waiting) every parallel region
  pays for waking a sleeping worker (about 0.1 ms on the 2-core development machine, a virtual
  machine), which cost 7-15 % of a two-thread cycle.  A short spin, ``GOMP_SPINCOUNT`` =
  :data:`SPIN_ROUNDS` (about 0.1 ms: it bridges the gaps between the regions of a cycle, not a
  busy core's time slices), is set in the environment when this module is imported, before numba
  starts its threading layer (at the first parallel kernel call), unless the user set
  ``GOMP_SPINCOUNT`` or ``OMP_WAIT_POLICY``; Intel's OpenMP gets ``KMP_BLOCKTIME=0`` (passive:
  its granularity is a millisecond, not measured here) unless set.
* **Count.** n is capped by numba's ``NUMBA_NUM_THREADS``; 0 takes the cores this process may
  run on (its CPU affinity), capped alike.
* **Load.** A busy core still slows a parallel region to its slowest thread.  With n > 1
  threads a :class:`ThreadGovernor` (run between cycles) times a few cycles on n threads and
  a few on the serial kernels every ``period`` (100) cycles, and keeps the faster until the
  next probe: when other jobs take the cores, the run falls back to one thread instead of
  collapsing, and takes the threads back when they free up.
* **Size.** With ``threads = 0`` a mesh below :data:`MIN_PARALLEL_CELLS` cells runs the serial
  kernels: the fixed cost of the parallel regions (three per cycle) exceeds what a second thread
  saves there (with the short spin, idle 2-core machine: 2 threads at 0.92-0.95 of 1 at 400 cells,
  x1.20-1.48 at 1600; with passive waiting 0.26 and 0.76).
  An explicit count n > 1 is obeyed whatever the size (the parallel kernels' tests run on
  small meshes).

The parallel kernels give the same sums whatever the thread count, so the policy changes only
the speed, never the results.
"""

from __future__ import annotations

import math
import os
import statistics
import time

#: below this many cells ``threads = 0`` runs the serial kernels (measured: benchmarks/threads.py --sizes)
MIN_PARALLEL_CELLS = 1600

#: libgomp's spin before an idle worker sleeps (rounds; libgomp counts about 1e5 per millisecond): measured with
#: benchmarks/threads.py --policies (docs/theory/threads.md, "A short spin")
SPIN_ROUNDS = 10000


def threading_layer_started() -> bool:
    """True once numba has started its threading layer (the environment is read then, not later)."""
    try:
        from numba.np.ufunc import parallel
    except ImportError:  # pragma: no cover - numba without parallel support
        return False
    return bool(getattr(parallel, "_is_initialized", False))


def set_short_spin() -> bool:
    """Put ``GOMP_SPINCOUNT`` = :data:`SPIN_ROUNDS` and ``KMP_BLOCKTIME=0`` in the environment where
    the user left them unset (no ``GOMP_SPINCOUNT`` where the user chose ``OMP_WAIT_POLICY``).
    Returns False when numba's threading layer has already started, so that the setting comes too
    late for this process."""
    if "OMP_WAIT_POLICY" not in os.environ:
        os.environ.setdefault("GOMP_SPINCOUNT", str(SPIN_ROUNDS))
    os.environ.setdefault("KMP_BLOCKTIME", "0")
    return not threading_layer_started()


def available_cores() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # not Linux
        return os.cpu_count() or 1


def effective_threads(requested: int, n_cells: int) -> int:
    """Threads the cycle uses for a request (deck ``threads`` / ``--threads``) on ``n_cells`` cells.

    0: all available cores (capped by numba's ``NUMBA_NUM_THREADS``), or 1 below
    :data:`MIN_PARALLEL_CELLS` cells; n >= 1: n, capped by ``NUMBA_NUM_THREADS``.  1 means the
    serial kernels."""
    import numba

    cap = int(numba.config.NUMBA_NUM_THREADS)
    if requested == 0:
        if n_cells < MIN_PARALLEL_CELLS:
            return 1
        return max(1, min(available_cores(), cap))
    return max(1, min(int(requested), cap))


def use_threads(threads: int) -> None:
    """Make the parallel kernels run on ``threads`` threads (the short spin first)."""
    import numba

    set_short_spin()
    numba.set_num_threads(threads)


class ThreadGovernor:
    """Keep whichever runs faster now: the parallel kernels on ``threads`` threads, or the serial
    kernels (one thread; ``Simulation.use_parallel``, when called with the simulation).

    Called between cycles (``Simulation.between_cycles``).  The first ``2 probe`` cycles of every
    ``period`` alternate between ``threads`` threads and 1 (so that a change of the machine's load
    hits both alike); the count with the smaller median wall time per cycle is kept until the
    next probe.  The parallel kernels give the same sums on any number of threads, and the same
    bytes as the serial ones, so only the speed changes.  ``chosen`` counts the periods won by
    each count."""

    def __init__(self, threads: int, period: int = 100, probe: int = 3):
        self.threads = int(threads)
        self.probe = max(int(probe), 1)
        self.period = max(int(period), 2 * self.probe + 1)
        self.current = self.threads
        self.chosen = {self.threads: 0, 1: 0}
        self._calls = 0
        self._last = None
        self._samples: dict[int, list] = {}

    def _set(self, threads: int, sim) -> None:
        import numba

        if threads != self.current:
            if sim is None:  # no simulation to switch: the parallel kernels on this many threads
                numba.set_num_threads(threads)
            else:  # one thread: the serial kernels (faster than the parallel ones on one), and one numba thread
                numba.set_num_threads(threads)  # for the kernels that choose by it (the sub-grid column solves)
                sim.use_parallel(threads > 1)
            self.current = threads

    def __call__(self, sim=None) -> None:
        now = time.perf_counter()
        pos = self._calls % self.period
        self._calls += 1
        if self._last is not None and 0 < pos <= 2 * self.probe:   # the cycle just done ran on self.current
            self._samples.setdefault(self.current, []).append(now - self._last)
        if pos == 0:
            self._samples = {}
        if pos < 2 * self.probe:
            self._set(self.threads if pos % 2 == 0 else 1, sim)
        elif pos == 2 * self.probe:
            many = statistics.median(self._samples.get(self.threads, [math.inf]))
            one = statistics.median(self._samples.get(1, [math.inf]))
            best = self.threads if many < one else 1
            self.chosen[best] += 1
            self._set(best, sim)
        self._last = time.perf_counter()


set_short_spin()
