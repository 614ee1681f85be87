"""The vectorised per-step API of the sub-grid interface models (what the slide line calls).

One :class:`SubgridInterface` holds ``n_columns`` 1D thermal columns, one per slide-line
node, all of the modelled body's material (by default the slave side, ARCHITECTURE.md).
Every hydro step the slide line calls :meth:`SubgridInterface.step` once with arrays of
shape ``(n_columns,)`` (scalars broadcast); all quantities are SI.

Inputs of ``step(sigma_n, v_free, slip_prev, m_slave, m_guide, area, dt)``:

``sigma_n`` (Pa)
    normal contact stress F_N from the contact step, **compression positive**.
    ``sigma_n <= 0`` means the node is not in contact: no friction, no heat.
``v_free`` (m/s)
    the free (uncorrected) relative tangential velocity [V*]^{n+1/2} =
    (v_slave - v_guide) . t, after the contact step, before friction.
``slip_prev`` (m/s)
    the corrected relative tangential velocity [V]^{n-1/2} of the previous step (the
    ``slip_corrected`` this method returned then; ``v_free`` on the first step), same sign
    convention.  It time-centres the slip that heats the interface, [V]^n = ([V]^{n+1/2} +
    [V]^{n-1/2})/2 (thesis eq. 7.100).
``m_slave``, ``m_guide`` (kg)
    mass of the slave node and of its projection on the guide surface.  ``np.inf`` for a
    rigid partner; both ``np.inf`` imposes the slip (the uncoupled solvers of §7.3.2, §8.2).
``area`` (m^2)
    the slave node's contact area S (> 0 where ``sigma_n > 0``; 0 is accepted out of contact).
``dt`` (s)
    the hydro step (the columns use the same step; factors are reused while it is unchanged).

Returns ``(tau, slip_corrected)``:

``tau`` (Pa, >= 0)
    magnitude of the friction stress F_T = tau(0).  The friction force **opposes the free
    slip**: the slave receives the impulse -sign(v_free) tau S dt, the guide point
    +sign(v_free) tau S dt (equal and opposite: momentum is conserved), to be shared
    between the guide nodes by the slide line (shares 1-coef, coef).
``slip_corrected`` (m/s)
    the macroscopic relative velocity after friction, [V]^{n+1/2} = v_free -
    sign(v_free) tau S dt (1/m_slave + 1/m_guide) (thesis eq. 7.99 with the sign erratum of
    digest §9 item 6 fixed).  It never reverses the slip: tau <= tau_stick =
    m_r |v_free|/(S dt), m_r = m_slave m_guide/(m_slave + m_guide) (reduced-mass sticking force
    F* of eq. 6.82), and tau = tau_stick gives slip_corrected = 0 (the node sticks).  A node with
    ``v_free == 0`` needs no friction and gets tau = 0 (also when the slip is imposed).

The stress is tau = min(mu0 sigma_n, tau_stick, f Ymax/sqrt(3) G(sigma_n, Theta(0))/G0)
(Coulomb cap, sticking cap and the thesis's SCG branch, eq. 7.12 / 8.28), solved together
with the heat flux beta_T tau |[v]| into the column and the interface temperature Theta(0)
(Brent, tolerance ``xtol`` kelvin).  ``slip`` in this module always means a relative
tangential *velocity* (m/s), not a displacement.

``model="viscoplastic"`` delegates to :class:`~shockfriction.friction.subgrid.viscoplastic.ViscoplasticColumns`
(options ``viscoplastic={"eta_vp": Pa s, "inertia": bool, "tresca": bool, "depth": m, "depth_ratio": r, "far_end": "impedance" | "held"}``; ``film_thickness`` in m; the
plastic heat is deposited in the same step, ``heat_plastic`` then also holds the viscous, softening and
numerical heat; column kinetic/elastic/radiated energies are in ``self.vp.energies()``).

Per-node diagnostics after a step (arrays ``(n_columns,)``): ``theta_interface`` (K, column
temperature at z = 0), ``slip_macro`` (|[V]^n|, m/s), ``slip_local`` ([v]^n, m/s, the true
interface slip that heats), ``slip_plastic`` (sqrt(3) int d_eps dz/dt, m/s; 0 for the
thermoelastic model), ``flux_in`` (beta_T tau [v], W/m^2 entering the column), ``iterations``
(Brent steps), and cumulative energies per unit area (J/m^2): ``friction_work`` (sum of
tau |[V]^n| dt), ``heat_interface`` (sum of flux_in dt), ``plastic_work`` (sum of sqrt(3) tau
int d_eps dz), ``heat_plastic`` (plastic heat deposited in the column, beta_Q times the plastic work,
one step late), ``heat_stored`` (rho c int (theta - T0) dz).  Balances: friction_work =
heat_interface/beta_T + plastic_work and heat_stored = heat_interface + heat_plastic.
``melt_energy`` (J/m^2, ch. 8): lagged plastic heat clipped off by the melt guard (below), so that
beta_Q plastic_work = heat_plastic + plastic_heat_pending + melt_energy.
``lag_temperature`` (K, ch. 8) is the largest local temperature rise that the lagged plastic heat of
this step will add in the next one: the size of the lag the thesis asks to check a posteriori (8.47).  Per-node profiles:
``theta`` and ``eps_p`` shaped ``(n_columns, n_nodes)`` on ``z`` (``theta`` is a view of the columns' state,
stored (n_nodes, n_columns) (docs/theory/subgrid-layout.md), that the next step overwrites: copy it to keep it).
"""

