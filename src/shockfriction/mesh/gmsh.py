"""Bodies from gmsh meshes: a ``.msh`` file (read with meshio) or a ``.geo`` file (meshed through
the gmsh Python API), turned into blocks that :class:`~shockfriction.mesh.assembly.Mesh` numbers
like the structured ones.

Rules (``docs/theory/meshes-and-outputs.md``):

* a **physical surface** names a body: its quadrilaterals become the body's cells; a body owns its
  nodes (bodies are never merged: two bodies sharing a gmsh curve get coincident copies of its
  nodes, which a tie or a slide line joins);
* a **physical curve** names a side: its line elements that lie on the body's boundary, chained
  into one path that runs counter-clockwise around the body (outward normal on the right,
  as :meth:`~shockfriction.mesh.block.Block.side_nodes`); a side may span several gmsh curves,
  may be shared by several bodies (each gets its own copy) and may be closed (first node repeated);
* a **physical point** names a location (probes);
* cells are ordered counter-clockwise (reversed when gmsh gives them clockwise); triangles and
  higher-order elements are refused with the element numbers (recombine: ``Recombine Surface``
  or ``Mesh.RecombineAll = 1``).

Coordinates are multiplied by ``scale`` (metres per mesh-file unit); z is ignored (the mesh
must lie in a plane z = const).
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


class MeshFileError(ValueError):
    """A mesh file that cannot be used (the deck layer turns it into an exit-2 DeckError)."""


@dataclass
class MeshData:
    """A mesh file as read: points (n, 2) in metres, and per physical group its elements."""

    path: Path
    points: np.ndarray
    quads: dict[str, np.ndarray] = field(default_factory=dict)      # surface group -> (n, 4) point ids
    others: dict[str, list[tuple[str, np.ndarray]]] = field(default_factory=dict)  # surface group -> non-quads
    lines: dict[str, np.ndarray] = field(default_factory=dict)      # curve group -> (n, 2) point ids
    vertices: dict[str, np.ndarray] = field(default_factory=dict)   # point group -> (n,) point ids


def _mesh_geo(path: Path, parameters: dict[str, float]) -> Path:
    """Mesh a .geo file with the gmsh API (``parameters`` set as parser numbers first: the
    file should define defaults with ``If (!Exists(name)) name = value; EndIf``); returns a .msh."""
    import gmsh

    folder = Path(tempfile.mkdtemp(prefix="shockfriction-gmsh-"))
    out = folder / (path.stem + ".msh")
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        for name, value in parameters.items():
            gmsh.parser.setNumber(name, [float(value)])
        gmsh.merge(str(path))
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(str(out))
    except Exception as exc:  # noqa: BLE001 -- gmsh raises a bare Exception carrying its last error
        out.unlink(missing_ok=True)
        folder.rmdir()
        raise MeshFileError(f"{path}: gmsh could not mesh it: {exc}") from None
    finally:
        gmsh.finalize()
    return out


def read_mesh_file(path: str | Path, scale: float = 1.0, parameters: dict[str, float] | None = None) -> MeshData:
    """Read a .msh (meshio) or mesh a .geo (gmsh API) into :class:`MeshData`."""
    import meshio

    path = Path(path)
    if not path.is_file():
        raise MeshFileError(f"{path}: no such file")
    msh = _mesh_geo(path, parameters or {}) if path.suffix == ".geo" else path
    try:
        m = meshio.read(msh, file_format="gmsh")
    except Exception as exc:  # noqa: BLE001 -- meshio raises ReadError, KeyError, ValueError, ... on bad files
        raise MeshFileError(f"{path}: not a readable gmsh mesh: {exc}") from None
    finally:
        if msh is not path:
            msh.unlink(missing_ok=True)
            msh.parent.rmdir()
    pts = np.asarray(m.points, dtype=float)
    if pts.shape[1] > 2 and np.ptp(pts[:, 2]) > 1e-9 * max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1]), 1e-300):
        raise MeshFileError(f"{path}: the mesh is not planar (z varies); shockfriction meshes lie in the x-y plane")
    data = MeshData(path, pts[:, :2] * scale)
    dims = {name: int(tag_dim[1]) for name, tag_dim in m.field_data.items() if len(tag_dim) == 2}
    for name, per_block in m.cell_sets.items():
        if name.startswith("gmsh:") or name not in dims:
            continue
        chosen: dict[str, list[np.ndarray]] = {}
        for block, idx in zip(m.cells, per_block):
            if idx is None or len(idx) == 0:
                continue
            chosen.setdefault(block.type, []).append(np.asarray(block.data)[np.asarray(idx)])
        dim = dims[name]
        if dim == 2:
            data.quads[name] = np.concatenate(chosen.pop("quad", [np.zeros((0, 4), np.int64)])).astype(np.int64)
            data.others[name] = [(t, np.concatenate(v)) for t, v in chosen.items()]
        elif dim == 1:
            extra = [t for t in chosen if t != "line"]
            if extra:
                raise MeshFileError(f"{path}: physical curve {name!r} has {', '.join(extra)} elements; "
                                    "only first-order lines (Mesh.ElementOrder = 1) are read")
            data.lines[name] = np.concatenate(chosen.get("line", [np.zeros((0, 2), np.int64)])).astype(np.int64)
        elif dim == 0:
            data.vertices[name] = np.concatenate(chosen.get("vertex", [np.zeros((0, 1), np.int64)])).ravel()
    return data


class FileBlock:
    """One body of a mesh file, with the interface of :class:`~shockfriction.mesh.block.Block`
    that the assembly uses (``x, y, n_nodes, n_cells, connectivity, side_nodes, side_cells``);
    sides and points are named by the file's physical groups.  ``nx = ny = None``: cells and
    nodes have no (i, j) indices."""

    nx = None
    ny = None

    def __init__(self, data: MeshData, group: str):
        self.source = f"{data.path}"
        self.group = group
        if group not in data.quads:
            known = sorted(data.quads)
            raise MeshFileError(f"{data.path}: no physical surface named {group!r}"
                                f" (physical surfaces: {', '.join(known) if known else 'none'})")
        others = data.others.get(group, [])
        if others:
            kinds = ", ".join(f"{len(v)} {t}" for t, v in others)
            centres = data.points[others[0][1][:3]].mean(axis=1)
            where = ", ".join(f"({x:.6g}, {y:.6g})" for x, y in centres)
            raise MeshFileError(
                f"{data.path}: physical surface {group!r} has {kinds} elements (the first centred at {where} m); "
                "only 4-node quadrilaterals are used: recombine the mesh "
                "(Recombine Surface{...}; or Mesh.RecombineAll = 1; first order)")
        quads = data.quads[group]
        if len(quads) == 0:
            raise MeshFileError(f"{data.path}: physical surface {group!r} has no quadrilaterals")
        ids = np.unique(quads)
        self._ids = ids  # file point index of each local node
        local = np.searchsorted(ids, quads)
        self.x = data.points[ids, 0].copy()
        self.y = data.points[ids, 1].copy()
        xa, ya = self.x[local], self.y[local]
        area2 = ((xa[:, 0] - xa[:, 2]) * (ya[:, 1] - ya[:, 3]) - (xa[:, 1] - xa[:, 3]) * (ya[:, 0] - ya[:, 2]))
        local[area2 < 0.0] = local[area2 < 0.0][:, ::-1]
        self._conn = local
        self._lines = data.lines
        self._vertices = data.vertices
        self._points = data.points
        self._sides: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        # directed edges of the counter-clockwise cells -> cell (a boundary edge appears once)
        a = local.ravel()
        b = np.roll(local, -1, axis=1).ravel()
        self._edge = {(int(p), int(q)): int(c) for p, q, c in zip(a, b, np.repeat(np.arange(len(local)), 4))}

    @property
    def n_nodes(self) -> int:
        return self.x.size

    @property
    def n_cells(self) -> int:
        return len(self._conn)

    def connectivity(self) -> np.ndarray:
        return self._conn

    @property
    def side_names(self) -> list[str]:
        """Physical curves with at least one element on this body's boundary."""
        return [n for n in self._lines if self._side_segments(n, strict=False)]

    def _side_segments(self, name: str, strict: bool = True) -> list[tuple[int, int, int]]:
        lines = self._lines[name]
        pos = np.searchsorted(self._ids, lines)
        pos = np.minimum(pos, self._ids.size - 1)
        inside = np.all(self._ids[pos] == lines, axis=1)
        segs = []
        for p, q in pos[inside]:
            p, q = int(p), int(q)
            fwd, bwd = (p, q) in self._edge, (q, p) in self._edge
            if fwd and bwd:
                if strict:
                    raise MeshFileError(f"{self.source}: physical curve {name!r} runs through the inside of body "
                                        f"{self.group!r}; a side must lie on the body's boundary")
                continue
            if fwd:
                segs.append((p, q, self._edge[(p, q)]))
            elif bwd:
                segs.append((q, p, self._edge[(q, p)]))
        return segs

    def _side(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        if name in self._sides:
            return self._sides[name]
        if name not in self._lines:
            raise KeyError(f"{self.source}: no physical curve named {name!r} (sides of body {self.group!r}: "
                           f"{', '.join(self.side_names) or 'none'})")
        segs = self._side_segments(name)
        if not segs:
            raise KeyError(f"{self.source}: physical curve {name!r} does not touch body {self.group!r} "
                           f"(its sides: {', '.join(self.side_names) or 'none'})")
        nxt = {}
        for p, q, c in segs:
            if p in nxt:
                raise MeshFileError(f"{self.source}: physical curve {name!r} branches at ({self.x[p]:.6g}, "
                                    f"{self.y[p]:.6g}) m on body {self.group!r}; a side is one path")
            nxt[p] = (q, c)
        heads = set(nxt) - {q for q, _ in nxt.values()}
        if len(heads) > 1:
            raise MeshFileError(f"{self.source}: physical curve {name!r} is in {len(heads)} pieces on body "
                                f"{self.group!r}; a side is one connected path")
        start = heads.pop() if heads else min(nxt)
        nodes, cells = [start], []
        while nodes[-1] in nxt and len(cells) < len(segs):
            q, c = nxt[nodes[-1]]
            nodes.append(q)
            cells.append(c)
        if len(cells) != len(segs):
            raise MeshFileError(f"{self.source}: physical curve {name!r} is in several pieces on body "
                                f"{self.group!r}; a side is one connected path")
        self._sides[name] = (np.array(nodes, np.int64), np.array(cells, np.int64))
        return self._sides[name]

    def side_nodes(self, side: str) -> np.ndarray:
        """Local nodes of a side (physical curve), counter-clockwise around the body (a closed
        side repeats its first node at the end)."""
        return self._side(side)[0].copy()

    def side_cells(self, side: str) -> np.ndarray:
        """Local cells along a side, cell k on segment (side_nodes[k], side_nodes[k+1])."""
        return self._side(side)[1].copy()

    def point(self, name: str) -> tuple[float, float]:
        """Coordinates of a physical point (its first vertex)."""
        if name not in self._vertices or len(self._vertices[name]) == 0:
            raise KeyError(f"{self.source}: no physical point named {name!r} "
                           f"(physical points: {', '.join(sorted(self._vertices)) or 'none'})")
        p = int(self._vertices[name][0])
        return float(self._points[p, 0]), float(self._points[p, 1])


_CACHE: dict[tuple, MeshData] = {}


def load_block(path: str | Path, group: str, scale: float = 1.0,
               parameters: dict[str, float] | None = None) -> FileBlock:
    """The body ``group`` (a physical surface) of a mesh file; files are read once per process
    (keyed by path, modification time, scale and parameters)."""
    path = Path(path).resolve()
    params = dict(parameters or {})
    key = (str(path), path.stat().st_mtime_ns if path.exists() else 0, scale, tuple(sorted(params.items())))
    if key not in _CACHE:
        _CACHE.clear()
        _CACHE[key] = read_mesh_file(path, scale, params)
    return FileBlock(_CACHE[key], group)
