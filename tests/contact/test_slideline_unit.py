"""SlideLine on hand-made node rows (no hydrocode): periodic wrapping, persistency on a
non-matching interface after the Gauss-Seidel sweeps, records and heat bookkeeping."""


import numpy as np
import pytest

from shockfriction.contact.pairing import guide_normal_sign
from shockfriction.contact.slideline import SlideLine
from shockfriction.friction.laws import COULOMB, law_parameters


def _rows(shift=0.0, n_guide=4, n_slave=6, width=1.0):
    gx = np.linspace(0.0, width, n_guide)
    sx = np.linspace(width, 0.0, n_slave) + shift      # slave runs the other way (ccw around its body)
    x = np.concatenate((gx, sx))
    y = np.concatenate((np.zeros(n_guide), np.zeros(n_slave)))
    guide = np.arange(n_guide)
    slave = np.arange(n_guide, n_guide + n_slave)
    return x, y, guide, slave


@pytest.mark.parametrize("share", ["segment", "point"])
@pytest.mark.parametrize("periodic,shift", [(False, 0.0), (True, 0.0), (True, 2.37), (True, -1.61)])
def test_nonmatching_rows_persistency_momentum_and_friction(periodic, shift, share):
    x, y, guide, slave = _rows(shift)
    ng, ns = guide.size, slave.size
    rng = np.random.default_rng(3)
    mass = rng.uniform(1.0, 2.0, x.size)
    if periodic:   # periodic images share mass and velocity (one node group)
        mass[guide[-1]] = mass[guide[0]]
        mass[slave[-1]] = mass[slave[0]]
    vx = np.concatenate((np.zeros(ng), np.full(ns, 10.0)))
    vy = np.concatenate((rng.uniform(0, 1, ng), rng.uniform(-5, -4, ns)))
    sign = guide_normal_sign(x, y, guide, 0.5, -1.0)
    line = SlideLine("l", slave, guide, np.arange(ns - 1), np.arange(ng - 1), sign, law=COULOMB,
                     law_params=law_parameters(mu0=0.2), periodic=periodic, x0=x, y0=y, record_interval=1e-6, guide_share=share)
    active_nodes = np.unique(np.concatenate((line.slave_imp, line.guide_imp)))
    p0 = np.array([np.sum(mass[active_nodes] * vx[active_nodes]), np.sum(mass[active_nodes] * vy[active_nodes])])
    if periodic:
        vy[guide[-1]] = vy[guide[0]]
        vy[slave[-1]] = vy[slave[0]]
    dt = 1e-7
    line.apply(x, y, vx, vy, mass, dt, 0.0)
    if periodic:    # what the hydrocode's group sync does: images take the representative's velocity
        for a, b in ((guide[0], guide[-1]), (slave[0], slave[-1])):
            vx[b], vy[b] = vx[a], vy[a]
    assert line.active.all()
    # persistency: every slave node moves with its projection in the normal direction
    np.testing.assert_allclose(line.gw.sum(axis=1), 1.0, rtol=1e-14)
    for j in range(line.slave.size):
        vG = np.sum(line.gw[j] * vy[line.gnode[j]])
        assert vy[line.slave[j]] - vG == pytest.approx(0.0, abs=1e-9)
    if share == "point":
        for j in range(line.slave.size):
            k, c = line.seg[j], line.coef[j]
            vG = (1 - c) * vy[line.guide[k]] + c * vy[line.guide[k + 1]]
            assert vy[line.slave[j]] - vG == pytest.approx(0.0, abs=1e-9)
    p1 = np.array([np.sum(mass[active_nodes] * vx[active_nodes]), np.sum(mass[active_nodes] * vy[active_nodes])])
    np.testing.assert_allclose(p1, p0, rtol=0, atol=1e-12 * np.abs(p0).max())
    # Coulomb: every slipping node carries |tau| = mu sigma_n
    slipping = np.abs(line.slip) > 1e-9
    assert slipping.any()
    np.testing.assert_allclose(np.abs(line.lam_t[slipping]), 0.2 * line.lam_n[slipping], rtol=1e-12)
    assert line.total_friction_work > 0
    assert line.maybe_record(dt, x, y, force=True)
    rec = line.record.arrays()
    assert rec["sigma_n"].shape == (1, line.slave.size)
    np.testing.assert_allclose(rec["sigma_n"][0] * line.area * dt, line.lam_n, rtol=1e-12)
    assert line.area.sum() == pytest.approx(1.0, rel=1e-12)     # the slave side's length (unit depth)


