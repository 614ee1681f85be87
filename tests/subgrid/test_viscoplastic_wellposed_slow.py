"""Well-posedness of the viscoplastic columns at the Ball loading (Al 5083 on AISI 321, 10 GPa, 200 m/s imposed
slip) with f = 0.7 and 0.9, where the rate-independent ch. 8 model is ill-posed (issue 10, item 2).

The column is a uniformly resolved interface layer (thickness h, cells dz) continued by geometric cells (ratio r)
down to the depth D = 1.2 c_s(10 GPa, 300 K) x 1 us = 4.93 mm, beyond the shear-wave reach, so that the body's own
plastic flow (f Ymax exceeds the cold bulk's yield: the plastic zone is ~0.3 mm deep at 0.25 us) lies inside the
column and nothing reaches its far end.  Interface temperature Theta and friction stress tau at 0.3 and 1 us:

  measured (eta_vp = 50 Pa s, inertia on)           f = 0.7               f = 0.9
  h 20 -> 40 um (dz 40 nm):        dTheta, dtau   3.9e-5, 8.5e-6        1.9e-5, 5.8e-6
  dz 40 -> 20 nm (h 20 um):        dTheta, dtau   9.1e-7, 3.1e-8        1.8e-7, 4.4e-8
  r 1.05 -> 1.025:                 dTheta, dtau   2.0e-3, 6.7e-5        4.7e-5, 3.0e-5   (the 1 us row sets these)

(maximum over both times).  The issue asks < 1 %.  Without the continuation (the column stops at h) the answer is
the column's: between h = 20 and 40 um at f = 0.7, 0.3 us, tau +18 % and Theta(0) -17 % (+87 % in tau with the
ambient melting temperature; last test).
"""

import math

import pytest

from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material, heat_share
from shockfriction.materials.strength import scg_shear_ratio

AL = get_material("Al5083-H111")
ST = get_material("AISI321")
TIMES = (300, 1000)
DEPTH = 1.2 * math.sqrt(AL.G0 * scg_shear_ratio(10e9, 300.0, AL.scg_g, AL.scg_h, AL.scg_xi,
                                                AL.melting_temperature) / AL.rho0) * 1e-6


def run(f, h, cells, ratio=1.05, depth=DEPTH, steps=max(TIMES), **kw):
    c = ViscoplasticColumns(1, AL, beta_T=heat_share(AL, ST), f=f, thickness=h, n_cells=cells, inertia=True,
                            depth=depth, depth_ratio=ratio, **kw)
    out = {}
    for n in range(1, steps + 1):
        tau, _ = c.step(10e9, 200.0, 200.0, 0.0, 3e9, 1e-9)
        assert c.status[0] == 0
        if n in TIMES:
            out[n] = (c.theta_interface[0], tau[0])
    return out


@pytest.fixture(scope="module", params=[0.7, 0.9])
def runs(request):
    f = request.param
    return f, run(f, 20e-6, 500), run(f, 40e-6, 1000), run(f, 20e-6, 1000), run(f, 20e-6, 500, ratio=1.025)


def worst(a, b):
    return (max(abs(b[n][0] / a[n][0] - 1) for n in TIMES), max(abs(b[n][1] / a[n][1] - 1) for n in TIMES))


# tolerances per f: (Theta, tau), a few times the measured values of the module docstring
TOL = {"h": {0.7: (1.2e-4, 3e-5), 0.9: (6e-5, 2e-5)},
       "dz": {0.7: (3e-6, 1e-6), 0.9: (1e-6, 1e-6)},
       "ratio": {0.7: (5e-3, 2e-4), 0.9: (2e-4, 1e-4)}}


@pytest.mark.slow
@pytest.mark.parametrize("which", ["h", "dz", "ratio"])
def test_independent_of_the_column(runs, which):
    f, base, thick, fine, graded = runs
    other = {"h": thick, "dz": fine, "ratio": graded}[which]
    dT, dtau = worst(base, other)
    print(f"\nf = {f}, {which}: dTheta {dT:.1e}, dtau {dtau:.1e}", end="")
    assert dT < 1e-2 and dtau < 1e-2  # the requirement
    assert dT < TOL[which][f][0] and dtau < TOL[which][f][1]


@pytest.mark.slow
def test_without_continuation_the_column_sets_the_answer():
    """The ch. 8 set-up (column ends at h, impedance there): the answer is the column's, not the physics'.
    h 20 -> 40 um at f = 0.7, 0.3 us: tau +18 %, Theta(0) 1478 -> 1220 K (-17 %).  With the ambient melting
    temperature (pressure_melting=False, as when this test was written) tau +87 % (Theta 1219 -> 1213 K): the thin
    column then sits at the ambient T_F (~1220 K) where G and Y vanish; the SCG melt law puts T_m(10 GPa) far above
    it, so the thin column now runs 260 K hotter instead and the column shows in Theta(0) more than in tau."""
    thin = run(0.7, 20e-6, 500, depth=None, steps=300)
    thick = run(0.7, 40e-6, 1000, depth=None, steps=300)
    dtau = thick[300][1] / thin[300][1] - 1
    dT = thick[300][0] / thin[300][0] - 1
    print(f"\nno continuation, f = 0.7, 0.3 us, h 20 -> 40 um: dtau {dtau:+.3f}, dTheta {dT:+.3f}", end="")
    assert dtau > 0.1 and dT < -0.1  # measured +0.176, -0.175
    thin = run(0.7, 20e-6, 500, depth=None, steps=300, pressure_melting=False)
    thick = run(0.7, 40e-6, 1000, depth=None, steps=300, pressure_melting=False)
    dtau = thick[300][1] / thin[300][1] - 1
    print(f"; ambient melting: dtau {dtau:+.3f}", end="")
    assert dtau > 0.5  # measured +0.874
