"""Digest §10 case 12 on the full Ball run (2.5 us): is 40 nm / 1 ns converged, and how much does h matter?

Marked slow (about 10 s after compilation): ``pytest -m slow tests/subgrid``.
"""

import numpy as np
import pytest

from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.materials.library import get_material

AL, ST = get_material("Al5083-H111"), get_material("AISI321")


def ball(dt=1e-9, h=20e-6, cells=500, model="thermoelastic", t_end=2.5e-6):
    sg = SubgridInterface(1, AL, ST, thickness=h, n_cells=cells, model=model, mu0=0.3, f=0.3)
    out = {}
    marks = {int(round(t / dt)): t for t in (0.25e-6, 0.5e-6, 1e-6, 2.5e-6)}
    for n in range(1, int(round(t_end / dt)) + 1):
        sg.step(10e9, 200.0, 200.0, np.inf, np.inf, 1.0, dt)
        if n in marks:
            out[marks[n]] = (sg.theta_interface[0], sg.tau[0])
    return out


@pytest.mark.slow
@pytest.mark.parametrize("model", ["thermoelastic", "thermoelastoplastic"])
def test_thesis_resolution_is_converged_to_plotting_accuracy(model):
    ref = ball(model=model)
    fine_z = ball(cells=2000, model=model)            # dz 10 nm
    fine_t = ball(dt=0.25e-9, model=model)            # dt 0.25 ns
    deep = ball(h=40e-6, cells=1000, model=model)     # h 40 um, same dz
    print(f"\n{model}: t, Theta(0) and tau at 40 nm/1 ns; change with 10 nm; with 0.25 ns; with h = 40 um")
    for t in sorted(ref):
        (T, tau), (Tz, tz), (Tt, tt), (Th, th) = ref[t], fine_z[t], fine_t[t], deep[t]
        print(f"  {t * 1e6:4.2f} us  {T:8.2f} K {tau / 1e6:7.2f} MPa | {Tz - T:+.3f} K {(tz - tau) / 1e6:+.2f} MPa | "
              f"{Tt - T:+.3f} K {(tt - tau) / 1e6:+.2f} MPa | {Th - T:+.3f} K {(th - tau) / 1e6:+.2f} MPa")
        assert abs(Tz - T) < 1.0 and abs(Tt - T) < 1.0
        assert abs(tz - tau) < 0.02 * tau and abs(tt - tau) < 0.05 * tau
        assert abs(Th - T) < 1.0
