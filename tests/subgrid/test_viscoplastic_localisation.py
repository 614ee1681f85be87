"""Localisation in the viscoplastic column vs the linear stability analysis (issue 10, item 5).

A column sheared homogeneously (surface stuck to the imposed slip, far end held, both ends insulated) is
run twice side by side: once as the base state, once with the most unstable eigenmode of the linearised
system (analysis/viscoplastic_stability.py) added at a small amplitude.  The difference of the two columns
is the perturbation; its growth rate, fitted on a window fixed before the run, is compared with the largest
eigenvalue of the linear system frozen at the base state of the window's middle.  Both the quasi-static
column (against the (E, Th) system, whose rate-independent limit is eq. 6.48) and the inertial one (against
the 4x4 Fourier system, whose rigid-plastic limit is the cubic of stability.inertial_growth_rate) are tested.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shockfriction.analysis import viscoplastic_stability as vs
from shockfriction.analysis.stability import ScgConstants, scg_moduli, shear_modulus_and_slope
from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material

SQRT3 = math.sqrt(3.0)
H = 20e-6            # column thickness (m)
N_CELLS = 200        # 100 nm cells: 400 cells per wavelength 2h
SIGMA_N = 5e9        # normal stress (Pa)
V_SLIP = 20.0        # imposed surface velocity (m/s): base shear rate 1e6 1/s
ETA_VP = 1.0         # overstress viscosity (Pa s), small enough for growth faster than the base drift
EPS0 = 2000.0        # beyond the saturation strain (1651 for Al 5083: Y_eps = 0): thermal softening drives the instability
T_BASE = 500.0       # base temperature (K)
DT = 0.25e-9
AMPLITUDE = 1e-3     # K, initial temperature amplitude of the mode


def _base_partials(m, c, eps, theta, tau_sol, gp0):
    mod = scg_moduli(c, eps, theta, SIGMA_N)
    G, dG = shear_modulus_and_slope(c, theta, SIGMA_N)
    kw = dict(rho=m.rho0, G=float(G), rho_c=c.rho_c, kappa=c.kappa, chi=0.9, tau0=tau_sol, gp0=gp0,
              G_theta_gamma_e=float(dG) * tau_sol / float(G),
              **vs.overstress_partials(ETA_VP, float(mod.Y_eps), float(mod.Y_theta)))
    return kw, float(mod.Y)


def _run(inertia: bool, n_steps: int):
    m = get_material("Al5083-H111")
    c = ScgConstants.of(m)
    cols = ViscoplasticColumns(2, m, beta_T=1.0, thickness=H, n_cells=N_CELLS, f=None, taylor_quinney=0.9,
                               eta_vp=ETA_VP, inertia=inertia, T0=T_BASE, latent_heat=3.97e5,
                               liquid_viscosity=1.3e-3, picard_tol=1e-14, far_end="held")
    z = cols.z
    zc = 0.5 * (z[1:] + z[:-1])
    gp0 = V_SLIP / H
    mod = scg_moduli(c, EPS0, T_BASE, SIGMA_N)
    G = float(shear_modulus_and_slope(c, T_BASE, SIGMA_N)[0])
    tau_sol = float(mod.Y) / SQRT3 + ETA_VP * gp0
    k = math.pi / H
    base, _ = _base_partials(m, c, EPS0, T_BASE, tau_sol, gp0)
    s, vec = vs.eigenmode(k, inertia=inertia, **base)
    assert abs(s.imag) < 1e-9 * abs(s.real) and s.real > 0.0  # a real, growing mode (set-up check)
    vec = vec / vec[-1]  # Th = 1
    cols.set_temperature(np.column_stack([np.full(z.size, T_BASE),
                                          T_BASE + AMPLITUDE * np.cos(k * z)]))
    cols.eps[:, 0] = EPS0
    cols.eps[:, 1] = EPS0 + AMPLITUDE * vec[-2].real * np.cos(k * zc)
    tau1 = tau_sol + (AMPLITUDE * vec[1].real * np.cos(k * zc) if inertia else 0.0)
    cols.Gs[:, :] = G
    cols.ge[:, 0] = tau_sol / G
    cols.ge[:, 1] = tau1 / G
    v_base = V_SLIP * (1.0 - z / H)
    cols.v[:, 0] = v_base
    # the stress-velocity pair of the mode (sign: the column's v is minus the analysis's V)
    cols.v[:, 1] = v_base + (AMPLITUDE * vec[0].imag * np.sin(k * z) if inertia else 0.0)
    w = cols.weights
    amp, times, states = [], [], []
    for n in range(n_steps):
        cols.step(SIGMA_N, V_SLIP, V_SLIP, 0.0, 1e30, DT)
        dT = cols.T[:, 1] - cols.T[:, 0]
        amp.append(float(np.sum(w * dT * np.cos(k * z)) / np.sum(w * np.cos(k * z) ** 2)))
        times.append((n + 1) * DT)
        mid = N_CELLS // 2
        tau_b = float(cols.Gs[mid, 0] * cols.ge[mid, 0])
        states.append((float(cols.eps[mid, 0]), float(0.5 * (cols.T[mid, 0] + cols.T[mid + 1, 0])), tau_b))
    return m, c, np.array(times), np.array(amp), states


@pytest.mark.parametrize("inertia", [False, True], ids=["quasi-static", "inertial"])
def test_perturbation_grows_at_the_linear_rate(inertia):
    n_steps = 400  # 100 ns; window: the second half, fixed in advance
    m, c, t, a, states = _run(inertia, n_steps)
    i0, i1 = n_steps // 2, n_steps - 1
    measured = math.log(a[i1] / a[i0]) / (t[i1] - t[i0])
    eps, theta, tau_sol = states[(i0 + i1) // 2]
    mod = scg_moduli(c, eps, theta, SIGMA_N)
    gp0 = (tau_sol - float(mod.Y) / SQRT3) / ETA_VP
    kw, _ = _base_partials(m, c, eps, theta, tau_sol, gp0)
    predicted = vs.growth_rate(math.pi / H, inertia=inertia, **kw).real
    print(f"localisation ({'inertial' if inertia else 'quasi-static'}): measured {measured:.5e} 1/s, "
          f"linear analysis {predicted:.5e} 1/s, ratio {measured / predicted:.4f}; base T {theta:.2f} K, "
          f"amplitude x{a[i1] / a[0]:.2f}")
    assert a[i1] / a[0] < 1e4  # stays linear
    assert abs(measured / predicted - 1.0) < 0.02  # measured 0.6 % (quasi-static), 0.14 % (inertial); issue: 5 %
