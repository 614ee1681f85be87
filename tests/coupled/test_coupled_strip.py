"""The coupled pressure-shear strip against the uncoupled sub-grid driver fed with the same
(sigma_n, slip) history, and against the elastic interface relation of the 1D strip.

Coupling check: every hydro step the columns receive F_N and the slip from the hydrocode and
return tau; an uncoupled run (``friction.subgrid.driver.run_subgrid``, slip and normal stress
imposed, the same step lengths) must reproduce the interface temperature, the friction stress
and the final column profile to the root finder's tolerance, and the hydrocode must apply
exactly tau S dt at every slipping node.

Physics check: before reflections return, a 1D elastic strip keeps slip = V_t - tau (1/Z1s + 1/Z2s)
at the interface (shear waves into both plates, Z_s = rho c_s); with the columns' softening tau(t)
the hydrocode's window-averaged slip follows it within 3%.
"""

import math

import numpy as np
import pytest

from shockfriction.deck.base import validate
from shockfriction.deck.subgrid import SubgridDeck
from shockfriction.friction.subgrid.driver import run_subgrid
from shockfriction.hydro.api import prepare, run_simulation
from shockfriction.io.columns import read_columns
from shockfriction.io.interface import read_interface
from shockfriction.materials.library import get_material


@pytest.fixture(scope="module")
def coupled(coupled_decks, tmp_path_factory):
    out = tmp_path_factory.mktemp("strip")
    deck = coupled_decks["strip"](end="1.4 us", profile_nodes=[0], profile_interval="0.2 us")
    sim = prepare(deck)
    fm = sim.interfaces[0].line.friction_model
    fm.trace = []
    res = run_simulation(sim, out)
    return res, fm, read_interface(out / "interface.h5")["interface"], read_columns(out / "columns.h5")["interface"]


def _trace(fm, key, node=0):
    return np.array([row[key][node] if np.ndim(row[key]) else row[key] for row in fm.trace])


def test_uncoupled_driver_with_the_same_history_reproduces_the_columns(coupled, tmp_path):
    res, fm, _, cols = coupled
    dt = _trace(fm, "dt")
    sigma = _trace(fm, "sigma_n")
    slip = _trace(fm, "slip_macro")
    starts = np.concatenate(([0.0], np.cumsum(dt)[:-1]))   # the columns' own clock: sum of the steps
    ends = np.cumsum(dt)
    assert sigma[5:].min() > 1e9 and slip[5:].min() > 20.0   # the strip is in contact and slipping
    deck = validate(SubgridDeck, {
        "model": "thermoelastic", "material": "Ti-6Al-4V", "other_material": "Steel4340",
        "duration": f"{ends[-1]} s", "dt": f"{ends[-1]} s", "output_times": [f"{float(e)!r} s" for e in ends[-1:]],
        "column": {"thickness": "20 um", "cells": 200},
        "friction": {"mu0": 0.15, "f": 0.15},
        "loading": [{"interpolation": "constant", "times": [f"{float(s)!r} s" for s in starts],
                     "slip_velocity": [f"{float(v)!r} m/s" for v in slip], "normal_stress": [f"{float(p)!r} Pa" for p in sigma]}],
    })
    # land the driver's steps on the coupled ones: every step end is an output time
    deck = deck.model_copy(update={"output_times": list(ends)})
    un = run_subgrid(deck, tmp_path)
    assert un.t.size == dt.size
    np.testing.assert_allclose(un.t, ends, rtol=1e-12)
    theta_c = _trace(fm, "theta_interface")
    tau_c = _trace(fm, "tau")
    d_theta = np.abs(un.theta_interface[:, 0] - theta_c).max()
    d_tau = np.abs(un.tau[:, 0] - tau_c).max() / tau_c.max()
    d_prof = np.abs(un.profiles[-1][0] - fm.columns.theta[0]).max()
    print(f"{dt.size} steps, interface temperature up to {theta_c.max():.2f} K: max |dTheta| = {d_theta:.2e} K, "
          f"max |dtau|/tau = {d_tau:.2e}, final profile max |dT| = {d_prof:.2e} K")
    assert theta_c.max() > 600.0
    assert d_theta < 1e-6
    assert d_tau < 1e-9
    assert d_prof < 1e-6
    # columns.h5: the chosen node's profiles every 0.2 us, from the uniform initial state
    assert cols["theta_K"].shape == (cols["t_s"].size, 1, 201) and cols["t_s"].size >= 7
    assert np.all(cols["theta_K"][0] == 300.0) and cols["theta_K"][-1, 0, 0] > 600.0


def test_hydrocode_applies_the_column_stress(coupled):
    _, fm, _, _ = coupled
    n_checked = 0
    for row in fm.trace:
        slipping = row["active"] & (np.abs(row["slip"]) > 1.0)
        force = np.abs(row["lam_t"]) / (row["area"] * row["dt"])
        np.testing.assert_allclose(force[slipping], row["tau"][slipping], rtol=1e-12)
        # the impulse opposes the free slip
        assert np.all(np.sign(row["lam_t"][slipping]) == -np.sign(row["v_free"][slipping]))
        n_checked += int(slipping.sum())
    print(f"{n_checked} node-steps: applied friction stress = column stress to 1e-12")
    assert n_checked > 100


def test_slip_follows_the_elastic_interface_relation(coupled, coupled_decks):
    _, _, d, _ = coupled
    steel, ti = get_material("Steel4340"), get_material("Ti-6Al-4V")
    inv_z = 1.0 / math.sqrt(steel.rho0 * steel.G0) + 1.0 / math.sqrt(ti.rho0 * ti.G0)
    t = d["t_s"]
    tau_all = np.abs(d["tau_Pa"].mean(axis=1))      # magnitude of the shear on the slave (target)
    slip_all = np.abs(d["slip_mps"].mean(axis=1))
    errs = []
    # averages over four windows of 0.275 us (the 100 um strip rings by a few m/s about the mean)
    for t0 in (0.3e-6, 0.575e-6, 0.85e-6, 1.125e-6):
        sel = (t > t0) & (t <= t0 + 0.275e-6)
        tau, slip = tau_all[sel].mean(), slip_all[sel].mean()
        want = 55.0 - tau * inv_z
        errs.append(abs(slip - want) / want)
        print(f"t in [{t0 * 1e6:.3f}, {(t0 + 0.275e-6) * 1e6:.3f}] us: tau {tau / 1e9:.4f} GPa, slip {slip:.2f} m/s, "
              f"V_t - tau (1/Z1s + 1/Z2s) = {want:.2f} m/s, relative error {errs[-1]:.2%}")
    sel = (t > 0.3e-6) & (t < 1.4e-6)
    assert tau_all[sel].max() - tau_all[sel].min() > 0.1 * tau_all[sel].max()   # the columns soften the friction
    assert max(errs) < 0.03
