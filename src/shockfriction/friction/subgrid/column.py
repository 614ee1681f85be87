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

Layout (docs/theory/subgrid-layout.md): the columns are stored (n_nodes, n_columns), the column
index innermost, so that each Thomas row update is vectorised across the columns, and the affine
update of a step is applied on the fly by the next step's forward sweep (:func:`sweep_columns`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


# --------------------------------------------------------------------------- per-column inputs
def per_column(x, n: int) -> np.ndarray:
    """``x`` as a writable, C-contiguous float64 array of shape (n,): scalars broadcast, an array that already is
    one passed as it is.  The column kernels then see one array type whatever the caller hands in: a read-only view
    or a broadcast (stride 0) would make numba compile a second version of each kernel, ~10 s apiece."""
    a = np.asarray(x, dtype=np.float64)
    if a.shape == (n,) and a.flags.c_contiguous and a.flags.writeable:
        return a
    return np.array(np.broadcast_to(a, (n,)), dtype=np.float64, order="C")


# --------------------------------------------------------------------------- the books' sums
@njit(cache=True)
def column_sums(w, X):
    """sum_i w_i X[i, j] for every column j of X (nodes x columns), summed in node order on one thread: the books'
    per-area sums (numpy's ``w @ X`` goes through a threaded BLAS gemv from ~0.5 M entries on, whose worker then
    spins between the steps on a core the run may need)."""
    n, nc = X.shape
    out = np.zeros(nc)
    for j in range(nc):
        acc = 0.0
        for i in range(n):
            acc += w[i] * X[i, j]
        out[j] = acc
    return out


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


# Row kernels of the sweep on 1-D row slices (columns j0..j1 of a row), indexed from 0 so that the compiler sees
# non-negative indices (no wraparound select) and vectorises them.
@njit(cache=True, inline="always")
def _source_row(cur, prev, q, s, clipped, deposited, u, m, w, rho_c, limit, factor, lazy, first):
    """Forward elimination of a row with a source (clipped to rho_c (limit - theta), booked per column)."""
    for j in range(cur.shape[0]):  # branch-free: an unclipped value adds w * 0 = 0 to clipped[j]
        th = cur[j] + q[j] * u if lazy else cur[j]
        p = s[j]
        room = rho_c * (limit - th)
        room = room if room > 0.0 else 0.0
        kept = room if p > room else p
        clipped[j] += w * (p - kept)
        s[j] = kept
        deposited[j] += w * kept
    for j in range(cur.shape[0]):
        th = cur[j] + q[j] * u if lazy else cur[j]
        v = th + s[j] * factor
        cur[j] = v if first else v - m * prev[j]


@njit(cache=True, inline="always")
def _plain_row(cur, prev, q, u, m, lazy, first):
    """Forward elimination of a row without a source: cur_j = (cur_j + q_j u) - m prev_j (lazy), cur_j - m prev_j."""
    if first:
        if lazy:
            for j in range(cur.shape[0]):
                cur[j] = cur[j] + q[j] * u
    elif lazy:
        for j in range(cur.shape[0]):
            cur[j] = (cur[j] + q[j] * u) - m * prev[j]
    else:
        for j in range(cur.shape[0]):
            cur[j] = cur[j] - m * prev[j]


@njit(cache=True, inline="always")
def _back_row(cur, nxt, ci, ib, last):
    """Back substitution of a row: cur_j = (cur_j - c_i nxt_j) / b'_i (the last row: cur_j / b'_i)."""
    if last:
        for j in range(cur.shape[0]):
            cur[j] = cur[j] * ib
    else:
        for j in range(cur.shape[0]):
            cur[j] = (cur[j] - ci * nxt[j]) * ib


@njit(cache=True, inline="always")
def _max_row(top, row):
    """top_j = max(top_j, row_j)."""
    for j in range(top.shape[0]):
        a = top[j]
        x = row[j]
        top[j] = x if x > a else a


