"""Viscoplastic sub-grid columns against exact solutions: d'Alembert shear wave and non-reflecting far end,
exact discrete energy balance, steady Couette melt film with viscous heating: constant viscosity, Arrhenius fully
molten, and partly molten (a melt front inside the layer, Arrhenius and pressure viscosity, inertia on; shooting
solution) (docs/theory/viscoplastic.md)."""

import math
import warnings

import numpy as np
import pytest

from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material, heat_share
from shockfriction.materials.strength import scg_shear_modulus

AL = get_material("Al5083-H111")
ST = get_material("AISI321")
BETA = heat_share(AL, ST)
P_WAVE = 1e9  # normal stress of the wave tests: G = G(p, 300 K) sets c_s and the impedance
G_P = scg_shear_modulus(P_WAVE, 300.0, AL.scg_params())
ZP = math.sqrt(AL.rho0 * G_P)
CS = math.sqrt(G_P / AL.rho0)
MELT = {"latent_heat": 3.97e5, "liquid_viscosity": 0.844e-3}


def wave_run(t_end, n_cells=100, h=4e-6, V=1.0, scheme="backward_euler"):
    c = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=h, n_cells=n_cells, inertia=True, time_scheme=scheme,
                            **MELT)
    dt = 0.25 * (h / n_cells) / CS
    n = int(round(t_end / dt))
    for _ in range(n):
        c.step(P_WAVE, V, V, 0.0, 1e12, dt)  # velocity step V imposed at z = 0 (stick, imposed slip)
    return c, n * dt


@pytest.mark.parametrize("scheme", ["bdf2", "backward_euler"])
def test_shear_wave_matches_dalembert(scheme):
    """tau(z, t) = rho c_s V H(c_s t - z): plateau value and front position (inertia on, elastic), at Courant 0.25
    (the production Courant number, ~80: tests/subgrid/test_viscoplastic_time.py).  BDF2 shows the staggered grid's
    dispersive ripples behind the front (max 0.146 of the plateau, mean -4.0e-3 over the 1.7 um behind it) that
    backward Euler damps (mean 1e-5)."""
    V = 1.0
    c, t = wave_run(0.6e-9, scheme=scheme)
    Z = ZP
    s = c.stress[0] / (Z * V)
    zc = 0.5 * (c.z[1:] + c.z[:-1])
    front = CS * t
    behind = zc < front - 0.3e-6
    plateau = np.mean(s[behind])
    # first cell (from z = 0) where the stress falls below half the plateau
    k = np.argmax(s < 0.5)
    dz = c.z[1]
    print(f"\nplateau {plateau:.5f} (exact 1), front {zc[k]*1e6:.3f} um vs {front*1e6:.3f} um (dz {dz*1e9:.0f} nm), "
          f"max |s - 1| behind {np.max(np.abs(s[behind] - 1)):.3f}")
    if scheme == "backward_euler":
        assert plateau == pytest.approx(1.0, abs=1e-4)  # measured 1e-5 (backward Euler: no ripples)
    else:
        assert plateau == pytest.approx(1.0, abs=6e-3)  # measured -4.0e-3 (the grid's ripples, not damped)
    assert abs(zc[k] - front) < 1.0 * dz
    assert np.all(np.abs(s[zc > front + 0.5e-6]) < 0.05)   # nothing ahead of the front
    # the surface traction is the impedance times the imposed velocity
    assert c.tau[0] == pytest.approx(Z * V, rel=2e-3)


def test_far_end_impedance_does_not_reflect():
    """After the front has left through z = h the column carries tau = rho c_s V and v = V uniformly
    (a reflection from a free/fixed end would give 0 or 2 rho c_s V)."""
    V = 1.0
    c, _ = wave_run(3.0e-9)
    Z = ZP
    s = c.stress[0] / (Z * V)
    print(f"\nafter exit: stress/ZV in [{s.min():.4f}, {s.max():.4f}], v/V in [{c.v.min():.4f}, {c.v.max():.4f}]")
    print(f"mean stress/ZV {s.mean():.5f}, mean v/V {c.v.mean():.5f}")
    assert abs(s.mean() - 1.0) < 1e-4 and abs(c.v.mean() / V - 1.0) < 1e-4   # a reflection would give O(1)
    assert np.max(np.abs(s - 1.0)) < 1e-3      # measured 3e-4 (the smeared tail of the front; BDF2: 4.5e-3, ripples)
    assert np.max(np.abs(c.v[:, 0] / V - 1.0)) < 1e-3
    assert c.energies()["radiated"][0] > 0.0


