"""Molten film of the viscoplastic column in the Yuan-Liou-Prakash regime (issue 10, item 7): 7075-T6 sliding on
tool steel at 250 m/s under 5 GPa at a kinetic Coulomb stress of 250 MPa (docs/theory/viscoplastic.md).

The film grows to ~13 nm in 1 us, thinner than the hydrocode's 40 nm cells; the sub-cell film law (a mushy cell
carries its melt as a liquid layer phi dz) must give the same friction stress and film thickness on 40, 20 and
10 nm cells. Checked against the plain Coulomb baseline (250 MPa throughout) and the film/conduction balance.
These tests check the film numerics at the ambient melting point and viscosity, with the fixed heat share
(``pressure_melting=False``, no other-body column: the model of version 0.3 on the Steinberg 7075-T6 set); the
pressure-dependent melt and the two-sided heat are tested in test_viscoplastic_heat_and_melt.py and the
YLP example's numbers with them in test_subgrid_cli.py."""

import math

import numpy as np
import pytest

from shockfriction.friction.subgrid.viscoplastic import ViscoplasticColumns
from shockfriction.materials.library import get_material, heat_share

AL = get_material("Al7075-T6")
BETA = heat_share(AL, get_material("Steel4340"))
SIGMA_N, V, MU0, DT = 5e9, 250.0, 0.05, 1e-9
T_END = 1e-6
SAMPLES = (500, 1000)  # steps: 0.5 and 1 us (fixed before the runs)


def run(dz):
    layer = 2e-6
    col = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=layer, n_cells=int(round(layer / dz)),
                              depth=1.2 * AL.shear_wave_speed * T_END, eta_vp=50.0, inertia=True,
                              pressure_melting=False)
    out = {"onset": None, "status": 0}
    for s in range(1, int(round(T_END / DT)) + 1):
        tau, _ = col.step(SIGMA_N, V, V, 0.0, MU0 * SIGMA_N, DT)  # imposed slip, Coulomb cap 250 MPa
        out["status"] = max(out["status"], int(col.status[0]))
        if out["onset"] is None and col.melt_fraction()[0, 0] > 0.0:
            out["onset"] = s
        if s in SAMPLES:
            out[s] = (tau[0], col.film_thickness[0])
    out["residual"] = abs(col.energy_residual()[0])
    return out


@pytest.fixture(scope="module")
def runs():
    return {dz: run(dz) for dz in (40e-9, 20e-9, 10e-9)}


def test_runs_clean_and_conserve_energy(runs):
    for r in runs.values():
        assert r["status"] == 0
        assert r["residual"] < 1e-13  # measured <= 1.3e-15


def test_film_is_grid_independent(runs):
    """tau and the film thickness at 0.5 and 1 us on 40 / 20 / 10 nm cells: measured spread <= 0.12 % (tau)
    and 0.15 % (film); the melt onset (first molten step) on every grid at step 92 (step 100 with the 2024-T4
    strength set of version 0.3)."""
    ref = runs[10e-9]
    for dz in (40e-9, 20e-9):
        for s in SAMPLES:
            assert runs[dz][s][0] == pytest.approx(ref[s][0], rel=3e-3)
            assert runs[dz][s][1] == pytest.approx(ref[s][1], rel=3e-3)
    assert {r["onset"] for r in runs.values()} == {92}


def test_friction_falls_far_below_coulomb(runs):
    """Plain Coulomb at the same loading gives mu0 sigma_n = 250 MPa throughout; the film: 38.2 MPa at 0.5 us,
    26.4 MPa at 1 us."""
    tau_half, tau_one = runs[10e-9][500][0], runs[10e-9][1000][0]
    assert tau_half == pytest.approx(38.24e6, rel=3e-3)  # regression pin (the model's own output)
    assert tau_one == pytest.approx(26.43e6, rel=3e-3)   # regression pin
    assert tau_one < 0.11 * MU0 * SIGMA_N


def test_film_thickness_follows_the_conduction_balance(runs):
    """Viscous heat eta_L V^2/delta against conduction into the cold solid kappa (T_F - T0)/sqrt(pi alpha t):
    delta ~ eta_L V^2 sqrt(pi alpha t)/(kappa (T_F - T0)), 13.8 nm at 1 us (measured 13.27 nm: -4 %), and
    delta ~ sqrt(t) (measured ratio 1 us / 0.5 us = 1.453 against sqrt 2 = 1.414: +2.7 %)."""
    m = AL
    eta_L = m.parameters["liquid_viscosity"].value
    kappa = m.conductivity
    alpha = kappa / (m.rho0 * m.heat_capacity)
    estimate = eta_L * V**2 * math.sqrt(math.pi * alpha * T_END) / (kappa * (m.melting_temperature - 300.0))
    d_half, d_one = runs[10e-9][500][1], runs[10e-9][1000][1]
    assert d_one == pytest.approx(estimate, rel=0.06)
    assert d_one / d_half == pytest.approx(math.sqrt(2.0), rel=0.04)
    assert np.isfinite(d_one)


def onset(dz, dt, t_end=0.15e-6):
    """tau (Pa) and film thickness after every step to t_end, and the time of the first molten step."""
    layer = 2e-6
    col = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=layer, n_cells=int(round(layer / dz)),
                              depth=1.2 * AL.shear_wave_speed * t_end, eta_vp=50.0, inertia=True,
                              pressure_melting=False)
    n = int(round(t_end / dt))
    t, tau, film = np.arange(1, n + 1) * dt, np.empty(n), np.empty(n)
    for s in range(n):
        tau[s] = col.step(SIGMA_N, V, V, 0.0, MU0 * SIGMA_N, dt)[0][0]
        film[s] = col.film_thickness[0]
        assert col.status[0] == 0
    return t, tau, film


