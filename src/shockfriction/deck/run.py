"""The ``run`` deck: bodies (structured blocks), materials, boundaries, ties, probes, time.

Documented field by field in ``docs/deck-run.md``.  This module validates and
converts units only; :mod:`shockfriction.hydro.setup` turns a :class:`RunDeck`
into arrays.  Slide lines (contact/friction between bodies) are the
``slide_lines`` list: the contact module validates and builds its entries (see
:func:`shockfriction.hydro.setup.build_slide_lines`).
"""

from __future__ import annotations

from typing import Annotated, Literal, Optional, Union

from pydantic import Field, model_validator

from shockfriction.contact.deck import SlideLineDeck
from shockfriction.deck.base import DeckModel
from shockfriction.units import (
    Density, Dimensionless, Length, Pressure, PositiveTime, SpecificEnergy, SpecificHeat, Temperature, Velocity,
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


class VelocityBC(DeckModel):
    """Prescribed velocity components (a component left out stays free)."""

    type: Literal["velocity"]
    vx: Optional[Velocity] = None
    vy: Optional[Velocity] = None


BoundaryKind = Union[Literal["free", "fixed", "symmetry", "periodic"], VelocityBC]


class Boundary(DeckModel):
    """Condition of each block side: free (default), fixed, symmetry (roller), periodic, velocity."""

    bottom: BoundaryKind = "free"
    right: BoundaryKind = "free"
    top: BoundaryKind = "free"
    left: BoundaryKind = "free"

    @model_validator(mode="after")
    def _periodic_pairs(self):
        for a, b in (("left", "right"), ("bottom", "top")):
            pa, pb = getattr(self, a) == "periodic", getattr(self, b) == "periodic"
            if pa != pb:
                raise ValueError(f"periodic must be given on both {a} and {b}")
        return self


class Body(DeckModel):
    """One body: a block of one material with its initial state."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")
    material: Optional[str] = None
    eos: Literal["mie-gruneisen", "ideal-gas"] = "mie-gruneisen"
    strength: Literal["none", "elastic-perfectly-plastic", "scg"] = "none"
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
    velocity: tuple[Velocity, Velocity] = (0.0, 0.0)
    radial_velocity: Optional[Velocity] = None
    temperature: Annotated[Temperature, Field(gt=0.0)] = 300.0
    mesh: MeshSpec
    boundary: Boundary = Field(default_factory=Boundary)

    @model_validator(mode="after")
    def _consistent(self):
        if self.eos == "mie-gruneisen" and self.material is None:
            raise ValueError("a Mie-Grueneisen body needs a library material (material = \"Al6061-T6\", ...)")
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
        if self.strength == "elastic-perfectly-plastic" and self.material is None:
            missing = [k for k in ("yield_stress", "shear_modulus") if getattr(self, k) is None]
            if missing:
                raise ValueError(f"elastic-perfectly-plastic without a material needs {' and '.join(missing)}")
        return self


class TimeSpec(DeckModel):
    """End time and time-step control (thesis eqs. 3.32-3.33)."""

    end: PositiveTime
    cfl: float = Field(default=0.6, gt=0.0, le=1.0)
    max_volume_change: float = Field(default=0.1, gt=0.0, le=0.5)
    dt_initial: Optional[PositiveTime] = None
    dt_max: Optional[PositiveTime] = None
    dt_growth: float = Field(default=1.1, ge=1.0)
    max_cycles: int = Field(default=10_000_000, ge=1)


class Viscosity(DeckModel):
    """Artificial viscosity (compression only) and hourglass control coefficients."""

    kind: Literal["scalar", "edge"] = "scalar"

    quadratic: float = Field(default=2.0, ge=0.0)
    linear: float = Field(default=0.15, ge=0.0)
    hourglass: float = Field(default=0.1, ge=0.0)
    #: deviatoric (shear) viscosity Q = 2 rho l (C_L c_S + C_Q^2 l |D'|) D' (shockfriction.hydro.shear_viscosity):
    #: "elastic" (default) acts in cells below yield, "all" in every cell with strength, "off" nowhere
    shear: Literal["elastic", "all", "off"] = "elastic"
    shear_linear: float = Field(default=0.15, ge=0.0, le=2.0)
    shear_quadratic: float = Field(default=0.0, ge=0.0, le=4.0)


class Output(DeckModel):
    """Field output times (HDF5 + XDMF) and the probe sampling."""

    field_interval: Optional[PositiveTime] = None
    field_times: list[PositiveTime] = Field(default_factory=list)
    probe_every: int = Field(default=1, ge=1)


class Tie(DeckModel):
    """Two body sides welded node to node (matching nodes, permanent, tension allowed)."""

    sides: tuple[str, str]


PROBE_QUANTITIES = {
    "x": "m", "y": "m", "vx": "m/s", "vy": "m/s",
    "p": "Pa", "q": "Pa", "sxx": "Pa", "syy": "Pa", "sxy": "Pa", "szz": "Pa",
    "sigma_xx": "Pa", "sigma_yy": "Pa", "sigma_xy": "Pa", "sigma_zz": "Pa",
    "rho": "kg/m3", "e": "J/kg", "T": "K", "eps_p": "1", "Y": "Pa", "G": "Pa",
}
NODE_QUANTITIES = ("x", "y", "vx", "vy")


class Probe(DeckModel):
    """A history: node quantities (x, y, vx, vy) at a node, cell quantities in a cell.

    Give exactly one of ``node = [i, j]``, ``cell = [i, j]`` (negative indices count
    from the end) or ``at = [x, y]`` (nearest node / containing cell at t = 0)."""

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")
    body: str
    node: Optional[tuple[int, int]] = None
    cell: Optional[tuple[int, int]] = None
    at: Optional[Point] = None
    quantities: list[Literal[tuple(PROBE_QUANTITIES)]] = Field(min_length=1)  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _one_place(self):
        given = [k for k in ("node", "cell", "at") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of node, cell or at")
        if self.node is not None and any(q not in NODE_QUANTITIES for q in self.quantities):
            raise ValueError(f"a node probe records only {', '.join(NODE_QUANTITIES)}")
        if self.cell is not None and any(q in NODE_QUANTITIES for q in self.quantities):
            raise ValueError(f"a cell probe records cell quantities only (not {', '.join(NODE_QUANTITIES)})")
        return self


class RunDeck(DeckModel):
    """A complete hydrocode problem."""

    title: str = ""
    geometry: Literal["planar", "axisymmetric"] = "planar"
    threads: int = Field(default=1, ge=0)
    time: TimeSpec
    viscosity: Viscosity = Field(default_factory=Viscosity)
    output: Output = Field(default_factory=Output)
    bodies: list[Body] = Field(min_length=1)
    ties: list[Tie] = Field(default_factory=list)
    probes: list[Probe] = Field(default_factory=list)
    # Slide lines between bodies (shockfriction.contact.deck.SlideLineDeck), built by the
    # contact module into interface objects registered in the cycle (hydro.setup.build_slide_lines).
    slide_lines: list[SlideLineDeck] = Field(default_factory=list)

    @model_validator(mode="after")
    def _references(self):
        names = [b.name for b in self.bodies]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"body names must be unique; repeated: {', '.join(sorted(dup))}")
        for k, tie in enumerate(self.ties):
            for ref in tie.sides:
                body, _, side = ref.partition(".")
                if body not in names or side not in SIDE_NAMES:
                    raise ValueError(f"ties[{k}]: {ref!r} is not BODY.SIDE with BODY in {names} and SIDE in "
                                     f"{list(SIDE_NAMES)}")
        for k, p in enumerate(self.probes):
            if p.body not in names:
                raise ValueError(f"probes[{k}].body = {p.body!r}: no such body ({', '.join(names)})")
        for k, sl in enumerate(self.slide_lines):
            for role in ("guide", "slave"):
                ref = getattr(sl, role)
                if ref.body not in names:
                    raise ValueError(f"slide_lines[{k}].{role}.body = {ref.body!r}: no such body ({', '.join(names)})")
        if len({sl.name for sl in self.slide_lines}) != len(self.slide_lines):
            raise ValueError("slide line names must be unique")
        pnames = [p.name for p in self.probes]
        if len(set(pnames)) != len(pnames):
            raise ValueError("probe names must be unique")
        if self.geometry == "axisymmetric":
            for b in self.bodies:
                if min(c[0] for c in b.mesh.corners) < 0.0:
                    raise ValueError(f"body {b.name!r}: axisymmetric meshes need x = r >= 0")
        return self