@pytest.mark.parametrize("inertia", [True, False])
def test_energy_balance_is_exact(inertia):
    """friction work = heat to the other body + stored heat (sensible + latent) + cold work + kinetic
    + elastic + radiated, to round-off, at Ball loading with f = 0.7 (plastic flow) and with no Tresca
    branch at 5 GPa (the column melts: latent heat and viscous film)."""
    cols = ViscoplasticColumns(2, AL, beta_T=BETA, thickness=10e-6, n_cells=100, inertia=inertia, f=None, **MELT)
    worst = 0.0
    film = 0.0
    for n in range(300):
        cols.step([10e9, 5e9], [200.0, 250.0], [200.0, 250.0], 0.0, [0.7 * 680e6 / math.sqrt(3), 3e9], 1e-9)
        assert np.all(cols.status == 0)
        worst = max(worst, np.max(np.abs(cols.energy_residual())))
        film = max(film, cols.film_thickness[1])
    d = cols.energies()
    print(f"\ninertia={inertia}: max relative energy residual {worst:.2e}; latent {d['latent']} J/m^2, "
          f"film {film*1e9:.0f} nm, T(0) {cols.theta_interface}")
    assert worst < 1e-10
    assert d["plastic_work"][0] > 0.0
    assert d["latent"][1] > 0.0 and d["viscous_heat"][1] > 0.0


def test_couette_film_with_viscous_heating():
    """Steady Couette film: surface (z = 0) stuck to the slider at V, adiabatic; z = h fixed, held at T_h.
    Constant viscosity: tau = eta V/h, T(z) = T_h + eta V^2/(2 kappa h^2) (h^2 - z^2)."""
    eta, V, h, T_h = 0.1, 500.0, 2e-6, AL.melting_temperature + 200.0
    c = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=h, n_cells=40, inertia=False, f=None,
                            latent_heat=3.97e5, liquid_viscosity=eta, liquid_activation=0.0, far_temperature=T_h)
    c.set_temperature(T_h)
    for _ in range(1000):
        c.step(1e9, V, V, 0.0, 1e12, 1e-9)
    tau_exact = eta * V / h
    T_exact = T_h + eta * V**2 / (2 * AL.conductivity * h**2) * (h**2 - c.z**2)
    rise = T_exact[0] - T_h
    err_T = np.max(np.abs(c.T[:, 0] - T_exact)) / rise
    err_tau = abs(c.tau[0] / tau_exact - 1)
    print(f"\nCouette: tau {c.tau[0]/1e6:.4f} MPa (exact {tau_exact/1e6:.4f}), rise {c.T[0,0]-T_h:.3f} K "
          f"(exact {rise:.3f}), rel. errors T {err_T:.2e}, tau {err_tau:.2e}; film {c.film_thickness[0]*1e6:.2f} um")
    assert err_tau < 1e-12
    assert err_T < 1e-9   # measured 2e-13: the vertex-centred scheme is exact for the parabola
    assert c.film_thickness[0] == pytest.approx(h)
    assert abs(c.energy_residual()[0]) < 1e-10