@njit(cache=True)
def sweep_columns(X, q, unit, lazy, src, n_src, factor, rho_c, limit, weights, clipped, deposited, mult, inv_bp, c,
                  idle, idle_val, sfx, j0, j1, s0, s1):
    """theta_ad for every column, in place: X (n_nodes, n_columns) holds theta on entry (or, when ``lazy``,
    the previous theta_ad with theta = X + q theta_unit_prev, eq. 7.70, applied here on the fly: the
    affine update of the last step folded into this forward sweep) and theta_ad on exit,
    K theta_ad = theta + factor src.

    Only the first ``n_src`` rows of ``src`` are read (zero below; ``n_src = 0``: no source, none read),
    and only in the columns s0 <= j < s1 (zero elsewhere; ``s1 < 0``: every column).
    Each source value p (J/m^3 or W/m^3 by ``factor``) is first clipped to rho_c (limit - theta) >= 0
    (melt guard, ``limit = inf``: none); ``clipped[j]`` receives the clipped energy sum_i w_i (p - kept),
    ``src`` keeps the clipped value and ``deposited[j]`` += sum_i w_i p_kept.  The columns listed in ``idle``
    (ascending) are uniform and source-free: they keep their value (``idle_val`` is scratch).  Only the columns
    j0 <= j < j1 are swept (``j1 < 0``: all); every column outside is idle too (not listed in ``idle``).
    ``sfx[b, j]`` receives the suffix maximum max_{i >= 8b} theta_ad[i, j] (``sfx[0]``: the column maximum).
    The factored Thomas sweeps (eq. A.6-A.12) run row by row, each row's update vectorised across the columns.
    (No defaults: a call that left the spans out would compile a second version of the kernel.)
    """
    ncol = X.shape[1]
    j0, j1, s0, s1 = sweep_span(ncol, j0, j1, s0, s1)
    sweep_block(X, q, unit, lazy, src, n_src, factor, rho_c, limit, weights, clipped, deposited, mult, inv_bp, c,
                idle, idle_val, sfx, j0, j1, s0, s1, 0, ncol)


@njit(cache=True)
def sweep_span(ncol, j0, j1, s0, s1):
    """The swept columns [j0, j1) and the source columns [s0, s1) within them, as :func:`sweep_columns` takes them
    (``j1 < 0``: every column; ``s1 < 0``: every swept column)."""
    j0 = max(j0, 0)
    j1 = ncol if j1 < 0 else min(j1, ncol)
    j1 = max(j1, j0)
    if s1 < 0:
        s1 = ncol
    s0 = min(max(s0, j0), j1)  # the source columns, within the swept ones
    s1 = max(min(s1, j1), s0)
    return j0, j1, s0, s1


@njit(cache=True, inline="always")
def sweep_block(X, q, unit, lazy, src, n_src, factor, rho_c, limit, weights, clipped, deposited, mult, inv_bp, c,
                idle, idle_val, sfx, j0, j1, s0, s1, a, e):
    """:func:`sweep_columns` of the columns a <= j < e only (spans from :func:`sweep_span`): every column's
    arithmetic is its own, so blocks that partition the columns give the whole sweep's bytes in any order or in
    parallel (:func:`~shockfriction.friction.subgrid.thermoelastoplastic.advance_and_solve_parallel`)."""
    nn = X.shape[0]
    ja = max(j0, a)  # this block's swept and source columns
    jb = max(min(j1, e), ja)
    sa = min(max(s0, ja), jb)
    sb = max(min(s1, jb), sa)
    u0 = unit[0]
    k0 = np.searchsorted(idle, a)  # this block's idle columns (``idle`` ascending)
    k1 = np.searchsorted(idle, e)
    for k in range(k0, k1):
        j = idle[k]
        idle_val[k] = X[0, j] + q[j] * u0 if lazy else X[0, j]
    for j in range(a, e):
        deposited[j] = 0.0
        clipped[j] = 0.0
    nb = sfx.shape[0]
    if jb > ja:  # a block with no swept column skips the rows (nothing of it is swept: the same bytes)
        qa, qs, qb = q[ja:sa], q[sa:sb], q[sb:jb]
        # forward elimination (eq. A.6-A.8): the source rows, then the rest; the columns without a source
        # take th + 0 factor = th
        ns = min(n_src, nn) if sb > sa else 0
        for i in range(max(ns, 1)):
            cur = X[i]
            prev = X[i - 1 if i > 0 else 0]
            u = unit[i]
            m = mult[i]
            first = i == 0
            if i < ns:
                _source_row(cur[sa:sb], prev[sa:sb], qs, src[i][sa:sb], clipped[sa:sb], deposited[sa:sb], u, m,
                            weights[i], rho_c, limit, factor, lazy, first)
                _plain_row(cur[ja:sa], prev[ja:sa], qa, u, m, lazy, first)
                _plain_row(cur[sb:jb], prev[sb:jb], qb, u, m, lazy, first)
            else:
                _plain_row(cur[ja:jb], prev[ja:jb], q[ja:jb], u, m, lazy, first)
        qj = q[ja:jb]
        for i in range(max(ns, 1), nn):
            _plain_row(X[i][ja:jb], X[i - 1][ja:jb], qj, unit[i], mult[i], lazy, False)
        # back substitution (eq. A.9-A.12) in blocks of 8 rows, then the block's suffix maxima
        for b in range(nb - 1, -1, -1):
            i0 = 8 * b
            i1 = min(i0 + 8, nn)
            for i in range(i1 - 1, i0 - 1, -1):
                cur = X[i]
                _back_row(cur[ja:jb], X[min(i + 1, nn - 1)][ja:jb], c[i], inv_bp[i], i == nn - 1)
                for k in range(k0, k1):
                    cur[idle[k]] = idle_val[k]
            top = sfx[b][ja:jb]
            first = X[i1 - 1] if b == nb - 1 else sfx[b + 1]
            top[:] = first[ja:jb]
            for i in range(i0, i1):
                _max_row(top, X[i][ja:jb])
    # the columns outside [j0, j1): idle, not swept (uniform, so every suffix maximum is theta(0))
    for b in range(nb):
        top = sfx[b]
        for j in range(a, min(j0, e)):
            top[j] = X[0, j] + q[j] * u0 if lazy else X[0, j]
        for j in range(max(j1, a), e):
            top[j] = X[0, j] + q[j] * u0 if lazy else X[0, j]


