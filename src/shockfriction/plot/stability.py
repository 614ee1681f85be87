"""Figure of the largest stable plastic strain against temperature (thesis figs. 6.1-6.2)."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

DEFAULT_PRESSURES = (0.0, 40e9)
MELT_MARGIN = 0.5  #: K below T_F where the curves stop


def plot_stability_limit(materials: Sequence, path: str | Path, pressures: Sequence[float] = DEFAULT_PRESSURES,
                         samples: int = 400, marker: tuple[float, float] | None = None) -> Path:
    """Draw eq. 6.72 (limited to [0, eps_sat]) against temperature, one panel per material.

    One curve per contact pressure |F_N| (Pa); the grey dashed line is Steinberg's xi = 0
    form, which does not depend on temperature or pressure.  ``marker`` = (theta, P)
    marks the operating point.  Writes a PNG (matplotlib Agg) and returns its path.
    """
    from shockfriction.plot import subplots

    from shockfriction.analysis.stability import ScgConstants, max_stable_strain

    path = Path(path)
    fig, axes = subplots(1, len(materials), figsize=(5.2 * len(materials), 4.0), squeeze=False)
    for ax, m in zip(axes[0], materials):
        c = ScgConstants.of(m)
        # geometric spacing of T_F - theta: the limit drops steeply just below melting. The
        # curve stops 0.5 K below T_F: closer, dG/dtheta -> 0 with G itself (Ball-Winter factor)
        # and eq. 6.72 rises again, an artefact of a strengthless state (docs/theory/analyses.md)
        theta = m.melting_temperature - np.geomspace(m.melting_temperature - 300.0, MELT_MARGIN, samples)
        for P in pressures:
            ax.plot(theta, max_stable_strain(c, theta, P), label=f"|F_N| = {P / 1e9:g} GPa")
        ref = ScgConstants.of(m, xi=0.0)
        ax.plot(theta, max_stable_strain(ref, theta, 0.0), color="0.5", ls="--", lw=1, label="xi = 0 (any F_N)")
        if marker is not None:
            t0, p0 = marker
            ax.plot([t0], [max_stable_strain(c, t0, p0)], "ko", ms=4,
                    label=f"{t0:g} K, {p0 / 1e9:g} GPa")
        ax.set_title(f"{m.name}: stable below the curve")
        ax.set_xlabel("temperature theta_0 (K)")
        ax.set_ylabel("largest stable plastic strain eps_p,0 (eq. 6.72)")
        ax.set_xlim(300.0, m.melting_temperature)
        ax.set_ylim(top=1.1 * float(max_stable_strain(ref, 300.0, 0.0)))
        ax.set_ylim(bottom=0.0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path
