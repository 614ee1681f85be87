"""Characteristic values, dimensionless numbers and layer thicknesses (thesis ch. 5).

Scales chosen by the thesis (section 5.2.1, eq. 5.145): Y^ = Y0, Theta^ = T_F,
rho^ = rho0, kappa^ = kappa0, V^_X = zeta_L = sqrt(G0/rho0) and T^ = the time of
interest.  Derived (section 5.1.2): L^ = zeta_L T^, h^ = kappa0 T_F/(Y0 zeta_L),
e^ = Y0 L^/(rho0 h^), V^_Z = h^/T^, plastic-rate scale V^_X/h^, strain scale L^/h^,
diffusivity scale alpha^ = h^^2/T^ (eq. 5.174).

The ten numbers (eq. 5.144, 5.146-5.147)::

    N1 = h^/L^ = kappa0 T_F/(Y0 zeta_L^2 T^)     N2 = rho0 kappa0 T_F/(Y0^2 T^)
    N3 = 1    N4 = Y0/G0    N5 = Ymax/Y0    N6 = 1    N7 = 1
    N8 = V0/zeta_L    N9 = Theta0/T_F    N10 = 1

Each small number lets a group of terms of the deviation problem drop
(section 5.3); :data:`TERMS` lists them with the thesis equations.  A term is
declared negligible when its coefficient is at most ``threshold`` (default 0.01,
i.e. the term is 1 % of the leading-order terms or less; documented in
docs/theory/analyses.md).

Layer thicknesses (SI):

* ``thesis_thickness`` h^ = kappa0 T_F/(Y0 zeta_L): the thesis's scale (table 5.2);
* ``thermal_depth`` sqrt(alpha t): the heat penetration depth, which the thesis's
  conclusion takes as the layer thickness h_eps ~ sqrt(alpha T);
* ``column_depth``: the depth at which the temperature rise under a constant
  surface flux falls to ``column_fraction`` (1 %) of its surface value,
  2 x sqrt(alpha t) with ierfc(x) = fraction ierfc(0): the depth an adiabatic
  sub-grid column needs;
* ``shear_band_thickness`` kappa0 T_F/(Y V): the thesis's h^ with its stress and
  velocity scales replaced by the flow stress at the contact pressure
  Y = Y(0, P, Theta0) and the sliding velocity V: the thickness over which the
  plastic dissipation Y V is conducted away with a temperature drop of order T_F
  (the mechanical, plastically sheared layer).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import brentq

from shockfriction.analysis.stability import ScgConstants, max_stable_strain
from shockfriction.friction.subgrid.analytic import ierfc
from shockfriction.materials.library import Material, heat_share
from shockfriction.materials.strength import yield_stress

DEFAULT_THRESHOLD = 0.01
DEFAULT_COLUMN_FRACTION = 0.01


@dataclass(frozen=True)
class Scales:
    """Characteristic values of the boundary-layer problem (SI), thesis section 5.2.1."""

    time: float                  #: T^ (s)
    stress: float                #: Y^ = Y0 (Pa)
    temperature: float           #: Theta^ = T_F (K)
    density: float               #: rho^ = rho0 (kg/m^3)
    conductivity: float          #: kappa^ = kappa0 (W/(m K))
    velocity: float              #: V^_X = zeta_L = sqrt(G0/rho0) (m/s), eq. 5.145
    length: float                #: L^ = zeta_L T^ (m)
    thickness: float             #: h^ = kappa0 T_F/(Y0 zeta_L) (m)
    specific_energy: float       #: e^ = Y0 L^/(rho0 h^) (J/kg), eq. 5.19
    transverse_velocity: float   #: V^_Z = h^/T^ (m/s), eq. 5.12
    plastic_rate: float          #: V^_X/h^ (1/s), eq. 5.13
    plastic_strain: float        #: L^/h^, eq. 5.16
    diffusivity: float           #: alpha^ = h^^2/T^ (m^2/s), eq. 5.174
    heat_capacity: float         #: c = kappa0/(rho0 alpha0) (J/(kg K)), derived


@dataclass(frozen=True)
class Term:
    """A group of terms of the deviation problem and the number that weighs it."""

    key: str
    description: str
    equations: str
    number: str
    value: float
    negligible: bool
    consequence: str


#: (key, description, thesis equations, number name, consequence when negligible)
TERMS: tuple[tuple[str, str, str, str, str], ...] = (
    ("tangential_gradients", "tangential (x) derivatives of stress and velocity",
     "5.95-5.96, 5.105-5.108, 5.148", "N1",
     "1D problem across the thickness; lateral boundary conditions and mass balance drop"),
    ("tangential_conduction", "tangential heat conduction", "5.97", "N1^2",
     "heat flows along the normal only"),
    ("pressure_work", "pressure work P div v in the energy balance", "5.97", "N1 N3",
     "no pressure work in the layer heat equation"),
    ("elastic_rates", "elastic stress-rate terms of the layer constitutive law", "5.105-5.108", "N1 N4",
     "rigid-plastic layer: d(v - V)/dz = sqrt(3) eps_p_dot (5.158)"),
    ("rotation_and_deviator", "Jaumann rotation terms; deviator s_zz against pressure", "5.105-5.108, 5.162", "N4",
     "P replaced by the normal stress F_N in SCG (5.162)"),
    ("shear_inertia", "inertia in the shear momentum balance", "5.154", "N2",
     "quasi-static layer: tau_xz = T_XZ through the thickness"),
    ("normal_inertia", "inertia in the normal momentum balance", "5.96, 5.152", "N1 N2",
     "normal stress uniform through the layer: sigma_zz = F_N (5.153)"),
    ("pressure_stiffening", "pressure dependence of the SCG shear modulus", "5.162", "g P",
     "G (and Y) independent of the contact pressure"),
)


@dataclass(frozen=True)
class MaterialAnalysis:
    """Every chapter-5 and chapter-6 figure for one material of the pair."""

    material: str
    scales: Scales
    numbers: dict[str, float]
    terms: tuple[Term, ...]
    thesis_thickness: float
    thermal_depth: float
    column_depth: float
    shear_band_thickness: float
    flow_stress: float
    heat_share: float
    max_stable_strain: float
    saturation_strain: float


@dataclass(frozen=True)
class PairAnalysis:
    """The analysis of a friction pair at one velocity, contact pressure and time."""

    velocity: float
    pressure: float
    time: float
    temperature: float
    threshold: float
    column_fraction: float
    materials: tuple[MaterialAnalysis, MaterialAnalysis]

    def to_dict(self) -> dict:
        """JSON-ready dictionary (SI values, keys with their units)."""
        return asdict(self)


def characteristic_scales(material: Material, time: float) -> Scales:
    """The thesis's characteristic values for ``material`` at the time scale ``time`` (s)."""
    m = material
    zeta = math.sqrt(m.G0 / m.rho0)
    length = zeta * time
    thickness = m.conductivity * m.melting_temperature / (m.Y0 * zeta)
    return Scales(
        time=time, stress=m.Y0, temperature=m.melting_temperature, density=m.rho0,
        conductivity=m.conductivity, velocity=zeta, length=length, thickness=thickness,
        specific_energy=m.Y0 * length / (m.rho0 * thickness),
        transverse_velocity=thickness / time, plastic_rate=zeta / thickness,
        plastic_strain=length / thickness, diffusivity=thickness**2 / time,
        heat_capacity=m.heat_capacity,
    )


