"""Uncoupled sub-grid runs: imposed histories of slip velocity and normal stress, or of heat flux.

This is the thesis's uncoupled solver (§7.3.2, §8.2) generalised to tables: the slip is
imposed (both masses infinite in :class:`SubgridInterface`, so the sticking cap and the
slip correction vanish), the loading of a step is the table's value at the step's midpoint
(exact for piecewise-constant tables whose breaks fall on step ends).  In the pure thermal
mode the table gives the generated flux and the column receives beta_T times it.

Outputs (written row by row and flushed, so that a run that fails leaves readable files):

* ``history.csv``: ``t [s],theta_interface [K],tau [Pa],slip_macro [m/s],slip_local [m/s],flux [W/m^2],iterations``
  at the end of every step; ``flux`` is the flux entering the column (beta_T tau [v]);
  tau and the slips are ``nan`` in the pure thermal mode.  The viscoplastic model adds ``film_thickness [m]``
  and ``substeps``: a step whose Picard iteration does not converge is redone as 2, 4, ... sub-steps
  (``substeps`` > 1; tau, slips and flux are then the step's means, ``iterations`` the sweeps of all
  sub-steps); ``iterations`` < 0: a sub-step of dt/16 still reached the Picard sweep limit and was kept
  (its energy balance is exact);
* ``profiles.csv``: ``t [s],z [m],theta [K],eps_p [-]`` in long form at the output times (and t = 0).

With several loadings (columns) the first writes these names and loading ``k`` writes
``history_<name>.csv`` / ``profiles_<name>.csv`` (name defaults to ``column<k>``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np

from shockfriction.errors import SimulationError
from shockfriction.friction.subgrid.column import ThermalColumns
from shockfriction.friction.subgrid.interface import SubgridInterface
from shockfriction.materials.library import get_material, heat_share

HISTORY_HEADER = "t [s],theta_interface [K],tau [Pa],slip_macro [m/s],slip_local [m/s],flux [W/m^2],iterations"
PROFILE_HEADER = "t [s],z [m],theta [K],eps_p [-]"
FLUSH_EVERY = 200


def table_value(times, values, t, interpolation: str):
    """Value of a loading table at times ``t`` (array): held constant or linearly interpolated."""
    times = np.asarray(times, float)
    values = np.asarray(values, float)
    t = np.asarray(t, float)
    if interpolation == "linear":
        return np.interp(t, times, values)
    idx = np.searchsorted(times, t, side="right") - 1
    return values[np.clip(idx, 0, values.size - 1)]


def step_ends(duration: float, dt: float, output_times) -> np.ndarray:
    """End times of the steps: multiples of dt, shortened to land on every output time and the end."""
    n = int(math.floor(duration / dt * (1 + 1e-12)))
    ends = dt * np.arange(1, n + 1)
    extra = [t for t in list(output_times) + [duration] if t > 0.0]
    ends = np.union1d(ends, extra)
    ends = ends[ends <= duration * (1 + 1e-12)]
    # merge ends closer than 1e-9 dt (round-off duplicates)
    keep = np.concatenate(([True], np.diff(ends) > 1e-9 * dt))
    return ends[keep]


@dataclass
class RunResult:
    """What a run produced (for plots and tests): per column, time series and profiles."""

    names: list[str]
    t: np.ndarray
    theta_interface: np.ndarray           # (n_steps, n_columns)
    tau: np.ndarray
    flux_in: np.ndarray
    iterations: np.ndarray
    z: np.ndarray
    profile_times: list[float] = field(default_factory=list)
    profiles: list[np.ndarray] = field(default_factory=list)   # each (n_columns, n_nodes)
    eps_profiles: list[np.ndarray] = field(default_factory=list)
    files: list[Path] = field(default_factory=list)
    melting_temperature: float = math.nan
    film: Optional[np.ndarray] = None     # (n_steps, n_columns) molten film thickness (viscoplastic model)
    substeps: Optional[np.ndarray] = None  # (n_steps, n_columns) sub-steps of each step (viscoplastic; > 1: split)


def _names(deck) -> list[str]:
    return [ld.name or f"column{k}" for k, ld in enumerate(deck.loading)]


def _file(out: Path, stem: str, k: int, names: list[str]) -> Path:
    return out / (f"{stem}.csv" if k == 0 else f"{stem}_{names[k]}.csv")


def run_subgrid(deck, out_dir: Path, source: str = "deck", force: bool = False) -> RunResult:
    """Run a validated :class:`~shockfriction.deck.subgrid.SubgridDeck`; write the CSV files in ``out_dir``
    (new or empty; a non-empty folder is refused unless ``force``, as on the command line)."""
    from shockfriction.io.outdir import prepare_out_dir

    out = prepare_out_dir(out_dir, force=force, option="out_dir")
    names = _names(deck)
    n = len(deck.loading)
    mat = get_material(deck.material)
    share = deck.heat_share if deck.heat_share is not None else heat_share(mat, get_material(deck.other_material))
    ends = step_ends(deck.duration, deck.dt, deck.output_times)
    starts = np.concatenate(([0.0], ends[:-1]))
    mids = 0.5 * (starts + ends)
    thermal = deck.mode == "flux"
    if thermal:
        flux = np.stack([table_value(ld.times, ld.heat_flux, mids, ld.interpolation) for ld in deck.loading], 1)
        columns = ThermalColumns(n, deck.column.thickness, deck.column.cells, mat.conductivity, mat.rho0,
                                 mat.heat_capacity, T0=deck.T0, grading=deck.column.grading)
        z = columns.z
        sg = None
    else:
        slip = np.stack([table_value(ld.times, ld.slip_velocity, mids, ld.interpolation) for ld in deck.loading], 1)
        sigma = np.stack([table_value(ld.times, ld.normal_stress, mids, ld.interpolation) for ld in deck.loading], 1)
        fr = deck.friction
        # the other body's material where the deck names it (the viscoplastic model's two-sided heat), else the share
        other = share if deck.heat_share is not None else get_material(deck.other_material)
        sg = SubgridInterface(n, mat, other, thickness=deck.column.thickness, n_cells=deck.column.cells,
                              grading=deck.column.grading, model=deck.model, mu0=fr.mu0, f=fr.f,
                              taylor_quinney=fr.taylor_quinney, T0=deck.T0,
                              viscoplastic=_viscoplastic_options(deck, mat, sigma))
        columns = sg.columns
        z = sg.z
    nsteps = ends.size
    res = RunResult(names, ends, np.empty((nsteps, n)), np.full((nsteps, n), np.nan), np.empty((nsteps, n)),
                    np.zeros((nsteps, n), dtype=np.int64), z, melting_temperature=mat.melting_temperature)
    hist_files = [_file(out, "history", k, names) for k in range(n)]
    prof_files = [_file(out, "profiles", k, names) for k in range(n)]
    res.files = hist_files + prof_files
    out_times = [t for t in deck.output_times]
    hist = [p.open("w", newline="") for p in hist_files]
    prof = [p.open("w", newline="") for p in prof_files]
    try:
        # extra columns of the viscoplastic model: molten film thickness (m), sub-steps of the step
        film = (not thermal) and deck.model == "viscoplastic"
        if film:
            res.film = np.zeros((nsteps, n))
            res.substeps = np.ones((nsteps, n), dtype=np.int64)
        for fh in hist:
            fh.write(HISTORY_HEADER + (",film_thickness [m],substeps" if film else "") + "\n")
        for fh in prof:
            fh.write(PROFILE_HEADER + "\n")
        eps0 = np.zeros((n, z.size))
        if out_times and out_times[0] == 0.0:
            _write_profiles(prof, res, 0.0, z, columns.theta, eps0)
        pending = [t for t in out_times if t > 0.0]
        for i in range(nsteps):
            dt = ends[i] - starts[i]
            if thermal:
                q = share * flux[i]
                columns.step(dt, q)
                theta_s = columns.surface()
                if columns.melt_index(mat.melting_temperature) >= 0:  # a node not finite or not below T_F
                    j = int(np.argmax(np.max(columns.theta, axis=1)))
                    hot = float(columns.theta[j].max())
                    raise SimulationError(f"{source}: column {names[j]!r} reached {hot:.6g} K "
                                          f"(melting {mat.melting_temperature:g} K) at step {i + 1}, "
                                          f"t = {ends[i]:.6e} s: the imposed flux melts the body")
                tau = slip_m = slip_l = np.full(n, np.nan)
                q_in = q
                iters = np.zeros(n, dtype=np.int64)
            else:
                tau, _ = sg.step(sigma[i], slip[i], slip[i], np.inf, np.inf, 1.0, dt, cycle=i + 1, time=ends[i])
                theta_s = sg.theta_interface
                slip_m, slip_l, q_in, iters = sg.slip_macro, sg.slip_local, sg.flux_in, sg.iterations
            _check_finite(source, names, i + 1, ends[i], thermal, theta_interface=theta_s, flux_in=q_in,
                          tau=tau, slip_macro=slip_m, slip_local=slip_l)
            res.theta_interface[i] = theta_s
            res.tau[i] = tau
            res.flux_in[i] = q_in
            res.iterations[i] = iters
            if film:
                res.film[i] = sg.film_thickness
                res.substeps[i] = sg.vp.substeps
            for k, fh in enumerate(hist):
                fh.write(f"{ends[i]:.9e},{theta_s[k]:.9e},{tau[k]:.9e},{slip_m[k]:.9e},{slip_l[k]:.9e},"
                         f"{q_in[k]:.9e},{int(iters[k])}"
                         + (f",{sg.film_thickness[k]:.9e},{int(sg.vp.substeps[k])}" if film else "") + "\n")
            if (i + 1) % FLUSH_EVERY == 0:
                for fh in hist:
                    fh.flush()
            if pending and ends[i] >= pending[0] * (1 - 1e-12):
                pending.pop(0)
                eps = sg.eps_p if sg is not None else eps0
                _write_profiles(prof, res, ends[i], z, columns.theta, eps)
    except SimulationError as exc:
        raise SimulationError(f"{exc}\n(output so far in {out})") from None
    finally:
        for fh in hist + prof:
            fh.close()
    return res


def _check_finite(source: str, names: list[str], step: int, t: float, thermal: bool, **values) -> None:
    """SimulationError naming the column, quantity, step and time of the first non-finite value of a step
    (the pure thermal mode has no tau and slips: those are nan by design and not checked)."""
    for what, v in values.items():
        if thermal and what in ("tau", "slip_macro", "slip_local"):
            continue
        bad = ~np.isfinite(np.asarray(v, dtype=float))
        if bad.any():
            j = int(np.argmax(bad))
            raise SimulationError(f"{source}: column {names[j]!r}: {what} became non-finite ({float(v[j])!r}) at "
                                  f"step {step}, t = {t:.6e} s")


def _write_profiles(files, res: RunResult, t: float, z, theta, eps) -> None:
    res.profile_times.append(t)
    res.profiles.append(theta.copy())
    res.eps_profiles.append(eps.copy())
    for k, fh in enumerate(files):
        fh.write("".join(f"{t:.9e},{zi:.9e},{th:.9e},{e:.9e}\n" for zi, th, e in zip(z, theta[k], eps[k])))
        fh.flush()


def _viscoplastic_options(deck, mat, sigma: np.ndarray) -> dict | None:
    """The [viscoplastic] options with ``depth = "auto"`` resolved to 1.2 c_s(p_max, T0) duration (the shear-wave
    reach at the highest normal stress of the loading: nothing reaches the far end) and "none" to no continuation."""
    if deck.model != "viscoplastic":
        return None
    from shockfriction.deck.subgrid import ViscoplasticDeck
    from shockfriction.materials.strength import scg_shear_ratio
    opts = (deck.viscoplastic or ViscoplasticDeck()).options()
    if opts["depth"] == "auto":
        r = scg_shear_ratio(float(np.max(sigma)), deck.T0, mat.scg_g, mat.scg_h, mat.scg_xi, mat.melting_temperature)
        opts["depth"] = 1.2 * math.sqrt(mat.G0 * max(r, 1.0) / mat.rho0) * deck.duration
    elif opts["depth"] == "none":
        opts["depth"] = None
    return opts
