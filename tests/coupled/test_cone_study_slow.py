"""The thesis's findings on the cone shot, judged honestly (examples/cone_study.py, docs/theory/cone-study.md):
21 runs at the thesis's 100 um cells (thermoelastic over mu0 x f, thermoelastoplastic and viscoplastic at (0.3, 0.7),
plain Coulomb 0.02 and 0.3, modified Coulomb), about 8-25 min on 2 cores (472 s measured, 2026-11-27).

Each finding is asserted against the plain-Coulomb baseline, on all nodes and on the interior nodes (more than 1 mm
from the cone-base corner), with melting judged at T_F = 1220 K.  Measured 2026-11-23 (the asserted verdicts):
the three findings that hold are not the sub-grid model's (the caps govern 98.6-100 % of the friction node-steps);
the melting finding does not hold; the model departs from Coulomb only where its SCG branch governs (f = 0.3).
The first test (fast) checks the work- and impulse-weighted branch tallies on two short coarse runs."""

import csv
import importlib.util
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "examples" / "cone_study.py"


def _study():
    sys.path.insert(0, str(ROOT / "examples"))   # cone_study imports cone_shot
    spec = importlib.util.spec_from_file_location("cone_study", STUDY)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_weighted_branch_tallies_short_cone_runs(tmp_path):
    """The work- and impulse-weighted branch tallies on two short, coarse cone runs (400 um cells, 0.5 us: plain
    Coulomb 0.3 and the thermoelastic model at mu0 = 0.3, f = 0.7): each weight's shares add up to 1; the work tally
    over the run is the friction work of interface.h5 (run_one checks it to 1e-9 and the slide line's own sum to
    1e-12, and raises otherwise); the sub-grid run's node-step tally is its model's own count; the windows are
    nested (0-0.3 us holds less work than 0-3 us; 0-3 and 0-8 us are the whole run here)."""
    study = _study()
    rows = {}
    for spec in ({"name": "coulomb_mu0.3", "law": "coulomb", "model": "coulomb", "mu0": 0.3, "f": 0.0},
                 {"name": "te_mu0.3_f0.7", "law": "subgrid-thermoelastic", "model": "thermoelastic", "mu0": 0.3,
                  "f": 0.7}):
        rows[spec["name"]] = study.run_one(spec, str(tmp_path), 400.0, 0.5, 40)
    for name, r in rows.items():
        for lab in study.WINDOW_LABELS:
            for w in study.WEIGHTS:
                shares = [r[f"tally_{w}_{b}_{lab}"] for b in study.TALLY_BRANCHES]
                assert sum(shares) == pytest.approx(1.0, abs=1e-12) and min(shares) >= 0.0, (name, w, lab)
        early, mid, late = (r[f"tally_work_J_{lab}"] for lab in study.WINDOW_LABELS)
        assert 0.0 < early < mid == late == pytest.approx(r["friction_work_J"], rel=1e-9), name
        assert r["tally_impulse_Ns_0-0.3us"] < r["tally_impulse_Ns_0-3us"]
        d = json.loads((tmp_path / name / "branch_tally.json").read_text())
        assert d["books"]["relative_difference"] == pytest.approx(0.0, abs=1e-12)
        inner = d["interior"]["sums"]["work"]["0-end"]
        assert 0.0 < sum(inner.values()) < sum(d["all"]["sums"]["work"]["0-end"].values())
    c, te = rows["coulomb_mu0.3"], rows["te_mu0.3_f0.7"]
    assert all(c[f"tally_{w}_subgrid_{lab}"] == 0.0 for w in study.WEIGHTS for lab in study.WINDOW_LABELS)
    for b in study.BRANCHES:   # the node-step tally is the model's own count (branch_* from interface.h5)
        assert te[f"tally_steps_{b}_0-8us"] == pytest.approx(te[f"branch_{b}_frac"], rel=1e-12)
    # a stuck node does no work: sticking carries impulse but (nearly) no work
    assert c["tally_impulse_sticking_cap_0-3us"] > 0.05 > c["tally_work_sticking_cap_0-3us"]
    table = study.tally_table(rows)
    print("\n" + table)
    assert table.count("| te_mu0.3_f0.7 |") == 3 and not math.isnan(te["tally_work_subgrid_0-0.3us"])
    assert np.isfinite([te[f"tally_work_subgrid_{lab}"] for lab in study.WINDOW_LABELS]).all()


