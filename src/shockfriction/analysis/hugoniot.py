"""Shock states of Mie-Grueneisen solids with a linear Us-up Hugoniot.

Hydrodynamic Hugoniot (Rankine-Hugoniot from rest, eta = 1 - rho0/rho):

    Us = c0 + s up,   P_H = rho0 Us up = rho0 c0^2 eta / (1 - s eta)^2,
    e_H = P_H (V0 - V) / 2 = P_H eta / (2 rho0),
    P(rho, e) = P_H(rho) + Gamma0 rho0 (e - e_H(rho))          (Gamma rho = Gamma0 rho0).

Impedance matching (plate impact, flyer at V on a target at rest): the interface
particle velocity u solves P_target(u) = P_flyer(V - u).

Uniaxial-strain elastic-plastic shocks (hypoelastic, von Mises, perfect plasticity or a
yield function of the state).  Longitudinal compressive stress Sigma = P - S_xx, with
S_xx = -(4/3) G ln(rho/rho0) while elastic and S_xx = -(2/3) Y on yield.  Each jump
satisfies, from the state ahead (index a) to the state behind (index b),

    mass      rho_a (U - u_a) = rho_b (U - u_b)
    momentum  Sigma_b - Sigma_a = rho_a (U - u_a) (u_b - u_a)
    energy    E_b - E_a = (Sigma_a + Sigma_b)(V_a - V_b)/2,  E = e + W_el,

where e is the EOS energy and W_el the stored elastic shear energy per unit mass
(e receives -P dV and the plastic work, as in the hydrocode).  Derivation and the
HEL formula sigma_HEL = (K + 4G/3) Y / (2G) in docs/theory/exact-solutions.md.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


@dataclass(frozen=True)
class LinearHugoniotEOS:
    """Mie-Grueneisen EOS on a linear Us = c0 + s up Hugoniot (SI units)."""

    rho0: float
    c0: float
    s: float
    gamma0: float

    @classmethod
    def from_material(cls, material) -> LinearHugoniotEOS:
        """Build from a library Material (eos_c0, eos_s, eos_gamma0, rho0)."""
        return cls(rho0=material.rho0, c0=material.eos_c0, s=material.eos_s, gamma0=material.eos_gamma0)

    @property
    def bulk_modulus(self) -> float:
        """Zero-pressure bulk modulus K0 = rho0 c0^2."""
        return self.rho0 * self.c0**2

    def shock_velocity(self, up: float) -> float:
        """Us = c0 + s up."""
        return self.c0 + self.s * up

    def hugoniot_pressure_of_up(self, up: float) -> float:
        """P_H = rho0 (c0 + s up) up."""
        return self.rho0 * self.shock_velocity(up) * up

    def hugoniot_density_of_up(self, up: float) -> float:
        """rho = rho0 Us / (Us - up)."""
        us = self.shock_velocity(up)
        return self.rho0 * us / (us - up)

    def hugoniot_pressure(self, rho):
        """P_H(rho) = rho0 c0^2 eta / (1 - s eta)^2, eta = 1 - rho0/rho."""
        eta = 1.0 - self.rho0 / np.asarray(rho, dtype=float)
        return self.rho0 * self.c0**2 * eta / (1.0 - self.s * eta) ** 2

    def hugoniot_energy(self, rho):
        """e_H(rho) = P_H eta / (2 rho0) (from rest at e = 0, P = 0)."""
        eta = 1.0 - self.rho0 / np.asarray(rho, dtype=float)
        return self.hugoniot_pressure(rho) * eta / (2.0 * self.rho0)

    def pressure(self, rho, e):
        """P(rho, e) = P_H(rho) + Gamma0 rho0 (e - e_H(rho))."""
        return self.hugoniot_pressure(rho) + self.gamma0 * self.rho0 * (e - self.hugoniot_energy(rho))

    def linear_in_energy(self, rho) -> tuple[float, float]:
        """(A, B) with P = A(rho) + B e."""
        return (self.hugoniot_pressure(rho) - self.gamma0 * self.rho0 * self.hugoniot_energy(rho),
                self.gamma0 * self.rho0)

    def isentropic_release_velocity(self, rho: float, e: float, p_end: float = 0.0) -> float:
        """Riemann integral int dP / (rho c) along the isentrope from (rho, e) down to p_end.

        The isentrope is de/dV = -P; along it dP/dV = dP/dV|_e - P dP/de|_V and the
        velocity gained is int sqrt(-dP/dV) dV.  For a symmetric impact without
        strength the free surface moves at up + this release velocity (~ 2 up).
        """
        def pressure_v(v, ee):
            return float(self.pressure(1.0 / v, ee))

        def rhs(v, y):
            ee = y[0]
            p = pressure_v(v, ee)
            h = 1e-7 * v
            dpdv_e = (pressure_v(v + h, ee) - pressure_v(v - h, ee)) / (2.0 * h)
            dpdv_s = dpdv_e - p * self.gamma0 * self.rho0
            return [-p, np.sqrt(max(-dpdv_s, 0.0))]

        def reached(v, y):
            return pressure_v(v, y[0]) - p_end
        reached.terminal = True
        v0 = 1.0 / rho
        sol = solve_ivp(rhs, (v0, 2.0 * v0), [e, 0.0], events=reached, rtol=1e-10, atol=1e-12,
                        method="DOP853")
        if sol.status != 1:
            raise RuntimeError("release isentrope did not reach the end pressure")
        return float(sol.y_events[0][0][1])


@dataclass(frozen=True)
class ImpactState:
    """Interface state of a plate impact: particle velocity, pressure, shock speeds, densities."""

    particle_velocity: float  # target material velocity (lab frame)
    pressure: float
    flyer_shock_speed: float  # relative to the flyer material
    target_shock_speed: float
    flyer_density: float
    target_density: float


def impedance_match(flyer: LinearHugoniotEOS, target: LinearHugoniotEOS, velocity: float) -> ImpactState:
    """Hydrodynamic impedance match: P_target(u) = P_flyer(V - u), root found by brentq."""
    if velocity <= 0.0:
        raise ValueError(f"impact velocity must be positive, got {velocity}")

    def mismatch(u):
        return target.hugoniot_pressure_of_up(u) - flyer.hugoniot_pressure_of_up(velocity - u)
    u = brentq(mismatch, 0.0, velocity, xtol=1e-14 * velocity, rtol=1e-15)
    return ImpactState(particle_velocity=u, pressure=target.hugoniot_pressure_of_up(u),
                       flyer_shock_speed=flyer.shock_velocity(velocity - u),
                       target_shock_speed=target.shock_velocity(u),
                       flyer_density=flyer.hugoniot_density_of_up(velocity - u),
                       target_density=target.hugoniot_density_of_up(u))


# --------------------------------------------------------------------------------------
# elastic-plastic uniaxial strain

YieldFunction = Callable[[float, float], float]  # Y(pressure, equivalent plastic strain)


@dataclass(frozen=True)
class UniaxialState:
    """A uniform state in uniaxial strain (SI; stress compressive positive)."""

    rho: float
    u: float
    e: float  # EOS (thermal + cold) specific energy
    pressure: float
    s_xx: float  # deviatoric stress along the wave (negative in compression)
    stress: float  # longitudinal compressive stress Sigma = P - S_xx
    plastic_strain: float
    elastic_energy: float  # stored shear energy per unit mass


@dataclass(frozen=True)
class TwoWaveSolution:
    """Elastic precursor and plastic shock driven by a piston (lab-frame speeds)."""

    precursor: UniaxialState
    final: UniaxialState
    precursor_speed: float
    plastic_speed: float | None  # None when the drive stays elastic (one wave)
    hel: float  # longitudinal stress of the Hugoniot elastic limit

    @property
    def two_waves(self) -> bool:
        return self.plastic_speed is not None


def _yield(yield_stress: float | YieldFunction, pressure: float, plastic_strain: float) -> float:
    return float(yield_stress(pressure, plastic_strain)) if callable(yield_stress) else float(yield_stress)


def _elastic_energy_hypo(G: float, rho0: float, rho: float) -> float:
    """Deviatoric work stored in uniaxial hypoelastic loading: (4/3) G int_V0^V ln(V'/V0) dV'."""
    v0, v = 1.0 / rho0, 1.0 / rho
    return 4.0 / 3.0 * G * (v * np.log(v / v0) - v + v0)


def _elastic_jump(eos: LinearHugoniotEOS, G: float, rho: float) -> UniaxialState:
    """State behind an elastic shock from rest that compresses to rho (RH closed form)."""
    s_xx = -4.0 / 3.0 * G * np.log(rho / eos.rho0)
    dv = 1.0 / eos.rho0 - 1.0 / rho
    w_el = _elastic_energy_hypo(G, eos.rho0, rho)
    a, b = eos.linear_in_energy(rho)
    # Sigma = A + B e - S_xx, e = Sigma dv/2 - W_el  ->  Sigma (1 - B dv/2) = A - B W_el - S_xx
    stress = (a - b * w_el - s_xx) / (1.0 - 0.5 * b * dv)
    e = 0.5 * stress * dv - w_el
    u = np.sqrt(stress * dv)
    return UniaxialState(rho=rho, u=u, e=e, pressure=stress + s_xx, s_xx=s_xx, stress=stress,
                         plastic_strain=0.0, elastic_energy=w_el)


def hugoniot_elastic_limit(eos: LinearHugoniotEOS, shear_modulus: float,
                           yield_stress: float | YieldFunction) -> UniaxialState:
    """State at the HEL: the elastic jump whose deviator reaches (4/3) G ln(rho/rho0) = (2/3) Y(P)."""
    G = shear_modulus

    def mismatch(log_ratio):
        state = _elastic_jump(eos, G, eos.rho0 * np.exp(log_ratio))
        return 4.0 / 3.0 * G * log_ratio - 2.0 / 3.0 * _yield(yield_stress, state.pressure, 0.0)
    hi = 1e-6
    while mismatch(hi) < 0.0:
        hi *= 2.0
        if hi > 1.0:
            raise ValueError("no Hugoniot elastic limit below a density ratio of e")
    log_ratio = brentq(mismatch, 0.0, hi, xtol=1e-15, rtol=1e-14)
    return _elastic_jump(eos, G, eos.rho0 * np.exp(log_ratio))


def _plastic_state(eos: LinearHugoniotEOS, G: float, yield_stress, ahead: UniaxialState,
                   rho: float, stored: float | None = None) -> UniaxialState:
    """State on yield at density rho reached by one shock from `ahead` (energy jump closed form).

    `stored` is the shear energy stored on yield for perfect plasticity (default: that of
    `ahead`, which is then itself on yield); a yield function uses 3 S_xx^2 / (8 G rho).
    """
    stored = ahead.elastic_energy if stored is None else stored
    dv = 1.0 / ahead.rho - 1.0 / rho
    log_total = np.log(rho / eos.rho0)
    a, b = eos.linear_in_energy(rho)
    y = _yield(yield_stress, ahead.pressure, 0.0)
    for _ in range(50):  # fixed point on Y(P, eps_p) (one pass for perfect plasticity)
        s_xx = -2.0 / 3.0 * y
        eps_p = max(2.0 / 3.0 * (log_total - y / (2.0 * G)), 0.0)
        w_el = 3.0 * s_xx**2 / (8.0 * G * rho) if callable(yield_stress) else stored
        base = ahead.e + ahead.elastic_energy - w_el
        stress = (a + b * (base + 0.5 * ahead.stress * dv) - s_xx) / (1.0 - 0.5 * b * dv)
        pressure = stress + s_xx
        y_new = _yield(yield_stress, pressure, eps_p)
        if abs(y_new - y) <= 1e-13 * max(abs(y), 1.0):
            break
        y = y_new
    e = base + 0.5 * (ahead.stress + stress) * dv
    jump = (stress - ahead.stress) * dv
    u = ahead.u + np.sqrt(max(jump, 0.0))
    return UniaxialState(rho=rho, u=u, e=e, pressure=pressure, s_xx=s_xx, stress=stress,
                         plastic_strain=eps_p, elastic_energy=w_el)


def elastic_plastic_piston(eos: LinearHugoniotEOS, shear_modulus: float,
                           yield_stress: float | YieldFunction, piston_velocity: float) -> TwoWaveSolution:
    """Waves driven into material at rest by a piston at constant velocity (uniaxial strain).

    Below the HEL particle velocity one elastic shock; above it the elastic precursor
    (HEL state) and a slower plastic shock to the piston velocity; when the plastic shock
    would be faster than the precursor (overdriven), one plastic shock from rest
    (`plastic_speed` None, `precursor` = `final`).
    """
    if piston_velocity <= 0.0:
        raise ValueError(f"piston velocity must be positive, got {piston_velocity}")
    G = shear_modulus
    hel = hugoniot_elastic_limit(eos, G, yield_stress)
    hel_speed = hel.rho * hel.u / (hel.rho - eos.rho0)
    if piston_velocity <= hel.u:
        def mismatch_elastic(log_ratio):
            return _elastic_jump(eos, G, eos.rho0 * np.exp(log_ratio)).u - piston_velocity
        log_ratio = brentq(mismatch_elastic, 0.0, np.log(hel.rho / eos.rho0), xtol=1e-16, rtol=1e-15)
        final = _elastic_jump(eos, G, eos.rho0 * np.exp(log_ratio))
        if final.rho - eos.rho0 > 1e-6 * eos.rho0:  # mass: U = rho u / (rho - rho0)
            speed = final.rho * final.u / (final.rho - eos.rho0)
        else:  # a jump of < 1e-6 in density: the acoustic limit c_L (within ~1e-6), where the jump's own
            speed = longitudinal_sound_speed(eos, G)  # rounding would cost more (0/0 once rho rounds to rho0)
        return TwoWaveSolution(precursor=final, final=final, precursor_speed=speed, plastic_speed=None,
                               hel=hel.stress)

    def mismatch(rho):
        return _plastic_state(eos, G, yield_stress, hel, rho).u - piston_velocity
    hi = hel.rho * 1.01
    while mismatch(hi) < 0.0:
        hi = hel.rho + 2.0 * (hi - hel.rho)
        if hi > 10.0 * eos.rho0:
            raise ValueError("no plastic shock state found below ten times the initial density")
    rho = brentq(mismatch, hel.rho * (1.0 + 1e-12), hi, xtol=1e-13 * hel.rho, rtol=1e-15)
    final = _plastic_state(eos, G, yield_stress, hel, rho)
    # lab-frame plastic shock speed from mass: rho_a (U - u_a) = rho_b (U - u_b)
    plastic_speed = (final.rho * final.u - hel.rho * hel.u) / (final.rho - hel.rho)
    if plastic_speed < hel_speed:
        return TwoWaveSolution(precursor=hel, final=final, precursor_speed=hel_speed,
                               plastic_speed=plastic_speed, hel=hel.stress)
    # overdriven: the plastic shock would outrun the precursor, so one shock from rest to yield
    rest = UniaxialState(rho=eos.rho0, u=0.0, e=0.0, pressure=0.0, s_xx=0.0, stress=0.0,
                         plastic_strain=0.0, elastic_energy=0.0)

    def mismatch_single(rho_b):
        return _plastic_state(eos, G, yield_stress, rest, rho_b, hel.elastic_energy).u - piston_velocity
    hi = final.rho * 1.01
    while mismatch_single(hi) < 0.0:
        hi = eos.rho0 + 2.0 * (hi - eos.rho0)
    rho = brentq(mismatch_single, hel.rho, hi, xtol=1e-13 * hel.rho, rtol=1e-15)
    final = _plastic_state(eos, G, yield_stress, rest, rho, hel.elastic_energy)
    speed = final.rho * final.u / (final.rho - eos.rho0)
    return TwoWaveSolution(precursor=final, final=final, precursor_speed=speed, plastic_speed=None,
                           hel=hel.stress)


def symmetric_impact(eos: LinearHugoniotEOS, shear_modulus: float, yield_stress: float | YieldFunction,
                     impact_velocity: float) -> TwoWaveSolution:
    """Symmetric plate impact: by symmetry the target is driven at half the impact velocity."""
    return elastic_plastic_piston(eos, shear_modulus, yield_stress, 0.5 * impact_velocity)


def elastic_hel_linear(eos: LinearHugoniotEOS, shear_modulus: float, yield_stress: float) -> float:
    """Small-strain HEL, sigma_HEL = (K + 4G/3) Y / (2G) with K = rho0 c0^2."""
    return (eos.bulk_modulus + 4.0 / 3.0 * shear_modulus) * yield_stress / (2.0 * shear_modulus)


def longitudinal_sound_speed(eos: LinearHugoniotEOS, shear_modulus: float) -> float:
    """c_L = sqrt((K + 4G/3) / rho0)."""
    return float(np.sqrt((eos.bulk_modulus + 4.0 / 3.0 * shear_modulus) / eos.rho0))


def free_surface_velocity_estimate(eos: LinearHugoniotEOS, shear_modulus: float,
                                   solution: TwoWaveSolution) -> float:
    """Free-surface velocity after a two-wave shock reaches a free surface (estimate).

    Hydrodynamic part: up + the isentropic release velocity (about 2 up).  Strength
    correction, first order in the HEL: the release unloads elastically over twice the
    HEL and the loading only over once, u_fs - 2 up ~ sigma_HEL (1/Z_L - 1/Z_B) with
    Z_L = rho0 c_L, Z_B = rho0 c0 (negative: strength lowers the free-surface velocity).
    It ignores the interaction of the reflected precursor with the plastic shock.
    """
    up = solution.final.u
    hydro = up + eos.isentropic_release_velocity(eos.hugoniot_density_of_up(up), 0.5 * up * up)
    if not solution.two_waves:
        return 2.0 * up
    z_l = eos.rho0 * longitudinal_sound_speed(eos, shear_modulus)
    z_b = eos.rho0 * eos.c0
    return hydro + solution.hel * (1.0 / z_l - 1.0 / z_b)


def scg_yield_function(material, temperature: float = 300.0) -> YieldFunction:
    """Y(P, eps_p) of the library's SCG model (materials/strength.py) at a fixed temperature.

    For the two-wave solution with SCG strength; the shock heating of a few kelvin at
    plate-impact pressures changes G/G0 by h dT ~ 1e-3 and is left out.
    """
    from shockfriction.materials.strength import yield_stress

    def y_of(pressure: float, plastic_strain: float) -> float:
        return float(yield_stress(material, plastic_strain, pressure, temperature))
    return y_of


@dataclass(frozen=True)
class ElasticPlasticImpact:
    """Plate impact with strength: interface velocity and the waves in flyer and target."""

    particle_velocity: float  # interface (target material) velocity, lab frame
    stress: float  # longitudinal compressive stress at the interface
    flyer: TwoWaveSolution  # waves in the flyer, in the flyer's rest frame
    target: TwoWaveSolution


def impedance_match_elastic_plastic(flyer: LinearHugoniotEOS, flyer_shear_modulus: float,
                                    flyer_yield: float | YieldFunction, target: LinearHugoniotEOS,
                                    target_shear_modulus: float, target_yield: float | YieldFunction,
                                    velocity: float) -> ElasticPlasticImpact:
    """Interface state of a plate impact when both plates have strength.

    Each plate carries its own elastic-plastic wave system (a piston problem in its rest
    frame); continuity of velocity and longitudinal stress at the interface gives
    Sigma_target(u) = Sigma_flyer(V - u), solved by brentq.
    """
    if velocity <= 0.0:
        raise ValueError(f"impact velocity must be positive, got {velocity}")

    def mismatch(u):
        t = elastic_plastic_piston(target, target_shear_modulus, target_yield, u).final.stress
        f = elastic_plastic_piston(flyer, flyer_shear_modulus, flyer_yield, velocity - u).final.stress
        return t - f
    eps = 1e-9 * velocity
    u = brentq(mismatch, eps, velocity - eps, xtol=1e-12 * velocity, rtol=1e-14)
    tgt = elastic_plastic_piston(target, target_shear_modulus, target_yield, u)
    fly = elastic_plastic_piston(flyer, flyer_shear_modulus, flyer_yield, velocity - u)
    return ElasticPlasticImpact(particle_velocity=u, stress=tgt.final.stress, flyer=fly, target=tgt)
