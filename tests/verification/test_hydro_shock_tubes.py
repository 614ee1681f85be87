"""Hydrocode against exact gas-dynamics solutions: Sod (Riemann), Noh, Sedov.

Every exact value is computed here by shockfriction.analysis; decks are in
examples/verification/.  Coarse meshes by default, refinement studies under `slow`.
"""

from pathlib import Path

import numpy as np
import pytest

from shockfriction.analysis import noh, riemann, sedov
from shockfriction.analysis.convergence import front_position, l1_error, observed_order
from shockfriction.analysis.strip import read_deck, strip_profile
from shockfriction.hydro.api import run

DECKS = Path(__file__).resolve().parents[2] / "examples" / "verification"
SOD_LEFT, SOD_RIGHT = riemann.GasState(1.0, 0.0, 1.0), riemann.GasState(0.125, 0.0, 0.1)


def sod_l1(cells_per_half: int) -> tuple[float, float]:
    deck = read_deck(DECKS / "sod.toml")
    for body in deck["bodies"]:
        body["mesh"]["ny"] = cells_per_half
    result = run(deck)
    prof = strip_profile(result.state, "y")
    rho, _, _ = riemann.profile(SOD_LEFT, SOD_RIGHT, 1.4, prof["coord"], result.state.t, x0=0.5)
    assert result.state.t == pytest.approx(0.2)
    return 0.5 / cells_per_half, l1_error(prof["rho"], rho, prof["size"])


def _sod_study(resolutions):
    h, err = zip(*(sod_l1(n) for n in resolutions))
    order = observed_order(h, err)
    pairwise = [np.log(err[i] / err[i + 1]) / np.log(h[i] / h[i + 1]) for i in range(len(h) - 1)]
    print(f"\nSod L1(rho): h = {h}, errors = {err}, observed order {order:.3f}, pairwise {pairwise}")
    return h, err, order


def test_sod_star_state_plateaus():
    """Pressure and velocity between the rarefaction tail and the shock, density of both star states."""
    deck = read_deck(DECKS / "sod.toml")
    for body in deck["bodies"]:
        body["mesh"]["ny"] = 200
    result = run(deck)
    prof = strip_profile(result.state, "y")
    star = riemann.solve_star(SOD_LEFT, SOD_RIGHT, 1.4)
    x = (prof["coord"] - 0.5) / result.state.t  # similarity coordinate
    c_star_l = np.sqrt(1.4 * star.p / star.rho_left)
    c_r = np.sqrt(1.4 * SOD_RIGHT.p / SOD_RIGHT.rho)
    shock = c_r * np.sqrt(2.4 / 2.8 * star.p / SOD_RIGHT.p + 0.4 / 2.8)  # right shock speed (1.7522)
    left_star = (x > star.u - c_star_l + 0.15) & (x < star.u - 0.15)
    right_star = (x > star.u + 0.15) & (x < shock - 0.15)
    both = left_star | right_star
    checks = {
        "p*": (np.median(prof["p"][both]), star.p),
        "u*": (np.median(prof["velocity"][both]), star.u),
        "rho*_L": (np.median(prof["rho"][left_star]), star.rho_left),
        "rho*_R": (np.median(prof["rho"][right_star]), star.rho_right),
    }
    print("\nSod star states (2x200 cells): " + ", ".join(
        f"{k} {got:.5f} vs {ref:.5f} ({got / ref - 1:+.1e})" for k, (got, ref) in checks.items()))
    for name, (got, ref) in checks.items():
        assert got == pytest.approx(ref, rel=0.01), name


def test_sod_l1_error_falls_with_refinement():
    h, err, order = _sod_study((50, 100, 200))
    # measured 5.3e-3, 2.7e-3, 1.8e-3: first order at shocks, less at the contact (~0.5 for
    # a first-order smeared contact): require a falling error and an order above 0.5
    assert err[0] > err[1] > err[2]
    assert order > 0.5
    assert err[1] < 4e-3


