"""Time accuracy of the viscoplastic columns (issue 25, item 5; docs/theory/viscoplastic.md, "Time accuracy").

With time_scheme = "bdf2" (an option; the default is backward Euler, see the docs' "Cost") the columns are
integrated by variable-step BDF2 (L-stable, second order; the first step of a run in sub-steps growing from dt/64)
for imposed slip on solid columns, its numerical dissipation deposited as heat and booked, so that the energy books
stay exact.

  d'Alembert at the production Courant number (1 ns steps, 40 nm cells, c_s dt/dz = 82), velocity step 1 m/s,
  numerical heat (rows numerical_heat + softening_heat: the kinetic and elastic parts) / wave's work:
                                  30 ns       300 ns
      backward Euler              10.3 %      3.3 %     (5.1 % / 1.6 % in numerical_heat alone)
      BDF2                        3.0 %       0.48 %
  Any L-stable scheme must damp the step's content above ~1/dt, about dt/(pi t) of the work (1 % at 30 ns).

  Ball loading, f = 0.7, continued column, dt 1 -> 0.5 ns (relative change; Theta(0) against its rise above 300 K):
                                  Theta(0) 0.3 us   tau 0.3 us   Theta(0) 1 us   tau 1 us
      backward Euler              1.13 %            4.8e-4       0.72 %          1.1e-4
      BDF2 (+ start sub-steps)    0.21 %            8.0e-5       0.10 %          3.6e-5
"""

import math

import numpy as np
import pytest

from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material, heat_share
from shockfriction.materials.strength import scg_shear_modulus, scg_shear_ratio

AL = get_material("Al5083-H111")
ST = get_material("AISI321")
BETA = heat_share(AL, ST)
P_WAVE = 1e9
G_P = scg_shear_modulus(P_WAVE, 300.0, AL.scg_params())
ZP = math.sqrt(AL.rho0 * G_P)
CS = math.sqrt(G_P / AL.rho0)
MELT = {"latent_heat": 3.97e5, "liquid_viscosity": 0.844e-3}


def wave(t_end, scheme, dt=1e-9, V=1.0):
    """Velocity step V at z = 0 (imposed, stuck) into the production layer (20 um / 500 cells of 40 nm),
    continued beyond the wave's reach; returns the columns and the numerical heat over the wave's work."""
    c = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=20e-6, n_cells=500, inertia=True,
                            depth=1.2 * CS * t_end, time_scheme=scheme, **MELT)
    for _ in range(int(round(t_end / dt))):
        c.step(P_WAVE, V, V, 0.0, 1e12, dt)
        assert c.status[0] == 0
    d = c.energies()
    return c, (d["numerical_heat"][0] + d["softening_heat"][0]) / d["friction_work"][0]


def test_dalembert_numerical_heat_at_production_courant():
    """The numerical heat of an elastic wave at c_s dt/dz = 82 is reported and below 1 % of its work (300 ns)."""
    c, frac = wave(300e-9, "bdf2")
    courant = CS * 1e-9 / c.dz[0]
    d = c.energies()
    print(f"\nCourant {courant:.0f}: numerical heat {frac:.2%} of the wave's work (rows: numerical "
          f"{d['numerical_heat'][0]:.4g}, softening {d['softening_heat'][0]:.4g} J/m^2), energy residual "
          f"{c.energy_residual()[0]:.1e}, tau/(rho c_s V) {c.tau[0] / ZP:.5f}")
    assert courant > 75.0
    assert frac < 0.01  # measured 0.48 % (backward Euler: 3.3 %)
    assert frac > 0.0
    assert abs(c.energy_residual()[0]) < 1e-10
    assert c.tau[0] == pytest.approx(ZP, rel=3e-3)  # d'Alembert: rho c_s V (measured -1.4e-3: the graded cells)
    s = c.stress[0] / ZP
    zc = 0.5 * (c.z[1:] + c.z[:-1])
    assert abs(zc[np.argmax(s < 0.5)] - CS * 300e-9) < 5e-6  # the front where the wave is (measured 1.2 um)