@pytest.mark.slow
def test_cone_study_findings_judged_against_plain_coulomb(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, str(STUDY), "--cell-um", "100", "--workers", "2", "--out", str(tmp_path)],
                          env=env, capture_output=True, text=True, timeout=3600, check=False)
    print(proc.stdout[-4000:], proc.stderr[-3000:])
    assert proc.returncode == 0
    findings = {f["id"]: f for f in json.loads((tmp_path / "findings.json").read_text())}
    rows = {r["name"]: r for r in csv.DictReader((tmp_path / "study.csv").open())}
    assert (tmp_path / "findings.md").exists()
    f1, f2, f3 = findings["f_insensitive_mu0_0.02"], findings["peak_slip_vs_modified_coulomb"], findings["melting"]
    f4, ctl = findings["thermoelastoplastic_vs_thermoelastic"], findings["control_subgrid_branch"]
    f5 = findings["viscoplastic_vs_thermoelastic"]

    # 1. f barely matters at mu0 = 0.02 -- because the Coulomb cap governs; plain Coulomb 0.02 gives the same
    n = f1["numbers"]
    assert f1["holds"] and not f1["attributable_to_model"]
    assert n["spread_over_f"] < 5e-4 and n["max_dev_from_coulomb_0.02"] < 5e-4 and n["cap_fraction_min"] > 0.9999
    assert n["f_0.7_and_0.9_bit_identical"]
    # 2. peak slip below modified Coulomb's: interior yes, all nodes no, and plain Coulomb 0.3 does the same
    n = f2["numbers"]
    assert f2["holds_interior"] and f2["holds"] and not f2["attributable_to_model"]  # all nodes too since the
    # energy-neutral contact (position projection) stopped the base-corner node from jetting
    assert n["peak_slip_interior_mps"]["subgrid"] == pytest.approx(76.7, abs=1.5)
    assert n["peak_slip_interior_mps"]["coulomb_0.3"] == pytest.approx(76.5, abs=1.5)
    assert n["peak_slip_interior_mps"]["modified_coulomb"] > 150.0 and n["cap_fraction"] > 0.97
    # 3. melting, judged at T_F: no node, interior or not, within 1 K of 1220 K with the thermoelastic model
    n = f3["numbers"]
    assert not f3["holds_interior"] and not f3["holds"]
    assert n["T_F_K"] == 1220.0 and n["max_interface_T_interior_K"] < 700.0 and n["max_interface_T_K"] < 1219.0
    # 4. thermoelastoplastic ~ thermoelastic, and both ~ plain Coulomb 0.3
    n = f4["numbers"]
    assert f4["holds"] and not f4["attributable_to_model"]
    assert n["max_diff"] < 0.005 and n["ref_vs_coulomb"] < 0.01 and n["model_vs_coulomb"] < 0.01
    # 5. viscoplastic (the excess layer) ~ thermoelastic (measured 2.6e-4 of the peak; both 0.39-0.40 % from
    # plain Coulomb 0.3), the sub-grid branch carrying the same share of the friction work (12.4 % against 12.7 %)
    n = f5["numbers"]
    assert f5["holds"] and not f5["attributable_to_model"]
    assert n["max_diff"] < 1e-3 and n["model_vs_coulomb"] < 0.01
    vp, te = rows["vp_mu0.3_f0.7"], rows["te_mu0.3_f0.7"]
    assert float(vp["tally_work_subgrid_0-8us"]) == pytest.approx(float(te["tally_work_subgrid_0-8us"]), abs=0.01)
    assert float(vp["friction_work_J"]) == pytest.approx(float(te["friction_work_J"]), rel=0.01)
    # control: where the SCG branch governs (f = 0.3) the model is visible
    assert ctl["attributable_to_model"] and ctl["numbers"]["subgrid_fraction"] > 0.4
    assert ctl["numbers"]["max_dev_from_coulomb_0.3"] > 0.1
    # the weighted tallies: every run (plain and modified Coulomb too), shares that add up in every window
    for name, r in rows.items():
        for lab in ("0-0.3us", "0-3us", "0-8us"):
            for w in ("steps", "work", "impulse"):
                shares = [float(r[f"tally_{w}_{b}_{lab}"]) for b in ("coulomb_cap", "sticking_cap", "subgrid")]
                assert sum(shares) == pytest.approx(1.0, abs=1e-9), (name, w, lab)
        # the window [0, 8 us) of the steps' start times leaves out the closing velocity stage at t = 8 us (the
        # final record's half step), whose friction work interface.h5 holds: measured -4.6e-6 to -8.5e-5 of it
        # (the whole-run tally equals it to 1e-9: run_one checks that)
        ratio = float(r["tally_work_J_0-8us"]) / float(r["friction_work_J"])
        assert 1.0 - 2e-4 < ratio <= 1.0 + 1e-12, (name, ratio)
    # the tally: three branches that add up, for every sub-grid run
    for name, r in rows.items():
        if r["model"] in ("thermoelastic", "thermoelastoplastic"):
            parts = [int(r[f"branch_{b}"]) for b in ("coulomb_cap", "sticking_cap", "subgrid")]
            assert sum(parts) == int(r["friction_node_steps"]) > 0, name
