"""The hydrocode state as a struct of arrays (SI units; per unit depth in plane
strain, per radian in axisymmetry).

Nodes (index n): ``x, y`` positions at t^n; ``vx, vy`` velocities at t^{n+1/2}
(during an interface's ``apply`` they hold the free, then corrected, velocities);
``mass`` the group mass used for accelerations and impulses (a tied or periodic
node group shares it), ``mass_own`` the node's own lumped mass (sum over groups
for totals); ``fx, fy`` the last nodal forces.

Cells (index c): ``conn[c]`` four global node indices (counter-clockwise);
``cell_mass``, ``volume``, ``rho``, ``e`` (specific internal energy e_M used by
the EOS), ``e_el`` (stored elastic shear energy per mass), ``pressure`` (EOS,
compression positive), ``q`` (artificial viscosity), deviator ``sxx, syy, sxy``
(szz = -(sxx+syy) is the out-of-plane / hoop component), ``eps_p`` (equivalent
plastic strain), ``temperature``, ``shear_modulus`` (G(P, T) of SCG, G0 for
elastic-perfectly-plastic, 0 without strength or molten), ``yield_stress`` (the
flow stress Y(eps_p, P, T) of the current state, the thesis's Y^n for the friction
laws), ``sound_speed`` (longitudinal), ``damage`` (spall damage, failed when >= 1:
hydro/spall.py), ``mat`` (row of ``props``; one row per body).
All cell values are at t^n; after an interface adds heat to ``e`` the temperature
follows at the next cell update.

Time: ``t`` (t^n), ``cycle`` (n), ``dt`` (the position step dt^{n+1/2}) and
``dt_velocity`` (the velocity step dt^n = (dt^{n-1/2} + dt^{n+1/2})/2).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class EnergyBudget:
    """Cumulative energy exchanges (J per unit depth, or per radian) since t = 0.

    The balance is kinetic + internal = initial + boundary_work + interface_work
    + interface_heat.  ``boundary_work`` and ``interface_work`` are measured by the
    cycle (the kinetic energy that the constraints' and the interface corrections'
    velocity jumps add; <= 0 for friction and inelastic contact);
    ``interface_heat`` is what interface objects put into cells' internal energy
    (they add it here themselves).  The interfaces also report, for the books
    (docs/theory/contact-energy-and-shear-viscosity.md):

    * ``friction_work``: the friction impulses' work (>= 0 dissipated; part of
      ``-interface_work``) and ``friction_heat``, what of it went into the cells (part of
      ``interface_heat``; the rest left the hydrocode: sub-grid columns, or ``heat = "none"``);
    * ``column_heat``: the heat the sub-grid columns took (part of friction_work - friction_heat);
    * ``contact_work``: the normal impulses' work on the bodies (<= 0: the contact only
      dissipates; part of ``interface_work``) and ``contact_heat``, its inelastic loss put
      into the contacting cells (part of ``interface_heat``; equal to -contact_work when
      every slide line has the cells' arrays);
    * ``projection_work``: -sum F.dx of the penetration projections' position shifts, the
      internal energy they would have made; neutralised (the cells keep their internal
      energy across a shift), so it is not in the balance: a measure of the shifts' size.

    The cycle's energy error counts max(0, contact_work), energy the contact created, as error.
    """

    initial: float = 0.0
    boundary_work: float = 0.0
    interface_work: float = 0.0
    interface_heat: float = 0.0
    friction_work: float = 0.0
    friction_heat: float = 0.0
    column_heat: float = 0.0
    contact_work: float = 0.0
    contact_heat: float = 0.0
    projection_work: float = 0.0


@dataclass
class State:
    """All arrays of the problem; see the module docstring for the meaning of each."""

    axisymmetric: bool
    conn: np.ndarray
    x: np.ndarray
    y: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    mass: np.ndarray
    mass_own: np.ndarray
    cell_mass: np.ndarray
    volume: np.ndarray
    rho: np.ndarray
    e: np.ndarray
    mat: np.ndarray
    props: np.ndarray
    isentrope: np.ndarray
    fx: np.ndarray = None
    fy: np.ndarray = None
    e_el: np.ndarray = None
    pressure: np.ndarray = None
    q: np.ndarray = None
    sxx: np.ndarray = None
    syy: np.ndarray = None
    sxy: np.ndarray = None
    eps_p: np.ndarray = None
    temperature: np.ndarray = None
    shear_modulus: np.ndarray = None
    yield_stress: np.ndarray = None
    sound_speed: np.ndarray = None
    damage: np.ndarray = None
    t: float = 0.0
    cycle: int = 0
    dt: float = 0.0
    dt_velocity: float = 0.0
    energy: EnergyBudget = field(default_factory=EnergyBudget)
    #: position shifts of the interfaces' penetration projections this step (nodes, m); the
    #: cycle adds them to x^n before the move and zeroes them
    shift_x: np.ndarray = None
    shift_y: np.ndarray = None

    def __post_init__(self):
        nn, nc = self.x.shape[0], self.conn.shape[0]
        for name in ("fx", "fy", "shift_x", "shift_y"):
            if getattr(self, name) is None:
                setattr(self, name, np.zeros(nn))
        for name in ("e_el", "pressure", "q", "sxx", "syy", "sxy", "eps_p", "temperature", "shear_modulus",
                     "yield_stress", "sound_speed", "damage"):
            if getattr(self, name) is None:
                setattr(self, name, np.zeros(nc))

    @property
    def n_nodes(self) -> int:
        return self.x.shape[0]

    @property
    def n_cells(self) -> int:
        return self.conn.shape[0]

    @property
    def szz(self) -> np.ndarray:
        """Out-of-plane (hoop) deviator -(sxx + syy)."""
        return -(self.sxx + self.syy)

    def stress(self) -> dict[str, np.ndarray]:
        """Cauchy stress components sigma = S - (P + q) 1 (tension positive)."""
        ptot = self.pressure + self.q
        return {"xx": self.sxx - ptot, "yy": self.syy - ptot, "xy": self.sxy.copy(), "zz": self.szz - ptot}

    @property
    def geometry_factor(self) -> float:
        """2 pi in axisymmetry (per-radian arrays -> whole body), 1 in plane strain."""
        return 2.0 * np.pi if self.axisymmetric else 1.0
