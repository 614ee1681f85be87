"""Which branch of the friction law governs a slide line, weighted three ways and over time windows.

The sub-grid friction models count the node-steps governed by each term of tau = min(mu0 F_N, tau_stick, sub-grid
branch) (``SubgridFriction.branch_counts``, kernel ``tally_branches``).  A node-step count says nothing about how
much of the friction's work or impulse each branch carries: a node that sits at the Coulomb cap while barely sliding
counts as much as one that carries the heat.  :class:`BranchTally` attaches to a prepared simulation's slide line
and tallies, per node and per branch, over cumulative windows [0, t_k) of the step's start time:

* ``steps``: the node-steps (for a sub-grid line the same classification as ``tally_branches``);
* ``work``: the friction work of the node-step, the hydro's impulse work ``line.work_t`` (J; per radian in
  axisymmetric runs), tau S dt times the step's mean slip: what the slide line adds up into ``total_friction_work``;
* ``impulse``: |lam_t| = tau S dt (N s; per radian in axisymmetric runs).

Branches: ``coulomb_cap`` (sub-grid: tau = mu0 F_N <= tau_stick; a hydro law (plain or modified Coulomb): the
law's sliding traction), ``sticking_cap`` (tau = tau_stick: the node sticks), ``subgrid`` (the sub-grid model's own
branch, below both caps) and ``none`` (node-steps with no friction: out of contact, no normal impulse, or no free
slip; for a hydro law a free slip below the sub-grid friction's ``IDLE_SLIP``, 1 um/s, is none too: contact
round-off, which the sub-grid models leave idle; such node-steps carry a negligible work, checked).  A
hydro-law node sticks when its corrected slip is at most ``STICK_REL`` of its free slip (plus ``STICK_ABS``): the
Gauss-Seidel sweeps leave a stuck node a slip of the order of their tolerance.

It needs no change in the friction code: it wraps the line's ``apply`` (for the step's time) and ``finish_step``
(where the step's impulses and works are final) on the instance.  The sums over the branches over the whole run
equal the line's friction work and the sub-grid model's own node-step counts (:meth:`BranchTally.check`).
"""

from __future__ import annotations

import math

import numpy as np

BRANCHES = ("coulomb_cap", "sticking_cap", "subgrid", "none")
WEIGHTS = ("steps", "work", "impulse")
#: the cone study's windows (s): cumulative, from t = 0
WINDOWS = (0.3e-6, 3.0e-6, 8.0e-6)
STICK_REL = 1e-6
STICK_ABS = 1e-9  # m/s
#: a free slip below this (m/s) is contact round-off: not a friction node-step (as the sub-grid friction's columns)
IDLE_SLIP = 1e-6
C, S, M, N = range(4)


def window_label(t_end: float) -> str:
    """'0-0.3us' for 0.3e-6 ('0-end' for inf)."""
    return "0-end" if not math.isfinite(t_end) else f"0-{t_end * 1e6:g}us"


