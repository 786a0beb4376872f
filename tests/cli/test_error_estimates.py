"""Every check result reports its numerical error beside its run time (issue 21, item 8).

Over every bundled fixture and every check: a check that ran (pass, marginal or fail) has a
finite, non-negative ``error_estimate``. Not applicable, by design and as docs/json-result.md
says: a skipped check (it did not run) and a crashed one (``error``); a fixture never crashes.
Also the cases the issue names: ``analytical-3d`` under gravity alone (the tool changer, a
full map with no boundary) and ``tolerances`` (its pass probability's sampling error, which
for n samples that all pass is half the Clopper–Pearson interval, (1 - (α/2)^(1/n)) / 2).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from tests.conftest import FIXTURES, PLANAR_SCENE, ROOT

BUILT_IN = {
    "analytical-2d",
    "analytical-3d",
    "graphical-2d",
    "hertz",
    "jamming",
    "maxwell",
    "tolerances",
}


@pytest.fixture(scope="module")
def fixture_results() -> dict:
    run = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(FIXTURES), "--format", "json"]
        + ["--no-cache", "-j", "1", "--color", "never"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    return json.loads(run.stdout)


def test_every_check_that_ran_reports_a_finite_error(fixture_results):
    ran: set[str] = set()
    for scene in fixture_results["scenes"]:
        for check in scene["checks"]:
            where = f"{scene['path']} {check['id']} ({check['status']})"
            if check["status"] == "skipped":
                assert "error_estimate" not in check, where  # it did not run
                continue
            assert check["status"] != "error", where
            estimate = check.get("error_estimate")
            assert isinstance(estimate, (int, float)), where
            assert math.isfinite(estimate) and estimate >= 0, where
            ran.add(check["id"])
    assert ran == BUILT_IN  # every check ran on some fixture


def test_gravity_alone_and_tolerances_have_theirs(fixture_results):
    by_path = {s["path"]: s for s in fixture_results["scenes"]}
    tool = by_path[str(FIXTURES.relative_to(ROOT) / "tool-changer" / "tool.kcheck.yaml")]
    spatial = next(c for c in tool["checks"] if c["id"] == "analytical-3d")
    assert spatial["swept_direction"] == "gravity" and spatial["status"] == "pass"
    assert spatial["error_estimate"] < 1e-6  # degrees: nothing rounding could open
    groove = by_path[str(FIXTURES.relative_to(ROOT) / "three-groove" / "coupling.kcheck.yaml")]
    tol = next(c for c in groove["checks"] if c["id"] == "tolerances")
    low, high = tol["pass_probability_bounds"]
    assert tol["error_estimate"] == pytest.approx((high - low) / 2)
    if tol["passed"] == tol["samples"]:
        alpha = 1 - tol["confidence"]
        closed = (1 - (alpha / 2) ** (1 / tol["samples"])) / 2
        assert tol["error_estimate"] == pytest.approx(closed, rel=1e-9)


def test_planar_gravity_alone_has_an_estimate(write_scene, cli_json):
    """A planar scene closed by gravity alone reports no range, but still its error: the
    closing conditions' boundaries, in degrees."""
    text = PLANAR_SCENE.split("load:")[0] + "gravity: [-5, -9.81, 0]\n"
    _, doc = cli_json(str(write_scene(text)), "--select", "analytical-2d", "--no-cache")
    (check,) = doc["scenes"][0]["checks"]
    assert check["status"] == "pass" and "safe_ranges_deg" not in check
    assert 0 <= check["error_estimate"] < 1e-6