def _couette_arrhenius_exact(eta_F, E_R, T_F, kappa, V, h, T_h, guess):
    """Steady Couette film with eta(T) = eta_F exp(E_R (1/T - 1/T_F)) (derived in docs/theory/viscoplastic.md):
    s uniform, kappa T'' = -s^2/eta(T), T'(0) = 0, T(h) = T_h; u' = -s/eta(T), u(0) = V, u(h) = 0.  Shooting on
    (T(0), s) with an adaptive Runge-Kutta integration (rtol 1e-12), from ``guess`` = (T(0), s) (the root does not
    depend on it); returns s and T(z) as a callable."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import fsolve

    def rhs(z, y, s):
        T, dT, u = y
        eta = eta_F * np.exp(E_R * (1.0 / T - 1.0 / T_F))
        return [dT, -s * s / (kappa * eta), -s / eta]

    def shoot(p):
        T0, s = p[0], p[1] * 1e6
        sol = solve_ivp(rhs, (0.0, h), [T0, 0.0, V], args=(s,), rtol=1e-12, atol=1e-12, dense_output=True)
        return sol, [sol.y[0, -1] - T_h, sol.y[2, -1] / V]

    with warnings.catch_warnings():  # "xtol too small": fsolve stops at round-off; the residual is checked below
        warnings.simplefilter("ignore", RuntimeWarning)
        p = fsolve(lambda p: shoot(p)[1], [guess[0], guess[1] / 1e6], xtol=1e-14)
    sol, res = shoot(p)
    assert max(abs(res[0]), abs(res[1])) < 1e-9
    return p[1] * 1e6, (lambda z: sol.sol(z)[0])


def test_couette_film_with_arrhenius_viscosity_and_inertia():
    """The Couette film with a temperature-dependent (Arrhenius) melt viscosity, shear inertia on and the far end
    held: steady stress and temperature against the shooting solution.  E_R = 2e4 K makes the viscosity vary by
    x3.8 across the film (111 K rise).  Measured on 200 cells: tau 4.8e-6, T 1.4e-6 of the rise."""
    eta_F, E_R, V, h = 0.2, 2.0e4, 600.0, 2e-6
    T_F = AL.melting_temperature
    T_h = T_F + 20.0
    c = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=h, n_cells=200, inertia=True, far_end="held", f=None,
                            latent_heat=3.97e5, liquid_viscosity=eta_F, liquid_activation=E_R, far_temperature=T_h,
                            pressure_melting=False)
    c.set_temperature(T_h)
    for _ in range(2000):
        c.step(1e9, V, V, 0.0, 1e12, 1e-9)
    s_exact, T_of = _couette_arrhenius_exact(eta_F, E_R, T_F, AL.conductivity, V, h, T_h,
                                             (1.02 * c.T[0, 0], 0.98 * c.tau[0]))
    T_exact = T_of(c.z)
    rise = T_exact[0] - T_h
    err_T = np.max(np.abs(c.T[:, 0] - T_exact)) / rise
    err_tau = abs(c.tau[0] / s_exact - 1)
    eta_ratio = np.exp(E_R * (1 / T_h - 1 / T_exact[0]))
    print(f"\nArrhenius Couette: tau {c.tau[0]/1e6:.5f} MPa (exact {s_exact/1e6:.5f}), rise {c.T[0,0]-T_h:.3f} K "
          f"(exact {rise:.3f}), viscosity ratio {eta_ratio:.2f}; rel. errors T {err_T:.2e}, tau {err_tau:.2e}")
    assert eta_ratio > 3.0
    assert err_tau < ERR_TAU and err_T < ERR_T
    assert abs(c.energy_residual()[0]) < 1e-10


ERR_TAU, ERR_T = 1e-5, 3e-6  # measured 4.8e-6, 1.4e-6


def _couette_partly_molten_exact(eta_of, T_m, kappa, V, h, T_h):
    """Steady Couette layer with a melt front inside it (docs/theory/viscoplastic.md, "partly molten"): a film
    0 < z < delta at T >= T_m sheared at the uniform stress s, on solid at rest (delta < z < h) that conducts the
    film's heat s V to z = h held at T_h < T_m.  Film: T' = -q/kappa, q' = s^2/eta(T), u' = -s/eta(T) from
    (T0, 0, V) at z = 0 to the front T = T_m.  The velocity drop to the front does not depend on s, so T0 is shot
    alone (brentq on u(front) = 0 over an adaptive Runge-Kutta integration, rtol 1e-12) at a trial s1; the film
    thickness scales as 1/s (delta = A/s, A = s1 delta(s1)) and the solid's conduction gives
    h - delta = B/s, B = kappa (T_m - T_h)/V, so s = (A + B)/h.  Returns s, delta, T0 and T(z) as a callable;
    cross-checked by the quadrature V^2 = 2 kappa int_{T_m}^{T0} dT/eta."""
    from scipy.integrate import quad, solve_ivp
    from scipy.optimize import brentq

    def film(T0, s):
        def rhs(z, y):
            eta = eta_of(y[0])
            return [-y[1] / kappa, s * s / eta, -s / eta]

        front = lambda z, y: y[0] - T_m  # noqa: E731
        front.terminal = True
        return solve_ivp(rhs, (0.0, 1.0), [T0, 0.0, V], method="DOP853", rtol=1e-12, atol=1e-14,
                         dense_output=True, events=front)

    s1 = kappa * (T_m - T_h) / (V * h)  # any trial stress: the velocity drop to the front does not depend on it

    def u_front(T0):
        return film(T0, s1).y_events[0][0][2] / V

    T0 = brentq(u_front, T_m + 1e-6, T_m + 3000.0, xtol=1e-12, rtol=1e-15)
    A = s1 * film(T0, s1).t_events[0][0]
    B = kappa * (T_m - T_h) / V
    s = (A + B) / h
    delta = A / s
    sol = film(T0, s)
    zf, yf = sol.t_events[0][0], sol.y_events[0][0]
    assert abs(zf / delta - 1) < 1e-9 and abs(yf[1] / (s * V) - 1) < 1e-9 and abs(yf[2]) < 1e-9 * V
    # the quadrature route: T0 from V^2 = 2 kappa int dT/eta alone
    I_m = quad(lambda T: 1.0 / eta_of(T), T_m, T0, epsabs=0.0, epsrel=1e-13, limit=200)[0]
    assert abs(2 * kappa * I_m / V**2 - 1) < 1e-9

    def T_of(z):
        z = np.asarray(z, float)
        out = T_m + (T_h - T_m) * (z - delta) / (h - delta)
        f = z < delta
        out[f] = sol.sol(z[f])[0]
        return out

    return s, delta, T0, T_of


PM = {"eta_F": 0.2, "E_R": 2.0e4, "V_act": 2.1e-6, "V": 600.0, "h": 4e-6, "p": 1e9}


def _partly_molten_run(n_cells, scheme="backward_euler"):
    """The partly molten Couette case on n_cells: (column, s, delta, T0, T_m, T_h, T_exact(z), viscosity(T)).
    Backward Euler: with BDF2 (used until the first melt) the run settles, after 2.5 us, in a state with
    tau 1.3 % above the exact one and the solid band at the front still creeping at 0.24 m/s (7e-4 m/s and tau
    +1.3 % after 10 us); backward Euler at 5 and 2.5 ns steps reaches the same state to 1e-6.  The steady partly
    molten state depends on the path (the creeping band's hardening); not settled (docs, "Time accuracy")."""
    from shockfriction.friction.subgrid.viscoplastic import R_GAS, liquid_viscosity
    from shockfriction.materials.strength import scg_melt_temperature

    eta_F, E_R, V_act, V, h, p = (PM[k] for k in ("eta_F", "E_R", "V_act", "V", "h", "p"))
    T_F = AL.melting_temperature
    T_m = scg_melt_temperature(p, *AL.melt_law())
    T_h = T_m - 100.0
    pV_R = p * V_act / R_GAS
    c = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=h, n_cells=n_cells, inertia=True, far_end="held", f=None,
                            latent_heat=3.97e5, liquid_viscosity=eta_F, liquid_activation=E_R, far_temperature=T_h,
                            pressure_melting=True, liquid_activation_volume=V_act, time_scheme=scheme)
    c.set_temperature(T_h)   # solid at T_h (the far node keeps it: the fixed far temperature)
    for _ in range(500):
        c.step(p, V, V, 0.0, 1e12, 5e-9)
    assert np.all(c.TF == pytest.approx(T_m, rel=1e-15))

    def eta_of(T):
        return liquid_viscosity(T, eta_F, E_R, T_F, T_m, pV_R)

    s, delta, T0, T_of = _couette_partly_molten_exact(eta_of, T_m, AL.conductivity, V, h, T_h)
    return c, s, delta, T0, T_m, T_h, T_of, eta_of


