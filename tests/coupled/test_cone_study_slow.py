"""The thesis's findings on the cone shot (examples/cone_study.py, thermoelastic model over mu0 x f, modified
Coulomb, thermoelastoplastic), at the thesis's 100 um cells: 19 runs, about 10-20 min on 2 cores."""

import importlib.util
from pathlib import Path

import pytest

STUDY = Path(__file__).resolve().parents[2] / "examples" / "cone_study.py"


@pytest.mark.slow
def test_cone_study_reproduces_the_thesis_findings(tmp_path):
    spec = importlib.util.spec_from_file_location("cone_study", STUDY)
    study = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(study)
    assert study.main(["--cell-um", "100", "--workers", "2", "--out", str(tmp_path)]) == 0
    import json

    findings = json.loads((tmp_path / "findings.json").read_text())
    for f in findings:
        print(f["finding"], "->", f["numbers"])
    assert len(findings) == 4 and all(f["reproduced"] for f in findings)
