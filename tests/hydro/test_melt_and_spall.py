"""Melting clamp through the cycle (SCG: no deviator at T >= T_F) and the pressure floor."""

import numpy as np

from shockfriction.hydro.api import prepare, run_dict, run_simulation
from shockfriction.materials.library import get_material


def _block(**kw):
    b = {"name": "b", "material": "Al5083-H111", "strength": "scg", "velocity": ["0 m/s", "-300 m/s"],
         "mesh": {"corners": [["0 mm", "0 mm"], ["2 mm", "0 mm"], ["2 mm", "2 mm"], ["0 mm", "2 mm"]],
                  "nx": 4, "ny": 4},
         "boundary": {"bottom": "fixed", "left": "symmetry"}}
    b.update(kw)
    return b


def test_molten_cells_carry_no_deviator_and_release_their_elastic_energy():
    al = get_material("Al5083-H111")
    sim = prepare({"time": {"end": "0.3 us"}, "bodies": [_block()]})
    s = sim.state
    s.e[:8] = 1.2 * al.heat_capacity * (al.melting_temperature - 300.0)  # the two bottom rows melt
    s.sxx[:] = 1e8  # a pre-stress everywhere, with its stored energy
    s.syy[:] = -1e8
    s.e_el[:] = (1e8**2 + 1e8**2) / (2 * al.G0 * al.rho0)  # S:S/(4 G rho): its stored energy
    sim.reinitialize()
    assert np.all(s.temperature[:8] > al.melting_temperature)
    assert np.all(s.shear_modulus[:8] == 0.0) and np.all(s.yield_stress[:8] == 0.0)
    run_simulation(sim)
    # (the hot cells expand and cool; those still clearly molten carry nothing)
    molten = s.temperature > al.melting_temperature + 20.0
    print(f"{molten.sum()} molten cells at the end")
    assert molten.sum() >= 4
    assert np.all(s.sxx[molten] == 0.0) and np.all(s.syy[molten] == 0.0) and np.all(s.sxy[molten] == 0.0)
    assert np.all(s.e_el[molten] == 0.0)
    assert np.abs(s.sxx[8:]).max() > 0.0  # the solid cells keep theirs


def test_pressure_floor_limits_tension(make_strip):
    deck = make_strip(ny_flyer=20, ny_target=40, end="1.6 us", extra_body={"pressure_floor": "-0.5 GPa"})
    deck["probes"].append({"name": "spall", "body": "target", "cell": [0, 20], "quantities": ["p"]})
    res = run_dict(deck)
    free = run_dict(make_strip(ny_flyer=20, ny_target=40, end="1.6 us"))
    print(f"min pressure {res.state.pressure.min() / 1e9:.3f} GPa with the floor, "
          f"{free.probes['mid.p'].min() / 1e9:.3f} GPa without")
    assert res.probes["spall.p"].min() >= -0.5e9 * (1 + 1e-12)
    assert free.probes["mid.p"].min() < -0.6e9  # the release waves do meet in tension
    assert res.summary["relative_energy_error"] < 2e-3
