"""The thesis's findings on the cone shot (examples/cone_study.py, thermoelastic model over mu0 x f, modified
Coulomb, thermoelastoplastic), at the thesis's 100 um cells: 19 runs, about 5-10 min on 2 cores."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "examples" / "cone_study.py"


@pytest.mark.slow
def test_cone_study_reproduces_the_thesis_findings(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, str(STUDY), "--cell-um", "100", "--workers", "2", "--out", str(tmp_path)],
                          env=env, capture_output=True, text=True, timeout=3600)
    print(proc.stdout[-3000:], proc.stderr[-3000:])
    findings = json.loads((tmp_path / "findings.json").read_text())
    for f in findings:
        print(f["finding"], "->", f["numbers"])
    assert proc.returncode == 0
    assert len(findings) == 4 and all(f["reproduced"] for f in findings)