@pytest.mark.slow
def test_sod_convergence_fine():
    h, err, order = _sod_study((100, 200, 400, 800))
    assert all(a > b for a, b in zip(err, err[1:]))
    assert order > 0.5 and err[-1] < 1.2e-3


def _noh(name, axis, geometry, cells):
    deck = read_deck(DECKS / f"{name}.toml")
    mesh = deck["bodies"][0]["mesh"]
    mesh["nx" if axis == "x" else "ny"] = cells
    if axis == "x":  # keep the r-z strip's cells square (one cell high in z)
        mesh["corners"][2][1] = mesh["corners"][3][1] = f"{1.0 / cells} m"
    result = run(deck)
    prof = strip_profile(result.state, axis)
    return result, prof


def test_noh_planar_density_and_shock_position():
    result, prof = _noh("noh_planar", "y", 1, 100)
    t = result.state.t
    shock = noh.shock_speed(1.0, 5.0 / 3.0) * t  # 0.2 m
    plateau = (prof["coord"] > 0.2 * shock) & (prof["coord"] < 0.75 * shock)  # away from wall heating
    rel = np.abs(prof["rho"][plateau] / 4.0 - 1.0)
    p_rel = np.abs(prof["p"][plateau] / (4.0 / 3.0) - 1.0)
    front = front_position(prof["coord"], prof["rho"], 2.5)  # halfway between 1 and 4
    print(f"\nNoh planar (100 cells): max |rho/4 - 1| = {rel.max():.4f}, max |p/p_exact - 1| = {p_rel.max():.4f}, "
          f"shock at {front:.5f} (exact {shock:.5f})")
    assert plateau.sum() >= 5
    assert rel.max() < 0.05 and p_rel.max() < 0.05
    assert front == pytest.approx(shock, rel=0.02)
    # ahead of the shock: cold gas moving at -1 m/s with rho0 = 1
    ahead = (prof["coord"] > 1.2 * shock) & (prof["coord"] < 0.5 * prof["coord"].max())  # the far end is free
    assert np.allclose(prof["rho"][ahead], 1.0, rtol=1e-3)


def _noh_cylindrical(cells):
    result, prof = _noh("noh_cylindrical", "x", 2, cells)
    t = result.state.t
    shock = noh.shock_speed(1.0, 5.0 / 3.0) * t
    plateau = (prof["coord"] > 0.4 * shock) & (prof["coord"] < 0.75 * shock)
    rho_err = np.abs(prof["rho"][plateau] / 16.0 - 1.0).max()
    p_err = np.abs(prof["p"][plateau] / (16.0 / 3.0) - 1.0).max()
    # the outer boundary (initially r = 1) has moved in to r = 1 - t: stay clear of it
    ahead = (prof["coord"] > 1.3 * shock) & (prof["coord"] < 0.8 * prof["coord"].max())
    rho_ahead, _, _, _ = noh.profile(prof["coord"][ahead], t, 2)
    ahead_err = np.abs(prof["rho"][ahead] / rho_ahead - 1.0).max()
    return rho_err, p_err, ahead_err


def test_noh_cylindrical_rz_density_16():
    errors = {n: _noh_cylindrical(n) for n in (200, 400)}
    order = observed_order([1 / 200, 1 / 400], [errors[200][0], errors[400][0]])
    print(f"\nNoh cylindrical r-z, plateau 0.4-0.75 R_s: (rho, p, ahead) errors {errors}, "
          f"observed order of the density error {order:.2f}")
    rho_err, p_err, ahead_err = errors[400]
    assert rho_err < 0.05 and p_err < 0.05 and ahead_err < 0.02
    assert errors[400][0] < errors[200][0]