from __future__ import annotations

import math

import numpy as np

from shockfriction.errors import SimulationError
from shockfriction.friction.subgrid.column import ThermalColumns, column_sums, per_column, sweep_columns
from shockfriction.friction.subgrid.thermoelastic import (ABOVE_MELT, BAD_INPUT, NO_CONVERGENCE, SQRT3,
                                                           book_step, first_nonfinite, first_nonzero,
                                                           solve_thermoelastic,
                                                           step_inputs)
from shockfriction.friction.subgrid.thermoelastoplastic import (advance_and_solve_parallel, parallel_blocks,
                                                                  solve_in_parallel, solve_thermoelastoplastic,
                                                                  source_span)
from shockfriction.materials.library import Material, get_material, heat_share

MODELS = ("thermoelastic", "thermoelastoplastic", "viscoplastic")
#: the keys of ``viscoplastic=`` (ViscoplasticColumns keywords; see _init_viscoplastic)
VISCOPLASTIC_OPTIONS = ("eta_vp", "inertia", "tresca", "depth", "depth_ratio", "far_end", "picard_tol", "heat",
                        "pressure_melting", "time_scheme")
#: how the viscoplastic columns share the frictional heat: "two-sided" (a thermal column in the other body, joined
#: by continuity of temperature and flux; the default where the other body's material is known) or "share" (the
#: fixed share beta_T of the thesis, eq. 2.101)
HEAT_MODES = ("two-sided", "share")
#: per-node diagnostics of every model, arrays (n_columns,) (see the module docstring)
NODE_DIAGNOSTICS = ("theta_interface", "slip_macro", "slip_local", "slip_plastic", "flux_in", "tau", "friction_work",
                    "heat_interface", "heat_plastic", "plastic_work", "lag_temperature", "melt_energy", "tau_coulomb",
                    "tau_stick")
MELT_MARGIN = 1.0  # K: the lagged plastic heat never takes a column node above T_F - MELT_MARGIN


def _material(m) -> Material:
    return get_material(m) if isinstance(m, str) else m


