"""Contact kernels on small hand-made configurations (no hydrocode).

Checks: friction laws (cases D, E of the digest's section 9), pairing with
re-association, corners and free ends, the normal step (gap closure, unilateral
release, bilateral option), the friction step (case C: stick exactly, slip
reduced by F_max dt (1/m_g + 1/m_G)), momentum conservation to round-off and
the energy identity (kinetic energy lost = friction work + contact loss) on
random configurations.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from shockfriction.analysis.pressure_shear import pressure_shear
from shockfriction.contact.impulses import (deposit_friction_heat, impulse_work, normal_step, point_weights,
                                            tangential_step)
from shockfriction.contact.pairing import (guide_normal_sign, pair_slave_nodes, slave_nodal_areas,
                                           slave_tributary_lengths)
from shockfriction.friction.laws import (COULOMB, COULOMB_TRESCA, FRICTIONLESS, MODIFIED_COULOMB, TRESCA,
                                         law_parameters, traction_limit, velocity_dependent_mu)


# ---------------------------------------------------------------- friction laws
def test_laws_limits_and_switch_over():
    p = law_parameters(mu0=0.4, mu_inf=0.1, gamma=0.05, mu_T=0.5)
    assert traction_limit(FRICTIONLESS, p, 1e9, 10.0, 1e9, 1e9) == 0.0
    assert traction_limit(COULOMB, p, -2e9, 100.0, 0.0, 0.0) == pytest.approx(0.8e9, rel=1e-15)
    # case D: mu -> mu0 at zero slip, -> mu_inf at large slip, exact exponential in between
    assert velocity_dependent_mu(0.0, p) == pytest.approx(0.4, rel=1e-15)
    assert velocity_dependent_mu(1e4, p) == pytest.approx(0.1, rel=1e-12)
    assert velocity_dependent_mu(20.0, p) == pytest.approx(0.1 + 0.3 * math.exp(-1.0), rel=1e-14)
    assert traction_limit(MODIFIED_COULOMB, p, 1e9, -20.0, 0, 0) == pytest.approx((0.1 + 0.3 / math.e) * 1e9)
    # case E: Tresca cap mu_T min(Y1, Y2)/sqrt(3), independent of F_N
    cap = 0.5 * 3e8 / math.sqrt(3.0)
    assert traction_limit(TRESCA, p, 1e6, 0.0, 5e8, 3e8) == pytest.approx(cap, rel=1e-15)
    assert traction_limit(TRESCA, p, 1e10, 0.0, 5e8, 3e8) == pytest.approx(cap, rel=1e-15)
    # Coulomb-Tresca switches at mu F_N = mu_T Y_min/sqrt(3)
    fn_switch = cap / 0.4
    assert traction_limit(COULOMB_TRESCA, p, 0.5 * fn_switch, 0.0, 5e8, 3e8) == pytest.approx(0.2 * fn_switch)
    assert traction_limit(COULOMB_TRESCA, p, 2.0 * fn_switch, 0.0, 5e8, 3e8) == pytest.approx(cap)
    # mu_T unset: mu_T = mu (eq. 3.81)
    q = law_parameters(mu0=0.4, mu_inf=0.1, gamma=0.05)
    assert traction_limit(COULOMB_TRESCA, q, 1e12, 20.0, 3e8, 4e8) == pytest.approx(
        velocity_dependent_mu(20.0, q) * 3e8 / math.sqrt(3.0))


# ---------------------------------------------------------------- pairing
def _pair(x, y, slave, guide, sign=1.0, max_gap=1.0, max_pen=1.0):
    n = slave.size
    seg = np.empty(n, np.int64)
    out = [np.empty(n) for _ in range(6)]
    active = np.empty(n, np.bool_)
    pair_slave_nodes(x, y, slave, x[guide].copy(), y[guide].copy(), sign, max_gap, max_pen, seg, *out, active)
    return seg, out, active


def test_pairing_flat_nonmatching_and_reassociation():
    # guide: y = 0, x = 0, 1, 2, 3 (body below: outward normal +y); slave nodes above at y = 0.01
    gx = np.array([0.0, 1.0, 2.0, 3.0])
    sx = np.array([0.2, 0.9, 1.5, 2.999, 3.2, -0.1])
    x = np.concatenate((gx, sx))
    y = np.concatenate((np.zeros(4), np.full(6, 0.01)))
    guide = np.arange(4)
    slave = np.arange(4, 10)
    sign = guide_normal_sign(x, y, guide, 0.5, -0.5)
    assert sign == -1.0                              # n = s (t_y, -t_x) = (0, 1)
    seg, (coef, nx, ny, tx, ty, gap), active = _pair(x, y, slave, guide, sign)
    assert list(seg) == [0, 0, 1, 2, -1, -1]          # the last two are past the free ends
    assert list(active) == [True, True, True, True, False, False]
    np.testing.assert_allclose(coef[:4], [0.2, 0.9, 0.5, 0.999], rtol=1e-12)
    np.testing.assert_allclose(gap[:4], 0.01, rtol=1e-12)
    np.testing.assert_allclose(ny[:4], 1.0)
    np.testing.assert_allclose(tx[:4], 1.0)
    # slide the second node past the end of segment 0: it is re-associated with segment 1
    x[5] = 1.3
    seg, (coef, *_), active = _pair(x, y, slave, guide, sign)
    assert seg[1] == 1 and coef[1] == pytest.approx(0.3)


def test_pairing_convex_corner_and_concave_corner():
    # guide along the top and down the right side of a unit block: (0,1) -> (1,1) -> (1,0)
    x = np.array([0.0, 1.0, 1.0, 1.1, 0.9, 1.2])
    y = np.array([1.0, 1.0, 0.0, 1.1, 1.05, 0.5])
    guide = np.array([0, 1, 2])
    slave = np.array([3, 4, 5])
    sign = guide_normal_sign(x, y, guide, 0.5, 0.5)
    seg, (coef, nx, ny, tx, ty, gap), active = _pair(x, y, slave, guide, sign)
    # node 3 lies in the wedge of the convex corner: paired with the corner node, radial normal
    assert seg[0] == 0 and coef[0] == 1.0
    np.testing.assert_allclose([nx[0], ny[0]], [1 / math.sqrt(2), 1 / math.sqrt(2)], rtol=1e-12)
    assert gap[0] == pytest.approx(0.1 * math.sqrt(2.0))
    assert tx[0] * nx[0] + ty[0] * ny[0] == pytest.approx(0.0, abs=1e-15)
    # node 4 above the top face, node 5 right of the side face
    assert seg[1] == 0 and ny[1] == pytest.approx(1.0) and gap[1] == pytest.approx(0.05)
    assert seg[2] == 1 and nx[2] == pytest.approx(1.0) and gap[2] == pytest.approx(0.2)
    assert coef[2] == pytest.approx(0.5)
    # concave corner (guide is the inside of an L): the nearer face wins
    x2 = np.array([0.0, 1.0, 1.0, 0.8, 0.95])
    y2 = np.array([0.0, 0.0, 1.0, 0.05, 0.5])
    guide2 = np.array([0, 1, 2])
    sign2 = guide_normal_sign(x2, y2, guide2, 0.5, -0.5)
    seg2, (coef2, nx2, ny2, *_r), _a = _pair(x2, y2, np.array([3, 4]), guide2, sign2)
    assert seg2[0] == 0 and ny2[0] == pytest.approx(1.0)
    assert seg2[1] == 1 and nx2[1] == pytest.approx(-1.0)


def test_axisymmetric_areas_sum_to_the_annulus():
    r = np.linspace(0.2, 1.0, 7) ** 1.3
    x = np.zeros_like(r)
    slave = np.arange(r.size)
    area = slave_nodal_areas(x, r, slave, axisymmetric=True, radius_axis=1)
    assert area.sum() == pytest.approx(0.5 * (r[-1] ** 2 - r[0] ** 2), rel=1e-14)
    b, a = slave_tributary_lengths(x, r, slave)
    np.testing.assert_allclose(slave_nodal_areas(x, r, slave, False), a + b)


# ---------------------------------------------------------------- one node on one segment
def _one_node(coef_val, m=(2.0, 3.0, 5.0), v_slave=(4.0, -1.0), v0=(0.0, 0.5), v1=(1.0, 0.0), gap_val=0.0):
    mass = np.array(m, float)
    vx = np.array([v_slave[0], v0[0], v1[0]])
    vy = np.array([v_slave[1], v0[1], v1[1]])
    arrays = dict(slave=np.array([0]), guide=np.array([1, 2]), seg=np.array([0]), coef=np.array([coef_val]),
                  nx=np.array([0.0]), ny=np.array([1.0]), tx=np.array([1.0]), ty=np.array([0.0]),
                  gap=np.array([gap_val]), active=np.array([True]))
    return mass, vx, vy, arrays


def _weights(guide, seg, coef, active):
    gnode = np.zeros((seg.size, 2), np.int64)
    gw = np.zeros((seg.size, 2))
    point_weights(guide, seg, coef, active, gnode, gw)
    return gnode, gw


def _run_both(mass, vx, vy, a, dt, law, params, area=1.0, bilateral=False, sweeps=50):
    v_free = (vx.copy(), vy.copy())
    gnode, gw = _weights(a["guide"], a["seg"], a["coef"], a["active"])
    lam_n = np.zeros(1)
    normal_step(vx, vy, mass, a["slave"], gnode, gw, a["nx"], a["ny"], a["gap"],
                a["active"], dt, bilateral, sweeps, 1e-12, lam_n)
    lam_t, s_free, s, work_t = (np.zeros(1) for _ in range(4))
    tangential_step(vx, vy, mass, a["slave"], gnode, gw, a["tx"], a["ty"], a["active"],
                    dt, np.array([area]), law, params, np.array([1e30]), np.array([1e30]), lam_n, sweeps,
                    1e-12, lam_t, s_free, s)
    work_n = np.zeros(1)
    impulse_work(vx, vy, *v_free, a["slave"], gnode, gw, a["nx"], a["ny"], a["active"],
                 lam_n, work_n)
    impulse_work(vx, vy, *v_free, a["slave"], gnode, gw, a["tx"], a["ty"], a["active"],
                 lam_t, work_t)
    return lam_n[0], lam_t[0], s_free[0], s[0], work_n[0], work_t[0]


@pytest.mark.parametrize("c", [0.0, 0.3, 0.5, 1.0])
def test_normal_closure_and_stick_for_any_coef(c):
    mass, vx, vy, a = _one_node(c)
    lam_n, lam_t, s_free, s, *_ = _run_both(mass, vx, vy, a, 1e-3, COULOMB, law_parameters(mu0=10.0))
    vg_y = vy[0]
    vG_y = (1 - c) * vy[1] + c * vy[2]
    vG_x = (1 - c) * vx[1] + c * vx[2]
    assert lam_n > 0.0
    assert vg_y - vG_y == pytest.approx(0.0, abs=1e-14)     # persistency: equal normal velocities
    assert s_free != 0.0
    assert s == pytest.approx(0.0, abs=1e-14)                # case C: sticks exactly (reduced mass, any coef)
    assert vx[0] - vG_x == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize("c", [0.0, 0.4, 1.0])
def test_slip_reduced_by_cap(c):
    mass, vx, vy, a = _one_node(c)
    mu, dt = 0.1, 1e-3
    lam_n, lam_t, s_free, s, _, work_t = _run_both(mass, vx, vy, a, dt, COULOMB, law_parameters(mu0=mu))
    inv_mG = (1 - c) ** 2 / mass[1] + c ** 2 / mass[2]
    inv_pair = 1 / mass[0] + inv_mG
    assert abs(lam_t) == pytest.approx(mu * lam_n, rel=1e-14)      # slip: F_T = mu F_N
    assert s == pytest.approx(s_free - math.copysign(mu * lam_n, s_free) * inv_pair, rel=1e-13)
    assert abs(s) < abs(s_free) and s * s_free > 0
    assert work_t == pytest.approx(mu * lam_n * 0.5 * abs(s + s_free), rel=1e-13)


def test_unilateral_release_and_bilateral_tension():
    # the slave node moves away from the guide: unilateral -> no impulse; bilateral -> tension
    for bilateral, expect_zero in ((False, True), (True, False)):
        mass, vx, vy, a = _one_node(0.5, v_slave=(0.0, 2.0), v0=(0.0, 0.0), v1=(0.0, 0.0))
        lam_n, lam_t, *_ = _run_both(mass, vx, vy, a, 1e-3, COULOMB, law_parameters(mu0=0.3), bilateral=bilateral)
        if expect_zero:
            assert lam_n == 0.0 and vy[0] == 2.0
        else:
            assert lam_n < 0.0 and vy[0] == pytest.approx(0.5 * vy[1] + 0.5 * vy[2], abs=1e-14)


def test_gap_closes_exactly_at_impact():
    dt = 1e-3
    # open gap 1.5 mm, approach 3 m/s: the gap closes within this step (3 mm > 1.5 mm)
    mass, vx, vy, a = _one_node(0.25, v_slave=(0.0, -3.0), v0=(0.0, 0.0), v1=(0.0, 0.0), gap_val=1.5e-3)
    lam_n, *_ = _run_both(mass, vx, vy, a, dt, FRICTIONLESS, law_parameters())
    v_rel = vy[0] - (0.75 * vy[1] + 0.25 * vy[2])
    assert lam_n > 0 and 1.5e-3 + dt * v_rel == pytest.approx(0.0, abs=1e-15)
    # a smaller approach does not reach the guide: no impulse
    mass, vx, vy, a = _one_node(0.25, v_slave=(0.0, -1.0), v0=(0.0, 0.0), v1=(0.0, 0.0), gap_val=1.5e-3)
    lam_n, *_ = _run_both(mass, vx, vy, a, dt, FRICTIONLESS, law_parameters())
    assert lam_n == 0.0 and vy[0] == -1.0


# ---------------------------------------------------------------- random configurations
@st.composite
def configurations(draw):
    ng = draw(st.integers(2, 6))
    ns = draw(st.integers(1, 8))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    n = ng + ns
    mass = rng.uniform(0.1, 10.0, n)
    vx = rng.normal(0.0, 50.0, n)
    vy = rng.normal(0.0, 50.0, n)
    guide = np.arange(ng)
    slave = np.arange(ng, n)
    seg = rng.integers(0, ng - 1, ns)
    coef = rng.uniform(0.0, 1.0, ns)
    ang = rng.uniform(0, 2 * np.pi, ns)
    nx, ny = np.cos(ang), np.sin(ang)
    tx, ty = -ny, nx
    gap = rng.uniform(-1e-6, 1e-5, ns)
    active = rng.uniform(size=ns) < 0.85
    law = draw(st.sampled_from([COULOMB, MODIFIED_COULOMB, COULOMB_TRESCA]))
    params = law_parameters(mu0=rng.uniform(0, 1), mu_inf=rng.uniform(0, 0.3), gamma=0.01, mu_T=0.6)
    bilateral = draw(st.booleans())
    sweeps = draw(st.sampled_from([1, 3, 50]))
    return mass, vx, vy, guide, slave, seg, coef, nx, ny, tx, ty, gap, active, law, params, bilateral, sweeps, rng


@settings(max_examples=60, deadline=None)
@given(configurations())
def test_momentum_conserved_and_energy_balanced(cfg):
    mass, vx, vy, guide, slave, seg, coef, nx, ny, tx, ty, gap, active, law, params, bilateral, sweeps, rng = cfg
    dt = 1e-6
    ns = slave.size
    vx_old = vx + rng.normal(0.0, 1.0, vx.size)     # velocities at t^{n-1/2}
    vy_old = vy + rng.normal(0.0, 1.0, vy.size)
    vx_free, vy_free = vx.copy(), vy.copy()
    if rng.uniform() < 0.5:
        # random multi-node projections (as the mortar-type share gives): weights sum to 1
        k = 4
        gnode = rng.integers(0, guide.size, (ns, k))
        gw = rng.uniform(0, 1, (ns, k))
        gw /= gw.sum(axis=1, keepdims=True)
        for j in range(ns):    # distinct nodes per row, as hat_weights guarantees
            _, first = np.unique(gnode[j], return_index=True)
            mask = np.zeros(k, bool)
            mask[first] = True
            gw[j, ~mask] = 0.0
            gw[j] /= gw[j].sum()
    else:
        gnode, gw = _weights(guide, seg, coef, active)
    p0 = np.array([np.sum(mass * vx), np.sum(mass * vy)])
    pscale = np.sum(mass * np.hypot(vx, vy))
    lam_n = np.zeros(ns)
    normal_step(vx, vy, mass, slave, gnode, gw, nx, ny, gap, active, dt, bilateral, sweeps, 1e-12, lam_n)
    p1 = np.array([np.sum(mass * vx), np.sum(mass * vy)])
    area = rng.uniform(1e-6, 1e-5, ns)
    lam_t, s_free, s = (np.zeros(ns) for _ in range(3))
    tangential_step(vx, vy, mass, slave, gnode, gw, tx, ty, active, dt, area, law, params,
                    rng.uniform(1e8, 1e9, ns), rng.uniform(1e8, 1e9, ns), lam_n, sweeps, 1e-12,
                    lam_t, s_free, s)
    p2 = np.array([np.sum(mass * vx), np.sum(mass * vy)])
    assert np.all(np.abs(p1 - p0) <= 1e-13 * pscale)
    assert np.all(np.abs(p2 - p0) <= 1e-13 * pscale)
    mu_max = max(params[0], params[1])
    assert np.all(np.abs(lam_t) <= mu_max * np.abs(lam_n) * (1 + 1e-12))   # friction within the cone
    if not bilateral:
        assert np.all(lam_n >= 0.0)
    # the pair works sum to the leapfrog energy change of the corrections, sum m dv.(v_old + v_new)/2
    work_n, work_t = np.zeros(ns), np.zeros(ns)
    impulse_work(vx, vy, vx_old, vy_old, slave, gnode, gw, nx, ny, active, lam_n, work_n)
    impulse_work(vx, vy, vx_old, vy_old, slave, gnode, gw, tx, ty, active, lam_t, work_t)
    de = np.sum(mass * ((vx - vx_free) * (vx_old + vx) + (vy - vy_free) * (vy_old + vy))) * 0.5
    scale = np.sum(mass * (vx_old ** 2 + vy_old ** 2 + vx ** 2 + vy ** 2))
    assert de == pytest.approx(-(work_n.sum() + work_t.sum()), abs=1e-12 * scale)


def test_heat_deposit_shares_and_total():
    work = np.array([2.0, 4.0, 0.0])
    active = np.array([True, True, True])
    seg = np.array([0, 1, 1])
    e = np.zeros(5)
    cm = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    deposit_friction_heat(work, active, seg, 0.7, np.array([-1, 0, 1]), np.array([0, 1, -1]),
                          np.array([0.0, 0.5, 0.5]), np.array([3, 4]), cm, e)
    np.testing.assert_allclose(e * cm, [0.7 * 2 + 0.5 * 0.7 * 4, 0.5 * 0.7 * 4, 0.0, 0.3 * 2, 0.3 * 4])
    assert np.sum(e * cm) == pytest.approx(6.0)


# ---------------------------------------------------------------- exact pressure-shear solution
def test_pressure_shear_example_of_materials_data():
    sol = pressure_shear(100.0, math.radians(30.0), 0.1, 7850, 5900, 3200, 7850, 5900, 3200)
    assert sol.sigma_n == pytest.approx(2.005e9, rel=5e-4)
    assert sol.tau == pytest.approx(0.2005e9, rel=5e-4)
    assert sol.slip_rate == pytest.approx(34.0, abs=0.05)
    assert sol.rear_transverse_fs_velocity == pytest.approx(16.0, abs=0.05)
    assert not sol.sticking
    welded = pressure_shear(100.0, math.radians(30.0), 1.0, 7850, 5900, 3200, 7850, 5900, 3200)
    assert welded.sticking and welded.slip_rate == pytest.approx(0.0, abs=1e-12)
    assert welded.tau == pytest.approx(50.0 * 7850 * 3200 / 2.0)
