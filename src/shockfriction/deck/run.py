"""The ``run`` deck: bodies (structured blocks), materials, boundaries, ties, probes, time.

Documented field by field in ``docs/deck-run.md``.  This module validates and
converts units only; :mod:`shockfriction.hydro.setup` turns a :class:`RunDeck`
into arrays.  Slide lines (contact/friction between bodies) are the
``slide_lines`` list: the contact module validates and builds its entries (see
:func:`shockfriction.hydro.setup.build_slide_lines`).
"""

from __future__ import annotations

import re
import math
from pathlib import Path
from typing import Annotated, Literal, Optional, Union

from pydantic import (ConfigDict, Discriminator, Field, Tag, TypeAdapter, ValidationError, ValidationInfo,
                      field_validator, model_validator)

from shockfriction.contact.deck import SlideLineDeck
from shockfriction.deck.base import DeckModel, known_material
from shockfriction.safety import MAX_CELLS
from shockfriction.units import (
    Density, Dimensionless, Length, PositiveLength, PositiveTime, Pressure, SpecificEnergy, SpecificHeat, Temperature,
    Velocity,
)


PositiveSpecificHeat = Annotated[SpecificHeat, Field(gt=0.0)]
PositiveDensity = Annotated[Density, Field(gt=0.0)]
PositivePressure = Annotated[Pressure, Field(gt=0.0)]

SIDE_NAMES = ("bottom", "right", "top", "left")
Side = Literal["bottom", "right", "top", "left"]
Point = tuple[Length, Length]


class MeshSpec(DeckModel):
    """A mapped quad: corners (i,j) = (0,0), (nx,0), (nx,ny), (0,ny), counter-clockwise."""

    corners: list[Point] = Field(min_length=4, max_length=4)
    nx: int = Field(ge=1, le=100000)
    ny: int = Field(ge=1, le=100000)
    sides: dict[Side, list[Point]] = Field(default_factory=dict)
    ratio_x: float = Field(default=1.0, gt=0.0)
    ratio_y: float = Field(default=1.0, gt=0.0)

    @model_validator(mode="after")
    def _outline(self):
        c = self.corners
        area2 = sum(c[k][0] * c[(k + 1) % 4][1] - c[(k + 1) % 4][0] * c[k][1] for k in range(4))
        if area2 <= 0.0:
            raise ValueError("corners must enclose a positive area, listed counter-clockwise "
                             "from (i,j)=(0,0) to (nx,0), (nx,ny), (0,ny)")
        ends = {"bottom": (0, 1), "right": (1, 2), "top": (2, 3), "left": (3, 0)}
        for name, pts in self.sides.items():
            if len(pts) < 2:
                raise ValueError(f"sides.{name}: a polyline needs at least two points")
            a, b = ends[name]
            for given, corner, which in ((pts[0], c[a], "first"), (pts[-1], c[b], "last")):
                tol = 1e-9 * (1 + abs(corner[0]) + abs(corner[1]))
                if max(abs(given[0] - corner[0]), abs(given[1] - corner[1])) > tol:
                    raise ValueError(f"sides.{name}: the {which} point must be the corner {corner} "
                                     "(side polylines run counter-clockwise from corner to corner)")
        return self


class MeshFile(DeckModel):
    """A body from a gmsh mesh: the physical surface ``group`` of ``file`` (.msh, or .geo meshed by
    the gmsh API with ``parameters`` set first), coordinates times ``scale`` (length of one file
    unit).  A relative path is relative to the deck's folder (docs/theory/meshes-and-outputs.md)."""

    file: str = Field(min_length=1)
    group: str = Field(min_length=1)
    scale: PositiveLength = 1.0
    parameters: dict[str, float] = Field(default_factory=dict)

    @field_validator("file")
    @classmethod
    def _exists(cls, v: str, info: ValidationInfo) -> str:
        from shockfriction.safety import TRUSTED, outside_message

        ctx = info.context or {}
        trust = ctx.get("trust") or TRUSTED  # the Python API trusts its caller; the command line does not
        path = Path(v).expanduser()
        folder = ctx.get("deck_dir")
        if not path.is_absolute() and folder is not None:
            path = Path(folder) / path
        if path.suffix not in (".msh", ".geo"):
            raise ValueError(f"expected a gmsh .msh or .geo file, got {v!r}")
        if not trust.allow_outside:
            message = outside_message(folder if folder is not None else Path.cwd(), str(path))
            if message:
                raise ValueError(message)
        if path.suffix == ".geo" and not trust.allow_geo:
            raise ValueError("a .geo file is a gmsh script that can run commands and write files: expected a "
                             ".msh mesh, or --allow-geo on the command line to mesh it")
        if not path.is_file():
            kind = "is not a regular file" if path.exists() else "does not exist"
            raise ValueError(f"expected an existing mesh file; {str(path)!r} {kind}")
        return str(path.resolve())


