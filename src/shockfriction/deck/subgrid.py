"""Deck of ``shockfriction subgrid``: sub-grid columns driven by imposed loading histories.

Every dimensional value is a string with its unit ("200 m/s", "10 GPa", "20 um").  Layout::

    title = "..."                       # optional
    model = "thermoelastic"             # or "thermoelastoplastic" (thesis ch. 7 / ch. 8), or "viscoplastic"
    material = "Al5083-H111"            # the modelled body (library name)
    other_material = "AISI321"          # heat share beta_T = e1/(e1+e2) ... or:
    # heat_share = 0.677                # ... the share of the frictional heat entering the body
    T0 = "300 K"                        # initial temperature, below the melting temperature
    duration = "2.5 us"
    dt = "1 ns"
    output_times = ["0.1 us", "1 us"]   # depth profiles written at these times

    [column]
    thickness = "20 um"                 # h (thesis h_epsilon)
    cells = 500                         # M
    grading = 1.0                       # ratio of successive cells, >= 1 (1: uniform grid)

    [friction]                          # needed unless every loading is a heat flux
    mu0 = 0.3                           # Coulomb coefficient
    f = 0.3                             # the model's coefficient on the SCG strength
    taylor_quinney = 0.9

    [viscoplastic]                      # optional, model = "viscoplastic" only (docs/theory/viscoplastic.md)
    eta_vp = "50 Pa*s"                  # overstress viscosity (rate sensitivity); default: the material's or 50 Pa s
    inertia = true                      # shear inertia + impedance far end (false: quasi-static, v = 0 at z = h)
    tresca = true                       # the f Ymax/sqrt(3) G/G0 cap on the surface traction (false: column only)
    depth = "auto"                      # continue the column below [column] thickness with geometric cells down to
                                        # this depth ("auto": 1.2 x the shear-wave reach c_s(p_max, T0) x duration,
                                        # so that nothing reaches the far end; "none": the column stops at thickness)
    depth_ratio = 1.05                  # ratio of successive cells in that continuation
    picard_tol = "1e-6 K"               # a step's Picard sweeps stop when no node's temperature moves by more
                                        # (looser: fewer sweeps, faster; docs/theory/viscoplastic.md, "Speed")
    time_scheme = "backward_euler"      # or "bdf2": second order in dt for solid columns under imposed slip
                                        # (docs/theory/viscoplastic.md, "Time accuracy"; ~2.5x the cost at f = 0.3)

    [[loading]]                         # one table per column (several: several columns)
    name = "ball"                       # optional; names the extra output files
    interpolation = "constant"          # or "linear" between the table's points
    times = ["0 us", "2.5 us"]
    slip_velocity = ["200 m/s", "200 m/s"]
    normal_stress = ["10 GPa", "10 GPa"]
    # heat_flux = ["6.12e9 W/m^2", ...] # instead: pure thermal mode (generated flux)

"constant" holds each value until the next time (the last one to the end).
"""

from __future__ import annotations

from typing import Annotated, Literal, Optional, Union

from pydantic import Field, ValidationInfo, field_validator, model_validator

from shockfriction.deck.base import DeckModel, known_material
from shockfriction.units import (Dimensionless, HeatFlux, NonNegativeTime, PicardTolerance, PositiveLength,
                                 PositiveTemperature, PositiveTime, Pressure, Velocity, Viscosity)


class ColumnDeck(DeckModel):
    """The 1D column under each interface node."""

    thickness: PositiveLength = Field(default=20e-6, description="column thickness h")
    cells: int = Field(default=500, ge=2, le=1_000_000, description="number of cells M")
    grading: float = Field(default=1.0, ge=1.0, le=2.0, description="ratio of successive cell sizes")

    @model_validator(mode="after")
    def _cells_above_an_atomic_spacing(self):
        check_smallest_cell(self.thickness, self.cells, self.grading)
        return self


def check_smallest_cell(thickness: float, cells: int, grading: float) -> None:
    """A column's smallest cell (the first, h (r - 1)/(r^M - 1)) must be at least ``MIN_CELL`` (an atomic spacing;
    :mod:`shockfriction.friction.subgrid.column`): else a ValueError naming thickness, cells and grading."""
    from shockfriction.friction.subgrid.column import MIN_CELL, smallest_cell

    dz0 = smallest_cell(thickness, cells, grading)
    if not dz0 >= MIN_CELL:
        raise ValueError(f"thickness = {thickness:g} m, cells = {cells}, grading = {grading:g} give a smallest cell of "
                         f"{dz0:.3g} m: expected at least {MIN_CELL:g} m (an atomic spacing, below which the "
                         f"continuum column means nothing and its solves lose their precision): fewer cells, a "
                         f"thicker column or a grading nearer 1")


