"""Deck conveniences: linear-elastic strength, bodies with inline (custom) materials, node probes.

Exact elastic shock (symmetric impact at v, u = v/2) for a custom material with s = 0, Gamma0 = 0
(P = K eta, K = rho0 c0^2, eta = 1 - rho0/rho) and the hypoelastic deviator in uniaxial strain
(S_yy = (4/3) G ln(1 - eta), S_xx = S_zz = -S_yy/2): the jump conditions sigma = rho0 U u,
eta = u/U with sigma = K eta - (4/3) G ln(1 - eta) give U; no yield however high the stress.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

from shockfriction.errors import DeckError
from shockfriction.hydro.api import prepare, run_dict

RHO, C0, G = 2700.0, 5000.0, 26e9
CUSTOM = {"material": None, "density": "2700 kg/m^3", "c0": "5000 m/s", "s": 0, "gamma0": 0,
          "heat_capacity": "900 J/(kg*K)", "strength": "elastic", "shear_modulus": "26 GPa"}


def test_elastic_custom_material_gives_the_exact_elastic_shock(make_strip):
    v = 1000.0
    u = v / 2
    k = RHO * C0**2

    def jump(U):
        eta = u / U
        return RHO * U * u - (k * eta - 4.0 / 3.0 * G * np.log(1.0 - eta))

    U = brentq(jump, 5000.0, 9000.0)
    eta = u / U
    sigma = RHO * U * u
    syy = 4.0 / 3.0 * G * np.log(1.0 - eta)
    deck = make_strip(ny_flyer=40, ny_target=100, velocity=f"{v} m/s", end="1.4 us", extra_body=CUSTOM)
    deck["probes"][1]["quantities"] = ["sigma_yy", "syy", "sxx", "eps_p"]
    res = run_dict(deck)
    t = res.probes["t_s"]
    sel = (t > 1.1e-6) & (t < 1.4e-6)  # mid cell (5 mm): shock at 0.71 us (spread over 0.3 us), release at 1.8 us
    sig = res.probes["mid.sigma_yy"][sel]
    e_sig = abs(-sig.mean() / sigma - 1)
    e_syy = abs(res.probes["mid.syy"][sel].mean() / syy - 1)
    print(f"U = {U:.2f} m/s, sigma = {sigma / 1e9:.4f} GPa (code {-sig.mean() / 1e9:.4f}, {e_sig:.2e}), "
          f"S_yy = {syy / 1e9:.4f} GPa ({e_syy:.2e}); energy error {res.summary['relative_energy_error']:.2e}")
    assert e_sig < 1e-3  # measured 3.2e-4
    assert e_syy < 1e-3  # measured 3.3e-4
    assert np.allclose(res.probes["mid.sxx"][sel], -0.5 * res.probes["mid.syy"][sel], rtol=1e-9)
    assert np.all(res.probes["mid.eps_p"] == 0.0) and np.all(res.state.eps_p == 0.0)  # no yield at 15 GPa
    assert (res.state.yield_stress == 1e300).all()  # the stand-in for 'no yield'
    assert res.summary["relative_energy_error"] < 2e-3


def test_custom_material_needs_every_property(make_strip):
    deck = make_strip(extra_body={"material": None, "c0": "5000 m/s", "gamma0": 2})
    with pytest.raises(DeckError) as err:
        prepare(deck)
    msg = str(err.value)
    print(msg)
    assert "missing: density, s, heat_capacity" in msg
    deck = make_strip(extra_body={**CUSTOM, "shear_modulus": None})
    with pytest.raises(DeckError, match="elastic.*needs shear_modulus"):
        prepare(deck)
    deck = make_strip(extra_body={**CUSTOM, "yield_stress": "1 GPa"})
    with pytest.raises(DeckError, match="no yield"):
        prepare(deck)


def test_node_probe_velocity_is_the_exact_particle_velocity(make_strip):
    """Symmetric Cu-on-Cu impact: the particle velocity behind the shock is v/2 exactly."""
    v = 500.0
    deck = make_strip(ny_flyer=20, ny_target=60, velocity=f"{v} m/s", material="Cu-OFHC", end="1.2 us")
    deck["probes"] = [{"name": "n", "body": "target", "node": [0, 30], "quantities": ["vy", "y"]},
                      {"name": "a", "body": "target", "at": ["0.05 mm", "3 mm"], "quantities": ["vy", "p"]}]
    res = run_dict(deck)
    t = res.probes["t_s"]
    sel = (t > 0.85e-6) & (t < 1.1e-6)  # 3 mm: shocked at 0.70 us; the flyer's release arrives after 1.15 us
    err = np.abs(res.probes["n.vy"][sel] / (v / 2) - 1).max()
    print(f"node probe u = {res.probes['n.vy'][sel].mean():.4f} m/s (exact {v / 2}), max rel error {err:.2e}")
    assert err < 1e-3  # measured 5.5e-4
    assert np.allclose(res.probes["a.vy"], res.probes["n.vy"])  # the same node, found by position


def test_cell_probe_asking_for_a_velocity_is_a_clear_deck_error(make_strip):
    deck = make_strip()
    deck["probes"] = [{"name": "bad", "body": "target", "cell": [0, 3], "quantities": ["p", "vy"]}]
    with pytest.raises(DeckError, match="not vy: velocities and positions live on nodes; add a probe with node"):
        prepare(deck)


def test_node_probes_are_read_before_the_update_and_give_the_same_rows(make_strip):
    """With probes of nodes only, a history row's viscous heat goes into the cells in the cell update (no pass of
    its own) and the probes are read before it; the rows and the state are the bytes of the path that puts the heat
    in before the row (as for probes of a cell), positions included (read after the update they would be
    x^{n+1})."""
    deck = make_strip(ny_flyer=10, ny_target=30, velocity="800 m/s", end="0.5 us")
    deck["probes"] = [{"name": "n", "body": "target", "node": [0, 15], "quantities": ["vx", "vy", "x", "y"]}]
    sims = [prepare(deck) for _ in range(2)]
    assert sims[0]._probes_on_nodes
    sims[1]._probes_on_nodes = False   # the heat before the row, as a cell probe needs
    for sim in sims:
        sim.run()
    a, b = sims
    rows = np.array(a.probe_rows)
    assert len(rows) > 50 and np.ptp(rows[:, 2]) > 10.0 and np.ptp(rows[:, 4]) > 1e-7   # the node moved
    np.testing.assert_array_equal(np.array(a.probe_rows), np.array(b.probe_rows))
    np.testing.assert_array_equal(np.array(a.energy_rows), np.array(b.energy_rows))
    for name in ("x", "y", "vx", "vy", "e", "pressure"):
        np.testing.assert_array_equal(getattr(a.state, name), getattr(b.state, name))
    deck["probes"].append({"name": "c", "body": "target", "cell": [0, 3], "quantities": ["p"]})
    assert not prepare(deck)._probes_on_nodes