def _mesh_kind(v) -> str:
    if isinstance(v, dict):
        return "kind:file" if "file" in v else "kind:block"
    return "kind:file" if isinstance(v, MeshFile) else "kind:block"


AnyMesh = Annotated[Union[Annotated[MeshSpec, Tag("kind:block")], Annotated[MeshFile, Tag("kind:file")]],
                    Discriminator(_mesh_kind)]


class VelocityBC(DeckModel):
    """Prescribed velocity components (a component left out stays free)."""

    type: Literal["velocity"]
    vx: Optional[Velocity] = None
    vy: Optional[Velocity] = None


BoundaryKind = Union[Literal["free", "fixed", "symmetry", "periodic"], VelocityBC]


class Boundary(DeckModel):
    """Condition of each block side: free (default), fixed, symmetry (roller), periodic, velocity.

    A body meshed from a file names its sides by physical curve: any key is accepted here and
    checked against the mesh when the problem is built."""

    model_config = ConfigDict(extra="allow", frozen=True)

    bottom: BoundaryKind = "free"
    right: BoundaryKind = "free"
    top: BoundaryKind = "free"
    left: BoundaryKind = "free"

    @model_validator(mode="after")
    def _periodic_pairs(self):
        for name, value in (self.__pydantic_extra__ or {}).items():
            if not re.fullmatch(r"[A-Za-z0-9_.\-]+", name):
                raise ValueError(f"boundary side {name!r}: expected a physical-curve name (letters, digits, _ . -)")
            try:
                self.__pydantic_extra__[name] = _BOUNDARY_KIND.validate_python(value)
            except ValidationError:
                raise ValueError(f"boundary.{name} = {value!r}: expected free, fixed, symmetry or "
                                 "{ type = \"velocity\", vx = ..., vy = ... }") from None
            if self.__pydantic_extra__[name] == "periodic":
                raise ValueError(f"boundary.{name} = 'periodic': periodic sides exist only on block meshes")
        for a, b in (("left", "right"), ("bottom", "top")):
            pa, pb = getattr(self, a) == "periodic", getattr(self, b) == "periodic"
            if pa != pb:
                raise ValueError(f"periodic must be given on both {a} and {b}")
        return self

    def given(self, file_mesh: bool) -> list[tuple[str, BoundaryKind]]:
        """(side, condition) pairs to apply: the four sides of a block; the named sides of a file mesh."""
        if not file_mesh:
            return [(side, getattr(self, side)) for side in SIDE_NAMES]
        named = [(k, getattr(self, k)) for k in SIDE_NAMES if k in self.model_fields_set]
        return named + list((self.__pydantic_extra__ or {}).items())


_BOUNDARY_KIND = TypeAdapter(BoundaryKind)


#: what a Mie-Grueneisen body without a library material must give inline
CUSTOM_MG_REQUIRED = ("density", "c0", "s", "gamma0", "heat_capacity")


