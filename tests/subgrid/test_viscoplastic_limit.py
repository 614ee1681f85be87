"""Rate-independent, quasi-static limit of the viscoplastic columns: the chapter 8 Ball curves.

With vanishing rate sensitivity (eta_vp -> 0) and no inertia the overstress law reduces to the SCG yield
sqrt(3) tau = Y(eps, p, T) of the thermoelastoplastic model (thesis ch. 8), which this test runs as the
independent reference (Al 5083-H111 on AISI 321, 200 m/s, 10 GPa, f = 0.3: examples/subgrid/ball_al_200ms.toml).
"""

import numpy as np

from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material, heat_share

AL = get_material("Al5083-H111")
ST = get_material("AISI321")


def test_vanishing_rate_sensitivity_reproduces_chapter8_ball_curves():
    ref = SubgridInterface(1, AL, ST, model="thermoelastoplastic", mu0=0.3, f=0.3)
    # the chapter 8 model's constant melting temperature (pressure_melting=False): the same physics
    # and its time scheme, backward Euler (the default; with BDF2 tau differs by up to 2.7e-3: the ch. 8 column's
    # own time error)
    vp = ViscoplasticColumns(1, AL, beta_T=heat_share(AL, ST), f=0.3, inertia=False, eta_vp=1e-3,
                             latent_heat=3.97e5, liquid_viscosity=0.844e-3, pressure_melting=False,
                             time_scheme="backward_euler")
    worst_T = worst_tau = 0.0
    for n in range(1, 2501):
        t_ref, _ = ref.step(10e9, 200.0, 200.0, np.inf, np.inf, 1.0, 1e-9)
        t_vp, _ = vp.step(10e9, 200.0, 200.0, 0.0, 3e9, 1e-9)   # mu0 sigma_n = 3 GPa never binds
        assert vp.status[0] == 0
        if n in (10, 100, 250, 500, 1000, 2500):
            eT = abs(vp.theta_interface[0] / ref.theta_interface[0] - 1)
            et = abs(t_vp[0] / t_ref[0] - 1)
            print(f"\n{n:5d} ns: Theta {vp.theta_interface[0]:.2f} vs {ref.theta_interface[0]:.2f} K ({eT:.1e}), "
                  f"tau {t_vp[0]/1e6:.3f} vs {t_ref[0]/1e6:.3f} MPa ({et:.1e})", end="")
            # at 10 ns the elastic compliance of the column (absent from ch. 8) still takes part of the slip
            assert eT < (1e-2 if n == 10 else 1.5e-3)
            assert et < 2.5e-3
            worst_T, worst_tau = max(worst_T, eT), max(worst_tau, et)
    assert abs(vp.energy_residual()[0]) < 1e-10
