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


#: the child process that meshes a .geo (a fresh interpreter: the gmsh library, an address-space
#: cap, the parent's death ends it; its working folder is a scratch folder deleted afterwards)
_GMSH_CHILD = r"""
import ctypes, json, math, resource, signal, sys
try:
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
except OSError:
    pass
src, out, params = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
limit, max_cells = int(sys.argv[4]), int(sys.argv[5])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
import gmsh
gmsh.initialize(readConfigFiles=False, interruptible=False)
try:
    gmsh.option.setNumber("General.Terminal", 0)
    for name, value in params.items():
        gmsh.parser.setNumber(name, [float(value)])
    gmsh.merge(src)
    gmsh.model.mesh.generate(1)
    estimate = 0.0
    for dim, tag in gmsh.model.getEntities(2):
        x0, y0, _, x1, y1, _ = gmsh.model.getBoundingBox(dim, tag)
        lengths = []
        for _, c in gmsh.model.getBoundary([(dim, tag)], oriented=False):
            _, xyz, u = gmsh.model.mesh.getNodes(1, abs(c), includeBoundary=True)
            order = sorted(range(len(u)), key=lambda k: u[k])  # along the curve (end nodes come last)
            p = [(xyz[3 * k], xyz[3 * k + 1]) for k in order]
            lengths += [math.dist(a, b) for a, b in zip(p, p[1:])]
        lengths = [h for h in lengths if h > 0.0]
        if lengths:
            h = sum(lengths) / len(lengths)
            estimate += (x1 - x0) * (y1 - y0) / (h * h)
    if estimate > 4 * max_cells:
        sys.stdout.write(json.dumps({"too_many": estimate, "estimated": True}) + "\n")
        sys.exit(3)
    gmsh.model.mesh.generate(2)
    n = sum(len(t) for t in gmsh.model.mesh.getElements(2)[1])
    if n > max_cells:
        sys.stdout.write(json.dumps({"too_many": n, "estimated": False}) + "\n")
        sys.exit(3)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(out)
except MemoryError:
    sys.stdout.write(json.dumps({"error": "out of memory"}) + "\n")
    sys.exit(1)
except Exception as exc:
    sys.stdout.write(json.dumps({"error": str(exc)}) + "\n")
    sys.exit(1)
finally:
    try:
        gmsh.finalize()
    except Exception:
        pass
"""


def _mesh_geo(path: Path, parameters: dict[str, float], folder: Path, max_cells: int) -> Path:
    """Mesh a .geo file with gmsh in a child process (``parameters`` set as parser numbers first: the
    file should define defaults with ``If (!Exists(name)) name = value; EndIf``); returns a .msh in
    ``folder``.  The child runs in ``folder`` under an address-space cap
    (:data:`shockfriction.safety.GMSH_MEMORY_BYTES`) and a time cap; a mesh estimated (from the 1D
    mesh, before the surfaces are meshed) or found to hold more than ``max_cells`` elements is refused."""
    import json
    import subprocess
    import sys

    from shockfriction.safety import GMSH_MEMORY_BYTES, GMSH_SECONDS

    out = folder / (path.stem + ".msh")
    argv = [sys.executable, "-c", _GMSH_CHILD, str(path.resolve()), str(out), json.dumps(parameters),
            str(GMSH_MEMORY_BYTES), str(max_cells)]
    try:
        res = subprocess.run(argv, cwd=folder, capture_output=True, text=True, timeout=GMSH_SECONDS,
                             stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        raise MeshFileError(f"{path}: gmsh did not mesh it within {GMSH_SECONDS:g} s") from None
    lines = [ln for ln in res.stdout.splitlines() if ln.startswith("{")]
    info = json.loads(lines[-1]) if lines else {}
    if "too_many" in info:
        what = "an estimated " if info["estimated"] else ""
        raise MeshFileError(f"{path}: gmsh would make {what}{info['too_many']:.3g} elements: expected at most "
                            f"max_cells = {max_cells:,} (raise max_cells in the run deck if it is meant)")
    if res.returncode != 0 or not out.is_file():
        why = info.get("error") or (res.stderr.strip().splitlines() or [f"exit status {res.returncode}"])[-1]
        if res.returncode < 0 or "memory" in why.lower() or "bad_alloc" in why:
            why = f"{why} (gmsh is capped at {GMSH_MEMORY_BYTES / 2**30:g} GiB)"
        raise MeshFileError(f"{path}: gmsh could not mesh it: {why}")
    return out


#: bytes of a .msh file per cell allowed before it is read (ASCII quads and nodes take ~100 B)
MSH_BYTES_PER_CELL = 400


def read_mesh_file(path: str | Path, scale: float = 1.0, parameters: dict[str, float] | None = None,
                   max_cells: int | None = None) -> MeshData:
    """Read a .msh (meshio) or mesh a .geo (gmsh, child process) into :class:`MeshData`; a mesh
    over ``max_cells`` elements (default: the run deck's default) is refused before it is read."""
    import shutil
    import meshio

    from shockfriction.safety import MAX_CELLS

    path = Path(path)
    max_cells = MAX_CELLS if max_cells is None else int(max_cells)
    if not path.is_file():
        raise MeshFileError(f"{path}: no such file")
    folder = None
    try:
        if path.suffix == ".geo":
            folder = Path(tempfile.mkdtemp(prefix="sf-gmsh-"))
            msh = _mesh_geo(path, parameters or {}, folder, max_cells)
        else:
            msh = path
            size = path.stat().st_size
            if size > MSH_BYTES_PER_CELL * max_cells:
                raise MeshFileError(f"{path}: {size:,} bytes, more than a mesh of max_cells = {max_cells:,} cells "
                                    f"needs ({MSH_BYTES_PER_CELL} bytes a cell): raise max_cells in the run deck "
                                    "if it is meant")
        try:
            m = meshio.read(msh, file_format="gmsh")
        except Exception as exc:  # noqa: BLE001 -- meshio raises ReadError, KeyError, ValueError, ... on bad files
            raise MeshFileError(f"{path}: not a readable gmsh mesh: {exc}") from None
    finally:
        if folder is not None:
            shutil.rmtree(folder, ignore_errors=True)
    n_cells = sum(len(b.data) for b in m.cells if b.dim == 2) if m.cells else 0
    if n_cells > max_cells:
        raise MeshFileError(f"{path}: {n_cells:,} surface elements: expected at most max_cells = {max_cells:,} "
                            "(raise max_cells in the run deck if it is meant)")
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
               parameters: dict[str, float] | None = None, max_cells: int | None = None) -> FileBlock:
    """The body ``group`` (a physical surface) of a mesh file; files are read once per process
    (keyed by path, modification time, scale and parameters)."""
    path = Path(path).resolve()
    params = dict(parameters or {})
    key = (str(path), path.stat().st_mtime_ns if path.exists() else 0, scale, tuple(sorted(params.items())))
    if key not in _CACHE:
        _CACHE.clear()
        _CACHE[key] = read_mesh_file(path, scale, params, max_cells)
    return FileBlock(_CACHE[key], group)