def test_couette_partly_molten_film_arrhenius_pressure_inertia():
    """A partly molten Couette layer (item 7 of issue 25): the surface z = 0 stuck to the slider at V and adiabatic,
    z = h at rest and held at T_h = T_m - 100 K below the melting point, so a molten film over solid forms and stays.
    Melt viscosity with the kernel's full law, eta_F exp(E_R (1/T - 1/T_F) + p V*/(R T)) at T >= T_m(p), melting at
    the SCG T_m(1 GPa) = 1273 K (pressure_melting on, V* = 2.1e-6 m^3/mol), inertia on, far end held; the run
    starts from solid at T_h and melts its way to the steady state.  Against the shooting solution: measured on 800
    cells tau 4.1e-6, T 9.0e-5 of the layer's temperature range; first order in dz (the front sits between two
    nodes, see the docs)."""
    c, s, delta, T0, T_m, T_h, T_of, eta_of = _partly_molten_run(800)
    from shockfriction.friction.subgrid.viscoplastic import R_GAS

    V, h, pV_R = PM["V"], PM["h"], PM["p"] * PM["V_act"] / R_GAS
    T_exact = T_of(c.z)
    span = T0 - T_h
    err_T = np.max(np.abs(c.T[:, 0] - T_exact)) / span
    err_tau = abs(c.tau[0] / s - 1)
    liquid = c.T[:, 0] > T_m
    solid_v = np.max(np.abs(c.v[~liquid, 0]))
    eta_ratio = eta_of(T_m) / eta_of(T0)
    print(f"\npartly molten Couette: tau {c.tau[0]/1e6:.6f} MPa (exact {s/1e6:.6f}), T(0) {c.T[0, 0]:.4f} K (exact "
          f"{T0:.4f}), film {delta*1e6:.4f} um of {h*1e6:g} (last liquid node {c.z[liquid][-1]*1e6:.4f} um), "
          f"viscosity ratio {eta_ratio:.2f}, pressure factor {np.exp(pV_R / T0):.3f}; rel. errors tau {err_tau:.2e}, "
          f"T {err_T:.2e} of {span:.1f} K; max |v| in the solid {solid_v:.1e} m/s")
    assert 0.4 < delta / h < 0.8 and eta_ratio > 3.0 and np.exp(pV_R / T0) > 1.15  # the regime is the one claimed
    assert np.all(liquid[c.z < delta - 2 * c.dz[0]]) and not np.any(liquid[c.z > delta + 2 * c.dz[0]])
    # the solid is at rest but for the band within ~0.5 K of T_m where the SCG melt factor leaves Y/sqrt3 < s: it
    # creeps at (s - Y/sqrt3)/eta_vp <= 2.6e5 /s over ~7 nm (measured 1.2e-3 m/s, 2e-6 of V; left out of the exact
    # solution)
    assert solid_v < 1e-5 * V
    assert err_tau < ERR_TAU_PM and err_T < ERR_T_PM
    assert abs(c.energy_residual()[0]) < 1e-10


