"""Run guards of the hydrocode: stop a run that cannot end, warn once when a state leaves the models' range.

Called by :class:`shockfriction.hydro.cycle.Simulation` (docs/theory/reliability.md):

* **time-step collapse**: the stable step dt_s (CFL and volume-change limits, before the growth
  cap) below ``time.dt_min_fraction`` times the largest dt_s of the run so far -> SimulationError
  naming the cell that limits dt;
* **projected cycle count**: n + (t_end - t)/min(dt_s, dt_max) above ``time.max_cycles`` ->
  SimulationError (checked every ``CHECK_EVERY`` cycles, from the first);
* **model range** (a warning, once per kind and body): pressure above ``P_RANGE_FACTOR`` times
  the bulk modulus rho0 c0^2 of a Mie-Grueneisen body (beyond where a linear Us-up fit is
  calibrated), temperature above ``T_SANITY_K``.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from shockfriction.errors import SimulationError
from shockfriction.hydro import matprops as mp

LOG = logging.getLogger("shockfriction")

CHECK_EVERY = 50
P_RANGE_FACTOR = 2.0   # p > 2 rho0 c0^2: Al 155 GPa, Cu 277 GPa, steels ~330 GPa
T_SANITY_K = 2.0e4     # no metal-friction problem here gets near 20,000 K


class RunGuards:
    """Collapse, runaway and model-range checks of one simulation."""

    def __init__(self, sim):
        self.sim = sim
        deck = sim.problem.deck
        self.min_fraction = deck.time.dt_min_fraction
        self.max_cycles = deck.time.max_cycles
        self.dt_ref = 0.0
        props = sim.state.props
        mg = props[:, mp.P_EOS] == mp.EOS_MIE_GRUNEISEN
        self.p_limit = np.where(mg, P_RANGE_FACTOR * props[:, mp.P_RHO0] * props[:, mp.P_C0] ** 2, np.inf)
        self.warned: set[tuple[str, int]] = set()
        self.warnings: list[str] = []

    def _where(self, cell: int) -> str:
        s = self.sim.state
        name, i, j = self.sim.mesh.cell_ij(cell)
        return f"body {name!r}, cell ({i}, {j}) at cycle {s.cycle}, t = {s.t:.4e} s"

    def after_step(self, dt_stable: float, dtcell: np.ndarray) -> None:
        """Checks after a cycle; ``dt_stable`` is the cells' stable step (before the growth cap)."""
        s = self.sim.state
        if not (math.isfinite(dt_stable) and dt_stable > 0.0):
            c = int(np.argmin(dtcell))
            raise SimulationError(f"{self._where(c)}: the stable time step is {float(dt_stable):.3e} s "
                                  "(no valid step; the state has left every model's range)")
        self.dt_ref = max(self.dt_ref, dt_stable)
        if dt_stable < self.min_fraction * self.dt_ref:
            c = int(np.argmin(dtcell))
            raise SimulationError(
                f"{self._where(c)}: time step collapsed to {dt_stable:.3e} s, below time.dt_min_fraction = "
                f"{self.min_fraction:g} of its largest value {self.dt_ref:.3e} s (a cell is being crushed or the "
                "state has left the models' range; lower time.dt_min_fraction only if this is expected)")
        if s.cycle == 1 or s.cycle % CHECK_EVERY == 0:
            self.project(dt_stable)
            self.model_range()

    def project(self, dt_stable: float) -> None:
        sim, s = self.sim, self.sim.state
        dt = min(dt_stable, sim.dt_max)
        left = max(sim.t_end - s.t, 0.0)
        projected = s.cycle + left / dt
        if projected > self.max_cycles:
            raise SimulationError(
                f"at cycle {s.cycle}, t = {s.t:.4e} s: reaching time.end = {sim.t_end:.4e} s at dt = {dt:.3e} s "
                f"needs about {projected:.3g} cycles, more than time.max_cycles = {self.max_cycles} "
                "(shorten time.end, coarsen the mesh, or raise time.max_cycles)")

    def model_range(self) -> None:
        s = self.sim.state
        for b in range(self.p_limit.size):
            if ("pressure", b) in self.warned and ("temperature", b) in self.warned:
                continue
            cells = np.flatnonzero(s.mat == b)
            if cells.size == 0:
                continue
            c = int(cells[np.argmax(s.pressure[cells])])
            if s.pressure[c] > self.p_limit[b]:
                self._warn("pressure", c, f"pressure {s.pressure[c] / 1e9:.4g} GPa is above {P_RANGE_FACTOR:g} "
                           f"rho0 c0^2 = {self.p_limit[b] / 1e9:.4g} GPa, beyond the Mie-Grueneisen (linear Us-up) "
                           "fit range")
            c = int(cells[np.argmax(s.temperature[cells])])
            if s.temperature[c] > T_SANITY_K:
                self._warn("temperature", c, f"temperature {s.temperature[c]:.4g} K is above {T_SANITY_K:g} K, "
                           "beyond the range of the thermal and strength models")

    def _warn(self, kind: str, cell: int, text: str) -> None:
        body = int(self.sim.state.mat[cell])
        if (kind, body) in self.warned:
            return
        self.warned.add((kind, body))
        msg = f"{self._where(cell)}: {text}; results past this point are outside the models' range"
        self.warnings.append(msg)
        LOG.warning(msg)

    def finished(self) -> None:
        """At the end of the loop: a run stopped by max_cycles before the end time is a failure."""
        sim, s = self.sim, self.sim.state
        if s.t < sim.t_end * (1.0 - 1e-12) and s.cycle >= self.max_cycles:
            raise SimulationError(f"stopped at cycle {s.cycle} = time.max_cycles, t = {s.t:.4e} s, before "
                                  f"time.end = {sim.t_end:.4e} s (raise time.max_cycles or shorten time.end)")