def test_melt_onset_transient():
    """The first nanoseconds after the melt (docs/theory/viscoplastic.md, "The melt onset").  The surface reaches
    T_F at the same step on 40 and 10 nm cells; the friction stress then falls from 250 MPa to ~120 MPa in ~5 ns,
    faster than the 1 ns step resolves, and the 40 nm surface cell starts melting later than the 10 nm one
    (enthalpy smearing over its 20 nm control volume), so the value at the first molten 1 ns step differs by
    9 % between the grids (measured 168.1 / 153.6 MPa; a limitation, pinned so that a change is noticed).
    5 ns later the four runs (40 / 10 nm cells, 1 / 0.25 ns steps) agree to 2.2 % (measured), 50 ns later to 0.55 %.
    (Onset at 92 ns on the Steinberg 7075-T6 set; 100 ns on the 2024-T4 set of version 0.3, with 1.8 / 0.6 %.)"""
    runs = {(dz, dt): onset(dz, dt) for dz in (40e-9, 10e-9) for dt in (1e-9, 0.25e-9)}
    first = {}
    for key, (t, tau, film) in runs.items():
        first[key] = t[np.argmax(film > 0.0)]
    onset_t = 92e-9
    assert first[40e-9, 1e-9] == first[10e-9, 1e-9] == pytest.approx(onset_t)
    assert first[40e-9, 0.25e-9] == first[10e-9, 0.25e-9] == pytest.approx(onset_t - 0.25e-9)

    def at(key, time):
        t, tau, _ = runs[key]
        return tau[int(np.argmin(np.abs(t - time)))]

    jump = at((40e-9, 1e-9), onset_t) / at((10e-9, 1e-9), onset_t) - 1.0
    assert 0.05 < jump < 0.12  # regression pin of the unresolved transient (measured 0.094)
    for time, tol in ((onset_t + 5e-9, 0.025), (onset_t + 50e-9, 0.007)):
        vals = [at(key, time) for key in runs]
        spread = max(vals) / min(vals) - 1.0
        print(f"\nt = {time * 1e9:.0f} ns: tau {[round(float(v) / 1e6, 2) for v in vals]} MPa, spread {spread:.2%}", end="")
        assert spread < tol


def _limited(max_picard, k=0.0, t_end=0.2e-6, dz=40e-9):
    col = ViscoplasticColumns(1, AL, beta_T=BETA, thickness=2e-6, n_cells=int(round(2e-6 / dz)),
                              depth=1.2 * AL.shear_wave_speed * t_end, eta_vp=50.0, inertia=True,
                              max_picard=max_picard, pressure_melting=False)
    tau, sub, its = [], [], []
    for _ in range(int(round(t_end / DT))):
        tau.append(col.step(SIGMA_N, V, V, k, MU0 * SIGMA_N, DT)[0][0])
        sub.append(col.substeps[0])
        its.append(col.iterations[0])
        assert col.status[0] == 0
    return np.array(tau), np.array(sub), np.array(its), abs(col.energy_residual()[0])


def test_unconverged_step_is_split():
    """A step of an imposed-slip column whose Picard iteration does not converge is redone as two half steps
    (recursively, down to dt/16).  With the sweep limit cut to 10, the onset on 40 nm cells needs it (measured: 29
    steps split, at most 5 sub-steps, none left unconverged); the history then follows the limit-100 run (no split)
    to 1.7e-3 / 1.9e-4 / 6.2e-4 in tau at 120 / 150 / 200 ns, with the energy balance exact.  The difference is the
    sub-steps' time error, up to 2.0e-3 over steps 110-200 of this run; which steps split is decided at round-off,
    so the value at a given step moves within that band from one kernel change to the next (40 steps split and
    4.6e-4 / 3.1e-4 / 2.7e-4 before issue 26's Picard test, 53 and 6.4e-4 / 7.5e-4 / 3.7e-4 with it)."""
    ref, ref_sub, ref_its, _ = _limited(100)
    tau, sub, its, residual = _limited(10)
    assert np.all(ref_sub == 1) and np.all(ref_its > 0)
    assert 1 <= np.count_nonzero(sub > 1) <= 60 and sub.max() <= 8 and np.all(its > 0)
    assert residual < 1e-13
    for step in (120, 150, 200):
        assert tau[step - 1] == pytest.approx(ref[step - 1], rel=2.5e-3)


def test_coupled_column_is_split_too():
    """With a macroscopic compliance (k > 0, a slide-line node) an unconverged step is split as well: each half step
    takes k/2 and the free slip the first half left, so the impulses add up to the step's and tau is their mean
    (version 0.3 kept the step unsplit).  With the sweep limit cut to 3: 29 steps split, up to 16 sub-steps, 17
    still unconverged on dt/16 (kept, flagged by negative iterations); energy balance 7.1e-12 (24 unconverged and
    4.1e-12 with the Picard test on the increment alone, before the error bound of issue 26)."""
    tau, sub, its, residual = _limited(3, k=1e-12, t_end=0.12e-6)
    assert np.count_nonzero(sub > 1) >= 20 and sub.max() == 16 and np.any(its < 0)
    assert residual < 1e-11  # measured 7.1e-12