class Body(DeckModel):
    """One body: a block of one material with its initial state."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")
    material: Optional[str] = Field(default=None, min_length=1)
    eos: Literal["mie-gruneisen", "ideal-gas"] = "mie-gruneisen"
    strength: Literal["none", "elastic", "elastic-perfectly-plastic", "scg"] = "none"
    yield_stress: Optional[PositivePressure] = None
    shear_modulus: Optional[PositivePressure] = None
    elastic_modulus: Literal["pressure-temperature", "constant"] = "pressure-temperature"
    c0: Optional[Annotated[Velocity, Field(gt=0.0)]] = None
    s: Optional[Annotated[Dimensionless, Field(ge=0.0)]] = None
    gamma0: Optional[Dimensionless] = None
    gamma: Optional[Annotated[Dimensionless, Field(gt=1.0)]] = None
    density: Optional[PositiveDensity] = None
    pressure: Optional[Pressure] = None
    specific_energy: Optional[SpecificEnergy] = None
    heat_capacity: Optional[PositiveSpecificHeat] = None
    pressure_floor: Optional[Pressure] = None
    eos_tension: Literal["linear", "cubic"] = "linear"
    spall: Literal["none", "cutoff", "tuler-butcher"] = "none"
    spall_strength: Optional[PositivePressure] = None
    tb_sigma0: Optional[Annotated[Pressure, Field(ge=0.0)]] = None
    tb_lambda: Optional[Annotated[Dimensionless, Field(gt=0.0)]] = None
    tb_K: Optional[str] = None  # pressure^lambda x time, converted in hydro.setup once lambda is known
    velocity: tuple[Velocity, Velocity] = (0.0, 0.0)
    radial_velocity: Optional[Velocity] = None
    temperature: Annotated[Temperature, Field(gt=0.0)] = 300.0
    mesh: AnyMesh
    boundary: Boundary = Field(default_factory=Boundary)

    _known_material = field_validator("material")(known_material)

    @model_validator(mode="after")
    def _consistent(self):
        if self.eos == "mie-gruneisen" and self.material is None:
            missing = [k for k in CUSTOM_MG_REQUIRED if getattr(self, k) is None]
            if missing:
                raise ValueError("every Mie-Grueneisen property inline when no library material is given; "
                                 f"missing: {', '.join(missing)} (with units; or give material = \"Al6061-T6\")")
        if self.eos == "ideal-gas":
            missing = [k for k in ("density", "gamma") if getattr(self, k) is None]
            if missing:
                raise ValueError(f"an ideal-gas body needs {' and '.join(missing)}")
            if (self.pressure is None) == (self.specific_energy is None):
                raise ValueError("an ideal-gas body needs exactly one of pressure or specific_energy")
            if self.pressure is not None and self.pressure <= 0.0:
                raise ValueError("an ideal-gas pressure must be positive")
        if self.strength == "scg" and self.material is None:
            raise ValueError("strength = \"scg\" needs a library material")
        if self.strength == "elastic" and self.material is None and self.shear_modulus is None:
            raise ValueError("strength = \"elastic\" without a material needs shear_modulus")
        if self.strength == "elastic" and self.yield_stress is not None:
            raise ValueError("strength = \"elastic\" has no yield: remove yield_stress (or use "
                             "\"elastic-perfectly-plastic\")")
        if self.eos_tension != "linear" and self.eos != "mie-gruneisen":
            raise ValueError("eos_tension applies to Mie-Grueneisen bodies only")
        if self.spall != "none" and self.eos != "mie-gruneisen":
            raise ValueError(f"spall = \"{self.spall}\" needs a Mie-Grueneisen (solid) body")
        if self.material is None:
            need = {"cutoff": ("spall_strength",), "tuler-butcher": ("tb_sigma0", "tb_lambda", "tb_K"),
                    "none": ()}[self.spall]
            missing = [k for k in need if getattr(self, k) is None]
            if missing:
                raise ValueError(f"spall = \"{self.spall}\" without a material needs {', '.join(missing)}")
        if self.strength == "elastic-perfectly-plastic" and self.material is None:
            missing = [k for k in ("yield_stress", "shear_modulus") if getattr(self, k) is None]
            if missing:
                raise ValueError(f"elastic-perfectly-plastic without a material needs {' and '.join(missing)}")
        extra = sorted(self.boundary.__pydantic_extra__ or {})
        if extra and not self.from_file:
            raise ValueError(f"boundary: {', '.join(extra)}: a block body has only the sides {', '.join(SIDE_NAMES)}")
        if self.from_file and any(kind == "periodic" for _, kind in self.boundary.given(True)):
            raise ValueError("boundary: 'periodic' exists only on block meshes (left/right, bottom/top pairs)")
        return self

    @property
    def from_file(self) -> bool:
        """True when the body is meshed from a gmsh file (sides named by physical curves)."""
        return isinstance(self.mesh, MeshFile)


class TimeSpec(DeckModel):
    """End time and time-step control (thesis eqs. 3.32-3.33)."""

    end: PositiveTime
    cfl: float = Field(default=0.6, gt=0.0, le=1.0)
    max_volume_change: float = Field(default=0.1, gt=0.0, le=0.5)
    dt_initial: Optional[PositiveTime] = None
    dt_max: Optional[PositiveTime] = None
    dt_growth: float = Field(default=1.1, ge=1.0)
    max_cycles: int = Field(default=10_000_000, ge=1)
    dt_min_fraction: float = Field(default=1e-5, gt=0.0, lt=1.0)


class Viscosity(DeckModel):
    """Artificial viscosity (compression only) and hourglass control coefficients."""

    kind: Literal["scalar", "edge"] = "scalar"

    quadratic: float = Field(default=2.0, ge=0.0)
    linear: float = Field(default=0.15, ge=0.0)
    hourglass: float = Field(default=0.1, ge=0.0)
    shear: Literal["elastic", "all", "off"] = Field(
        default="elastic", description="deviatoric (shear) viscosity Q = 2 phi rho l (C_L c_S + C_Q^2 l |D'|) D' "
        "(shockfriction.hydro.shear_viscosity): 'elastic' in cells below yield, 'all' in every cell with "
        "strength, 'off' nowhere")
    shear_linear: float = Field(default=0.15, ge=0.0, le=2.0, description="C_L of the shear viscosity")
    shear_quadratic: float = Field(default=0.0, ge=0.0, le=4.0, description="C_Q of the shear viscosity")


class Output(DeckModel):
    """Field output times (HDF5 + XDMF) and the probe sampling."""

    field_interval: Optional[PositiveTime] = None
    field_times: list[PositiveTime] = Field(default_factory=list)
    probe_every: int = Field(default=1, ge=1)
    # write the full state to checkpoint.h5 every interval (restart: ``shockfriction run --restart``)
    checkpoint_interval: Optional[PositiveTime] = None
    max_fields: int = Field(default=10_000, ge=1)


class Tie(DeckModel):
    """Two body sides welded node to node (matching nodes, permanent, tension allowed)."""

    sides: tuple[str, str]


PROBE_QUANTITIES = {
    "x": "m", "y": "m", "vx": "m/s", "vy": "m/s",
    "p": "Pa", "q": "Pa", "sxx": "Pa", "syy": "Pa", "sxy": "Pa", "szz": "Pa",
    "sigma_xx": "Pa", "sigma_yy": "Pa", "sigma_xy": "Pa", "sigma_zz": "Pa",
    "rho": "kg/m3", "e": "J/kg", "T": "K", "eps_p": "1", "Y": "Pa", "G": "Pa", "damage": "1",
}
NODE_QUANTITIES = ("x", "y", "vx", "vy")


class Probe(DeckModel):
    """A history: node quantities (x, y, vx, vy) at a node, cell quantities in a cell.

    Give exactly one of ``node = [i, j]``, ``cell = [i, j]`` (negative indices count
    from the end), ``at = [x, y]`` (nearest node / containing cell at t = 0) or
    ``point = "name"`` (a gmsh physical point of a file-meshed body, then as ``at``)."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")
    body: str
    node: Optional[tuple[int, int]] = None
    cell: Optional[tuple[int, int]] = None
    at: Optional[Point] = None
    point: Optional[str] = None
    quantities: list[Literal[tuple(PROBE_QUANTITIES)]] = Field(min_length=1)  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _one_place(self):
        given = [k for k in ("node", "cell", "at", "point") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of node, cell, at or point")
        if self.node is not None and any(q not in NODE_QUANTITIES for q in self.quantities):
            raise ValueError(f"a node probe records only {', '.join(NODE_QUANTITIES)}")
        if self.cell is not None and any(q in NODE_QUANTITIES for q in self.quantities):
            bad = [q for q in self.quantities if q in NODE_QUANTITIES]
            raise ValueError(f"a cell probe records cell quantities only, not {', '.join(bad)}: velocities and "
                             "positions live on nodes; add a probe with node = [i, j] (or at = [x, y])")
        return self


class RunDeck(DeckModel):
    """A complete hydrocode problem."""

    title: str = ""
    geometry: Literal["planar", "axisymmetric"] = "planar"
    threads: int = Field(default=1, ge=0)
    max_cells: int = Field(default=MAX_CELLS, ge=1, description="largest number of cells in all bodies "
                           "(block meshes: nx * ny summed; gmsh meshes: checked before they are read or meshed); "
                           "a guard against a deck that would exhaust the memory, ~300 bytes a cell")
    time: TimeSpec
    viscosity: Viscosity = Field(default_factory=Viscosity)
    output: Output = Field(default_factory=Output)
    bodies: list[Body] = Field(min_length=1)
    ties: list[Tie] = Field(default_factory=list)
    probes: list[Probe] = Field(default_factory=list)
    # Slide lines between bodies (shockfriction.contact.deck.SlideLineDeck), built by the
    # contact module into interface objects registered in the cycle (hydro.setup.build_slide_lines).
    slide_lines: list[SlideLineDeck] = Field(default_factory=list)

    def _no_degenerate_pairs(self) -> None:
        """A tie or slide line joins two different sides, and each pair of sides is joined once."""
        seen: dict[frozenset, str] = {}
        pairs = [(f"ties[{k}].sides", tuple(t.sides)) for k, t in enumerate(self.ties)]
        pairs += [(f"slide_lines[{k}]", (f"{sl.guide.body}.{sl.guide.side}", f"{sl.slave.body}.{sl.slave.side}"))
                  for k, sl in enumerate(self.slide_lines)]
        for where, (a, b) in pairs:
            if a == b:
                what = "guide and slave" if where.startswith("slide") else "sides"
                raise ValueError(f"{where}: {what} = {a!r} twice: expected two different sides (a side cannot be "
                                 "joined to itself)")
            key = frozenset((a, b))
            if key in seen:
                raise ValueError(f"{where}: {a!r} and {b!r} are already joined by {seen[key]}: expected each pair "
                                 "of sides joined once (one tie or one slide line)")
            seen[key] = where

    @model_validator(mode="after")
    def _references(self):
        names = [b.name for b in self.bodies]
        by_name = {b.name: b for b in self.bodies}
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"body names must be unique; repeated: {', '.join(sorted(dup))}")
        for k, tie in enumerate(self.ties):
            for ref in tie.sides:
                body, _, side = ref.partition(".")
                if body not in names or not side or (side not in SIDE_NAMES and not by_name[body].from_file):
                    raise ValueError(f"ties[{k}]: {ref!r} is not BODY.SIDE with BODY in {names} and SIDE in "
                                     f"{list(SIDE_NAMES)}")
        for k, p in enumerate(self.probes):
            if p.body not in names:
                raise ValueError(f"probes[{k}].body = {p.body!r}: no such body ({', '.join(names)})")
            if by_name[p.body].from_file and (p.node is not None or p.cell is not None):
                raise ValueError(f"probes[{k}]: body {p.body!r} is meshed from a file: its nodes and cells have no "
                                 "(i, j); place the probe with at = [x, y] or point = \"physical point\"")
            if p.point is not None and not by_name[p.body].from_file:
                raise ValueError(f"probes[{k}].point: body {p.body!r} is a block; point names a gmsh physical point")
        for k, sl in enumerate(self.slide_lines):
            for role in ("guide", "slave"):
                ref = getattr(sl, role)
                if ref.body not in names:
                    raise ValueError(f"slide_lines[{k}].{role}.body = {ref.body!r}: no such body ({', '.join(names)})")
                if ref.side not in SIDE_NAMES and not by_name[ref.body].from_file:
                    raise ValueError(f"slide_lines[{k}].{role}.side = {ref.side!r}: expected one of "
                                     f"{', '.join(SIDE_NAMES)} (body {ref.body!r} is a block)")
        self._no_degenerate_pairs()
        if len({sl.name for sl in self.slide_lines}) != len(self.slide_lines):
            raise ValueError("slide line names must be unique")
        pnames = [p.name for p in self.probes]
        if len(set(pnames)) != len(pnames):
            raise ValueError("probe names must be unique")
        cells = sum(b.mesh.nx * b.mesh.ny for b in self.bodies if not b.from_file)  # file meshes: counted as read
        if cells > self.max_cells:
            raise ValueError(f"{cells:,} cells in all (nx * ny summed over the bodies): expected at most max_cells = "
                             f"{self.max_cells:,} (raise max_cells in the deck if the machine has the memory, "
                             "~300 bytes a cell)")
        out = self.output
        n_fields = len(out.field_times)
        if out.field_interval is not None:
            n_fields += math.floor(self.time.end / out.field_interval) + 1
        if n_fields > out.max_fields:
            raise ValueError(f"output: {n_fields:.3g} field outputs planned (time.end / output.field_interval + "
                             f"field_times): expected at most output.max_fields = {out.max_fields} (raise it, or "
                             "a longer field_interval)")
        late = [t for t in out.field_times if t > self.time.end * (1 + 1e-9)]
        if late:
            raise ValueError(f"output.field_times: {late[0]:.4g} s is after time.end = {self.time.end:.4g} s")
        if self.geometry == "axisymmetric":
            for b in self.bodies:
                if not b.from_file and min(c[0] for c in b.mesh.corners) < 0.0:
                    raise ValueError(f"body {b.name!r}: axisymmetric meshes need x = r >= 0")
        return self
