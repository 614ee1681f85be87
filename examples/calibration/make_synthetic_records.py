"""Make the synthetic "measured" records of the example fits: runs of the built-in decks at known
parameters, plus seeded Gaussian noise.  Run from the repository root:

    python examples/calibration/make_synthetic_records.py
"""

from pathlib import Path

from shockfriction.deck.base import read_toml
from shockfriction.sweep.paths import set_paths
from shockfriction.sweep.spec import flatten
from shockfriction.sweep.synthetic import synthetic_record, write_csv

HERE = Path(__file__).resolve().parent


def deck_of(fit_file: str, values: dict, dataset: int | None = None) -> dict:
    spec = read_toml(HERE / fit_file)
    if dataset is not None:
        spec = spec["dataset"][dataset]
    base = read_toml(HERE / spec["base"])
    return set_paths(base, {**flatten(spec.get("set", {})), **values})


# sub-grid ball, two-stage loading: mu0 = 0.2, f = 0.7, noise 10 MPa
deck = deck_of("ball_two_stage_fit.toml", {"friction.mu0": 0.2, "friction.f": 0.7})
t, tau = synthetic_record("subgrid", deck, "ball", "time", "tau", noise=10e6, seed=2009)
write_csv(HERE / "ball_two_stage_synthetic.csv", t, tau, "us", "MPa", ("time", "tau"),
          "synthetic: shockfriction subgrid, ball two-stage loading, mu0 = 0.2, f = 0.7, noise 10 MPa (seed 2009)")

# plate impact: flyer at 250 m/s, record delayed by 40 ns, noise 2 m/s
deck = deck_of("plate_impact_velocity_fit.toml", {"bodies[0].velocity[1]": "250 m/s"})
t, v = synthetic_record("run", deck, "fs", "time", "vy", noise=2.0, seed=2009)
write_csv(HERE / "plate_impact_synthetic.csv", t + 40e-9, v, "us", "m/s", ("time", "vy"),
          "synthetic: shockfriction run, plate impact, flyer 250 m/s, time shift +40 ns, noise 2 m/s (seed 2009)")

# sub-grid ball under 1 GPa and under 10 GPa: mu0 = 0.2, f = 0.7, noise 5 MPa
for k, name in enumerate(("low", "high")):
    deck = deck_of("ball_two_loadings_fit.toml", {"friction.mu0": 0.2, "friction.f": 0.7}, dataset=k)
    t, tau = synthetic_record("subgrid", deck, "ball", "time", "tau", noise=5e6, seed=2009 + k)
    write_csv(HERE / f"ball_{name}_synthetic.csv", t, tau, "us", "MPa", ("time", "tau"),
              f"synthetic: shockfriction subgrid, ball, {deck['loading'][0]['normal_stress'][0]}, "
              "mu0 = 0.2, f = 0.7, noise 5 MPa")