@njit(cache=True)
def busy_span(active, extra, s0, s1):
    """(j0, j1, idle) of :meth:`ThermalColumns._span`: [j0, j1) spans the busy columns (active[j] or extra[j]) and
    the columns s0 <= j < s1; ``idle`` lists the columns inside that are not busy; (0, 0, empty) when none."""
    ncol = active.shape[0]
    j0, j1 = ncol, 0
    for j in range(ncol):
        if active[j] or extra[j]:
            if j < j0:
                j0 = j
            j1 = j + 1
    if s1 > s0:
        j0, j1 = min(j0, s0), max(j1, s1)
    if j1 <= j0:
        return 0, 0, np.empty(0, dtype=np.int64)
    n_idle = 0
    for j in range(j0, j1):
        if not (active[j] or extra[j]):
            n_idle += 1
    idle = np.empty(n_idle, dtype=np.int64)
    k = 0
    for j in range(j0, j1):
        if not (active[j] or extra[j]):
            idle[k] = j
            k += 1
    return j0, j1, idle


@njit(cache=True)
def melt_check(X, q, unit, unit_max, col_max, limit):
    """First flat index j n_nodes + i of theta = X[i, j] + q[j] unit[i] (eq. 7.70) that is not below
    ``limit``, else -1.  A column is scanned only when its bound col_max[j] + q[j] unit_max is not below
    (rounding is monotone, so the bound is exact for q >= 0)."""
    nn, ncol = X.shape
    for j in range(ncol):
        qj = q[j]
        if qj >= 0.0 and col_max[j] + qj * unit_max < limit:
            continue
        for i in range(nn):
            if not X[i, j] + qj * unit[i] < limit:
                return j * nn + i
    return -1


@njit(cache=True)
def materialise(X, q, unit):
    """X <- X + q unit (eq. 7.70, in place), rows (n_nodes) by columns."""
    nn, ncol = X.shape
    for i in range(nn):
        u = unit[i]
        row = X[i]
        for j in range(ncol):
            row[j] = row[j] + q[j] * u


@njit(cache=True)
def weighted_rise(X, q, unit, lazy, T0, weights, out):
    """out[j] = sum_i w_i (theta_ij - T0), theta = X (+ q unit when ``lazy``)."""
    nn, ncol = X.shape
    for j in range(ncol):
        out[j] = 0.0
    for i in range(nn):
        u = unit[i]
        w = weights[i]
        row = X[i]
        for j in range(ncol):
            th = row[j] + q[j] * u if lazy else row[j]
            out[j] += w * (th - T0)


# --------------------------------------------------------------------------- grids
#: the smallest cell a deck may ask for (m): an atomic spacing.  Below it the continuum column means nothing, and its
#: heat and mechanics solves (conditioning ~ alpha dt / dz^2) lose the precision their iterations need: 5 pm cells
#: of the YLP deck ran 41 of 50 steps to the Picard sweep limit, 6e-23 m cells failed at the first step
MIN_CELL = 1e-10


