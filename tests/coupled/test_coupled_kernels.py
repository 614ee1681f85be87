"""Kernels of the coupled friction step: the guide mass under a uniform traction (checked by applying the
impulses), the capped Gauss-Seidel step, and the clipping of the lagged plastic heat below melting."""

import math

import numpy as np
import pytest

from shockfriction.contact.impulses import _apply
from shockfriction.coupled.kernels import capped_tangential_step, column_inputs
from shockfriction.friction.subgrid.column import sweep_columns


def _config(seed=0):
    """4 slave nodes (0..3) over 3 guide nodes (4..6), random masses, mortar-like weights summing to 1 per slave node."""
    rng = np.random.default_rng(seed)
    mass = rng.uniform(0.5, 2.0, 7)
    slave = np.arange(4, dtype=np.int64)
    gnode = np.array([[4, 5], [4, 5], [5, 6], [5, 6]], dtype=np.int64)
    a = rng.uniform(0.1, 0.9, 4)
    gw = np.column_stack([a, 1.0 - a])
    area = rng.uniform(0.5, 1.5, 4)
    return mass, slave, gnode, gw, area


def test_guide_mass_is_the_projection_mobility_under_uniform_traction():
    mass, slave, gnode, gw, area = _config()
    n = 7
    tx, ty = np.ones(4), np.zeros(4)
    active = np.ones(4, np.bool_)
    lam_n = np.ones(4)
    vx = np.zeros(n)
    vy = np.zeros(n)
    out = [np.zeros(4) for _ in range(5)]
    column_inputs(vx, vy, vx, vy, mass, slave, gnode, gw, tx, ty, active, lam_n, area, 1.0, False, np.zeros(n),
                  1e-6, *out)
    m_guide = out[4]
    # apply a uniform friction stress tau = 1: impulse tau S_i dt on every pair, then read the projections
    v = np.zeros(n)
    for j in range(4):
        _apply(v, vy, mass, j, slave[j], gnode, gw, 1.0, 0.0, area[j])
    for j in range(4):
        dv_projection = -(gw[j] @ v[gnode[j]])          # the projection moves opposite to the slave's impulse
        assert dv_projection == pytest.approx(area[j] / m_guide[j], rel=1e-12)
    np.testing.assert_allclose(out[3], mass[:4])          # m_slave
    np.testing.assert_allclose(out[0], 1.0 / area)        # sigma_n = P_n/(S dt)


def test_round_off_slip_and_nodes_out_of_contact_are_idle():
    mass, slave, gnode, gw, area = _config(1)
    n = 7
    vx = np.zeros(n)
    vx[:4] = [1e-9, 5.0, 0.0, 0.0]
    vy = np.zeros(n)
    active = np.array([True, True, True, False])
    lam_n = np.array([1.0, 1.0, 0.0, 1.0])
    out = [np.zeros(4) for _ in range(5)]
    column_inputs(vx, vy, vx, vy, mass, slave, gnode, gw, np.ones(4), np.zeros(4), active, lam_n, area, 1.0, False,
                  np.zeros(n), 1e-6, *out)
    sigma, v_free, v_prev, _, m_guide = out
    assert v_free[0] == 0.0 and v_free[1] == pytest.approx(5.0)   # 1e-9 m/s is round-off
    assert sigma[2] == 0.0 and math.isinf(m_guide[2])              # no normal impulse: out of contact
    assert sigma[3] == 0.0 and v_free[3] == 0.0                    # not paired


def test_capped_step_applies_the_cap_against_the_slip_and_sticks_below_it():
    mass, slave, gnode, gw, area = _config(2)
    n = 7
    vx = np.zeros(n)
    vx[:4] = 10.0       # slave nodes slide at +10 m/s over a guide at rest
    vy = np.zeros(n)
    cap = np.array([0.5, 0.5, 0.5, 1e3])
    lam = np.zeros(4)
    slip = np.zeros(4)
    momentum0 = mass @ vx
    capped_tangential_step(vx, vy, mass, slave, gnode, gw, np.ones(4), np.zeros(4), np.ones(4, np.bool_), cap, 200,
                           1e-12, lam, slip)
    np.testing.assert_allclose(lam[:3], -0.5, rtol=1e-14)            # slipping: the cap, against the slip
    assert abs(slip[3]) < 1e-9 and abs(lam[3]) < 1e3                 # a cap above the sticking force: it sticks
    assert mass @ vx == pytest.approx(momentum0, rel=1e-14)          # equal and opposite impulses


def test_plastic_heat_clipped_below_melting_with_the_energy_booked():
    """The melt guard in the forward sweep (columns innermost: arrays (n_nodes, n_columns)); with K = I the
    swept temperatures are theta + kept/(rho c), which must stay at or below the limit."""
    rho_c, limit = 2.4e6, 1219.0
    theta = np.array([[1000.0, 1218.0, 1218.9], [300.0, 300.0, 300.0]])
    pending = np.array([[1e6, 4.8e6, 1e6], [5e6, 0.0, 1e5]])
    w = np.array([0.5, 1.0, 0.5])
    area = np.array([2.0, 3.0])
    before = (pending @ w) @ area
    per_column, deposited = np.zeros(2), np.zeros(2)
    X, src = np.ascontiguousarray(theta.T), np.ascontiguousarray(pending.T)
    zero, one = np.zeros(3), np.ones(3)
    sweep_columns(X, np.zeros(2), zero, False, src, 3, 1.0 / rho_c, rho_c, limit, w, per_column, deposited,
                  zero, one, zero, np.zeros(0, np.int64), np.zeros(2), np.empty((1, 2)), 0, -1, 0, -1)
    lost = per_column @ area
    pending = src.T
    np.testing.assert_allclose(pending, [[1e6, 2.4e6, 0.24e6], [5e6, 0.0, 1e5]])
    np.testing.assert_allclose(X.T, theta + pending / rho_c, rtol=1e-15)
    assert np.all(X <= limit + 1e-12)
    assert lost == pytest.approx(before - (pending @ w) @ area, rel=1e-14)
    assert lost == pytest.approx(2.0 * (1.0 * 2.4e6 + 0.5 * 0.76e6))
    np.testing.assert_allclose(deposited, pending @ w, rtol=1e-15)
