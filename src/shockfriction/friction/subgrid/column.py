"""Batched 1D thermal columns through the interface layer (thesis §7.2.3, eq. 7.57-7.70).

Each column is the segment z in [0, h] under one interface node (z = 0 is the
sliding interface).  Heat equation rho c dtheta/dt = kappa d2theta/dz2 + s(z),
backward Euler in time, nodes z_0 = 0 < ... < z_M = h.

Discretisation (vertex-centred finite volumes).  Node i owns the control volume
of width w_i = (dz_{i-1} + dz_i)/2 (w_0 = dz_0/2, w_M = dz_{M-1}/2)::

    rho c w_i (theta_i^{n+1} - theta_i^n)/dt
        = kappa (theta_{i+1} - theta_i)/dz_i - kappa (theta_i - theta_{i-1})/dz_{i-1}
          + w_i s_i + [i = 0] q_in

with the flux term of the missing neighbour dropped at i = M (zero flux at z = h).
On the thesis's uniform grid (dz_i = h/M) this is exactly the ghost-node
Neumann scheme of eq. 7.60-7.65 (the reconstructed table 7.66: row 0 is
(1 + 2 Fo) theta_0 - 2 Fo theta_1 = theta_0^{n-1} + 2 Fo dz q_in/kappa), and the
sums telescope: rho c sum_i w_i (theta_i^{n+1} - theta_i^n) = dt (q_in + sum_i w_i s_i)
exactly (to round-off) -- the energy check of the thesis digest §10 item 11.
The graded grid uses dz_i = dz_0 r^i (r >= 1, finer at z = 0).

Linearity in the step's interface flux (eq. 7.67-7.70): with K the (fixed while
dt is fixed) matrix, theta^{n+1} = theta_ad + q_in * theta_unit, where theta_ad
solves K theta_ad = theta^n + dt s/(rho c) ("adiabatic" solve, q_in = 0) and
theta_unit = K^{-1} e_0 dt/(rho c w_0) is the response to a unit flux (1 W/m^2)
from a zero field.  theta_unit and the Thomas factors are cached per dt: one
batched adiabatic solve per step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


# --------------------------------------------------------------------------- Thomas (Annex A)
@njit(cache=True)
def thomas_solve(a, b, c, d):
    """Solve a_i x_{i-1} + b_i x_i + c_i x_{i+1} = d_i (a_0 = c_{n-1} = 0) by the Thomas algorithm (eq. A.3-A.12)."""
    n = d.shape[0]
    bp = np.empty(n)
    dp = np.empty(n)
    bp[0] = b[0]
    dp[0] = d[0]
    for k in range(1, n):
        m = a[k] / bp[k - 1]
        bp[k] = b[k] - m * c[k - 1]
        dp[k] = d[k] - m * dp[k - 1]
    x = np.empty(n)
    x[n - 1] = dp[n - 1] / bp[n - 1]
    for k in range(n - 2, -1, -1):
        x[k] = (dp[k] - c[k] * x[k + 1]) / bp[k]
    return x


@njit(cache=True)
def thomas_factor(a, b, c):
    """Forward-elimination factors of a tridiagonal matrix: multipliers m_k and 1/b'_k (eq. A.6-A.7)."""
    n = b.shape[0]
    mult = np.zeros(n)
    inv_bp = np.empty(n)
    bp = b[0]
    inv_bp[0] = 1.0 / bp
    for k in range(1, n):
        mult[k] = a[k] * inv_bp[k - 1]
        bp = b[k] - mult[k] * c[k - 1]
        inv_bp[k] = 1.0 / bp
    return mult, inv_bp


@njit(cache=True)
def thomas_apply(mult, inv_bp, c, d, x):
    """Solve with precomputed factors for one right-hand side ``d`` into ``x`` (``d`` may alias ``x``)."""
    n = d.shape[0]
    x[0] = d[0]
    for k in range(1, n):
        x[k] = d[k] - mult[k] * x[k - 1]
    x[n - 1] = x[n - 1] * inv_bp[n - 1]
    for k in range(n - 2, -1, -1):
        x[k] = (x[k] - c[k] * x[k + 1]) * inv_bp[k]


@njit(cache=True)
def adiabatic_solve_batched(theta, source_dt, mult, inv_bp, c, active, out):
    """theta_ad for every column: K theta_ad = theta + source_dt (rows of 2D arrays).

    ``source_dt`` is dt*s/(rho c) in K (pass zeros for none); columns with ``active[j] == False``
    are uniform and source-free, so theta_ad = theta there.  The factored Thomas sweeps run on
    blocks of 8 columns at once (independent recurrences interleaved: about twice the speed of
    one column after the other).
    """
    ncol, n = theta.shape
    idx = np.empty(ncol, np.int64)
    na = 0
    for j in range(ncol):
        if active[j]:
            idx[na] = j
            na += 1
        else:
            for i in range(n):
                out[j, i] = theta[j, i]
    for s in range(0, na, 8):
        e = min(s + 8, na)
        for b in range(s, e):
            j = idx[b]
            out[j, 0] = theta[j, 0] + source_dt[j, 0]
        for i in range(1, n):
            m = mult[i]
            for b in range(s, e):
                j = idx[b]
                out[j, i] = theta[j, i] + source_dt[j, i] - m * out[j, i - 1]
        for b in range(s, e):
            j = idx[b]
            out[j, n - 1] *= inv_bp[n - 1]
        for i in range(n - 2, -1, -1):
            ci = c[i]
            ib = inv_bp[i]
            for b in range(s, e):
                j = idx[b]
                out[j, i] = (out[j, i] - ci * out[j, i + 1]) * ib


