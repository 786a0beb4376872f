"""A poor Maxwell case says which normal to turn, by how much, and to what (issue 21).

Planar layout: y1 (20, 0) and y2 (80, 0) with normals +y, x1 at (0, 120) with normal +x.
Retracting y1 leaves y2 and x1, whose normal lines meet at (80, 120): the free motion is a
rotation about that pole, so y1 moves perpendicular to (−60, −120), at θ = atan(120 / 60) =
63.43° from its normal (closed form). The freed motion depends only on the other supports, so
turning y1's normal by Δ towards it gives θ − Δ: Δ = θ − arccos(0.7) reaches cos θ = 0.7.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

SCENE = """\
version: 1
name: tall block
units: mm
supports:
  - {{name: y1, position: [20, 0, 0], normal: [{y1}]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 120, 0], normal: [1, 0, 0]}}
"""


def _maxwell(tmp_path: Path, cli_json, y1: str) -> dict:
    path = tmp_path / "tall.kcheck.yaml"
    path.write_text(SCENE.format(y1=y1), encoding="utf-8")
    _, doc = cli_json(str(path), "--select", "maxwell")
    (check,) = doc["scenes"][0]["checks"]
    return check


def test_a_poor_case_names_the_turn_that_reaches_the_limit(tmp_path, cli_json) -> None:
    check = _maxwell(tmp_path, cli_json, "0, 1, 0")
    theta = math.degrees(math.atan2(120, 60))  # closed form, see the module docstring
    least = theta - math.degrees(math.acos(0.7))
    finding = next(f for f in check["findings"] if f["message"].startswith("retracting y1"))
    found = re.search(
        r"turn y1's normal ([\d.]+)° towards its freed motion, to \(([^)]*)\)", finding["hint"]
    )
    assert found is not None, finding
    by = float(found.group(1))
    assert least <= by <= least + 0.07  # the slack of the written normal, rounded up to 0.01°
    normal = [float(x) for x in found.group(2).split(",")]
    # The written normal is the old one turned by the written angle (to the 4 decimals shown).
    assert math.degrees(math.acos(normal[1])) == pytest.approx(by, abs=0.01)
    again = _maxwell(tmp_path, cli_json, found.group(2))
    case = next(c for c in again["cases"] if c["retracted"] == "y1")
    assert case["cos_maxwell"] >= 0.7
    assert math.degrees(math.acos(case["cos_maxwell"])) == pytest.approx(theta - by, abs=0.01)
