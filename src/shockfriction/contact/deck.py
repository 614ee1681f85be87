"""Deck section ``[[slide_lines]]``: a slide line between two body sides (validation only, no physics).

Example::

    [[slide_lines]]
    name = "interface"
    guide = { body = "target", side = "top" }      # master surface
    slave = { body = "flyer", side = "bottom" }    # sliding surface
    contact = "unilateral"                          # or "bilateral" (thesis's permanent contact)
    heat = "none"                                   # or "effusivity" (beta_T = e1/(e1+e2), eq. 2.101)
    record_interval = "10 ns"                       # records: window averages (default: output.field_interval)
    guide_share = "segment"                         # or "point" (the thesis's (1 - coef, coef))
    max_sweeps = 50                                 # Gauss-Seidel sweeps per step (1: thesis single pass)
    friction = { law = "coulomb", mu0 = 0.1 }      # frictionless, coulomb, modified_coulomb
                                                    # (mu0, mu_inf, gamma "s/m"), tresca (mu_T),
                                                    # coulomb_tresca (mu0, mu_inf, gamma, mu_T);
                                                    # evaluation = "corrected" (default) | "free" (eq. 3.79),
                                                    # relaxation_steps = 5 (slip of a velocity-dependent mu)
"""

from __future__ import annotations

from typing import Literal, Optional

from pydantic import Field, model_validator

from shockfriction.coupled.deck import SubgridFrictionOptions
from shockfriction.deck.base import DeckModel
from shockfriction.units import Dimensionless, PositiveTime, Slowness

NonNegative = Dimensionless


class SideRef(DeckModel):
    """A path of nodes: a body side (``bottom``, ``right``, ``top``, ``left``; for a body meshed
    from a gmsh file, a physical curve name), optionally a sub-range.

    ``first`` and ``last`` are node positions along the side in its own (counter-clockwise)
    order, counted from 0; negative values count from the end (-1 is the last node).
    """

    body: str
    side: str = Field(pattern=r"^[A-Za-z0-9_.\-]+$")
    first: int = 0
    last: int = -1


class FrictionDeck(SubgridFrictionOptions, DeckModel):
    """Friction law and its parameters (``shockfriction.friction.laws``; sub-grid laws: ``coupled.deck``)."""

    law: Literal["frictionless", "coulomb", "modified_coulomb", "tresca", "coulomb_tresca",
                 "subgrid-thermoelastic", "subgrid-thermoelastoplastic", "subgrid-viscoplastic"] = "frictionless"
    mu0: Optional[Dimensionless] = Field(None, ge=0.0, description="static coefficient (eq. 2.87)")
    mu_inf: Optional[Dimensionless] = Field(None, ge=0.0, description="dynamic coefficient (eq. 2.90)")
    gamma: Slowness = Field(0.0, ge=0.0, description="inverse threshold slip velocity, e.g. '0.01 s/m'")
    mu_T: Optional[Dimensionless] = Field(None, ge=0.0, description="Tresca coefficient; unset: mu_T = mu (eq. 3.81)")
    evaluation: Literal["corrected", "free"] = Field(
        "corrected", description="slip at which a velocity-dependent mu is evaluated: after this step's friction "
                                 "correction (converges under refinement) or the free slip of the thesis's eq. 3.79")
    relaxation_steps: float = Field(
        5.0, ge=0.0, le=1000.0, description="relaxation time of the slip seen by the law with evaluation = "
                                            "'corrected', in time steps (0: none; it then flutters)")

    @model_validator(mode="after")
    def _needs(self):
        need = {
            "coulomb": ("mu0",),
            "modified_coulomb": ("mu0", "mu_inf"),
            "tresca": ("mu_T",),
            "coulomb_tresca": ("mu0",),
        }.get(self.law, ())
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"friction law {self.law!r} needs {', '.join(missing)}")
        return self


class SlideLineDeck(DeckModel):
    """One slide line: guide (master) and slave (sliding) sides, contact kind, friction, heat."""

    name: str = Field("interface", pattern=r"^[A-Za-z0-9_.-]+$")
    guide: SideRef
    slave: SideRef
    contact: Literal["unilateral", "bilateral"] = "unilateral"
    friction: FrictionDeck = FrictionDeck()
    heat: Literal["none", "effusivity"] = "none"
    record_interval: Optional[PositiveTime] = None
    guide_share: Literal["segment", "point"] = "segment"
    max_sweeps: int = Field(50, ge=1, le=10000, description="Gauss-Seidel sweeps per step (1 = thesis single pass)")

    @model_validator(mode="after")
    def _distinct(self):
        if self.guide.body == self.slave.body and self.guide.side == self.slave.side:
            raise ValueError("guide and slave must be different sides")
        return self
