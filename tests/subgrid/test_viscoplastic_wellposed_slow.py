"""Well-posedness of the viscoplastic columns at the Ball loading with f = 0.7 and 0.9 (where the
rate-independent ch. 8 model is ill-posed): interface temperature and friction stress under mesh refinement
(dz = 40 -> 20 nm) and under column thickening (h = 20 -> 40 um), at 0.3 and 1 us.

Measured (eta_vp = 50 Pa s, inertia on, impedance far end):
  dz 40 -> 20 nm: |dTheta|/Theta <= 1.1e-8, |dtau|/tau <= 6.6e-6 (f = 0.7 and 0.9, both times): converged.
  h 20 -> 40 um, f = 0.7: 0.3 us: Theta -0.5 %, tau +87 %; 1 us: Theta 2e-6, tau -0.4 %.
  h 20 -> 40 um, f = 0.9: 0.3 us: Theta -53 %, tau +270 % (the 40 um column sticks); 1 us: Theta -7.6 %.
The thickness dependence is physical in this 1D setting, not a discretisation defect: f Ymax exceeds the cold
bulk's yield Y0 (1 + beta eps)^n up to eps ~ 46, and in plane shear the stress does not decay with depth, so
the whole column flows at (tau - Y/sqrt3)/eta_vp and a thicker column absorbs more of the slip.  The item is
kept as a strict xfail until the column's far end couples to a plastic body (see docs/theory/viscoplastic.md).
"""

import pytest

from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material, heat_share

AL = get_material("Al5083-H111")
ST = get_material("AISI321")
TIMES = (300, 1000)


def run(f, h, cells):
    c = ViscoplasticColumns(1, AL, beta_T=heat_share(AL, ST), f=f, thickness=h, n_cells=cells, inertia=True)
    out = {}
    for n in range(1, max(TIMES) + 1):
        tau, _ = c.step(10e9, 200.0, 200.0, 0.0, 3e9, 1e-9)
        assert c.status[0] == 0
        if n in TIMES:
            out[n] = (c.theta_interface[0], tau[0])
    return out


@pytest.fixture(scope="module", params=[0.7, 0.9])
def runs(request):
    f = request.param
    return f, run(f, 20e-6, 500), run(f, 20e-6, 1000), run(f, 40e-6, 1000)


def rel(a, b):
    return abs(b[0] / a[0] - 1), abs(b[1] / a[1] - 1)


@pytest.mark.slow
def test_mesh_refinement_converged(runs):
    f, base, fine, _ = runs
    for n in TIMES:
        dT, dtau = rel(base[n], fine[n])
        print(f"\nf = {f}, {n} ns, dz 40 -> 20 nm: dTheta {dT:.1e}, dtau {dtau:.1e}", end="")
        assert dT < 3e-8 and dtau < 2e-5   # measured <= 1.1e-8 and 6.6e-6 (f = 0.7, 0.3 us)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="1D plane shear above the cold-bulk yield: the whole column flows (see module doc)")
def test_column_thickness_independent(runs):
    f, base, _, thick = runs
    for n in TIMES:
        dT, dtau = rel(base[n], thick[n])
        print(f"\nf = {f}, {n} ns, h 20 -> 40 um: dTheta {dT:.1e}, dtau {dtau:.1e}", end="")
        assert dT < 1e-2 and dtau < 1e-2