class SubgridInterface:
    """Sub-grid columns under ``n_columns`` slide-line nodes (see the module docstring for the API).

    ``other`` is the opposite body's material (heat share beta_T = e1/(e1 + e2), thesis eq. 2.101)
    or directly the share beta_T in [0, 1] of the frictional heat entering the modelled body.
    """

    def __init__(self, n_columns: int, material, other, *, thickness: float = 20e-6, n_cells: int = 500,
                 grading: float = 1.0, model: str = "thermoelastic", mu0: float, f: float,
                 taylor_quinney: float = 0.9, T0: float = 300.0, xtol: float = 1e-9, max_iter: int = 100,
                 viscoplastic: dict | None = None):
        if model not in MODELS:
            raise ValueError(f"model must be one of {MODELS}, got {model!r}")
        self.material = _material(material)
        self.other = None  # the other body's material, where known (two-sided heat of the viscoplastic model)
        if isinstance(other, (int, float)) and not isinstance(other, bool):
            self.beta_T = float(other)
        else:
            self.other = _material(other)
            self.beta_T = heat_share(self.material, self.other)
        if not 0.0 <= self.beta_T <= 1.0:
            raise ValueError(f"heat share must lie in [0, 1], got {self.beta_T!r}")
        if not (mu0 >= 0.0 and f >= 0.0 and 0.0 <= taylor_quinney <= 1.0):
            raise ValueError(f"need mu0 >= 0, f >= 0, 0 <= taylor_quinney <= 1; got {mu0}, {f}, {taylor_quinney}")
        T_F = self.material.melting_temperature
        if not T0 < T_F:
            raise ValueError(f"initial temperature {T0} K must be below the melting temperature {T_F} K")
        m = self.material
        if model == "viscoplastic":  # options: eta_vp (Pa s), inertia (bool), tresca (bool: the f branch)
            self._init_viscoplastic(n_columns, thickness, n_cells, grading, mu0, f, taylor_quinney, T0,
                                    dict(viscoplastic or {}))
            return
        self.columns = ThermalColumns(n_columns, thickness, n_cells, m.conductivity, m.rho0, m.heat_capacity,
                                      T0=T0, grading=grading)
        self.model = model
        self.mu0, self.f, self.beta_Q = float(mu0), float(f), float(taylor_quinney)
        self.scg = m.scg_params()
        self._T_F = float(T_F)
        self.xtol, self.max_iter = float(xtol), int(max_iter)
        n, nn = self.n_columns, self.columns.n_nodes
        self.eps_p = np.zeros((n, nn))
        self._hard = np.ones((n, nn))  # (1 + beta eps_p)^n, or minus a lower bound of it where stale (lazy hardening)
        self._hard_blk = np.ones((n, (nn + 7) // 8))  # min_{i >= 8b} |_hard[j, i]|: the plastic-front bound uses it
        # J/m^3, deposited next step (lagged source); (n_nodes, n_columns) like the temperatures it heats
        self._pending_plastic_heat = np.zeros((nn, n))
        self._pending_flags = np.zeros(n, dtype=np.bool_)  # column j has pending heat (a nonzero source)
        self._pending_sum = np.zeros(n)  # sum_i w_i pending_ij (J/m^2), from finish_column
        self._deps = np.zeros((n, nn))
        self._depth = np.full(n, nn, dtype=np.int64)  # plastic-front bound: _deps[j, _depth[j]:] == 0
        self._pending_depth = np.zeros(n, dtype=np.int64)  # _pending_plastic_heat[_pending_depth[j]:, j] == 0
        self._use_front = True  # skip the nodes proven elastic (False: visit all, for the tests)
        for name in NODE_DIAGNOSTICS:
            setattr(self, name, np.zeros(n))
        self.theta_interface[:] = T0
        self.iterations = np.zeros(n, dtype=np.int64)
        self._status = np.zeros(n, dtype=np.int64)
        self._theta_s = np.zeros(n)
        self._v_half = np.zeros(n)
        self._k, self._tau_cap, self._F_N = np.zeros(n), np.zeros(n), np.zeros(n)

    def _init_viscoplastic(self, n, thickness, n_cells, grading, mu0, f, beta_Q, T0, opts):
        from shockfriction.friction.subgrid.viscoplastic import PICARD_TOL, ViscoplasticColumns
        unknown = set(opts) - set(VISCOPLASTIC_OPTIONS)
        if unknown:
            raise ValueError(f"unknown viscoplastic options {sorted(unknown)}: expected {', '.join(VISCOPLASTIC_OPTIONS)}")
        self.model = "viscoplastic"
        self.mu0, self.f, self.beta_Q = float(mu0), float(f), float(beta_Q)
        heat = opts.get("heat") or ("two-sided" if self.other is not None else "share")
        if heat not in HEAT_MODES:
            raise ValueError(f"viscoplastic heat = {heat!r}: expected one of {', '.join(HEAT_MODES)}")
        if heat == "two-sided" and self.other is None:
            raise ValueError("viscoplastic heat = 'two-sided' needs the other body's material (not a heat share)")
        self.heat_mode = heat
        self.vp = ViscoplasticColumns(n, self.material, beta_T=self.beta_T, thickness=thickness, n_cells=n_cells,
                                      grading=grading, f=self.f if opts.get("tresca", True) else None,
                                      taylor_quinney=beta_Q, eta_vp=opts.get("eta_vp"),
                                      inertia=bool(opts.get("inertia", True)), T0=T0, depth=opts.get("depth"),
                                      depth_ratio=opts.get("depth_ratio", 1.05),
                                      far_end=opts.get("far_end", "impedance"),
                                      picard_tol=opts.get("picard_tol") or PICARD_TOL,
                                      other=self.other if heat == "two-sided" else None,
                                      pressure_melting=bool(opts.get("pressure_melting", True)),
                                      time_scheme=opts.get("time_scheme") or "backward_euler")
        self.beta_T = self.vp.beta_T  # 1 with two-sided heat: all the slip heat enters at z = 0 and is conducted
        self.v_far = np.zeros(n)  # the far end's velocity relative to the hydro node (coupled closure)
        self.columns = self.vp
        for name in NODE_DIAGNOSTICS:
            setattr(self, name, np.zeros(n))
        self.theta_interface[:] = T0
        self.iterations = np.zeros(n, dtype=np.int64)
        self._k, self._tau_cap, self._F_N = np.zeros(n), np.zeros(n), np.zeros(n)
        self.eps_p = np.zeros((n, self.vp.z.size))  # cell values on the node above (last node: last cell)
        self._pending_plastic_heat = np.zeros((self.vp.z.size, n))  # no lagged heat: deposited in the same step

    def _step_viscoplastic(self, F_N, vf, vp, k, tau_cap, dt, when):
        c = self.vp
        try:
            tau, v_half = c.step(F_N, vf, vp, k, tau_cap, dt, v_far=self.v_far)
        except SimulationError as exc:
            raise SimulationError(f"sub-grid step {self._when(*when)}: {exc}") from None
        j = first_nonzero(c.status)
        if j >= 0:
            raise SimulationError(f"sub-grid step {self._when(*when)}: node {j}: the viscoplastic column solve failed "
                                  f"(status {int(c.status[j])}, theta(0) = {c.T[0, j]!r} K)")
        self.tau[:] = tau
        self.theta_interface[:] = c.T[0]
        self.slip_macro[:] = c.slip_macro
        self.slip_local[:] = c.slip_local
        self.flux_in[:] = c.flux_in
        self.slip_plastic[:] = self.slip_macro - self.slip_local
        self.iterations[:] = c.iterations  # negative: the Picard sweep limit was reached (step kept)
        self.eps_p[:, :-1] = c.eps.T
        self.eps_p[:, -1] = c.eps[-1]
        E = c.energies()
        self.friction_work[:] = E["friction_work"]
        self.heat_interface[:] = E["heat_interface"]
        self.plastic_work[:] = E["plastic_work"]
        self.heat_plastic[:] = self.beta_Q * E["plastic_work"] + E["viscous_heat"] + E["softening_heat"] \
            + E["numerical_heat"]
        return tau, v_half

    @property
    def film_thickness(self) -> np.ndarray:
        """Molten layer thickness per column (m; viscoplastic model only, zeros otherwise)."""
        return self.vp.film_thickness.copy() if self.model == "viscoplastic" else np.zeros(self.n_columns)

    # ------------------------------------------------------------------ views
    @property
    def n_columns(self) -> int:
        return self.columns.n_columns

    @property
    def z(self) -> np.ndarray:
        return self.columns.z

    @property
    def theta(self) -> np.ndarray:
        return self.columns.theta

    @property
    def heat_stored(self) -> np.ndarray:
        if self.model == "viscoplastic":
            return self.vp.heat_stored()
        return self.columns.heat_content()

    @property
    def plastic_heat_pending(self) -> np.ndarray:
        """Plastic heat of the last step not yet deposited in the column (J/m^2)."""
        if self.model == "thermoelastoplastic":
            return self._pending_sum.copy()  # summed node by node as finish_column writes it
        return column_sums(self.columns.weights, self._pending_plastic_heat)

    # ------------------------------------------------------------------ the step
    def step(self, sigma_n, v_free, slip_prev, m_slave, m_guide, area, dt: float, *,
             cycle: int | None = None, time: float | None = None):
        """Advance every column by ``dt``; return ``(tau, slip_corrected)`` (see module docstring)."""
        n = self.n_columns
        sig, vf, vp, ms, mg, S = (per_column(x, n) for x in (sigma_n, v_free, slip_prev, m_slave, m_guide, area))
        dt = float(dt)
        if not (dt > 0.0 and math.isfinite(dt)):
            raise SimulationError(f"sub-grid step {self._when(cycle, time)}: time step {dt!r} is not positive and finite")
        k, tau_cap, F_N = self._k, self._tau_cap, self._F_N
        j = step_inputs(sig, vf, vp, ms, mg, S, dt, self.mu0, k, self.tau_stick, tau_cap, self.tau_coulomb, F_N)
        if j >= 0:  # a node out of contact may have no area
            raise SimulationError(f"sub-grid step {self._when(cycle, time)}: bad input at node {j}: "
                                  f"sigma_n={float(sig[j]):.6g} Pa, "
                                  f"v_free={float(vf[j]):.6g} m/s, slip_prev={float(vp[j]):.6g} m/s, "
                                  f"m_slave={float(ms[j]):.6g}, m_guide={float(mg[j]):.6g}, area={float(S[j]):.6g}")
        when = (cycle, time)  # formatted only in a message
        if self.model == "viscoplastic":
            return self._step_viscoplastic(F_N, vf, vp, k, tau_cap, dt, when)

        plastic = self.model == "thermoelastoplastic"
        cols = self.columns
        T_F = self._T_F
        # Melt guard (thermoelastoplastic): the plastic heat of step n is deposited in step n + 1 (eq. 8.46);
        # near melting that deposit alone can carry a node past T_F, where the model has no state (strength
        # and friction vanish, no latent heat).  By the maximum principle of the backward-Euler solve,
        # theta_ad <= max_i (theta_i + deposit_i/(rho c)), so each node's deposit is clipped to
        # rho c (T_F - MELT_MARGIN - theta_i) in the forward sweep; the clipped energy (what melting would
        # absorb) is added to melt_energy.
        tau = self.tau
        q_in = self.flux_in
        if plastic:
            pend = self._pending_plastic_heat
            s0, s1, n_src = source_span(self._pending_depth)  # the columns whose pending heat may be nonzero
            sweep = cols.sweep_plan(dt, pend, n_src, 1.0 / cols.rho_c, T_F - MELT_MARGIN, self._pending_flags,
                                    (s0, s1))
            solve = (cols.theta_unit, cols.weights, self.eps_p, self._hard, self._hard_blk, F_N,
                     vf, vp, k, tau_cap, self.beta_T, self.f, self.scg, dt,
                     self.xtol, self.max_iter, self._theta_s, tau, self._v_half, self.slip_local, self.slip_plastic,
                     q_in, self._deps, self.iterations, self._status, self._depth, self.beta_Q * SQRT3,
                     self._pending_plastic_heat, self._pending_depth, self.plastic_work, self.lag_temperature,
                     cols.rho_c, self._pending_flags, self._pending_sum, self._use_front)
            if solve_in_parallel(self.n_columns):  # the sweep and the solve in one parallel region, the same bytes
                advance_and_solve_parallel(sweep, *solve, parallel_blocks(self.n_columns))
                X = cols.swept()
            else:
                sweep_columns(*sweep)
                X = cols.swept()
                solve_thermoelastoplastic(X, cols._sfx, *solve)
            self.melt_energy += cols._clipped  # the sweep's melt guard
            deposited = cols._deposited  # J/m^2 put in this step
        else:
            X = cols.advance(dt)
        unit = cols.theta_unit
        if self.model == "thermoelastic":
            solve_thermoelastic(X[0], unit[0], F_N, vf, vp, k, tau_cap, self.beta_T, self.f, self.scg, self.xtol,
                                self.max_iter, self._theta_s, tau, self._v_half, self.slip_local, q_in,
                                self.iterations, self._status)
            self.slip_plastic[:] = 0.0
        self._check(when)
        self._check_finite(when, plastic)
        cols.set_flux(q_in)  # theta = theta_ad + q_in theta_unit (eq. 7.70), applied by the next sweep
        bad = cols.melt_index(T_F)
        if bad >= 0:
            j, i = divmod(int(bad), cols.n_nodes)
            raise SimulationError(f"sub-grid step {self._when(*when)}: column {j} reached {X[i, j] + q_in[j] * unit[i]!r} K at "
                                  f"z = {self.z[i]:.3e} m (melting {T_F} K)")
        book_step(X[0], unit[0], q_in, tau, self._v_half, vp, dt, deposited if plastic else q_in, plastic, cols.active,
                  self.theta_interface, self.slip_macro, self.friction_work, self.heat_interface, self.heat_plastic)
        v_half = self._v_half.copy()
        if plastic:  # the solve has finished each column's plastic step (eps, hardening, work, pending heat)
            k, j = first_nonfinite((self.plastic_work,))
            if k >= 0:
                raise SimulationError(f"sub-grid step {self._when(*when)}: node {j}: non-finite plastic strain increment "
                                      f"(interface {self.theta_interface[j]!r} K, tau = {tau[j]!r} Pa)")
        return tau.copy(), v_half

    # ------------------------------------------------------------------ helpers
    @staticmethod
    def _when(cycle, time) -> str:
        parts = []
        if cycle is not None:
            parts.append(f"cycle {cycle}")
        if time is not None:
            parts.append(f"t = {time:.6e} s")
        return "(" + ", ".join(parts) + ")" if parts else ""

    def _check_finite(self, when: tuple, plastic: bool) -> None:
        """A step whose accepted state is not finite fails here, in that step (not as bad input in the next)."""
        vals = (self._theta_s, self.tau, self._v_half, self.slip_local, self.flux_in, self.slip_plastic)
        k, j = first_nonfinite(vals if plastic else vals[:5])
        if k >= 0:
            raise SimulationError(f"sub-grid step {self._when(*when)}: node {j}: the interface solve returned a non-finite "
                                  f"state (interface {self._theta_s[j]!r} K, tau = {self.tau[j]!r} Pa, "
                                  f"local slip {self.slip_local[j]!r} m/s, plastic slip "
                                  f"{self.slip_plastic[j]!r} m/s)")

    def _check(self, when: tuple) -> None:
        st = self._status
        j = first_nonzero(st)
        if j < 0:
            return
        what = {ABOVE_MELT: "the column is at or above the melting temperature before the step",
                NO_CONVERGENCE: f"the interface root finder did not converge in {self.max_iter} iterations",
                BAD_INPUT: "non-finite input"}.get(int(st[j]), f"status {int(st[j])}")
        raise SimulationError(f"sub-grid step {self._when(*when)}: node {j}: {what} "
                              f"(theta_ad(0) = {self.columns.X[0, j]!r} K)")