@njit(cache=True)
def scale_rows(values, factor, out, nonzero):
    """out = values * factor; nonzero[j] = any value of row j is not 0 (no temporaries)."""
    ncol, n = values.shape
    for j in range(ncol):
        flag = False
        for i in range(n):
            v = values[j, i] * factor
            out[j, i] = v
            if v != 0.0:
                flag = True
        nonzero[j] = flag


@njit(cache=True)
def affine_update(theta_ad, q_in, theta_unit, limit, out):
    """out = theta_ad + q_in theta_unit (eq. 7.70) for every column; return the flat index of the
    first value that is not finite or not below ``limit`` (the melting temperature), else -1."""
    ncol, n = theta_ad.shape
    bad = -1
    for j in range(ncol):
        q = q_in[j]
        for i in range(n):
            v = theta_ad[j, i] + q * theta_unit[i]
            out[j, i] = v
            if bad < 0 and not v < limit:
                bad = j * n + i
    return bad


# --------------------------------------------------------------------------- grids
@njit(cache=True)
def clip_deposit(pending, theta, rho_c, limit, weights, clipped):
    """Melt guard of the lagged plastic heat: clip each node's pending heat (J/m^3) to
    rho_c (limit - theta) (>= 0) and add each row's clipped energy sum_i w_i (pending - kept)
    (J/m^2) to ``clipped[j]``.  By the maximum principle of the backward-Euler solve,
    theta_ad <= max_i (theta_i + deposit_i/(rho c)) <= limit after the clip."""
    for j in range(pending.shape[0]):
        row = 0.0
        for i in range(pending.shape[1]):
            p = pending[j, i]
            if p > 0.0:
                room = rho_c * (limit - theta[j, i])
                if room < 0.0:
                    room = 0.0
                if p > room:
                    row += weights[i] * (p - room)
                    pending[j, i] = room
        clipped[j] += row


def make_grid(thickness: float, n_cells: int, grading: float = 1.0) -> np.ndarray:
    """Node positions z_0 = 0 .. z_M = h; uniform (grading = 1, thesis eq. 6.73) or geometric dz_i = dz_0 r^i."""
    if not thickness > 0.0:
        raise ValueError(f"column thickness must be positive, got {thickness!r}")
    if n_cells < 2:
        raise ValueError(f"a column needs at least 2 cells, got {n_cells!r}")
    if not grading >= 1.0:
        raise ValueError(f"grading ratio must be >= 1 (finer at z = 0), got {grading!r}")
    if grading == 1.0:
        return np.linspace(0.0, thickness, n_cells + 1)
    r = float(grading)
    dz0 = thickness * (r - 1.0) / (r**n_cells - 1.0)
    z = np.concatenate(([0.0], np.cumsum(dz0 * r ** np.arange(n_cells))))
    z[-1] = thickness
    return z


def extend_grid(z: np.ndarray, depth: float, ratio: float = 1.05) -> np.ndarray:
    """Append geometric cells below z_M out to ``depth``: dz_{k+1} = r dz_k from the last cell (the last one
    absorbs the remainder, so z ends exactly at ``depth``).  Nothing is added when depth <= z_M."""
    if not ratio > 1.0:
        raise ValueError(f"extension ratio must be > 1, got {ratio!r}")
    if not depth > z[-1]:
        return z
    out = list(z)
    dz = z[-1] - z[-2]
    while depth - out[-1] > 1e-12 * depth:
        dz *= ratio
        nxt = out[-1] + dz
        if depth - nxt < 0.5 * dz * ratio:
            nxt = depth
        out.append(nxt)
    return np.asarray(out)


def control_weights(z: np.ndarray) -> np.ndarray:
    """Control-volume widths w_i (trapezoid weights): sum_i w_i g_i is the trapezoid rule of g."""
    dz = np.diff(z)
    w = np.zeros(z.size)
    w[:-1] += 0.5 * dz
    w[1:] += 0.5 * dz
    return w