class BranchTally:
    """Branch tallies of one slide line (``line``: a :class:`~shockfriction.contact.slideline.SlideLine`).

    ``acc[w, k, b, j]``: weight w (:data:`WEIGHTS`) of node j in branch b (:data:`BRANCHES`) over the window k of
    ``windows`` (s, cumulative from 0), the last window being the whole run.  Use :meth:`attach`.
    """

    def __init__(self, line, windows=WINDOWS):
        self.line = line
        self.windows = tuple(float(w) for w in windows) + (math.inf,)
        ns = line.slave.size
        self.acc = np.zeros((len(WEIGHTS), len(self.windows), len(BRANCHES), ns))
        self._t = 0.0
        self._apply = line.apply
        self._finish = line.finish_step
        line.apply = self._wrapped_apply
        line.finish_step = self._wrapped_finish

    @classmethod
    def attach(cls, sim, name: str, windows=WINDOWS) -> BranchTally:
        """Attach to the slide line ``name`` of a prepared :class:`~shockfriction.hydro.cycle.Simulation`."""
        for obj in sim.interfaces:
            line = getattr(obj, "line", None)
            if line is not None and line.name == name:
                return cls(line, windows)
        names = [obj.line.name for obj in sim.interfaces if hasattr(obj, "line")]
        raise KeyError(f"no slide line {name!r} (have {names})")

    def detach(self) -> None:
        self.line.apply = self._apply
        self.line.finish_step = self._finish

    # ------------------------------------------------------------------ the hooks
    def _wrapped_apply(self, *args, **kwargs):
        # apply(x, y, vx, vy, mass, dt, t, ...)
        self._t = float(kwargs["t"] if "t" in kwargs else args[6])
        return self._apply(*args, **kwargs)

    def _wrapped_finish(self, *args, **kwargs):
        work = self._finish(*args, **kwargs)
        self._tally()
        return work

    def classify(self) -> np.ndarray:
        """Branch index (:data:`BRANCHES`) of each node at the step just done."""
        line = self.line
        fm = line.friction_model
        b = np.full(line.slave.size, N, dtype=np.int64)
        if fm is not None:   # the sub-grid friction: tally_branches' rule
            sg = fm.columns
            tau, tc, ts = sg.tau, sg.tau_coulomb, sg.tau_stick
            live = (fm.sigma_n > 0.0) & (fm.v_free != 0.0)
            coul = live & (tau >= tc) & (tc <= ts)
            stick = live & ~coul & (tau >= ts)
            b[live] = M
            b[stick] = S
            b[coul] = C
            return b
        live = line.active & (line.lam_n != 0.0) & (line.area > 0.0) & (np.abs(line.slip_free) > IDLE_SLIP)
        stuck = np.abs(line.slip) <= STICK_REL * np.abs(line.slip_free) + STICK_ABS
        b[live & stuck] = S
        b[live & ~stuck] = C
        return b

    def _tally(self) -> None:
        line = self.line
        b = self.classify()
        j = np.arange(b.size)
        w = (np.ones(b.size), line.work_t, np.abs(line.lam_t))
        for k, t_end in enumerate(self.windows):
            if self._t < t_end:
                for i in range(len(WEIGHTS)):
                    self.acc[i, k, b, j] += w[i]

    # ------------------------------------------------------------------ results
    def sums(self, mask=None) -> dict:
        """{weight: {window label: {branch: sum}}} over the nodes of ``mask`` (default all)."""
        a = self.acc if mask is None else self.acc[..., np.asarray(mask, bool)]
        tot = a.sum(axis=-1)
        return {wn: {window_label(te): {bn: float(tot[i, k, m]) for m, bn in enumerate(BRANCHES)}
                     for k, te in enumerate(self.windows)} for i, wn in enumerate(WEIGHTS)}

    def fractions(self, mask=None) -> dict:
        """As :meth:`sums`, each branch's share of the node-steps / work / impulse carried by friction (the
        ``none`` node-steps left out of the node-step shares: they are not friction node-steps)."""
        out = {}
        for wn, by_w in self.sums(mask).items():
            out[wn] = {}
            for lab, d in by_w.items():
                total = sum(v for bn, v in d.items() if bn != "none")
                out[wn][lab] = {bn: (d[bn] / total if total else math.nan) for bn in BRANCHES if bn != "none"}
        return out

    def check(self, rel: float = 1e-12, idle: float = 1e-6) -> dict:
        """The sums that must hold (raises AssertionError otherwise): over the whole run, the work tallies add up
        to the line's friction work (to round-off, ``rel``), the ``none`` node-steps carry at most ``idle`` of the
        work and of the impulse (none at all on a sub-grid line), the windows are nested, and a sub-grid line's
        node-step tally is its model's own count, exactly."""
        line = self.line
        s = self.sums()
        end = window_label(math.inf)
        work = sum(s["work"][end].values())
        scale = max(abs(line.total_friction_work), 1e-300)
        assert abs(work - line.total_friction_work) <= rel * scale + 1e-300, (work, line.total_friction_work)
        fm = line.friction_model
        lim = 0.0 if fm is not None else idle
        for w in ("work", "impulse"):
            tot_w = sum(abs(v) for v in s[w][end].values())
            assert abs(s[w][end]["none"]) <= lim * tot_w, (w, s[w][end])
        tot = self.acc.sum(axis=(2, 3))
        assert np.all(np.diff(tot[0]) >= 0.0), tot[0]   # node-steps nested in the windows
        if fm is not None:
            counts = fm.branch_counts
            mine = {bn: int(round(s["steps"][end][bn])) for bn in BRANCHES[:3]}
            assert mine == counts, (mine, counts)
        return {"friction_work": work, "line_friction_work": line.total_friction_work,
                "relative_difference": (work - line.total_friction_work) / scale,
                "idle_work_share": s["work"][end]["none"] / scale,
                "idle_impulse_share": s["impulse"][end]["none"] / max(sum(s["impulse"][end].values()), 1e-300)}
