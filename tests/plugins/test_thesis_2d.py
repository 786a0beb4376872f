"""The thesis fixtures (docs/validation.md, planar section): pinned results and why.

Thesis numbers are from the seed document (methods.md §6); kcheck numbers are pinned to what
the closed forms give for the fixtures' chosen coordinates, at the resolution that matters for
the comparison (0.01 deg), except where a hand closed form gives more.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from kcheck.cli import main
from kcheck.mechanics.arcs import intersect

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"


def check_json(tmp_path: Path, folder: str) -> dict[str, dict[str, Any]]:
    """Run `kcheck check` on a fixture folder; the JSON results of each check by id."""
    out = tmp_path / "out.json"
    main(["check", str(FIXTURES / folder), "--format", "json", "-o", str(out)])
    scene = json.loads(out.read_text())["scenes"][0]
    assert scene["error"] is None
    return {c["id"]: c for c in scene["checks"]}


def cases(check: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Case results by retracted support."""
    return {c["retracted"]: c for c in check["cases"]}


def test_block_4_2(tmp_path: Path) -> None:
    """§4.2: the x1 case is a translation; lambda > 0 iff -cos a + mu sin a > 0, i.e.
    90 - atan(0.11) = 83.72 to 263.72 deg (thesis, frictionless reading: 90-270), and both y
    contacts are kept iff F_y < 0: 180-360 deg (thesis: 180-270 within its desired range)."""
    result = check_json(tmp_path, "thesis-block-4-2")["analytical-2d"]
    x1 = cases(result)["x1"]
    t = np.degrees(np.arctan(0.11))
    assert x1["desired_motion_deg"] == [[pytest.approx(90 - t), pytest.approx(270 - t)]]
    assert x1["contacts_kept_deg"] == [[pytest.approx(180.0), pytest.approx(360.0)]]
    assert result["safe_ranges_deg"] == [[pytest.approx(197.46, abs=0.01), pytest.approx(270 - t)]]
    # The rotations' desired ranges are the thesis's 180-360 deg shifted by friction.
    assert cases(result)["y1"]["desired_motion_deg"][0][0] == pytest.approx(197.46, abs=0.01)
    assert cases(result)["y2"]["desired_motion_deg"][0][0] == pytest.approx(184.90, abs=0.01)


def test_appendix_a(tmp_path: Path) -> None:
    """Appendix A: graphical-2d calls 300 deg safe; analytical-2d finds support 1 lifting off
    with N1 = -mu F cos(phi) y / x = -0.1 cos 30 deg (30 mm / 30 mm) = -0.0866 N (eq. A.4)."""
    checks = check_json(tmp_path, "thesis-appendix-a")
    analytical = checks["analytical-2d"]
    assert analytical["status"] == "fail" and analytical["safe_ranges_deg"] == []
    x3 = cases(analytical)["x3"]
    assert x3["outcome"] == "loses_contact"
    assert x3["normal_forces"]["y1"] == pytest.approx(-0.1 * np.cos(np.radians(30)), rel=1e-9)
    graphical = checks["graphical-2d"]
    assert graphical["status"] == "pass"
    assert graphical["safe_ranges_deg"] == [
        [pytest.approx(292.41, abs=0.01), pytest.approx(317.76, abs=0.01)]
    ]


def test_potato(tmp_path: Path) -> None:
    """§2.2 with the chosen coordinates: thesis 103-165 (desired rotation), 78-150 (contacts),
    103-150 (combined); kcheck within 1 deg of each (the thesis read 0.1 rad sampled plots)."""
    result = check_json(tmp_path, "thesis-potato")["analytical-2d"]

    def common(key: str) -> tuple[float, float]:
        # JSON ranges end below their start when they pass 0° (docs/json-result.md)
        arcs = [
            tuple((np.radians(s), np.radians(e + 360.0 * (e <= s))) for s, e in c[key])
            for c in result["cases"]
        ]
        ((start, end),) = intersect(*arcs)
        return float(np.degrees(start)), float(np.degrees(end))

    assert common("desired_motion_deg") == pytest.approx((103, 165), abs=1.0)
    assert common("contacts_kept_deg") == pytest.approx((78, 150), abs=1.0)
    assert result["safe_ranges_deg"] == [[pytest.approx(103, abs=1.0), pytest.approx(150, abs=1.0)]]
    assert result["safe_ranges_deg"][0] == pytest.approx([102.96, 149.31], abs=0.01)
