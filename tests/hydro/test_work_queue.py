"""The work queue of the parallel partition loops (jit_bits.fetch_add; docs/theory/threads.md, "A work queue for
the partitions"): every item is taken exactly once, and a thread held up by a costly item leaves the others to the
other threads.  Why it is needed: numba's prange gives each thread a fixed contiguous share of the iterations
(checked here too, so that the day numba hands them out dynamically the note in threads.md is revisited)."""

import numba
import numpy as np
import pytest
from numba import njit, prange

from shockfriction.jit_bits import fetch_add


@njit(cache=True, parallel=True)
def _take(cost, taken, owner, queue):
    """Items by the work queue, as forces_parallel and update_parallel take their partitions.  ``queue`` (zero)
    comes from the caller, who can read it after: read inside the function after the loop it shows 0, numba
    not knowing that the intrinsic writes it."""
    n = cost.shape[0]
    for _ in prange(n):
        while True:
            i = fetch_add(queue, 0)
            if i >= n:
                break
            s = 0.0
            for r in range(cost[i]):
                s += np.sqrt(r + s)
            taken[i] += 1
            owner[i] = numba.get_thread_id() + int(s < 0.0)


@njit(cache=True, parallel=True)
def _static(cost, owner):
    """The same items by prange alone."""
    for i in prange(cost.shape[0]):
        s = 0.0
        for r in range(cost[i]):
            s += np.sqrt(r + s)
        owner[i] = numba.get_thread_id() + int(s < 0.0)


def test_fetch_add_counts_and_returns_the_value_before():
    @njit
    def three(a):
        return fetch_add(a, 1), fetch_add(a, 1), fetch_add(a, 1)

    a = np.array([7, 40], dtype=np.int64)
    assert three(a) == (40, 41, 42)
    assert list(a) == [7, 43]


@pytest.mark.parametrize("threads", [1, 2, 3, 4])
def test_every_item_taken_once(threads):
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        n = 37
        taken = np.zeros(n, np.int64)
        owner = np.full(n, -1, np.int64)
        queue = np.zeros(1, np.int64)
        _take(np.full(n, 1000, np.int64), taken, owner, queue)
        assert (taken == 1).all()
        # n takes of an item, and one more per iteration of the prange, which ends on the empty queue
        assert queue[0] == 2 * n
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs two threads")
def test_a_costly_item_leaves_the_rest_to_the_other_thread():
    numba.set_num_threads(2)
    try:
        n = 16
        cost = np.full(n, 1000, np.int64)
        cost[0] = 20_000_000  # ~0.1-0.2 s: long against any thread's wake-up
        owner = np.full(n, -1, np.int64)
        _static(cost, owner)
        # prange alone: the first half of the items on the costly item's thread, whatever their cost
        assert (owner[: n // 2] == owner[0]).all(), (
            "numba's prange now shares its iterations otherwise: revisit docs/theory/threads.md's work queue")
        owner[:] = -1
        taken = np.zeros(n, np.int64)
        _take(cost, taken, owner, np.zeros(1, np.int64))
        mine = int((owner == owner[0]).sum())
        assert (taken == 1).all()
        assert mine < n // 2, f"the costly item's thread took {mine} of {n} items"
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
