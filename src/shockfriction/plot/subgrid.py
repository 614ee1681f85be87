"""Figures of an uncoupled sub-grid run (matplotlib, Agg): interface histories and depth profiles."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shockfriction.plot import subplots


def plot_interface(t, theta, tau, names, melting_temperature, path: Path, title: str = "", film=None) -> Path:
    """Interface temperature and friction stress against time, one curve per column (Figs. 7.8-7.9);
    with ``film`` (viscoplastic model, m) a third panel with the molten film thickness and a log stress axis (where
    some stress is positive)."""
    if film is None:
        fig, (ax1, ax2) = subplots(2, 1, figsize=(7, 6.5), sharex=True)
    else:
        fig, (ax1, ax2, ax3) = subplots(3, 1, figsize=(7, 8.5), sharex=True)
        for k, name in enumerate(names):
            ax3.plot(np.asarray(t) * 1e6, np.asarray(film)[:, k] * 1e9, label=name)
        ax3.set_ylabel("molten film (nm)")
    tus = np.asarray(t) * 1e6
    for k, name in enumerate(names):
        ax1.plot(tus, theta[:, k], label=name)
        if np.any(np.isfinite(tau[:, k])):
            ax2.plot(tus, tau[:, k] / 1e6, label=name)
    if film is not None and np.any(np.asarray(tau) > 0.0):  # (a run out of contact has no stress to log-scale)
        ax2.set_yscale("log")
    ax1.axhline(melting_temperature, color="k", ls="--", lw=0.8, label="melting")
    ax1.set_ylabel("interface temperature (K)")
    ax1.legend(loc="lower right", fontsize=8)
    ax2.set_ylabel("friction stress (MPa)")
    (ax2 if film is None else ax3).set_xlabel("time (us)")
    if not np.any(np.isfinite(tau)):
        ax2.text(0.5, 0.5, "pure thermal run: no friction stress", ha="center", transform=ax2.transAxes)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return path


def plot_profiles(z, times, profiles, eps_profiles, path: Path, column: int = 0, title: str = "") -> Path:
    """Temperature and plastic strain through the layer at the output times (Fig. 7.5-7.7, 8.4)."""
    fig, (ax1, ax2) = subplots(1, 2, figsize=(10, 4.2))
    zum = np.asarray(z) * 1e6
    for t, th, ep in zip(times, profiles, eps_profiles):
        label = f"{t * 1e6:.3g} us"
        ax1.plot(zum, th[column], label=label)
        ax2.plot(zum, ep[column], label=label)
    ax1.set_xlabel("depth z (um)")
    ax1.set_ylabel("temperature (K)")
    ax2.set_xlabel("depth z (um)")
    ax2.set_ylabel("equivalent plastic strain")
    if times:
        ax1.legend(fontsize=8)
    if not any(np.any(ep[column] > 0.0) for ep in eps_profiles):
        ax2.text(0.5, 0.5, "no plastic strain\n(thermoelastic or pure thermal run)", ha="center", va="center",
                 transform=ax2.transAxes)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return path