@pytest.mark.slow
def test_noh_cylindrical_fine():
    rho_err, p_err, ahead_err = _noh_cylindrical(800)
    print(f"\nNoh cylindrical 800 cells: rho {rho_err:.4f}, p {p_err:.4f}, ahead {ahead_err:.4f}")
    assert rho_err < 0.03 and p_err < 0.03


def _sedov(geometry, cells):
    name, axis = ("sedov_planar", "y") if geometry == 1 else ("sedov_cylindrical", "x")
    deck = read_deck(DECKS / f"{name}.toml")
    hot, cold = deck["bodies"]
    d = 1.0 / cells
    if geometry == 1:
        hot["mesh"]["corners"] = [["0 m", "0 m"], [f"{d} m", "0 m"], [f"{d} m", f"{d} m"], ["0 m", f"{d} m"]]
        hot["specific_energy"] = f"{0.5 / d} J/kg"  # E_half = 0.5 J/m^2, rho0 = 1
        cold["mesh"]["corners"] = [["0 m", f"{d} m"], [f"{d} m", f"{d} m"], [f"{d} m", "1 m"], ["0 m", "1 m"]]
        cold["mesh"]["ny"] = cells - 1
        energy = 1.0  # the symmetric blast of twice the half-space energy
    else:
        hot["mesh"]["corners"] = [["0 m", "0 m"], [f"{d} m", "0 m"], [f"{d} m", f"{d} m"], ["0 m", f"{d} m"]]
        hot["specific_energy"] = f"{1.0 / (np.pi * d * d)} J/kg"  # E = 1 J/m in the axis cell
        cold["mesh"]["corners"] = [[f"{d} m", "0 m"], ["1 m", "0 m"], ["1 m", f"{d} m"], [f"{d} m", f"{d} m"]]
        cold["mesh"]["nx"] = cells - 1
        energy = 1.0
    result = run(deck)
    prof = strip_profile(result.state, axis)
    sol = sedov.solve(geometry, 1.4)
    radius = sol.shock_radius(energy, result.state.t)
    front = front_position(prof["coord"], prof["rho"], 0.5 * (1.0 + prof["rho"].max()))
    rho, _, p = sol.profile(prof["coord"], result.state.t, energy)
    inside = prof["coord"] < 1.2 * radius
    weights = prof["size"][inside] * prof["coord"][inside] ** (geometry - 1)  # volume weights
    rho_l1 = l1_error(prof["rho"][inside], rho[inside], weights) / 6.0  # relative to the shock density
    p_l1 = l1_error(prof["p"][inside], p[inside], weights) / p.max()
    return front / radius - 1.0, prof["rho"].max(), result.summary["relative_energy_error"], rho_l1, p_l1


@pytest.mark.parametrize("geometry", [1, 2])
def test_sedov_shock_position(geometry):
    err, peak, energy_err, rho_l1, p_l1 = _sedov(geometry, 100)
    print(f"\nSedov j={geometry} (100 cells): shock position error {err:+.4f}, peak density {peak:.3f} "
          f"(exact 6), relative energy error {energy_err:.1e}, L1(rho)/6 = {rho_l1:.4f}, L1(p)/p_shock = {p_l1:.4f}")
    assert abs(err) < 0.02
    assert rho_l1 < 0.05 and p_l1 < 0.05


@pytest.mark.slow
@pytest.mark.parametrize("geometry", [1, 2])
def test_sedov_shock_position_refined(geometry):
    runs = [_sedov(geometry, n) for n in (100, 200, 400)]
    errs = [abs(r[0]) for r in runs]
    rho_l1 = [r[3] for r in runs]
    order = observed_order([1 / 100, 1 / 200, 1 / 400], rho_l1)
    print(f"\nSedov j={geometry}: |shock position error| at 100/200/400 cells = {errs}; "
          f"L1(rho)/6 = {rho_l1}, observed order {order:.2f}")
    assert errs[-1] < 0.01 and errs[-1] < errs[0]
    assert rho_l1[0] > rho_l1[1] > rho_l1[2]