ERR_TAU_PM, ERR_T_PM = 1e-5, 1.2e-4  # measured 4.1e-6, 9.0e-5 (800 cells; first order, see the docs)


@pytest.mark.slow
def test_couette_partly_molten_film_converges_first_order():
    """The partly molten case on 200 / 400 / 800 cells: the temperature error stays under 0.2 dz/h of the range and
    falls by more than 2 from 400 to 800 cells (first order: the front is held at a cell's midpoint, so the error's
    sign and size oscillate with where it falls); tau within 3e-5 throughout.  Measured: T 1.9e-4 / 3.6e-4 / 9.0e-5,
    tau 1.9e-5 / 1.6e-5 / 4.1e-6.  Not 1600 cells: there the first solid cells lie within 0.2 K of T_m, where the
    SCG melt factor leaves G/G0 < 1e-4, Maxwell cells whose relaxation time eta_vp/G (~20 us) is longer than the run:
    no steady state, tau wanders by up to 1e-4 in bursts (docs/theory/viscoplastic.md)."""
    errs = {}
    for n in (200, 400, 800):
        c, s, delta, T0, T_m, T_h, T_of, _ = _partly_molten_run(n)
        errs[n] = (abs(c.tau[0] / s - 1), np.max(np.abs(c.T[:, 0] - T_of(c.z))) / (T0 - T_h))
        print(f"\n{n} cells: tau {errs[n][0]:.2e}, T {errs[n][1]:.2e}")
        assert errs[n][0] < 3e-5 and errs[n][1] < 0.2 / n
    assert errs[800][1] < errs[400][1] / 2
