"""Figures of sub-grid friction: interface temperature and slip maps (thesis Figs. 7.15-7.17), profiles."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shockfriction.plot import subplots


def plot_subgrid_interface(interface_h5: str | Path, out_dir: str | Path) -> list[Path]:
    """Per sub-grid slide line: ``subgrid_<name>.png`` with node-by-time maps of the interface
    temperature (Fig. 7.15), the macroscopic and local slip velocities (Figs. 7.16-7.17) and
    the plastic slip."""
    from shockfriction.io.interface import read_interface

    out_dir = Path(out_dir)
    written = []
    for name, d in read_interface(interface_h5).items():
        if "theta_interface_K" not in d or d["t_s"].size == 0:
            continue
        t_us = d["t_s"] * 1e6
        nodes = np.arange(d["theta_interface_K"].shape[1])
        T_F = float(d["attrs"].get("melting_temperature_K", np.nan))
        panels = [("theta_interface_K", "interface temperature (K)", "inferno", (None, T_F)),
                  ("slip_mps", "macroscopic slip rate (m/s)", "RdBu_r", None),
                  ("slip_local_mps", "local slip |[v]| (m/s)", "viridis", None),
                  ("slip_plastic_mps", "plastic slip rate (m/s)", "viridis", None)]
        fig, axes = subplots(1, len(panels), figsize=(4.3 * len(panels), 3.8), constrained_layout=True)
        for ax, (key, label, cmap, lim) in zip(axes, panels):
            z = d[key]
            kw = {}
            if cmap == "RdBu_r":  # symmetric, 99.5th percentile (a few corner nodes would wash out the map)
                m = float(np.percentile(np.abs(z), 99.5)) or float(np.max(np.abs(z))) or 1.0
                kw = dict(vmin=-m, vmax=m)
            elif key != "theta_interface_K":
                kw = dict(vmin=0.0, vmax=float(np.percentile(z, 99.5)) or float(np.max(z)) or 1.0)
            elif lim is not None:
                kw = dict(vmin=float(np.min(z)), vmax=lim[1])
            mesh = ax.pcolormesh(nodes, t_us, z, shading="nearest", cmap=cmap, **kw)
            fig.colorbar(mesh, ax=ax, label=label)
            if key == "theta_interface_K" and np.isfinite(T_F) and z.max() >= T_F - 20.0:
                ax.contour(nodes, t_us, z, levels=[T_F - 20.0], colors="cyan", linewidths=0.8)
            ax.set_xlabel("slave node")
            ax.set_ylabel("time (us)")
            ax.set_title(label)
        fig.suptitle(f"slide line {name}: sub-grid {d['attrs'].get('subgrid_model', '')} "
                     f"(mu0 = {d['attrs'].get('mu0', np.nan):g}, f = {d['attrs'].get('f', np.nan):g})")
        path = out_dir / f"subgrid_{name}.png"
        fig.savefig(path, dpi=110)
        written.append(path)
    return written


def plot_columns(columns_h5: str | Path, out_dir: str | Path) -> list[Path]:
    """Per slide line: ``columns_<name>.png``, T(z) and eps_p(z) of the chosen nodes at the profile times."""
    from shockfriction.io.columns import read_columns

    out_dir = Path(out_dir)
    written = []
    for name, d in read_columns(columns_h5).items():
        z_um = d["z_m"] * 1e6
        t = d["t_s"]
        fig, axes = subplots(1, 2, figsize=(10, 4), constrained_layout=True)
        from matplotlib import colormaps

        cmap = colormaps["viridis"]
        shown = np.unique(np.linspace(0, t.size - 1, min(t.size, 8)).round().astype(int))
        for k, node in enumerate(d["node"]):
            for m in shown:
                colour = cmap(m / max(t.size - 1, 1))
                style = ["-", "--", ":", "-."][k % 4]
                lab = f"t = {t[m] * 1e6:.2f} us" if k == 0 else None
                axes[0].plot(z_um, d["theta_K"][m, k], style, color=colour, lw=1, label=lab)
                axes[1].plot(z_um, d["eps_p"][m, k], style, color=colour, lw=1)
        axes[0].set_xlabel("depth z (um)")
        axes[0].set_ylabel("temperature (K)")
        axes[1].set_xlabel("depth z (um)")
        axes[1].set_ylabel("equivalent plastic strain")
        axes[0].legend(fontsize=7)
        fig.suptitle(f"slide line {name}: column profiles under nodes {[int(k) for k in d['node']]} "
                     "(line style: node, colour: time)")
        path = out_dir / f"columns_{name}.png"
        fig.savefig(path, dpi=110)
        written.append(path)
    return written
