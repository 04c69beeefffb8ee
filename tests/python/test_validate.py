"""The binary as a Python user drives it: `flapwing validate --json` reproduces every
published number (the paper's Table 5, MODEL.md section 5, Dickinson et al. 1999, ...)."""

import json


def test_validate_json_all_cases_pass(run_flapwing):
    doc = json.loads(run_flapwing("validate", "--json").stdout)
    failed = [c["case"] for c in doc["cases"] if not c["pass"]]
    assert failed == [], f"cases that do not reproduce: {failed}"
    assert doc["total"] == len(doc["cases"]) == doc["passed"]
    assert doc["all_passed"] is True
