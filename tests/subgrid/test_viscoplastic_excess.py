"""The excess layer (``far_end = "excess"``): the coupled closure of the viscoplastic columns (issue 25, item 1).

A quasi-static layer under the uniform stress s slips by W(s) = sum_c dz_c r_c(s): a solid cell flows in excess of the
reference layer (the body at T0, hardened by its homogeneous flow) by max(x_c - x_ref, 0)/dt, x = (s - k)^+/(eta_vp/dt
+ dk/dgamma), a molten cell at s/eta_c.  The node's slip is V - k s; below the cap the two are equal (docs/theory/viscoplastic.md,
"Coupled closure: the excess layer")."""

import numpy as np
import pytest
from scipy.optimize import brentq

from shockfriction.friction.subgrid.excess_layer import _layer_solve
from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material


def _W(s, kc, hc, liquid, eta_l, dz, k_ref, h_ref, eta_dt, dt):
    """The layer's slip rate, written independently of the kernel (numpy, vectorised): each solid cell's plastic
    increment (s - k)^+/(eta_vp/dt + dk/dgamma) in excess of the reference's, molten cells s/eta."""
    xc = np.maximum(s - kc, 0.0) / (eta_dt + hc)
    xr = max(s - k_ref, 0.0) / (eta_dt + h_ref)
    solid = dz * np.maximum(xc - xr, 0.0) / dt
    return solid[~liquid].sum() + (dz[liquid] * s / eta_l[liquid]).sum()


@pytest.mark.parametrize("seed", range(6))
def test_excess_stress_is_the_root_of_the_slip_balance(seed):
    """Random layers (yields below and above the reference's, hardening or saturated, some molten cells): the
    kernel's stress against a Brent root of V - k s - W(s) = 0 (or the cap where the layer cannot take the slip)
    to 1e-12 of the cap."""
    rng = np.random.default_rng(seed)
    M = 40
    dz = rng.uniform(2e-8, 6e-8, M)
    Y0, beta, n, Ymax = 0.29e9, 125.0, 0.1, 0.68e9
    eps = rng.uniform(0.0, 0.3, M)
    yh = np.minimum(Ymax, Y0 * (1.0 + beta * eps) ** n)
    yh[:3] = Ymax  # saturated cells: no hardening
    kf = rng.uniform(0.2, 0.6, M)  # G/G0/sqrt3 at each cell's temperature
    kc = yh * kf
    hc = np.where(yh < Ymax, kf * n * beta * yh / ((1.0 + beta * eps) * np.sqrt(3.0)), 0.0)
    eps_ref = 0.05
    y_ref = min(Ymax, Y0 * (1.0 + beta * eps_ref) ** n)
    k_ref = y_ref * 0.5
    h_ref = 0.5 * n * beta * y_ref / ((1.0 + beta * eps_ref) * np.sqrt(3.0))
    liquid = rng.random(M) < (0.1 if seed % 2 else 0.0)
    eta_l = rng.uniform(1e-3, 1e-2, M)
    eta_vp = [50.0, 1e-2, 1e-3][seed % 3]
    dt = 1e-9
    G = np.where(liquid, 0.0, 27e9)
    eta = np.where(liquid, eta_l, 0.0)
    hden = np.where(liquid, 1.0, eta_vp / dt + hc)  # the kernel's cell data: eta_vp/dt + dk/dgamma
    cap = 0.9 * Ymax * 0.5
    for V, k in ((5.0, 1e-7), (0.2, 1e-8), (40.0, 2e-9), (3.0, 0.0)):
        s, W, ok = _layer_solve(V, k, cap, M, G, np.where(liquid, 0.0, kc), hden, eta, dz, k_ref, eta_vp / dt + h_ref,
                                dt, bool(liquid.any()))
        assert ok
        g = lambda x: V - k * x - _W(x, kc, hc, liquid, eta_l, dz, k_ref, h_ref, eta_vp / dt, dt)  # noqa: E731
        ref = cap if g(cap) >= 0.0 else brentq(g, 0.0, cap, xtol=1e-14 * cap, rtol=1e-15)
        assert abs(s - ref) <= 1e-12 * cap, (V, k, s, ref)
        assert W == pytest.approx(_W(s, kc, hc, liquid, eta_l, dz, k_ref, h_ref, eta_vp / dt, dt), rel=1e-12,
                                  abs=1e-15)


def _columns(h_um, cells, **kw):
    return ViscoplasticColumns(1, get_material("Al7075-T6"), beta_T=1.0, thickness=h_um * 1e-6, n_cells=cells,
                               f=0.7, far_end="excess", other=get_material("Steel4340"), **kw)


def test_a_layer_that_deforms_like_its_body_adds_no_slip():
    """An unheated layer: its cells are the reference, W = 0 whatever s, so the node takes the slide-line answer
    itself: s = min(cap, V/k) (stick, or the Coulomb cap), no plastic work, for any thickness."""
    for h, n in ((20, 500), (40, 1000)):
        c = _columns(h, n)
        tau, vh = c.step(2e9, 10.0, 10.0, 1e-7, 5e7, 1e-10)  # V/k = 100 MPa > cap: slides at the cap
        assert tau[0] == pytest.approx(5e7, rel=1e-15) and vh[0] == pytest.approx(10.0 - 5.0, rel=1e-14)
        c = _columns(h, n)
        tau, vh = c.step(2e9, 10.0, 10.0, 1e-7, 6e8, 1e-10)  # V/k = 100 MPa < every cap and k_ref: sticks
        E = c.energies()
        assert abs(vh[0]) < 1e-12 and tau[0] == pytest.approx(1e8, rel=1e-12)
        assert E["plastic_work"][0] == 0.0
