"""Figure of a fit: measured against computed (best values), and the residual (matplotlib Agg)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def _label(name: str, value: float, sigma: float, unit: str) -> str:
    if unit == "s":
        value, sigma, unit = value * 1e9, sigma * 1e9, "ns"
    sig = f"{sigma:.2g}" if np.isfinite(sigma) else "not identifiable"
    return f"{name} = {value:.4g} ± {sig} {unit}".rstrip()


def plot_fit(result, path: Path) -> Path:
    """Write ``path`` (PNG): top, measured points and computed curve; bottom, residual."""
    fig, (ax, axr) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    us = 1e6
    ax.plot(result.t_measured * us, result.y_measured, ".", ms=3, color="0.3", label="measured")
    ax.plot(result.t_computed * us, result.y_computed, "-", color="C3", label="computed (best fit)")
    ax.set_ylabel(result.label)
    ax.legend(loc="best")
    ax.set_title("\n".join(_label(n, v, s, u) for n, v, s, u in
                           zip(result.names, result.values, result.sigma, result.units)), fontsize=9)
    resid = np.interp(result.t_measured, result.t_computed, result.y_computed) - result.y_measured
    axr.plot(result.t_measured * us, resid, ".", ms=3, color="C0")
    axr.axhline(0.0, color="0.5", lw=0.8)
    axr.set_xlabel("time (us)")
    axr.set_ylabel(f"residual\nrms {result.rms:.3g}")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)