class FrictionDeck(DeckModel):
    """Friction-law parameters: tau = min(mu0 F_N, f Ymax/sqrt(3) G/G0)."""

    mu0: Dimensionless = Field(ge=0.0)
    f: Dimensionless = Field(ge=0.0)
    taylor_quinney: Dimensionless = Field(default=0.9, ge=0.0, le=1.0)


class ViscoplasticDeck(DeckModel):
    """Options of the viscoplastic column model."""

    eta_vp: Optional[Annotated[Viscosity, Field(ge=0.0)]] = None
    inertia: bool = True
    tresca: bool = True
    depth: Union[Literal["auto", "none"], PositiveLength] = Field(
        default="auto", description="depth of the graded continuation of the column ('auto', 'none' or a length)")
    depth_ratio: float = Field(default=1.05, gt=1.0, le=1.5, description="ratio of successive continuation cells")
    picard_tol: Optional[PicardTolerance] = Field(
        default=None, description="Picard tolerance in kelvin, e.g. '1e-3 K' (omitted: 1e-6 K)")
    heat: Optional[Literal["two-sided", "share"]] = Field(
        default=None, description="'two-sided': a thermal column in the other body (default with other_material); "
                                  "'share': the fixed heat share beta_T (default with heat_share)")
    pressure_melting: bool = Field(
        default=True, description="melting temperature T_m(sigma_n) by the SCG melt law and the melt viscosity's "
                                  "pressure factor (false: the ambient melting point and viscosity)")
    time_scheme: Literal["backward_euler", "bdf2"] = Field(
        default="backward_euler", description="time integration of the columns: 'backward_euler' (first order) or "
                                              "'bdf2' (second order for solid columns under imposed slip; backward "
                                              "Euler where melt, a partner mass or unloading make BDF2 unfit)")

    @model_validator(mode="after")
    def _quasi_static_needs_no_bound(self):
        if not self.inertia and self.depth == "none":
            raise ValueError("inertia = true, or a continued column (depth), not inertia = false with depth = 'none': "
                             "a quasi-static column bounded at h has one "
                             "uniform stress, and once its surface layer softens the step has no unique solution "
                             "(it alternates from step to step); keep inertia, or continue the column (depth)")
        return self

    def options(self) -> dict:
        return {"eta_vp": self.eta_vp, "inertia": self.inertia, "tresca": self.tresca, "depth": self.depth,
                "depth_ratio": self.depth_ratio, "picard_tol": self.picard_tol, "heat": self.heat,
                "pressure_melting": self.pressure_melting, "time_scheme": self.time_scheme}


class LoadingDeck(DeckModel):
    """A loading history for one column: (slip velocity, normal stress) or a heat flux, at given times."""

    name: Optional[str] = Field(default=None, min_length=1, pattern=r"^[A-Za-z0-9_\-]+$")
    interpolation: Literal["constant", "linear"] = "constant"
    times: list[NonNegativeTime] = Field(min_length=1)
    slip_velocity: Optional[list[Velocity]] = None
    normal_stress: Optional[list[Pressure]] = None
    heat_flux: Optional[list[HeatFlux]] = None

    @field_validator("times")
    @classmethod
    def _increasing(cls, v):
        if v[0] != 0.0:
            raise ValueError("a table starting at time 0 (e.g. ['0 us', ...])")
        if any(b <= a for a, b in zip(v, v[1:])):
            raise ValueError("strictly increasing times")
        return v

    @model_validator(mode="after")
    def _one_kind(self):
        mech = self.slip_velocity is not None or self.normal_stress is not None
        if mech and self.heat_flux is not None:
            raise ValueError("either slip_velocity and normal_stress, or heat_flux, not both")
        if mech and (self.slip_velocity is None or self.normal_stress is None):
            raise ValueError("both slip_velocity and normal_stress (or heat_flux alone)")
        if not mech and self.heat_flux is None:
            raise ValueError("a history: slip_velocity and normal_stress, or heat_flux")
        n = len(self.times)
        for key in ("slip_velocity", "normal_stress", "heat_flux"):
            vals = getattr(self, key)
            if vals is not None and len(vals) != n:
                raise ValueError(f"{key} with one value per time ({n} values, got {len(vals)})")
        return self

    @property
    def kind(self) -> str:
        return "flux" if self.heat_flux is not None else "slip"


