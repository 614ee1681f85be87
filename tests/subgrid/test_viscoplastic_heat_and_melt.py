"""The viscoplastic columns' two-sided heat and pressure-dependent melting (docs/theory/viscoplastic.md).

* Two semi-infinite bodies under a constant interface flux q (Carslaw & Jaeger; digest part 1): both surfaces at
  T0 + 2 q sqrt(t/pi)/(e1 + e2) and the heat split e1/(e1 + e2), e = sqrt(kappa rho c) the effusivities.  The
  flux is made by a column that slides at a fixed Coulomb cap under an imposed slip, quasi-static and elastic
  (its surface velocity is then only the thermal change of its elastic strain, ~1e-6 of the slip).
* The melting temperature of the columns against the SCG melt law written out here with an independent root
  finder for the Hugoniot compression.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material

AL = get_material("Al5083-H111")
ST = get_material("AISI321")
A7 = get_material("Al7075-T6")


def _effusivity(m):
    return math.sqrt(m.conductivity * m.rho0 * m.heat_capacity)


def test_two_semi_infinite_bodies_under_a_constant_flux():
    tau, V, dt = 50e6, 100.0, 1e-9
    vp = ViscoplasticColumns(1, AL, beta_T=0.5, inertia=False, far_end="held", other=ST, pressure_melting=False)
    q = tau * V
    e1, e2 = _effusivity(AL), _effusivity(ST)
    worst_T = worst_split = 0.0
    for n in range(1, 501):
        vp.step(1e9, V, V, 0.0, tau, dt)
        if n in (100, 250, 500):
            t = n * dt
            T_exact = 300.0 + 2.0 * q * math.sqrt(t / math.pi) / (e1 + e2)
            E = vp.energies()
            split = E["heat_conducted_other"][0] / E["friction_work"][0]
            eT = abs(vp.theta_interface[0] - T_exact) / (T_exact - 300.0)
            es = abs(split / (e2 / (e1 + e2)) - 1.0)
            # the other body's column holds what it took
            assert vp.other_heat_stored()[0] == pytest.approx(E["heat_conducted_other"][0], rel=1e-12)
            print(f"\n{n} ns: T(0) {vp.theta_interface[0]:.3f} vs {T_exact:.3f} K (rise {eT:.2e}); other body's "
                  f"share {split:.5f} vs e2/(e1 + e2) = {e2 / (e1 + e2):.5f} ({es:.2e})", end="")
            worst_T, worst_split = max(worst_T, eT), max(worst_split, es)
    assert abs(vp.slip_local[0] - V) < 2e-3  # the flux is tau V to 2e-5
    assert worst_T < 4e-3 and worst_split < 3.5e-3  # measured 3.05e-3, 2.53e-3 (first-order start)
    assert abs(vp.energy_residual()[0]) < 1e-12


def _melt_law_independent(P, m):
    """T_m = T_m0 exp(2a(1 - 1/eta)) eta^(2(gamma0 - a - 1/3)) with eta from P = rho0 c0^2 mu/(1 - s mu)^2 by brentq."""
    rho0, c0, s, g0 = m.rho0, m.eos_c0, m.eos_s, m.eos_gamma0
    a = m.scg_melt_a
    if P == 0.0:
        return m.melting_temperature
    mu = brentq(lambda x: rho0 * c0 ** 2 * x / (1.0 - s * x) ** 2 - P, 0.0, 0.5 / s, xtol=1e-16, rtol=1e-15)
    eta = 1.0 / (1.0 - mu)
    return m.melting_temperature * math.exp(2.0 * a * (1.0 - 1.0 / eta)) * eta ** (2.0 * (g0 - a - 1.0 / 3.0))


@pytest.mark.parametrize("material", ["Al7075-T6", "Al5083-H111"])
def test_melting_temperature_follows_the_scg_melt_law(material):
    m = get_material(material)
    vp = ViscoplasticColumns(3, m, beta_T=0.7, n_cells=20, thickness=1e-6)
    P = np.array([0.0, 5e9, 10e9])
    vp.step(P, 1.0, 1.0, 0.0, 1e3, 1e-10)
    for k, p in enumerate(P):
        ref = _melt_law_independent(float(p), m)
        print(f"\n{material}: T_m({p / 1e9:.0f} GPa) = {vp.TF[k]:.3f} K (independent {ref:.3f} K)", end="")
        assert vp.TF[k] == pytest.approx(ref, rel=1e-12)
        assert m.melting_temperature_at(p) == pytest.approx(ref, rel=1e-12)
    assert vp.TF[1] > vp.TF[0] + 150.0  # 7075: 908 -> 1120 K at 5 GPa


def test_melt_viscosity_rises_with_pressure():
    """eta_L(T_m(p), p) = eta_F exp(E/R (1/T_m - 1/T_F) + p V*/(R T_m)) (7075: V* = 2.1e-6 m^3/mol)."""
    from shockfriction.friction.subgrid.viscoplastic import R_GAS, liquid_viscosity
    m = A7
    p = 5e9
    Tm = float(m.melting_temperature_at(p))
    eta = liquid_viscosity(Tm, m.liquid_viscosity, m.liquid_viscosity_activation, m.melting_temperature, Tm,
                           p * m.liquid_viscosity_activation_volume / R_GAS)
    ref = m.liquid_viscosity * math.exp(m.liquid_viscosity_activation * (1 / Tm - 1 / m.melting_temperature)
                                        + p * 2.1e-6 / (R_GAS * Tm))
    assert eta == pytest.approx(ref, rel=1e-14)
    assert eta > m.liquid_viscosity  # the pressure factor outweighs the hotter melting point
