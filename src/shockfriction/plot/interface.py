"""Node-by-time maps of slide-line records (normal stress, shear, slip rate, cumulated slip, work).

Colour limits are the 1st and 99th percentiles (symmetric about 0 for signed quantities), so a
one-window impact spike does not wash out the map; unpaired nodes are blank.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

PANELS = (
    ("sigma_n_Pa", "normal stress (GPa)", 1e-9, "viridis"),
    ("tau_Pa", "shear stress (GPa)", 1e-9, "RdBu_r"),
    ("slip_mps", "slip rate (m/s)", 1.0, "RdBu_r"),
    ("cum_slip_m", "cumulated slip (um)", 1e6, "RdBu_r"),
    ("friction_work_J", "friction work (J)", 1.0, "magma"),
)


def plot_interface(data: dict[str, dict[str, np.ndarray]], out_dir: str | Path) -> list[Path]:
    """One PNG per slide line in ``out_dir``: a node-by-time map per recorded quantity."""
    from shockfriction.plot import subplots

    out_dir = Path(out_dir)
    written = []
    for name, d in data.items():
        t_us = d["t_s"] * 1e6
        if t_us.size == 0:
            continue
        nodes = np.arange(d["sigma_n_Pa"].shape[1])
        fig, axes = subplots(1, len(PANELS), figsize=(4.2 * len(PANELS), 3.6), constrained_layout=True)
        paired = d["active"].astype(bool) if "active" in d else np.ones(d[PANELS[0][0]].shape, bool)
        for ax, (key, label, scale, cmap) in zip(axes, PANELS):
            z = np.where(paired, d[key] * scale, np.nan)
            finite = z[np.isfinite(z)]
            if finite.size == 0:
                finite = np.zeros(1)
            if cmap == "RdBu_r":
                lim = float(np.percentile(np.abs(finite), 99)) or 1.0
                kw = dict(vmin=-lim, vmax=lim)
            else:
                lo, hi = np.percentile(finite, [1, 99])
                kw = dict(vmin=float(lo), vmax=float(hi) if hi > lo else float(lo) + 1.0)
            mesh = ax.pcolormesh(nodes, t_us, z, shading="nearest", cmap=cmap, **kw)
            fig.colorbar(mesh, ax=ax, label=label)
            ax.set_xlabel("slave node")
            ax.set_ylabel("time (us)")
            ax.set_title(label)
        fig.suptitle(f"slide line {name}")
        path = out_dir / f"interface_{name}.png"
        fig.savefig(path, dpi=110)
        written.append(path)
    return written
