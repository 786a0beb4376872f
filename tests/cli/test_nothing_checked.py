"""A scene on which no check gave a verdict is never a pass: every check was n/a or not
checked (a check whose input is unknown says "not checked, because ..."), so the scene
warns that nothing was checked, and --strict fails on it."""

from __future__ import annotations

import json

from tests.conftest import FIXTURES

KELVIN = str(FIXTURES / "kelvin" / "coupling.kcheck.yaml")


def test_nothing_checked_is_a_warning_not_a_pass(cli):
    # pose-error needs a point of interest the Kelvin fixture does not give: not checked.
    code, out, _ = cli("check", KELVIN, "--select", "pose-error", "--format", "json")
    scene = json.loads(out)["scenes"][0]
    assert [c["status"] for c in scene["checks"]] == ["skipped"]
    assert scene["status"] == "warn"
    codes = [w.get("code") for w in scene["warnings"]]
    assert "nothing-checked" in codes
    assert code == 0  # a warning fails the run only with --strict
    code, _, _ = cli("check", KELVIN, "--select", "pose-error", "--strict", "--no-cache")
    assert code == 1


def test_a_scene_with_a_verdict_gets_no_such_warning(cli):
    code, out, _ = cli("check", KELVIN, "--select", "maxwell", "--format", "json")
    scene = json.loads(out)["scenes"][0]
    assert scene["status"] == "pass" and code == 0
    assert "nothing-checked" not in [w.get("code") for w in scene["warnings"]]
