"""Elastic pressure-shear plate impact through a Coulomb slide line against the exact 1D
solution (materials-data.md section 4): normal and shear stress, slip rate and the target's
rear transverse free-surface velocity within 3%; a large mu welds the plates; momentum is
conserved to round-off and energy + friction work within 0.5%."""

import math

import numpy as np
import pytest

from shockfriction.analysis.pressure_shear import pressure_shear
from shockfriction.hydro.api import prepare, run_simulation
from shockfriction.io.interface import read_interface


def _run(deck, tmp_path):
    sim = prepare(deck)
    p0 = np.array(sim.momentum())
    res = run_simulation(sim, tmp_path)
    return res, p0, read_interface(tmp_path / "interface.h5")["interface"]


def _interface_means(d, t0=0.15e-6, t1=0.9e-6):
    """Time and area average of the window records over [t0, t1] (before reflections return)."""
    sel = (d["t_s"] > t0) & (d["t_s"] < t1)
    return {k: float(np.mean(d[k][sel])) for k in ("sigma_n_Pa", "tau_Pa", "slip_mps")}


def _rear_vx(res, t0=1.05e-6, t1=1.45e-6):
    t = res.probes["t_s"]
    return float(res.probes["rear.vx"][(t > t0) & (t < t1)].mean())


@pytest.fixture(scope="module")
def slipping(contact_decks, tmp_path_factory):
    return _run(contact_decks["pressure_shear"](mu=0.1), tmp_path_factory.mktemp("ps_slip"))


@pytest.fixture(scope="module")
def welded(contact_decks, tmp_path_factory):
    return _run(contact_decks["pressure_shear"](mu=2.0), tmp_path_factory.mktemp("ps_weld"))


def _exact(contact_decks, mu):
    rho, cl, cs, *_ = contact_decks["steel"]
    return pressure_shear(100.0, math.radians(30.0), mu, rho, cl, cs, rho, cl, cs)


def _report(name, got, want):
    err = abs(got - want) / abs(want)
    print(f"{name}: {got:.5g} (exact {want:.5g}), relative error {err:.2%}")
    return err


def test_coulomb_slip_against_exact_solution(slipping, contact_decks):
    res, _, d = slipping
    ex = _exact(contact_decks, 0.1)
    assert not ex.sticking
    m = _interface_means(d)
    assert _report("sigma_n", m["sigma_n_Pa"], ex.sigma_n) < 0.03
    # tau is the traction on the slave (flyer) along the guide tangent +x: it brakes the flyer
    assert _report("tau", -m["tau_Pa"], ex.tau) < 0.03
    assert _report("slip", m["slip_mps"], ex.slip_rate) < 0.03
    assert _report("rear transverse fs", _rear_vx(res), ex.rear_transverse_fs_velocity) < 0.03
    # Coulomb in every window: |tau| = mu sigma_n exactly where the node slips
    sel = (d["t_s"] > 0.05e-6) & (d["t_s"] < 0.9e-6)
    np.testing.assert_allclose(-d["tau_Pa"][sel], 0.1 * d["sigma_n_Pa"][sel], rtol=1e-9)


def test_large_mu_welds_the_plates(welded, contact_decks):
    res, _, d = welded
    ex = _exact(contact_decks, 2.0)
    assert ex.sticking
    m = _interface_means(d)
    print(f"welded: slip {m['slip_mps']:.3e} m/s")
    assert abs(m["slip_mps"]) < 1e-6 * 50.0
    assert _report("sigma_n (welded)", m["sigma_n_Pa"], ex.sigma_n) < 0.03
    assert _report("tau (welded)", -m["tau_Pa"], ex.tau_stick) < 0.03
    assert _report("rear transverse fs (welded)", _rear_vx(res), ex.rear_transverse_fs_velocity) < 0.03


@pytest.mark.parametrize("case", ["slipping", "welded"])
def test_momentum_to_round_off_and_energy_with_friction_work(case, request):
    res, p0, d = request.getfixturevalue(case)
    p1 = np.array(res.simulation.momentum())
    scale = np.abs(p0).max()
    print(f"{case}: momentum change {p1 - p0} (scale {scale:.4e})")
    np.testing.assert_allclose(p1, p0, rtol=0, atol=1e-12 * scale)
    e = res.energy
    total0 = e["total"][0]
    balance = (e["total"] + e["friction_work"] - total0) / total0
    print(f"{case}: max |total + friction work - initial|/initial = {np.abs(balance).max():.3e}, "
          f"friction work {e['friction_work'][-1] / total0:.3%} of the initial energy")
    assert np.abs(balance).max() < 0.005
    if case == "slipping":
        assert e["friction_work"][-1] > 0.01 * total0
        # friction work of the records = the energy budget's
        assert d["friction_work_J"][-1].sum() == pytest.approx(e["friction_work"][-1], rel=1e-9)