@pytest.mark.parametrize("n_guide,n_slave,periodic,axisymmetric", [
    (5, 8, False, False), (4, 7, True, False), (7, 4, False, False), (3, 11, True, False), (4, 3, True, False),
    (5, 8, False, True), (7, 4, False, True), (6, 9, False, True)])
def test_hat_weights_give_consistent_guide_forces(n_guide, n_slave, periodic, axisymmetric):
    """Uniform pressure on non-matching rows: guide node i receives sigma int N_i r dl exactly."""
    x, y, guide, slave = _rows(0.0, n_guide, n_slave)
    if axisymmetric:          # x is the radius: move the rows off the axis (and one test on it)
        x += 0.0 if n_guide == 6 else 0.3
    if periodic:
        x[slave] += 0.123     # slide the slave row: the wrap must keep the weights consistent
    sign = guide_normal_sign(x, y, guide, 0.5, -1.0)
    line = SlideLine("l", slave, guide, np.arange(n_slave - 1), np.arange(n_guide - 1), sign,
                     periodic=periodic, axisymmetric=axisymmetric, radius_axis=0, x0=x, y0=y)
    from shockfriction.contact.pairing import slave_nodal_areas
    line.geometry(x, y)
    np.testing.assert_allclose(line.gw.sum(axis=1), 1.0, rtol=1e-13)
    area = line.nodal_areas(x, y)
    force = np.zeros(x.size)
    for j in range(line.slave.size):
        np.add.at(force, line.gnode[j], line.gw[j] * area[j])
    expect = slave_nodal_areas(x, y, guide, axisymmetric, radius_axis=0)
    if periodic:              # the seam node carries both halves
        expect[0] += expect[-1]
        expect[-1] = 0.0
    np.testing.assert_allclose(force[guide], expect, rtol=1e-12, atol=1e-15)


def test_heat_is_deposited_with_the_share():
    x, y, guide, slave = _rows()
    ng, ns = guide.size, slave.size
    mass = np.ones(x.size)
    vx = np.concatenate((np.zeros(ng), np.full(ns, 10.0)))
    vy = np.concatenate((np.zeros(ng), np.full(ns, -3.0)))
    cells_slave = np.arange(ns - 1)
    cells_guide = np.arange(ns - 1, ns - 1 + ng - 1)
    cell_mass = np.full(ns - 1 + ng - 1, 2.0)
    energy = np.zeros_like(cell_mass)
    sign = guide_normal_sign(x, y, guide, 0.5, -1.0)
    line = SlideLine("l", slave, guide, cells_slave, cells_guide, sign, law=COULOMB,
                     law_params=law_parameters(mu0=0.3), heat_share_slave=0.677, x0=x, y0=y)
    ke0 = 0.5 * np.sum(mass * (vx ** 2 + vy ** 2))
    w = line.apply(x, y, vx, vy, mass, 1e-7, 0.0, cell_mass=cell_mass, cell_energy=energy)
    ke1 = 0.5 * np.sum(mass * (vx ** 2 + vy ** 2))
    q = energy * cell_mass
    d = line.total_contact_loss
    assert w > 0 and d > 0
    # the cells get the friction heat (beta_T 0.677 to the slave side) and the contact's inelastic loss (the
    # slave side's share M_G/(m_g + M_G), M_G = sum w_i m_i: 1/2 with equal nodal masses)
    assert line.total_contact_heat == pytest.approx(d, rel=1e-12)
    assert q.sum() == pytest.approx(w + d, rel=1e-12)
    assert q[cells_slave].sum() == pytest.approx(0.677 * w + 0.5 * d, rel=1e-12)
    # kinetic energy lost = friction work + contact (inelastic) loss
    assert ke0 - ke1 == pytest.approx(w + d, rel=1e-10)
