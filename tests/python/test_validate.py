"""The binary as a Python user drives it: `flapwing validate --json` reproduces every
published number (the paper's Table 5, MODEL.md section 5, Dickinson et al. 1999, ...) and
the operating points. The vehicles section (seconds of tethered runs) is checked by
crates/cli/tests/validate/vehicles.rs."""

import json


def test_validate_json_all_cases_pass(run_flapwing):
    doc = json.loads(run_flapwing("validate", "--section", "cases,operating-points", "--json").stdout)
    failed = [c["case"] for c in doc["cases"] if not c["pass"]]
    assert failed == [], f"cases that do not reproduce: {failed}"
    # The six published operating points of the built-in insects (issue 17): each passes or
    # is a known limitation with its note, and none fails.
    points = doc["operating_points"]
    assert len(points) == 6
    for p in points:
        assert p["verdict"] in ("pass", "known limitation"), p
        assert (p["verdict"] == "known limitation") == (p["limitation"] is not None), p
    assert doc["total"] == len(doc["cases"]) + len(points) == doc["passed"]
    assert doc["all_passed"] is True