def smallest_cell(thickness: float, n_cells: int, grading: float = 1.0) -> float:
    """The first (smallest) cell of :func:`make_grid`'s grid, dz_0 = h (r - 1)/(r^M - 1) (h/M for r = 1); 0 where
    r^M overflows a float."""
    if grading == 1.0:
        return thickness / n_cells
    if n_cells * math.log(grading) >= 700.0:  # r^M beyond a float's range
        return 0.0
    return thickness * (grading - 1.0) / (grading**n_cells - 1.0)


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
    dz0 = smallest_cell(thickness, n_cells, r)
    if not dz0 > 0.0:
        raise ValueError(f"grading {r!r} over {n_cells} cells: the first cell h (r - 1)/(r^M - 1) underflows to 0")
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


@njit(cache=True)
def control_weights(z):
    """Control-volume widths w_i (trapezoid weights): sum_i w_i g_i is the trapezoid rule of g."""
    n = z.size
    w = np.zeros(n)
    for i in range(n - 1):
        w[i] += 0.5 * (z[i + 1] - z[i])
    for i in range(n - 1):
        w[i + 1] += 0.5 * (z[i + 1] - z[i])
    return w


@njit(cache=True)
def heat_matrix(z, diffusivity, dt):
    """Diagonals (a, b, c) of the backward-Euler matrix K (table 7.66 on a uniform grid)."""
    return _heat_diagonals(z, control_weights(z), diffusivity, dt)


@njit(cache=True)
def _heat_diagonals(z, w, diffusivity, dt):
    """:func:`heat_matrix` with the control-volume widths ``w`` of ``z`` given."""
    n = z.size
    a = np.zeros(n)
    c = np.zeros(n)
    num = -diffusivity * dt
    for i in range(n - 1):
        dz = z[i + 1] - z[i]
        a[i + 1] = num / (w[i + 1] * dz)
        c[i] = num / (w[i] * dz)
    b = np.empty(n)
    for i in range(n):
        b[i] = 1.0 - a[i] - c[i]
    return a, b, c


@njit(cache=True)
def factor_step(z, w, diffusivity, dt, rho_c):
    """Everything a step of ``dt`` needs: the Thomas factors (mult, 1/b') and c of K, the unit-flux response
    theta_unit = K^{-1} e_0 dt/(rho c w_0) (K m^2/W) and its maximum; ``w`` = control_weights(z)."""
    a, b, c = _heat_diagonals(z, w, diffusivity, dt)
    mult, inv_bp = thomas_factor(a, b, c)
    rhs = np.zeros(z.size)
    rhs[0] = dt / (rho_c * w[0])
    unit = np.empty(z.size)
    thomas_apply(mult, inv_bp, c, rhs, unit)
    return mult, inv_bp, c, unit, unit.max()