def heat_matrix(z: np.ndarray, diffusivity: float, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Diagonals (a, b, c) of the backward-Euler matrix K (table 7.66 on a uniform grid)."""
    dz = np.diff(z)
    w = control_weights(z)
    n = z.size
    a = np.zeros(n)
    c = np.zeros(n)
    a[1:] = -diffusivity * dt / (w[1:] * dz)
    c[:-1] = -diffusivity * dt / (w[:-1] * dz)
    b = 1.0 - a - c
    return a, b, c


# --------------------------------------------------------------------------- the columns
class ThermalColumns:
    """``n_columns`` identical 1D columns of one material, temperatures shaped (n_columns, n_nodes).

    Parameters are SI: thickness h (m), conductivity kappa (W/m/K), density rho (kg/m^3),
    heat capacity c (J/kg/K), initial temperature T0 (K).  ``grading`` is the ratio of
    successive cell sizes (1 = the thesis's uniform grid).
    """

    CACHE_SIZE = 4

    def __init__(self, n_columns: int, thickness: float, n_cells: int, conductivity: float,
                 density: float, heat_capacity: float, T0: float = 300.0, grading: float = 1.0):
        if n_columns < 1:
            raise ValueError(f"n_columns must be >= 1, got {n_columns!r}")
        self.z = make_grid(thickness, int(n_cells), grading)
        self.weights = control_weights(self.z)
        self.kappa = float(conductivity)
        self.rho_c = float(density) * float(heat_capacity)
        self.alpha = self.kappa / self.rho_c
        self.T0 = float(T0)
        self.n_columns = int(n_columns)
        self.theta = np.full((self.n_columns, self.z.size), self.T0)
        self.active = np.zeros(self.n_columns, dtype=np.bool_)  # False: uniform T0, nothing to diffuse
        self._zero_source = np.zeros_like(self.theta)
        self._out = np.empty_like(self.theta)
        self._src = np.empty_like(self.theta)
        self._flags = np.zeros(self.n_columns, dtype=np.bool_)
        self.dt = math.nan
        self.factorisations = 0
        self._cache: dict[float, tuple] = {}  # dt -> (mult, inv_bp, c, theta_unit), the last few steps

    @property
    def n_nodes(self) -> int:
        return self.z.size

    def prepare(self, dt: float) -> None:
        """Factor K and compute the unit-flux response for ``dt``; reused while dt does not change.

        The factors of the last ``CACHE_SIZE`` distinct steps are kept (alternating steps cost nothing).
        """
        if dt == self.dt:
            return
        if not (dt > 0.0 and math.isfinite(dt)):
            raise ValueError(f"time step must be positive and finite, got {dt!r}")
        if dt in self._cache:
            self.mult, self.inv_bp, self.c, self.theta_unit = self._cache[dt]
            self.dt = dt
            return
        a, b, c = heat_matrix(self.z, self.alpha, dt)
        self.mult, self.inv_bp = thomas_factor(a, b, c)
        self.c = c
        rhs = np.zeros(self.n_nodes)
        rhs[0] = dt / (self.rho_c * self.weights[0])
        unit = np.empty(self.n_nodes)
        thomas_apply(self.mult, self.inv_bp, c, rhs, unit)
        self.theta_unit = unit  #: temperature rise per W/m^2 of interface flux over one step, K m^2/W
        self.dt = dt
        self.factorisations += 1
        if len(self._cache) >= self.CACHE_SIZE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[dt] = (self.mult, self.inv_bp, self.c, self.theta_unit)

    def adiabatic(self, dt: float, source: np.ndarray | None = None, deposit: np.ndarray | None = None) -> np.ndarray:
        """theta_ad (eq. 7.68): the step with zero interface flux, shaped (n_columns, n_nodes).

        ``source`` is a volumetric heat source s (W/m^3) over the step, or ``deposit`` an energy
        density (J/m^3) put in during the step (the lagged plastic heat); at most one of them.
        The returned array is a buffer reused by the next call.
        """
        self.prepare(dt)
        if source is None and deposit is None:
            src = self._zero_source
            active = self.active
        else:
            values, factor = (source, dt / self.rho_c) if source is not None else (deposit, 1.0 / self.rho_c)
            src = self._src
            scale_rows(values, factor, src, self._flags)
            active = self._flags
            active |= self.active
        adiabatic_solve_batched(self.theta, src, self.mult, self.inv_bp, self.c, active, self._out)
        return self._out

    def affine(self, theta_ad: np.ndarray, q_in: np.ndarray) -> np.ndarray:
        """theta^{n+1} = theta_ad + q_in theta_unit (eq. 7.70); ``q_in`` (n_columns,) in W/m^2 entering."""
        return theta_ad + np.asarray(q_in, float)[:, None] * self.theta_unit[None, :]

    def commit(self, theta_new: np.ndarray, heated: np.ndarray | None = None) -> None:
        """Store the new temperatures; ``heated`` marks the columns that received heat this step."""
        self.theta[...] = theta_new
        if heated is not None:
            self.active |= heated

    def step(self, dt: float, q_in, source: np.ndarray | None = None) -> np.ndarray:
        """One backward-Euler step with interface flux ``q_in`` (W/m^2 entering, per column); returns theta."""
        q = np.broadcast_to(np.asarray(q_in, float), (self.n_columns,))
        theta_ad = self.adiabatic(dt, source)
        new = self.affine(theta_ad, q)
        heated = q != 0.0
        if source is not None:
            heated = heated | np.any(source != 0.0, axis=1)
        self.commit(new, heated)
        return self.theta

    def heat_content(self) -> np.ndarray:
        """Stored heat per unit interface area, rho c sum_i w_i (theta_i - T0), J/m^2 (per column)."""
        return self.rho_c * ((self.theta - self.T0) @ self.weights)