def dimensionless_numbers(material: Material, time: float, velocity: float,
                          temperature: float = 300.0, pressure: float = 0.0) -> dict[str, float]:
    """N1..N10 (eq. 5.144) with the thesis scales, plus the products and g P used in :data:`TERMS`."""
    m = material
    s = characteristic_scales(m, time)
    n = {
        "N1": s.thickness / s.length,                                            # 5.146
        "N2": s.density * s.thickness * s.length / (s.stress * s.time**2),       # 5.147
        "N3": s.stress * s.thickness * s.length / (s.conductivity * s.temperature * s.time),
        "N4": s.stress / m.G0,
        "N5": m.Ymax / s.stress,
        "N6": m.Y0 / s.stress,
        "N7": m.melting_temperature / s.temperature,
        "N8": abs(velocity) / s.velocity,
        "N9": temperature / s.temperature,
        "N10": m.rho0 / s.density,
    }
    n["N1^2"] = n["N1"] ** 2
    n["N1 N3"] = n["N1"] * n["N3"]
    n["N1 N4"] = n["N1"] * n["N4"]
    n["N1 N2"] = n["N1"] * n["N2"]
    n["g P"] = m.scg_g * abs(pressure)
    return n


def column_depth(diffusivity: float, time: float, fraction: float = DEFAULT_COLUMN_FRACTION) -> float:
    """Depth where the constant-flux temperature rise is ``fraction`` of the surface rise (Carslaw-Jaeger)."""
    if not 0.0 < fraction < 1.0:
        raise ValueError(f"fraction must lie in (0, 1), got {fraction}")
    x = brentq(lambda u: float(ierfc(u)) - fraction / math.sqrt(math.pi), 0.0, 10.0, xtol=1e-14)
    return 2.0 * x * math.sqrt(diffusivity * time)


