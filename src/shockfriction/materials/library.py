"""Material library: one TOML file per material in ``data/``, every parameter
with its unit, its source and a status (``thesis``, ``checked``, ``to verify``).

Parameters (SI inside; the files carry unit strings):

==================  ==============  ==============================================
key                 kind            meaning
==================  ==============  ==============================================
rho0                density         initial density
conductivity        conductivity    thermal conductivity kappa
diffusivity         diffusivity     thermal diffusivity alpha (or heat_capacity)
heat_capacity       specific_heat   c = kappa / (rho0 alpha) (or diffusivity)
melting_temperature temperature     Theta_F (constant, as in the thesis)
G0, Y0, Ymax        pressure        SCG shear modulus, initial and saturation yield
scg_beta, scg_n     dimensionless   SCG hardening Y0 (1 + beta eps)^n
scg_g               inverse_pressure SCG pressure coefficient of G (thesis g)
scg_h               inverse_temperature SCG thermal softening of G (thesis h_Theta)
scg_xi              dimensionless   melt softening exp(-xi T/(T_F - T)) (Ball & Winter)
eos_c0, eos_s       velocity, -     linear Us = c0 + s up Hugoniot
eos_gamma0          dimensionless   Grueneisen coefficient (Gamma rho = const)
scg_melt_a          dimensionless   a of the SCG melt law T_m(eta) (optional; default eos_gamma0: Gamma rho = const)
spall_strength      pressure        spall strength p_spall of the cut-off model
tb_sigma0, tb_lambda pressure, -    Tuler-Butcher threshold and exponent
tb_K                pressure^lambda x time  Tuler-Butcher damage constant (e.g. "1 GPa^2*us")
latent_heat         specific_energy latent heat of fusion L (optional; viscoplastic sub-grid model)
liquid_viscosity    viscosity       melt viscosity at Theta_F (optional; Arrhenius law, viscoplastic model)
liquid_viscosity_activation temperature  E/R of eta_L = eta_F exp(E/R (1/T - 1/Theta_F)) (optional)
liquid_viscosity_activation_volume molar_volume  V* of the melt viscosity's pressure factor exp(p V*/(R T)) (optional)
viscoplastic_viscosity viscosity    overstress viscosity eta_vp of the solid (optional; viscoplastic model)
==================  ==============  ==============================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources

import numpy as np

from shockfriction.tomlio import read_toml
from shockfriction.errors import DeckError
from shockfriction.units import UnitError, pressure_power_time_to_si, to_si

PARAMETER_KINDS: dict[str, str] = {
    "rho0": "density",
    "conductivity": "conductivity",
    "diffusivity": "diffusivity",
    "heat_capacity": "specific_heat",
    "melting_temperature": "temperature",
    "G0": "pressure",
    "Y0": "pressure",
    "Ymax": "pressure",
    "scg_beta": "dimensionless",
    "scg_n": "dimensionless",
    "scg_g": "inverse_pressure",
    "scg_h": "inverse_temperature",
    "scg_xi": "dimensionless",
    "eos_c0": "velocity",
    "eos_s": "dimensionless",
    "eos_gamma0": "dimensionless",
    "scg_melt_a": "dimensionless",
    "spall_strength": "pressure",
    "tb_sigma0": "pressure",
    "tb_lambda": "dimensionless",
    "tb_K": "pressure^lambda x time",
    "latent_heat": "specific_energy",
    "liquid_viscosity": "viscosity",
    "liquid_viscosity_activation": "temperature",
    "liquid_viscosity_activation_volume": "molar_volume",
    "viscoplastic_viscosity": "viscosity",
}
REQUIRED = ("rho0", "conductivity", "melting_temperature", "G0", "Y0", "Ymax",
            "scg_beta", "scg_n", "scg_g", "scg_h", "scg_xi")
STATUSES = ("thesis", "checked", "to verify", "derived")

#: order of the SCG parameters in :meth:`Material.scg_params` (used by numba kernels)
SCG_ORDER = ("G0", "Y0", "Ymax", "scg_beta", "scg_n", "scg_g", "scg_h", "scg_xi", "melting_temperature")


@dataclass(frozen=True)
class Parameter:
    """One material parameter: SI value, the text given in the file, its source and status."""

    value: float
    text: str
    unit: str
    source: str
    status: str


@dataclass(frozen=True)
class Material:
    """A material with SI-valued parameters.  Derived thermal data are properties."""

    name: str
    description: str
    parameters: dict[str, Parameter] = field(repr=False)

    def __getattr__(self, key: str) -> float:
        params = self.__dict__.get("parameters", {})
        if key in params:
            return params[key].value
        raise AttributeError(f"material {self.__dict__.get('name')!r} has no parameter {key!r}")

    def has(self, key: str) -> bool:
        return key in self.parameters

    @property
    def heat_capacity(self) -> float:
        """c = kappa / (rho0 alpha) when the file gives the diffusivity."""
        if "heat_capacity" in self.parameters:
            return self.parameters["heat_capacity"].value
        return self.conductivity / (self.rho0 * self.parameters["diffusivity"].value)

    @property
    def diffusivity(self) -> float:
        """alpha = kappa / (rho0 c)."""
        if "diffusivity" in self.parameters:
            return self.parameters["diffusivity"].value
        return self.conductivity / (self.rho0 * self.heat_capacity)

    @property
    def effusivity(self) -> float:
        """Thermal effusivity e = kappa / sqrt(alpha) (thesis eq. 2.101)."""
        return self.conductivity / math.sqrt(self.diffusivity)

    @property
    def bulk_sound_speed(self) -> float:
        return self.eos_c0

    @property
    def shear_wave_speed(self) -> float:
        return math.sqrt(self.G0 / self.rho0)

    def scg_params(self) -> np.ndarray:
        """SCG parameters as a float64 array in :data:`SCG_ORDER` (for njit kernels)."""
        return np.array([self.parameters[k].value for k in SCG_ORDER], dtype=np.float64)

    def melt_law(self) -> tuple[float, float, float, float, float]:
        """(T_m0, K0 = rho0 c0^2, s, gamma0, a) of the SCG melt law
        (:func:`~shockfriction.materials.strength.scg_melt_temperature`); K0 = 0 (a constant T_m) when the
        material has no Hugoniot (eos_c0, eos_s) or no eos_gamma0.  a defaults to gamma0 (Gamma rho = const,
        the Mie-Grueneisen form of the hydrocode)."""
        if not (self.has("eos_c0") and self.has("eos_s") and self.has("eos_gamma0")):
            return (self.melting_temperature, 0.0, 0.0, 0.0, 0.0)
        g0 = self.eos_gamma0
        a = self.scg_melt_a if self.has("scg_melt_a") else g0
        return (self.melting_temperature, self.rho0 * self.eos_c0 ** 2, self.eos_s, g0, a)

    def melting_temperature_at(self, pressure) -> np.ndarray:
        """T_m at the pressure (Pa, compression > 0; arrays broadcast): the SCG melt law of :meth:`melt_law`."""
        from shockfriction.materials.strength import scg_melt_temperature
        law = self.melt_law()
        P = np.asarray(pressure, float)
        return np.vectorize(lambda x: scg_melt_temperature(x, *law), otypes=[float])(P)


def heat_share(first: Material, second: Material) -> float:
    """Share of the frictional heat entering ``first``: e1/(e1+e2) (thesis eq. 2.101)."""
    e1, e2 = first.effusivity, second.effusivity
    return e1 / (e1 + e2)


def _data_dir():
    return resources.files("shockfriction.materials") / "data"


@lru_cache(maxsize=None)
def _index() -> dict[str, str]:
    """Material name (as written in the file) -> file name."""
    out = {}
    for entry in _data_dir().iterdir():
        if entry.name.endswith(".toml"):
            with resources.as_file(entry) as p:
                out[read_toml(p)["name"]] = entry.name
    return out


def material_names() -> list[str]:
    return sorted(_index(), key=str.lower)


def _resolve(name: str) -> str:
    idx = _index()
    if name in idx:
        return name
    folded = {k.lower(): k for k in idx}
    if name.lower() in folded:
        return folded[name.lower()]
    raise DeckError(f"unknown material {name!r}: expected one of {', '.join(material_names())}")


@lru_cache(maxsize=None)
def get_material(name: str) -> Material:
    """Load a library material by name (case-insensitive)."""
    name = _resolve(name)
    with resources.as_file(_data_dir() / _index()[name]) as path:
        raw = read_toml(path)
        return parse_material(raw, str(path))


def parse_material(raw: dict, source: str = "material file") -> Material:
    """Build a :class:`Material` from the parsed TOML of a material file."""
    params: dict[str, Parameter] = {}
    for key, entry in raw.items():
        if key in ("name", "description"):
            continue
        if key not in PARAMETER_KINDS:
            raise DeckError(f"{source}: {key}: unknown parameter; expected one of {', '.join(PARAMETER_KINDS)}")
        if not isinstance(entry, dict) or not {"value", "source", "status"} <= set(entry):
            raise DeckError(f"{source}: {key}: expected a table with value, source and status")
        if entry["status"] not in STATUSES:
            raise DeckError(f"{source}: {key}.status = {entry['status']!r}: expected one of {STATUSES}")
        kind = PARAMETER_KINDS[key]
        try:
            if key == "tb_K":
                if "tb_lambda" not in raw:
                    raise UnitError("tb_K needs tb_lambda (its unit is pressure^lambda x time)")
                value = pressure_power_time_to_si(entry["value"], to_si(raw["tb_lambda"]["value"], "dimensionless"))
            else:
                value = to_si(entry["value"], kind)
        except UnitError as exc:
            raise DeckError(f"{source}: {key}.value = {entry['value']!r}: {exc}") from None
        has_unit = isinstance(entry["value"], str) and " " in entry["value"].strip()
        unit = str(entry["value"]).split(maxsplit=1)[1] if has_unit else ""
        params[key] = Parameter(value, str(entry["value"]), unit, entry["source"], entry["status"])
    missing = [k for k in REQUIRED if k not in params]
    if not ("diffusivity" in params or "heat_capacity" in params):
        missing.append("diffusivity or heat_capacity")
    if missing:
        raise DeckError(f"{source}: missing parameters: {', '.join(missing)}")
    return Material(raw.get("name", "?"), raw.get("description", ""), params)
