"""The `maxwell` check on planar layouts with hand-derived answers."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from tests.conftest import PLANAR_SCENE


def _maxwell(path):
    result = check_scene(path, [lc for lc in load_checks() if lc.spec.name == "maxwell"])
    (check,) = result.checks
    return check


def test_block_cosines_from_the_poles(write_scene):
    check = _maxwell(write_scene(PLANAR_SCENE))
    cos = {c.retracted: c.cos_maxwell for c in check.cases}
    # Retracting y1 leaves a rotation about the pole (80, 30) mm where the y2 and x1 normal
    # lines meet; y1 at (20, 0) moves perpendicular to (-60, -30): cos = 60 / sqrt(60^2 + 30^2).
    assert cos["y1"] == pytest.approx(60 / np.hypot(60, 30), abs=1e-14)
    # Retracting y2: pole (20, 30); y2 at (80, 0) -> the same by symmetry.
    assert cos["y2"] == pytest.approx(60 / np.hypot(60, 30), abs=1e-14)
    # Retracting x1: y1 and y2 are parallel -> pure translation along x: cos = 1.
    assert cos["x1"] == pytest.approx(1.0, abs=1e-14)
    assert check.status.value == "pass" and check.details["rank"] == 3
    assert check.error_estimate < 1e-13


def test_min_cos_option_fails_the_check(write_scene):
    check = _maxwell(write_scene(PLANAR_SCENE + "checks:\n  maxwell: {min_cos: 0.9}\n"))
    assert check.status.value == "fail"
    assert [c.outcome for c in check.cases] == ["poor", "poor", "ok"]
    assert "y1, y2" in check.message


def test_concurrent_normals_are_not_deterministic(write_scene):
    # Three normals through the point (0, 0): a disc on three radial supports (thesis §2.1.2).
    text = PLANAR_SCENE.replace(
        "  - {name: y1, position: [20, 0, 0], normal: [0, 1, 0]}\n"
        "  - {name: y2, position: [80, 0, 0], normal: [0, 1, 0]}\n"
        "  - {name: x1, position: [0, 30, 0], normal: [1, 0, 0]}\n",
        "  - {name: a, position: [0, -50, 0], normal: [0, 1, 0]}\n"
        "  - {name: b, position: [43.30127, 25, 0], normal: [-0.866025, -0.5, 0]}\n"
        "  - {name: c, position: [-43.30127, 25, 0], normal: [0.866025, -0.5, 0]}\n",
    )
    check = _maxwell(write_scene(text))
    assert check.status.value == "fail" and check.details["rank"] == 2
    assert "not deterministic" in check.message
    assert {c.outcome for c in check.cases} == {"undetermined"}


def test_maxwell_alone_does_not_fail_the_run(cli_json):
    """The thesis potato closes in every case but has a cos θ below 0.7: Maxwell's rule of thumb
    is a warning (issue 9 #10), so the scene warns and the run exits 0."""
    from pathlib import Path

    potato = Path(__file__).resolve().parents[2] / "fixtures" / "thesis-potato"
    code, doc = cli_json(str(potato))
    (scene,) = doc["scenes"]
    maxwell = next(c for c in scene["checks"] if c["id"] == "maxwell")
    assert maxwell["status"] == "fail" and maxwell["severity"] == "warning"
    assert all(c["status"] != "fail" for c in scene["checks"] if c["id"] != "maxwell")
    assert scene["status"] == "warn" and code == 0
