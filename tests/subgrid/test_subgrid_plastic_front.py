"""The plastic-front shortcut of the thermoelastoplastic kernel is exact.

The root iterations visit only the nodes above a bound on the plastic front (plastic_depth:
suffix maxima of the trial temperatures and suffix minima of the hardening, with the SCG
modulus decreasing in T).  Reference: the same solver visiting every node.  The results must be
bit-identical, also with a deep front (first step of a uniform column: every node yields) and a
non-monotone profile (a buried hot layer, where temperature does not fall with depth), and with
nodes out of contact or without slip (no friction: nothing visited).
"""

import numpy as np

from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.friction.subgrid.thermoelastoplastic import plastic_depth
from shockfriction.materials.library import get_material

AL, ST = get_material("Al5083-H111"), get_material("AISI321")
NCOL, CELLS = 12, 200


def pair(buried_layer):
    out = []
    for use_front in (True, False):
        sg = SubgridInterface(NCOL, AL, ST, n_cells=CELLS, model="thermoelastoplastic", mu0=0.3, f=0.3)
        sg._use_front = use_front
        if buried_layer:  # 300 K at the surface, up to 700 K at 8 um depth: temperature rises with depth
            sg.columns.theta[:] = 300.0 + 400.0 * np.exp(-((sg.z - 8e-6) / 2e-6) ** 2)[None, :]
            sg.columns.active[:] = True
        out.append(sg)
    return out


def drive(sgs, steps):
    sig = np.linspace(1e9, 12e9, NCOL)
    v = np.linspace(20.0, 400.0, NCOL)
    sig[[0, 3]] = 0.0, -1e8  # out of contact and in tension: no friction
    v[5] = 0.0  # no slip: no friction
    depths, fronts = [], []
    for n in range(steps):
        dt = 1e-9 * (1.0 + 0.5 * (n % 3))  # changing steps refactor the columns
        res = [sg.step(sig, v, v, np.inf, np.inf, 1.0, dt) for sg in sgs]
        fast, full = sgs
        np.testing.assert_array_equal(res[0][0], res[1][0])
        np.testing.assert_array_equal(res[0][1], res[1][1])
        for name in ("theta", "eps_p", "theta_interface", "slip_local", "slip_plastic", "flux_in",
                     "lag_temperature", "plastic_work", "heat_plastic", "iterations"):
            np.testing.assert_array_equal(getattr(fast, name), getattr(full, name), err_msg=f"{name}, step {n}")
        np.testing.assert_array_equal(fast._deps, full._deps)
        assert np.all(full._depth == CELLS + 1)
        assert np.all(fast._depth[[0, 3, 5]] == 0) and np.all(fast.eps_p[[0, 3, 5]] == 0.0)
        yielded = [np.nonzero(row > 0.0)[0] for row in fast._deps]
        deepest = np.array([r[-1] + 1 if r.size else 0 for r in yielded])
        assert np.all(deepest <= fast._depth)  # the bound holds
        depths.append(fast._depth.copy())
        fronts.append(deepest)
    return np.array(depths), np.array(fronts)


def test_deep_front_and_ball_loading_bit_identical():
    depths, fronts = drive(pair(False), 150)
    assert fronts[0].max() == CELLS + 1  # step 1: the whole of the slower columns yields
    print(f"\nfront bound after step 1: {depths[1:].min()}-{depths[1:].max()} of {CELLS + 1} nodes "
          f"(deepest yielded node {fronts[1:].max()})")
    # the shortcut engages (the slowest, coldest column stays on the yield surface to depth: no bound there)
    assert np.median(depths[1:]) < CELLS // 10


def test_buried_hot_layer_bit_identical():
    depths, fronts = drive(pair(True), 60)
    print(f"\nburied layer: front bound {depths.min()}-{depths.max()}, deepest yielded node {fronts.max()}")
    assert fronts.max() > CELLS // 4  # the hot, soft buried layer yields below a cold surface


def test_plastic_depth_bound_is_conservative():
    """Brute force: nodes at or below the bound never reach sqrt(3) tau_max/Y0 for q in [0, q_hi]."""
    rng = np.random.default_rng(7)
    p = AL.scg_params()
    nn = 101
    unit = np.exp(-np.linspace(0.0, 12.0, nn)) * 2e-7
    checked = 0
    for _ in range(200):
        ad = 300.0 + rng.uniform(0, 500) * rng.random(nn) ** 3
        hard = 1.0 + rng.uniform(0, 0.3) * rng.random(nn)
        q_hi = rng.uniform(0.0, 0.5) * (AL.melting_temperature - ad.max()) / unit[0]
        F_N, tau_max = rng.uniform(0, 12e9), rng.uniform(0, 400e6)
        ad_s = np.maximum.accumulate(ad[::-1])[::-1].copy()
        unit_s = np.maximum.accumulate(unit[::-1])[::-1].copy()
        hard_s = np.minimum.accumulate(hard[::-1])[::-1].copy()
        m = plastic_depth(tau_max, F_N, q_hi, ad, ad_s[::8].copy(), unit_s, hard, hard_s[::8].copy(), p, -1)  # no guess
        for guess in (0, m - 1, m, m + 1, nn - 1, int(rng.integers(nn))):  # galloping from a guess: same m
            assert plastic_depth(tau_max, F_N, q_hi, ad, ad_s[::8].copy(), unit_s, hard, hard_s[::8].copy(), p,
                                 guess) == m
        for q in np.linspace(0.0, q_hi, 7):
            T = ad[m:] + q * unit[m:]
            G = (1 + AL.scg_g * F_N - AL.scg_h * (T - 300.0)) * np.exp(-AL.scg_xi * T / (AL.melting_temperature - T))
            assert np.all(G * hard[m:] > np.sqrt(3) * tau_max / AL.Y0)
            checked += T.size
        if m > 0:  # and the bound is the smallest: node m-1 fails the suffix test at q_hi
            c = ad_s[m - 1] + q_hi * unit_s[m - 1]
            G = (1 + AL.scg_g * F_N - AL.scg_h * (c - 300.0)) * np.exp(-AL.scg_xi * c / (AL.melting_temperature - c))
            assert not G * hard_s[m - 1] > np.sqrt(3) * tau_max / AL.Y0 * (1 + 1e-9)
    assert checked > 1000


