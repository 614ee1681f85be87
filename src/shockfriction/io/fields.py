"""Fields at output times: one HDF5 file (``fields.h5``) and an XDMF3 index
(``fields.xmf``) that ParaView and ``meshio.xdmf.TimeSeriesReader`` open as a time series
of quad meshes.

Layout of ``fields.h5``: ``/connectivity`` (cells x 4), ``/body`` (cell body
index), and per output ``/step_NNNNN/`` with node arrays ``x, y, vx, vy``, ``xy``
(nodes x 2, the XDMF geometry) and cell arrays ``rho, p, q, e, T, eps_p, sxx, syy,
sxy, szz, Y, damage`` (SI; damage >= 1: failed by spall), attribute ``time``.
The HDF5 file is flushed after every output and closed on failure; ``fields.xmf`` is
rewritten whole (atomically) by :meth:`FieldWriter.write_index`, which the run's outputs call
at their next flush, just after ``summary.json`` (so that a killed run's index never lists an
output past the summary's time; a kill between the two writes leaves it one flush behind, the
outputs it does not list still complete in ``fields.h5``), and at the close.

``fields.xmf``: a temporal collection of uniform grids, each with its own Geometry
``XY`` (the Lagrangian mesh moves), Topology ``Quadrilateral``, node attributes
(``vx, vy`` and the current ``x, y``) and cell attributes; meshio reads the geometry of
the first output (its points) and every output's attributes (``x, y`` give the motion).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from shockfriction.io.atomic import atomic_write_text as write_text_atomic

CELL_FIELDS = {"rho": "rho", "p": "pressure", "q": "q", "e": "e", "T": "temperature", "eps_p": "eps_p",
               "sxx": "sxx", "syy": "syy", "sxy": "sxy", "Y": "yield_stress",
               "damage": "damage"}


class FieldWriter:
    """Writes the state when the time passes the next output time."""

    def __init__(self, out_dir: Path, times: list[float], conn: np.ndarray, body: np.ndarray, body_names,
                 keep: tuple[int, int] | None = None):
        self.out_dir = Path(out_dir)
        self.times = sorted(times)
        self._next = 0
        self._written: list[tuple[int, float]] = []
        self._n_nodes = None
        self._n_indexed = 0  # outputs listed in fields.xmf
        if keep is not None:  # restart: (outputs kept, next output time index) from the checkpoint
            self._resume(*keep)
            return
        self._h5 = h5py.File(self.out_dir / "fields.h5", "w")
        self._h5.create_dataset("connectivity", data=conn.astype(np.int64))
        self._h5.create_dataset("body", data=body.astype(np.int64))
        self._h5.attrs["bodies"] = ",".join(body_names)

    def _resume(self, n_kept: int, next_index: int) -> None:
        """Reopen ``fields.h5``, keep its first ``n_kept`` outputs, drop later ones (restart)."""
        self._h5 = h5py.File(self.out_dir / "fields.h5", "a")
        for name in [n for n in self._h5 if n.startswith("step_") and int(n[5:]) >= n_kept]:
            del self._h5[name]
        for k in range(n_kept):
            g = self._h5[f"step_{k:05d}"]
            self._written.append((k, float(g.attrs["time"])))
            self._n_nodes = g["x"].shape[0]
        self._next = next_index
        self._h5.flush()
        if self._written:
            self._write_xdmf(self._h5["connectivity"].shape[0])

    @property
    def position(self) -> tuple[int, int]:
        """(outputs written, next output time index): what a checkpoint keeps for a restart."""
        return len(self._written), self._next

    @classmethod
    def from_output(cls, out_dir: Path, sim, keep: tuple[int, int] | None = None) -> "FieldWriter | None":
        out = sim.problem.deck.output
        times = list(out.field_times)
        if out.field_interval is not None:
            times += list(np.arange(0.0, sim.t_end * (1 + 1e-9), out.field_interval))
        if not times:
            return None
        return cls(out_dir, times, sim.state.conn, sim.mesh.cell_body, sim.mesh.names, keep)

    def maybe_write(self, sim) -> None:
        s = sim.state
        if self._next >= len(self.times) or s.t < self.times[self._next] * (1 - 1e-12):
            return
        while self._next < len(self.times) and self.times[self._next] <= s.t * (1 + 1e-12):
            self._next += 1
        self.write(sim)

    def write(self, sim) -> None:
        s = sim.state
        k = len(self._written)
        g = self._h5.create_group(f"step_{k:05d}")
        g.attrs["time"] = s.t
        g.attrs["cycle"] = s.cycle
        g.create_dataset("x", data=s.x)
        g.create_dataset("y", data=s.y)
        g.create_dataset("xy", data=np.column_stack([s.x, s.y]))
        g.create_dataset("vx", data=0.5 * (sim._vx_old + s.vx))
        g.create_dataset("vy", data=0.5 * (sim._vy_old + s.vy))
        for name, attr in CELL_FIELDS.items():
            g.create_dataset(name, data=getattr(s, attr))
        g.create_dataset("szz", data=s.szz)
        self._h5.flush()
        self._written.append((k, s.t))
        self._n_nodes = s.n_nodes

    def write_index(self) -> None:
        """Rewrite ``fields.xmf`` if outputs were written since the last call."""
        if self._n_indexed != len(self._written):
            self._write_xdmf(self._h5["connectivity"].shape[0])

    def _write_xdmf(self, n_cells: int) -> None:
        write_text_atomic(self.out_dir / "fields.xmf", xdmf_text("fields.h5", self._written, self._n_nodes, n_cells))
        self._n_indexed = len(self._written)

    def close(self, sim=None) -> None:
        """Write the final state if an output time was reached at the end, then close the file."""
        if sim is not None and self._h5.id.valid and self._next < len(self.times) \
                and sim.state.t >= self.times[self._next] * (1 - 1e-9):
            self._next = len(self.times)
            self.write(sim)
        self.write_index()
        if self._h5.id.valid:
            self._h5.close()


def _item(h5: str, path: str, dims: str, kind: str = "Float") -> str:
    return (f'<DataItem Dimensions="{dims}" NumberType="{kind}" Precision="8" Format="HDF">'
            f"{h5}:{path}</DataItem>")


def xdmf_text(h5: str, written: list[tuple[int, float]], n_nodes: int, n_cells: int) -> str:
    """The whole XDMF3 document of the outputs ``written`` ((step, time) pairs) in ``h5``."""
    lines = ['<?xml version="1.0" ?>', '<Xdmf Version="3.0">', "<Domain>",
             '<Grid Name="fields" GridType="Collection" CollectionType="Temporal">']
    for k, t in written:
        step = f"step_{k:05d}"
        lines += [f'<Grid Name="{step}" GridType="Uniform">', f'<Time Value="{t:.12e}"/>',
                  f'<Topology TopologyType="Quadrilateral" NumberOfElements="{n_cells}">',
                  _item(h5, "/connectivity", f"{n_cells} 4", "Int"), "</Topology>",
                  '<Geometry GeometryType="XY">', _item(h5, f"/{step}/xy", f"{n_nodes} 2"), "</Geometry>"]
        for name in ("vx", "vy", "x", "y"):
            lines += [f'<Attribute Name="{name}" AttributeType="Scalar" Center="Node">',
                      _item(h5, f"/{step}/{name}", f"{n_nodes}"), "</Attribute>"]
        for name in list(CELL_FIELDS) + ["szz"]:
            lines += [f'<Attribute Name="{name}" AttributeType="Scalar" Center="Cell">',
                      _item(h5, f"/{step}/{name}", f"{n_cells}"), "</Attribute>"]
        lines += ['<Attribute Name="body" AttributeType="Scalar" Center="Cell">',
                  _item(h5, "/body", f"{n_cells}", "Int"), "</Attribute>", "</Grid>"]
    lines += ["</Grid>", "</Domain>", "</Xdmf>"]
    return "\n".join(lines) + "\n"
