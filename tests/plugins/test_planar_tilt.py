"""A planar scene closed by gravity alone is told the tilt it tolerates (issue 21, item 11).

The planar block of methods.md §7 without a load: y1, y2 (normals +y) and x1 (normal +x),
μ = 0.1, gravity g = (−4, −9) m/s² in the plane. Retracting x1, the weight slides the block
along y1 and y2 towards x1 only while its component along −x beats their friction, μ times
its component along −y: while the gravity direction is more than atan μ from −y, towards −x
(closed form). The installed gravity is atan(4/9) from −y, so the installation tolerates a
tilt of atan(4/9) − atan(0.1) before that case stops closing; the y1 and y2 retractions
close farther out (the weight's line passes well inside the supports).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

SCENE = """\
version: 1
name: gravity block
units: mm
body: {{mass: 1, center_of_mass: [50, 30, 0], inertia: 0.001}}
supports:
  - {{name: y1, position: [20, 0, 0], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 0], normal: [1, 0, 0]}}
friction: 0.1
gravity: [{gx}, {gy}, 0]
"""


def _check(tmp_path: Path, cli_json, gx: float, gy: float) -> dict:
    path = tmp_path / "block.kcheck.yaml"
    path.write_text(SCENE.format(gx=gx, gy=gy), encoding="utf-8")
    _, doc = cli_json(str(path), "--select", "analytical-2d")
    (check,) = doc["scenes"][0]["checks"]
    return check


def test_a_planar_gravity_only_scene_is_told_its_tolerated_tilt(tmp_path, cli_json) -> None:
    check = _check(tmp_path, cli_json, -4, -9)
    tilt = math.degrees(math.atan2(4, 9) - math.atan(0.1))  # closed form, see above
    assert check["status"] == "pass"
    assert check["tolerated_tilt_deg"] == pytest.approx(tilt, abs=1e-6)
    assert f"safe for tilts up to {tilt:.2f}° from the installed attitude" in check["message"]
    assert "turn" not in check["message"]


def test_a_level_installation_that_fails_tolerates_no_tilt(tmp_path, cli_json) -> None:
    """Level (gravity along −y), nothing pushes the block towards x1: that retraction does not
    close, so the installation tolerates no tilt, and the verdict does not claim one."""
    check = _check(tmp_path, cli_json, 0, -9.81)
    assert check["status"] == "fail"
    assert check["tolerated_tilt_deg"] == 0.0
    assert "safe for tilts" not in check["message"]
