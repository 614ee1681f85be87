"""Interface temperature of the coupled pressure-shear example against the uncoupled Prakash 9702 case.

    python examples/pressure_shear_compare.py [OUT]        (default OUT = out/ps_compare)

Runs examples/pressure_shear_ti6al4v.toml (hydrocode + sub-grid columns, the flux follows from the
computed stress and slip) and examples/subgrid/prakash_9702.toml (the thesis's imposed two-stage
flux, §7.2.4), prints both interface temperatures at a few times and writes
OUT/interface_temperature.png.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from shockfriction.deck.base import load_deck
from shockfriction.deck.subgrid import SubgridDeck
from shockfriction.friction.subgrid.driver import run_subgrid
from shockfriction.hydro.api import run
from shockfriction.io.interface import read_interface

HERE = Path(__file__).resolve().parent


def main(out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    run(HERE / "pressure_shear_ti6al4v.toml", out / "coupled")
    d = read_interface(out / "coupled" / "interface.h5")["interface"]
    t_c = d["t_s"]
    theta_c = d["theta_interface_K"].mean(axis=1)
    flux_c = np.abs(d["tau_Pa"] * d["slip_local_mps"]).mean(axis=1)
    un = run_subgrid(load_deck(HERE / "subgrid" / "prakash_9702.toml", SubgridDeck), out / "uncoupled")
    rows = {}
    print(f"{'t (us)':>7} {'coupled T(0) (K)':>17} {'uncoupled T(0) (K)':>19}")
    for t in (0.5e-6, 1.0e-6, 1.5e-6, 1.7e-6, 2.5e-6, 3.2e-6):
        tc = float(np.interp(t, t_c, theta_c))
        tu = float(np.interp(t, un.t, un.theta_interface[:, 0]))
        rows[t] = (tc, tu)
        print(f"{t * 1e6:7.2f} {tc:17.1f} {tu:19.1f}")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    a.plot(t_c * 1e6, theta_c, label="coupled (hydrocode + columns)")
    a.plot(un.t * 1e6, un.theta_interface[:, 0], "--", label="uncoupled, Prakash 9702 flux")
    a.set_xlabel("time (us)")
    a.set_ylabel("interface temperature (K)")
    a.legend()
    b.plot(t_c * 1e6, flux_c / 1e9, label="coupled tau [v]")
    b.step([0, 1.8, 3.3], [6.12, 2.88, 2.88], where="post", ls="--", label="Prakash 9702 (thesis table)")
    b.set_xlabel("time (us)")
    b.set_ylabel("generated heat flux (GW/m^2)")
    b.legend()
    fig.savefig(out / "interface_temperature.png", dpi=110)
    print(f"wrote {out / 'interface_temperature.png'}")
    return rows


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/ps_compare"))