# --------------------------------------------------------------------------- the columns
class ThermalColumns:
    """``n_columns`` identical 1D columns of one material.

    Parameters are SI: thickness h (m), conductivity kappa (W/m/K), density rho (kg/m^3),
    heat capacity c (J/kg/K), initial temperature T0 (K).  ``grading`` is the ratio of
    successive cell sizes (1 = the thesis's uniform grid).

    Layout (docs/theory/subgrid-layout.md): the state ``X`` is (n_nodes, n_columns), the column
    index innermost, so that every Thomas row update runs across the columns in SIMD.  After
    :meth:`advance` + :meth:`set_flux` the state is *lazy*: X holds theta_ad and theta = X +
    q theta_unit (eq. 7.70) is applied by the next forward sweep (or by :attr:`theta`).  ``theta``
    is the (n_columns, n_nodes) view of the materialised state (writes go through).
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
        nn = self.z.size
        self.X = np.full((nn, self.n_columns), self.T0)  # theta, or theta_ad when lazy (node, column)
        self.q_lazy = np.zeros(self.n_columns)  # W/m^2 of the last step, not yet applied to X
        self.unit_lazy = np.zeros(nn)  # the theta_unit it goes with
        self.unit_lazy_max = 0.0
        self.lazy = False
        self.active = np.zeros(self.n_columns, dtype=np.bool_)  # False: uniform, nothing to diffuse
        self.col_max = np.zeros(self.n_columns)  # max_i theta_ad after the last sweep
        self._sfx = np.zeros(((nn + 7) // 8, self.n_columns))  # suffix maxima of theta_ad every 8 rows
        self._out = np.empty_like(self.X)  # theta_ad of the public adiabatic()
        self._clipped = np.zeros(self.n_columns)
        self._deposited = np.zeros(self.n_columns)
        self._idle_val = np.empty(self.n_columns)
        self._no_src = np.empty((0, self.n_columns))
        self._rise = np.empty(self.n_columns)
        self.dt = math.nan
        self.factorisations = 0
        self._cache: dict[float, tuple] = {}  # dt -> (mult, inv_bp, c, theta_unit, max theta_unit), the last few

    @property
    def n_nodes(self) -> int:
        return self.z.size

    @property
    def theta(self) -> np.ndarray:
        """Temperatures (n_columns, n_nodes): a view of the state (applies a pending flux first)."""
        if self.lazy:
            materialise(self.X, self.q_lazy, self.unit_lazy)
            self.lazy = False
        return self.X.T

    @theta.setter
    def theta(self, value) -> None:
        self.lazy = False
        self.X.T[...] = value

    def prepare(self, dt: float) -> None:
        """Factor K and compute the unit-flux response for ``dt``; reused while dt does not change.

        The factors of the last ``CACHE_SIZE`` distinct steps are kept (alternating steps cost nothing).
        """
        if dt == self.dt:
            return
        if not (dt > 0.0 and math.isfinite(dt)):
            raise ValueError(f"time step must be positive and finite, got {dt!r}")
        if dt in self._cache:
            self.mult, self.inv_bp, self.c, self.theta_unit, self.unit_max = self._cache[dt]
            self.dt = dt
            return
        self.mult, self.inv_bp, self.c, unit, unit_max = factor_step(self.z, self.weights, self.alpha, dt, self.rho_c)
        self.theta_unit = unit  #: temperature rise per W/m^2 of interface flux over one step, K m^2/W
        self.unit_max = float(unit_max)
        self.dt = dt
        self.factorisations += 1
        if len(self._cache) >= self.CACHE_SIZE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[dt] = (self.mult, self.inv_bp, self.c, self.theta_unit, self.unit_max)

    def _span(self, extra: np.ndarray | None = None, src_span: tuple[int, int] = (0, 0)) -> tuple[int, int, np.ndarray]:
        """(j0, j1, idle): the columns j0 <= j < j1 span every column the sweep must visit (active or, with
        ``extra``, with a source; and the columns of ``src_span``, whose source sums are booked even where the
        source rounds to no temperature); ``idle`` lists the idle columns inside (those outside are all idle)."""
        return busy_span(self.active, self.active if extra is None else extra, src_span[0], src_span[1])

    def advance(self, dt: float, src: np.ndarray | None = None, n_src: int = 0, factor: float = 1.0,
                limit: float = math.inf, src_flags: np.ndarray | None = None,
                src_span: tuple[int, int] | None = None) -> np.ndarray:
        """In place: the state becomes theta_ad (eq. 7.68), returned as (n_nodes, n_columns).

        ``src`` (n_nodes, n_columns), rows below ``n_src`` zero, is a source scaled by ``factor`` into
        kelvin (``src_flags[j]``: column j has one), clipped first to rho_c (limit - theta) (the clipped
        energy per column goes to ``self._clipped``, sum_i w_i src_kept to ``self._deposited``).
        ``src_span = (s0, s1)``: ``src`` is zero outside the columns s0 <= j < s1 (default: anywhere).
        """
        args = self.sweep_plan(dt, src, n_src, factor, limit, src_flags, src_span)
        sweep_columns(*args)
        return self.swept()

    def sweep_plan(self, dt: float, src: np.ndarray | None = None, n_src: int = 0, factor: float = 1.0,
                   limit: float = math.inf, src_flags: np.ndarray | None = None,
                   src_span: tuple[int, int] | None = None) -> tuple:
        """The arguments of :func:`sweep_columns` for :meth:`advance` (its keywords; the kernel that takes them
        resolves the spans by :func:`sweep_span`); after the sweep (here or in a caller's fused kernel) call
        :meth:`swept`."""
        self.prepare(dt)
        if src is None:
            src, n_src = self._no_src, 0
        if n_src <= 0:
            j0, j1, idle = self._span()
        else:
            j0, j1, idle = self._span(src_flags, (0, self.n_columns) if src_span is None else src_span)
        s0, s1 = src_span if src_span is not None else (j0, j1)
        return (self.X, self.q_lazy, self.unit_lazy, self.lazy, src, int(n_src), float(factor), self.rho_c,
                float(limit), self.weights, self._clipped, self._deposited, self.mult, self.inv_bp, self.c,
                idle, self._idle_val, self._sfx, j0, j1, s0, s1)

    def swept(self) -> np.ndarray:
        """After the sweep of :meth:`sweep_plan`: the state is theta_ad (returned, (n_nodes, n_columns))."""
        self.lazy = False
        self.col_max = self._sfx[0]
        return self.X

    def set_flux(self, q_in: np.ndarray) -> None:
        """Complete the step lazily: theta = theta_ad + q_in theta_unit (eq. 7.70), applied by the next sweep."""
        self.q_lazy[:] = q_in
        self.unit_lazy[:] = self.theta_unit
        self.unit_lazy_max = self.unit_max
        self.lazy = True

    def melt_index(self, limit: float) -> int:
        """Flat index (column n_nodes + node) of the first node of theta not below ``limit``, else -1."""
        if not self.lazy:
            return melt_check(self.X, np.zeros(self.n_columns), self.unit_lazy, 0.0, self.X.max(axis=0), limit)
        return melt_check(self.X, self.q_lazy, self.unit_lazy, self.unit_lazy_max, self.col_max, limit)

    def adiabatic(self, dt: float, source: np.ndarray | None = None, deposit: np.ndarray | None = None) -> np.ndarray:
        """theta_ad (eq. 7.68): the step with zero interface flux, shaped (n_columns, n_nodes); the state is kept.

        ``source`` is a volumetric heat source s (W/m^3) over the step, or ``deposit`` an energy
        density (J/m^3) put in during the step (the lagged plastic heat); at most one of them, each
        (n_columns, n_nodes).  The returned array is a buffer reused by the next call.
        """
        self.prepare(dt)
        out = self._out
        out[...] = self.X
        src, n_src, factor, flags = self._no_src, 0, 1.0, None
        if source is not None or deposit is not None:
            values, factor = (source, dt / self.rho_c) if source is not None else (deposit, 1.0 / self.rho_c)
            src = np.ascontiguousarray(np.asarray(values, float).T)
            n_src = src.shape[0]
            flags = np.any(src * factor != 0.0, axis=0)
        scratch = np.empty(self.n_columns)  # the state's own sums and maxima are left alone
        j0, j1, idle = self._span(flags)
        sweep_columns(out, self.q_lazy, self.unit_lazy, self.lazy, src, n_src, factor, self.rho_c, math.inf,
                      self.weights, scratch, scratch.copy(), self.mult, self.inv_bp, self.c,
                      idle, self._idle_val, np.empty_like(self._sfx), j0, j1, 0, -1)
        return out.T

    def affine(self, theta_ad: np.ndarray, q_in: np.ndarray) -> np.ndarray:
        """theta^{n+1} = theta_ad + q_in theta_unit (eq. 7.70); ``q_in`` (n_columns,) in W/m^2 entering."""
        return theta_ad + np.asarray(q_in, float)[:, None] * self.theta_unit[None, :]

    def commit(self, theta_new: np.ndarray, heated: np.ndarray | None = None) -> None:
        """Store the new temperatures (n_columns, n_nodes); ``heated`` marks the columns heated this step."""
        self.theta = theta_new
        if heated is not None:
            self.active |= heated

    def surface(self) -> np.ndarray:
        """theta at z = 0 of every column (n_columns,), a new array (the state is left as it is)."""
        return self.X[0] + self.q_lazy * self.unit_lazy[0] if self.lazy else self.X[0].copy()

    def step(self, dt: float, q_in, source: np.ndarray | None = None) -> None:
        """One backward-Euler step with interface flux ``q_in`` (W/m^2 entering, per column) and an optional
        volumetric source (W/m^3, (n_columns, n_nodes)); the result is read through :attr:`theta`."""
        q = np.broadcast_to(np.asarray(q_in, float), (self.n_columns,))
        heated = q != 0.0
        if source is None:
            self.advance(dt)
        else:
            src = np.ascontiguousarray(np.asarray(source, float).T)
            factor = dt / self.rho_c
            flags = np.any(src * factor != 0.0, axis=0)
            self.advance(dt, src, src.shape[0], factor, src_flags=flags)
            heated = heated | np.any(source != 0.0, axis=1)
        self.set_flux(q)
        self.active |= heated

    def heat_content(self) -> np.ndarray:
        """Stored heat per unit interface area, rho c sum_i w_i (theta_i - T0), J/m^2 (per column)."""
        weighted_rise(self.X, self.q_lazy, self.unit_lazy, self.lazy, self.T0, self.weights, self._rise)
        return self.rho_c * self._rise