def analyze_material(material: Material, other: Material, velocity: float, pressure: float, time: float,
                     temperature: float = 300.0, threshold: float = DEFAULT_THRESHOLD,
                     column_fraction: float = DEFAULT_COLUMN_FRACTION) -> MaterialAnalysis:
    """Scales, numbers, droppable terms, thicknesses and the stability limit of ``material``."""
    m = material
    numbers = dimensionless_numbers(m, time, velocity, temperature, pressure)
    terms = tuple(
        Term(key, desc, eqs, num, numbers[num], numbers[num] <= threshold, consequence)
        for key, desc, eqs, num, consequence in TERMS
    )
    flow = float(yield_stress(m, 0.0, abs(pressure), temperature))
    band = m.conductivity * m.melting_temperature / (flow * abs(velocity)) if flow > 0 and velocity else math.inf
    scg = ScgConstants.of(m)
    scales = characteristic_scales(m, time)
    return MaterialAnalysis(
        material=m.name,
        scales=scales,
        numbers=numbers,
        terms=terms,
        thesis_thickness=scales.thickness,
        thermal_depth=math.sqrt(m.diffusivity * time),
        column_depth=column_depth(m.diffusivity, time, column_fraction),
        shear_band_thickness=band,
        flow_stress=flow,
        heat_share=heat_share(m, other),
        max_stable_strain=float(max_stable_strain(scg, temperature, abs(pressure))),
        saturation_strain=scg.saturation_strain,
    )


def analyze_pair(first: Material, second: Material, velocity: float, pressure: float, time: float,
                 temperature: float = 300.0, threshold: float = DEFAULT_THRESHOLD,
                 column_fraction: float = DEFAULT_COLUMN_FRACTION) -> PairAnalysis:
    """Chapter-5 analysis of both materials of a friction pair (SI inputs).

    ``velocity``: impact/sliding velocity V0 (m/s); ``pressure``: contact pressure |F_N| (Pa);
    ``time``: the time scale T^ (s); ``temperature``: initial temperature Theta0 (K).
    """
    if time <= 0.0:
        raise ValueError(f"time must be positive, got {time} s")
    if threshold <= 0.0:
        raise ValueError(f"threshold must be positive, got {threshold}")
    if not np.isfinite([velocity, pressure, time, temperature]).all():
        raise ValueError("velocity, pressure, time and temperature must be finite")
    kw = dict(velocity=velocity, pressure=pressure, time=time, temperature=temperature,
              threshold=threshold, column_fraction=column_fraction)
    return PairAnalysis(velocity, abs(pressure), time, temperature, threshold, column_fraction,
                        (analyze_material(first, second, **kw), analyze_material(second, first, **kw)))
