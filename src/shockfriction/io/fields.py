"""Fields at output times: one HDF5 file (``fields.h5``) and an XDMF index
(``fields.xmf``) that ParaView opens as a time series of quad meshes.

Layout of ``fields.h5``: ``/connectivity`` (cells x 4), ``/body`` (cell body
index), and per output ``/step_NNNNN/`` with node arrays ``x, y, vx, vy`` and cell
arrays ``rho, p, q, e, T, eps_p, sxx, syy, sxy, szz, Y, damage`` (SI; damage >= 1: failed by spall), attribute ``time``.
The HDF5 file is flushed after every output and closed on failure.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

CELL_FIELDS = {"rho": "rho", "p": "pressure", "q": "q", "e": "e", "T": "temperature", "eps_p": "eps_p",
               "sxx": "sxx", "syy": "syy", "sxy": "sxy", "Y": "yield_stress",
               "damage": "damage"}


class FieldWriter:
    """Writes the state when the time passes the next output time."""

    def __init__(self, out_dir: Path, times: list[float], conn: np.ndarray, body: np.ndarray, body_names):
        self.out_dir = Path(out_dir)
        self.times = sorted(times)
        self._next = 0
        self._h5 = h5py.File(self.out_dir / "fields.h5", "w")
        self._h5.create_dataset("connectivity", data=conn.astype(np.int64))
        self._h5.create_dataset("body", data=body.astype(np.int64))
        self._h5.attrs["bodies"] = ",".join(body_names)
        self._written: list[tuple[int, float]] = []
        self._n_nodes = None

    @classmethod
    def from_output(cls, out_dir: Path, sim) -> "FieldWriter | None":
        out = sim.problem.deck.output
        times = list(out.field_times)
        if out.field_interval is not None:
            times += list(np.arange(0.0, sim.t_end * (1 + 1e-9), out.field_interval))
        if not times:
            return None
        return cls(out_dir, times, sim.state.conn, sim.mesh.cell_body, sim.mesh.names)

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
        g.create_dataset("vx", data=0.5 * (sim._vx_old + s.vx))
        g.create_dataset("vy", data=0.5 * (sim._vy_old + s.vy))
        for name, attr in CELL_FIELDS.items():
            g.create_dataset(name, data=getattr(s, attr))
        g.create_dataset("szz", data=s.szz)
        self._h5.flush()
        self._written.append((k, s.t))
        self._n_nodes = s.n_nodes
        self._write_xdmf(s.n_cells)

    def _write_xdmf(self, n_cells: int) -> None:
        nn = self._n_nodes
        h5 = "fields.h5"
        lines = ['<?xml version="1.0" ?>', '<Xdmf Version="3.0">', "<Domain>",
                 '<Grid Name="series" GridType="Collection" CollectionType="Temporal">']
        for k, t in self._written:
            step = f"step_{k:05d}"
            lines += [f'<Grid Name="{step}" GridType="Uniform">', f'<Time Value="{t:.12e}"/>',
                      f'<Topology TopologyType="Quadrilateral" NumberOfElements="{n_cells}">',
                      f'<DataItem Dimensions="{n_cells} 4" NumberType="Int" Precision="8" Format="HDF">'
                      f"{h5}:/connectivity</DataItem>", "</Topology>",
                      '<Geometry GeometryType="X_Y">']
            for c in ("x", "y"):
                lines.append(f'<DataItem Dimensions="{nn}" NumberType="Float" Precision="8" Format="HDF">'
                             f"{h5}:/{step}/{c}</DataItem>")
            lines.append("</Geometry>")
            for name in ("vx", "vy"):
                lines += [f'<Attribute Name="{name}" AttributeType="Scalar" Center="Node">',
                          f'<DataItem Dimensions="{nn}" NumberType="Float" Precision="8" Format="HDF">'
                          f"{h5}:/{step}/{name}</DataItem>", "</Attribute>"]
            for name in list(CELL_FIELDS) + ["szz"]:
                lines += [f'<Attribute Name="{name}" AttributeType="Scalar" Center="Cell">',
                          f'<DataItem Dimensions="{n_cells}" NumberType="Float" Precision="8" Format="HDF">'
                          f"{h5}:/{step}/{name}</DataItem>", "</Attribute>"]
            lines += [f'<Attribute Name="body" AttributeType="Scalar" Center="Cell">',
                      f'<DataItem Dimensions="{n_cells}" NumberType="Int" Precision="8" Format="HDF">'
                      f"{h5}:/body</DataItem>", "</Attribute>", "</Grid>"]
        lines += ["</Grid>", "</Domain>", "</Xdmf>"]
        (self.out_dir / "fields.xmf").write_text("\n".join(lines) + "\n")

    def close(self, sim=None) -> None:
        """Write the final state if an output time was reached at the end, then close the file."""
        if sim is not None and self._h5.id.valid and self._next < len(self.times) \
                and sim.state.t >= self.times[self._next] * (1 - 1e-9):
            self._next = len(self.times)
            self.write(sim)
        if self._h5.id.valid:
            self._h5.close()