class SubgridDeck(DeckModel):
    """The whole deck of ``shockfriction subgrid``."""

    title: str = ""
    model: Literal["thermoelastic", "thermoelastoplastic", "viscoplastic"] = "thermoelastic"
    material: str
    other_material: Optional[str] = None
    heat_share: Optional[Dimensionless] = Field(default=None, validate_default=True)
    T0: PositiveTemperature = Field(default=300.0)
    duration: PositiveTime
    dt: PositiveTime
    output_times: list[NonNegativeTime] = Field(default_factory=list)
    column: ColumnDeck = Field(default_factory=ColumnDeck)
    friction: Optional[FrictionDeck] = None
    viscoplastic: Optional[ViscoplasticDeck] = None
    loading: list[LoadingDeck] = Field(min_length=1)
    max_steps: int = Field(default=10_000_000, ge=1)

    _known_material = field_validator("material", "other_material")(known_material)

    @field_validator("heat_share")
    @classmethod
    def _share(cls, v, info: ValidationInfo):
        other = info.data.get("other_material")
        if v is None and other is None and "other_material" in info.data:
            raise ValueError("a heat share in [0, 1], or other_material to derive it from the effusivities")
        if v is not None and other is not None:
            raise ValueError("either heat_share or other_material, not both")
        if v is not None and not 0.0 <= v <= 1.0:
            raise ValueError("a heat share in [0, 1]")
        return v

    @field_validator("T0")
    @classmethod
    def _below_melting(cls, v, info: ValidationInfo):
        name = info.data.get("material")
        if name is not None:
            from shockfriction.materials.library import get_material
            T_F = get_material(name).melting_temperature
            if not v < T_F:
                raise ValueError(f"an initial temperature below the melting temperature of {name} ({T_F:g} K)")
        return v

    @field_validator("dt")
    @classmethod
    def _step_within_duration(cls, v, info: ValidationInfo):
        d = info.data.get("duration")
        if d is not None and v > d:
            raise ValueError(f"a time step no longer than the duration ({d:g} s)")
        return v

    @field_validator("output_times")
    @classmethod
    def _within_duration(cls, v, info: ValidationInfo):
        d = info.data.get("duration")
        if d is not None and any(t > d * (1 + 1e-12) for t in v):
            raise ValueError(f"output times within the duration ({d:g} s)")
        return sorted(set(v))

    @field_validator("loading")
    @classmethod
    def _consistent(cls, v, info: ValidationInfo):
        kinds = {ld.kind for ld in v}
        if len(kinds) > 1:
            raise ValueError("every loading of one kind: all slip/normal-stress histories or all heat fluxes")
        if "slip" in kinds and "friction" in info.data and info.data["friction"] is None:
            raise ValueError("a friction table with mu0 and f for slip/normal-stress loading")
        names = [ld.name for ld in v if ld.name]
        if len(set(names)) != len(names):
            raise ValueError("distinct loading names")
        return v

    @model_validator(mode="after")
    def _step_count(self):
        n = self.duration / self.dt
        if n > self.max_steps:
            raise ValueError(f"duration / dt = {n:.3g} steps: expected at most max_steps = {self.max_steps} "
                             "(a longer dt, a shorter duration, or raise max_steps)")
        return self

    @model_validator(mode="after")
    def _viscoplastic_options(self):
        if self.viscoplastic is not None and self.model != "viscoplastic":
            raise ValueError("a [viscoplastic] table only with model = 'viscoplastic'")
        if self.viscoplastic is not None and self.viscoplastic.heat == "two-sided" and self.other_material is None:
            raise ValueError("viscoplastic.heat = 'two-sided' needs other_material (the other body's thermal column)")
        if self.model == "viscoplastic":
            from shockfriction.materials.library import get_material
            m = get_material(self.material)
            missing = [k for k in ("latent_heat", "liquid_viscosity") if not m.has(k)]
            if missing:
                raise ValueError(f"model 'viscoplastic' needs a material with {' and '.join(missing)} "
                                 f"({self.material} has none)")
        return self

    @property
    def mode(self) -> str:
        """'slip' (friction models) or 'flux' (pure thermal)."""
        return self.loading[0].kind

