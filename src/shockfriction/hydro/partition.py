"""The mesh split into partitions for threads (docs/theory/threads.md, "Partitions").

A partition is a contiguous range of cells, a whole number of ``SUM_CHUNK`` cells (the last one excepted), about
as many cells in each.  A node whose cells all lie in one partition is that partition's own ("interior"); a node
touched by cells of two or more partitions, or by none, is a border node.  In the force pass each thread adds its
cells' corner forces into its own nodes in cell order (as the serial pass does) and stores those on border nodes
per corner; the border nodes' forces are then summed from the stored corners in cell order, from 0.0, so that
every node's force is the same sum of the same terms in the same order whatever the number of partitions.

The same partitions are what a distributed-memory rank would own: its cells, its interior nodes, and the border
nodes it shares with its neighbours (the halo of the force exchange).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from shockfriction.hydro.kernels import SUM_CHUNK


@dataclass(frozen=True)
class Partition:
    """Cells ``cbounds[i] .. cbounds[i + 1] - 1`` are partition i's; ``pnodes[pnode_ptr[i]:pnode_ptr[i + 1]]`` its
    own nodes (ascending); ``border[n]`` 1 for a border node; ``bnodes`` the border nodes (ascending), the corners
    (4 c + k, ascending) of ``bnodes[j]`` in ``bcorn[bptr[j]:bptr[j + 1]]``."""

    cbounds: np.ndarray
    pnode_ptr: np.ndarray
    pnodes: np.ndarray
    border: np.ndarray
    bnodes: np.ndarray
    bptr: np.ndarray
    bcorn: np.ndarray

    @property
    def parts(self) -> int:
        return self.cbounds.shape[0] - 1

    def arrays(self) -> tuple:
        return (self.cbounds, self.pnode_ptr, self.pnodes, self.border)


#: partitions per thread (at most): the force pass and the cell update hand them out to the threads one at a time
#: (a work queue, jit_bits.fetch_add), so that a thread whose cells cost more (a plastic zone, a shock front) takes
#: fewer of them
PARTS_PER_THREAD = 4
#: cells per partition below which fewer partitions per thread are made (each cut adds border nodes; 512: four per
#: thread on the cone shot and the 200 x 200 block at 16 threads, docs/theory/threads.md "Partitions for the queue")
MIN_PART_CELLS = 512


def partition_count(threads: int, n_cells: int) -> int:
    """Partitions for ``threads`` threads on ``n_cells`` cells: a whole number k of partitions per thread (so that
    no thread is left with one more than the others), k = PARTS_PER_THREAD where each partition keeps
    MIN_PART_CELLS cells, fewer on a smaller mesh, at least 1."""
    threads = max(int(threads), 1)
    return threads * max(1, min(PARTS_PER_THREAD, n_cells // (MIN_PART_CELLS * threads)))


def cell_bounds(n_cells: int, parts: int, chunk: int = SUM_CHUNK) -> np.ndarray:
    """``parts`` + 1 increasing cell bounds, 0 and ``n_cells`` at the ends, the others multiples of ``chunk``,
    the ranges as equal as the chunks allow (an empty range where there are fewer chunks than parts)."""
    chunks = -(-n_cells // chunk)
    cuts = [min(n_cells, (i * chunks // parts) * chunk) for i in range(parts + 1)]
    cuts[-1] = n_cells
    return np.array(cuts, dtype=np.int64)


def make_partition(conn: np.ndarray, n_nodes: int, parts: int, cbounds: np.ndarray | None = None) -> Partition:
    """The partition of a mesh (``conn``, cells x 4 node numbers) into ``parts`` cell ranges (:func:`cell_bounds`,
    or the bounds ``cbounds`` given)."""
    nc = conn.shape[0]
    cb = cell_bounds(nc, parts) if cbounds is None else np.asarray(cbounds, dtype=np.int64)
    cell_part = np.repeat(np.arange(parts, dtype=np.int64), np.diff(cb))
    flat = conn.reshape(-1).astype(np.int64)
    corner_part = np.repeat(cell_part, conn.shape[1])
    lo = np.full(n_nodes, parts, dtype=np.int64)
    hi = np.full(n_nodes, -1, dtype=np.int64)
    np.minimum.at(lo, flat, corner_part)
    np.maximum.at(hi, flat, corner_part)
    own = lo == hi  # every cell of the node in one partition (a node of no cell: lo > hi, a border node)
    border = (~own).astype(np.uint8)
    owner = np.where(own, lo, parts)
    order = np.argsort(owner, kind="stable")
    counts = np.bincount(owner, minlength=parts + 1)
    pnode_ptr = np.concatenate([[0], np.cumsum(counts[:parts])]).astype(np.int64)
    pnodes = order[:pnode_ptr[-1]].astype(np.int64)
    bnodes = np.flatnonzero(border).astype(np.int64)
    # the corners of the border nodes, in cell order (4 c + k ascending)
    corners = np.flatnonzero(border[flat])
    cnodes = flat[corners]
    srt = np.argsort(cnodes, kind="stable")
    bcorn = corners[srt].astype(np.int64)
    counts_b = np.bincount(np.searchsorted(bnodes, cnodes), minlength=bnodes.shape[0])
    bptr = np.concatenate([[0], np.cumsum(counts_b)]).astype(np.int64)
    return Partition(cb, pnode_ptr, pnodes, border, bnodes, bptr, bcorn)
