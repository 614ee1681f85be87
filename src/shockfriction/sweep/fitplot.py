"""Figure of a fit: measured against computed (best values), and the residual (matplotlib Agg)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shockfriction.plot import subplots


def _label(name: str, value: float, sigma: float, unit: str) -> str:
    if unit == "s":
        value, sigma, unit = value * 1e9, sigma * 1e9, "ns"
    sig = f"{sigma:.2g}" if np.isfinite(sigma) else "not identifiable"
    return f"{name} = {value:.4g} ± {sig} {unit}".rstrip()


def plot_fit(result, path: Path) -> Path:
    """Write ``path`` (PNG): per dataset, measured points and computed curve, then the residual."""
    n = len(result.curves)
    fig, axes = subplots(2 * n, 1, figsize=(7, 1 + 5 * n), sharex=False, squeeze=False,
                             gridspec_kw={"height_ratios": [3, 1] * n})
    us = 1e6
    for k, c in enumerate(result.curves):
        ax, axr = axes[2 * k, 0], axes[2 * k + 1, 0]
        ax.plot(c.t_measured * us, c.y_measured, ".", ms=3, color="0.3", label=f"measured {c.name}".rstrip())
        ax.plot(c.t_computed * us, c.y_computed, "-", color="C3", label="computed (best fit)")
        ax.set_ylabel(c.label)
        ax.legend(loc="best")
        resid = np.interp(c.t_measured, c.t_computed, c.y_computed) - c.y_measured
        axr.plot(c.t_measured * us, resid, ".", ms=3, color="C0")
        axr.axhline(0.0, color="0.5", lw=0.8)
        axr.set_xlim(ax.get_xlim())
        axr.set_xlabel("time (us)")
        axr.set_ylabel(f"residual\nrms {c.rms:.3g}")
    axes[0, 0].set_title("\n".join(_label(n_, v, s, u) for n_, v, s, u in
                                   zip(result.names, result.values, result.sigma, result.units)), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return Path(path)
