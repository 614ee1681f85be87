"""Deck fields of a sub-grid friction law on a slide line (validation only, no physics).

A slide line's ``friction`` table takes ``law = "subgrid-thermoelastic"`` (thesis ch. 7),
``law = "subgrid-thermoelastoplastic"`` (ch. 8) or ``law = "subgrid-viscoplastic"`` (docs/theory/viscoplastic.md)
with::

    friction = { law = "subgrid-thermoelastic",
                 mu0 = 0.3,                 # Coulomb coefficient (cap mu0 F_N)
                 f = 0.7,                   # the model's coefficient on the SCG strength
                 thickness = "20 um",       # column thickness h (thesis h_epsilon)
                 cells = 500,               # cells M of the column
                 grading = 1.0,             # ratio of successive cells (>= 1, finer at the interface)
                 body = "slave",            # the body the columns model: "slave" (default) or "guide"
                 heat_share = 0.677,        # optional: share beta_T entering that body (default e1/(e1+e2))
                 taylor_quinney = 0.9,      # beta_Q (thermoelastoplastic)
                 profile_nodes = [0, 100],  # slave nodes whose T(z), eps_p(z) go to columns.h5
                 profile_interval = "100 ns",  # default: 5 nodes, every 10th record
                 picard_tol = "1e-6 K",     # subgrid-viscoplastic only: its Picard tolerance (default 1e-6 K)
                 pressure_melting = true,   # subgrid-viscoplastic only: T_m(sigma_n) by the SCG melt law
                 closure = "excess",        # subgrid-viscoplastic only: the layer adds only its flow in excess
                                            # of the body's ("excess", default); "shear", "held": far end driven
                                            # or held (thickness-dependent, kept for comparison)
                 depth = "1 mm" }           # closure "excess" only: the column continued thermally to this depth
                                            # (default 1 mm; at least 4 sqrt(alpha time.end) of the modelled body)

With ``law = "subgrid-viscoplastic"`` and no ``heat_share`` the columns share the heat with the other body by
conduction (a thermal column in it, two-sided heat); ``heat_share`` keeps the fixed share of the thesis.

These keys are the :class:`SubgridFrictionOptions` mix-in of the slide line's ``FrictionDeck``;
they are refused for the other laws.
"""

from __future__ import annotations

from typing import Literal, Optional

from pydantic import BaseModel, Field, model_validator

from shockfriction.units import Dimensionless, PicardTolerance, PositiveLength, PositiveTime

SUBGRID_LAWS = {"subgrid-thermoelastic": "thermoelastic", "subgrid-thermoelastoplastic": "thermoelastoplastic",
                "subgrid-viscoplastic": "viscoplastic"}
_OPTIONS = ("f", "thickness", "cells", "grading", "body", "heat_share", "taylor_quinney", "profile_nodes",
            "profile_interval", "picard_tol", "pressure_melting", "closure", "depth")
_VISCOPLASTIC_ONLY = ("picard_tol", "pressure_melting", "closure", "depth")


class SubgridFrictionOptions(BaseModel):
    """The keys of a ``subgrid-*`` friction law (mixed into the slide line's friction table)."""

    f: Optional[Dimensionless] = Field(None, ge=0.0, description="coefficient on the SCG strength (eq. 7.12)")
    thickness: PositiveLength = Field(20e-6, le=1e-2, description="column thickness h")
    cells: int = Field(500, ge=2, le=100_000, description="cells M of each column")
    grading: float = Field(1.0, ge=1.0, le=2.0, description="ratio of successive cell sizes")
    body: Literal["slave", "guide"] = "slave"
    heat_share: Optional[Dimensionless] = Field(None, ge=0.0, le=1.0, description="beta_T of the modelled body")
    taylor_quinney: Dimensionless = Field(0.9, ge=0.0, le=1.0, description="beta_Q")
    profile_nodes: Optional[list[int]] = Field(None, max_length=1000)
    profile_interval: Optional[PositiveTime] = None
    picard_tol: Optional[PicardTolerance] = Field(
        None, description="subgrid-viscoplastic only: Picard tolerance in kelvin, e.g. '1e-3 K' (omitted: 1e-6 K)")
    pressure_melting: bool = Field(
        True, description="subgrid-viscoplastic only: melting temperature T_m(sigma_n) by the SCG melt law "
                          "and the melt viscosity's pressure factor (false: the ambient T_F and eta_L)")
    closure: Literal["excess", "shear", "held"] = Field(
        "excess", description="subgrid-viscoplastic only: how the column under a node is closed against the hydro "
                              "('excess': a quasi-static layer that slips only by its flow in excess of the "
                              "unheated body's, continued thermally to 1 mm, independent of the thickness; "
                              "'shear': far end driven by the hydro's shear of the layer; 'held': far end held at "
                              "the node, version 0.3; the last two depend on the thickness)")
    depth: Optional[PositiveLength] = Field(
        None, le=1.0, description="subgrid-viscoplastic with closure 'excess' only: the depth to which the column is "
                                  "continued thermally below its thickness by geometric cells (omitted: 1 mm); at "
                                  "least 4 sqrt(alpha time.end) of the modelled body, which the run checks")

    @model_validator(mode="after")
    def _subgrid_keys(self):
        law = getattr(self, "law", None)
        if law in SUBGRID_LAWS:
            missing = [k for k in ("mu0", "f") if getattr(self, k, None) is None]
            if missing:
                raise ValueError(f"friction law {law!r} needs {', '.join(missing)}")
            from shockfriction.deck.subgrid import check_smallest_cell
            check_smallest_cell(self.thickness, self.cells, self.grading)
            given = [k for k in _VISCOPLASTIC_ONLY if k in self.model_fields_set]
            if law != "subgrid-viscoplastic" and given:
                raise ValueError(f"{', '.join(given)} only with the subgrid-viscoplastic law (law is {law!r})")
            if self.depth is not None and self.closure != "excess":
                raise ValueError(f"depth only with closure = 'excess' (closure is {self.closure!r}: its column ends "
                                 "at the thickness)")
            if self.depth is not None and not self.depth > self.thickness:
                raise ValueError(f"depth = {self.depth:g} m: expected more than thickness = {self.thickness:g} m")
        else:
            given = [k for k in _OPTIONS if k in self.model_fields_set]
            if given:
                raise ValueError(f"{', '.join(given)} only with a subgrid-thermoelastic, subgrid-thermoelastoplastic "
                                 f"or subgrid-viscoplastic law (law is {law!r})")
        return self

    @property
    def subgrid_model(self) -> Optional[str]:
        """'thermoelastic' / 'thermoelastoplastic' / 'viscoplastic' for a sub-grid law, else None."""
        return SUBGRID_LAWS.get(getattr(self, "law", None))