def test_dalembert_early_against_backward_euler():
    """30 ns (30 steps): BDF2 3.0 %, backward Euler 10.3 % of the work (the step's unresolved content)."""
    _, bdf = wave(30e-9, "bdf2")
    _, be = wave(30e-9, "backward_euler")
    print(f"\n30 ns: numerical heat BDF2 {bdf:.2%}, backward Euler {be:.2%}")
    assert bdf < 0.035 and be > 0.09
    assert bdf < 0.35 * be


def ball(dt, steps_at=(300e-9, 1e-6), f=0.7, scheme="bdf2"):
    depth = 1.2 * math.sqrt(AL.G0 * scg_shear_ratio(10e9, 300.0, AL.scg_g, AL.scg_h, AL.scg_xi,
                                                    AL.melting_temperature) / AL.rho0) * 1e-6
    c = ViscoplasticColumns(1, AL, beta_T=BETA, f=f, thickness=20e-6, n_cells=500, inertia=True, depth=depth,
                            time_scheme=scheme)
    marks = {int(round(t / dt)): t for t in steps_at}
    out = {}
    for n in range(1, max(marks) + 1):
        tau, _ = c.step(10e9, 200.0, 200.0, 0.0, 3e9, dt)
        assert c.status[0] == 0
        if n in marks:
            out[marks[n]] = (c.theta_interface[0], tau[0])
    assert abs(c.energy_residual()[0]) < 1e-10
    return out


@pytest.mark.slow
def test_ball_time_step_converged():
    """Ball loading, f = 0.7, continued column: Theta(0) and tau at 0.3 and 1 us change < 0.5 % from dt = 1 to
    0.5 ns (Theta(0) relative to its rise above 300 K, the stricter measure)."""
    a, b = ball(1e-9), ball(0.5e-9)
    for t in a:
        dT = abs(b[t][0] - a[t][0]) / (b[t][0] - 300.0)
        dtau = abs(b[t][1] / a[t][1] - 1.0)
        print(f"\nt = {t * 1e6:.1f} us: Theta(0) {a[t][0]:.3f} -> {b[t][0]:.3f} K ({dT:.2e} of the rise), "
              f"tau {a[t][1] / 1e6:.4f} -> {b[t][1] / 1e6:.4f} MPa ({dtau:.1e})", end="")
        assert dT < 0.005 and dtau < 0.005  # the requirement
        assert dT < 3e-3 and dtau < 2e-4  # measured 2.1e-3 / 1.0e-3 and 8.0e-5 / 3.6e-5 (0.3 / 1 us)


def test_unloading_and_partner_mass():
    """A falling normal stress with imposed slip (a step whose last mean traction exceeds the new cap is backward
    Euler): tau within the cap, books exact.  With a partner mass (k > 0, slide lines) the columns are stepped by
    backward Euler: the same bytes as time_scheme = "backward_euler"."""
    c = ViscoplasticColumns(2, AL, beta_T=BETA, thickness=10e-6, n_cells=100, inertia=True, f=0.7,
                            time_scheme="bdf2", **MELT)
    for n in range(150):
        sn = 10e9 * (1.0 - 0.005 * max(n - 50, 0))
        cap = 0.3 * sn
        tau, _ = c.step(sn, [200.0, 150.0], [200.0, 150.0], 0.0, cap, 1e-9)
        assert np.all(c.status == 0)
        assert np.all(np.abs(tau) <= cap * (1.0 + 1e-12))
    res = np.max(np.abs(c.energy_residual()))
    print(f"\nunloading: energy residual {res:.1e}, tau {tau / 1e6} MPa", end="")
    assert res < 1e-10
    out = []
    for scheme in ("bdf2", "backward_euler"):
        c = ViscoplasticColumns(2, AL, beta_T=BETA, thickness=10e-6, n_cells=100, inertia=True, f=0.7,
                                time_scheme=scheme, **MELT)
        slip = np.array([200.0, 150.0])
        for n in range(30):
            tau, v_half = c.step(10e9, slip, slip, [2e-7, 5e-8], 3e9, 1e-9)
            slip = v_half
        out.append((tau, v_half, c.T.copy()))
        assert np.max(np.abs(c.energy_residual())) < 1e-10
    assert all(np.array_equal(a, b) for a, b in zip(*out))
