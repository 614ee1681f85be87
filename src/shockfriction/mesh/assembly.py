"""Several blocks (one per body) numbered into one global mesh.

A block is a structured :class:`~shockfriction.mesh.block.Block` or a body read from a gmsh
file (:class:`~shockfriction.mesh.gmsh.FileBlock`: sides named by physical curves, no (i, j)).

Body b owns the contiguous node range ``node_start[b] : node_start[b+1]`` and
cell range ``cell_start[b] : cell_start[b+1]``; the block's local numbering
(:mod:`shockfriction.mesh.block`) is kept inside each range.  Nodes are never
merged: ties and periodic sides are node *groups* that the cycle treats as one
node (shared mass, force and velocity), see :mod:`shockfriction.hydro.state`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from shockfriction.mesh.block import SIDES, Block


@dataclass
class Mesh:
    """Global node coordinates, connectivity and the body each item belongs to."""

    names: list[str]
    blocks: list[Block]
    x: np.ndarray = field(init=False)
    y: np.ndarray = field(init=False)
    conn: np.ndarray = field(init=False)
    node_start: np.ndarray = field(init=False)
    cell_start: np.ndarray = field(init=False)
    cell_body: np.ndarray = field(init=False)
    node_body: np.ndarray = field(init=False)

    def __post_init__(self):
        nn = [b.n_nodes for b in self.blocks]
        nc = [b.n_cells for b in self.blocks]
        self.node_start = np.concatenate([[0], np.cumsum(nn)]).astype(np.int64)
        self.cell_start = np.concatenate([[0], np.cumsum(nc)]).astype(np.int64)
        self.x = np.concatenate([b.x.ravel() for b in self.blocks])
        self.y = np.concatenate([b.y.ravel() for b in self.blocks])
        self.conn = np.concatenate(
            [b.connectivity() + self.node_start[k] for k, b in enumerate(self.blocks)]).astype(np.int64)
        self.cell_body = np.repeat(np.arange(len(self.blocks)), nc).astype(np.int64)
        self.node_body = np.repeat(np.arange(len(self.blocks)), nn).astype(np.int64)

    @property
    def n_nodes(self) -> int:
        return int(self.node_start[-1])

    @property
    def n_cells(self) -> int:
        return int(self.cell_start[-1])

    def body_index(self, body: str | int) -> int:
        if isinstance(body, (int, np.integer)):
            return int(body)
        try:
            return self.names.index(body)
        except ValueError:
            raise KeyError(f"no body named {body!r}; bodies are {', '.join(self.names)}") from None

    def side_nodes(self, body: str | int, side: str) -> np.ndarray:
        """Global node indices of a body side, counter-clockwise around the body
        (``bottom``: j=0, ``right``: i=nx, ``top``: j=ny, ``left``: i=0)."""
        b = self.body_index(body)
        return self.blocks[b].side_nodes(side) + self.node_start[b]

    def side_cells(self, body: str | int, side: str) -> np.ndarray:
        """Global indices of the cells along a body side; cell k lies on segment
        (side_nodes[k], side_nodes[k+1])."""
        b = self.body_index(body)
        return self.blocks[b].side_cells(side) + self.cell_start[b]

    def node_index(self, body: str | int, i: int, j: int) -> int:
        """Global index of node (i, j) of a block body (negative i, j count from the end)."""
        b = self.body_index(body)
        blk = self.blocks[b]
        if blk.nx is None:
            raise KeyError(f"body {self.names[b]!r} is meshed from a file: its nodes have no (i, j)")
        i = i % (blk.nx + 1)
        j = j % (blk.ny + 1)
        return int(self.node_start[b] + j * (blk.nx + 1) + i)

    def cell_index(self, body: str | int, i: int, j: int) -> int:
        """Global index of cell (i, j) of a block body (negative i, j count from the end)."""
        b = self.body_index(body)
        blk = self.blocks[b]
        if blk.nx is None:
            raise KeyError(f"body {self.names[b]!r} is meshed from a file: its cells have no (i, j)")
        i = i % blk.nx
        j = j % blk.ny
        return int(self.cell_start[b] + j * blk.nx + i)

    def cell_ij(self, cell: int) -> tuple[str, int, int]:
        """(body name, i, j) of a global cell index; (body name, local index, -1) in a body
        meshed from a file (its cells have no (i, j))."""
        b = int(self.cell_body[cell])
        local = int(cell - self.cell_start[b])
        nx = self.blocks[b].nx
        if nx is None:
            return self.names[b], local, -1
        return self.names[b], local % nx, local // nx

    def node_ij(self, node: int) -> tuple[str, int, int]:
        """(body name, i, j) of a global node index."""
        b = int(self.node_body[node])
        local = int(node - self.node_start[b])
        nx = self.blocks[b].nx
        if nx is None:
            return self.names[b], local, -1
        return self.names[b], local % (nx + 1), local // (nx + 1)


__all__ = ["Mesh", "SIDES"]
