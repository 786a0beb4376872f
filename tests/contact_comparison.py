"""Comparing what `kcheck contacts` finds with a hand-written scene: the scenes' point contacts
(shorthands expanded by the scene loader), each reference contact paired with the nearest
found one, and the checks' verdicts and margins of two scenes (tests/cli/test_public_couplings.py,
tests/cli/test_fixture_contacts.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from kcheck.cli import main
from kcheck.scene.load import load_scene

POINT_TOL_MM = 0.01  # issue 29: every contact within 0.01 mm
NORMAL_TOL_DEG = 0.1  # and every normal within 0.1 deg


def supports(scene_path):
    """The scene's point contacts (scene units, unit normals), shorthands expanded as kcheck
    loads them."""
    scene = load_scene(scene_path, allow_outside=True)
    return [(s.position / scene.scale, s.normal / np.linalg.norm(s.normal)) for s in scene.supports]


def matched(found, reference):
    """Each reference contact paired with the nearest found one: (distance, angle deg)."""
    out = []
    for p, n in reference:
        k = int(np.argmin([np.linalg.norm(q - p) for q, _ in found]))
        q, m = found[k]
        out.append(
            (float(np.linalg.norm(q - p)), float(np.degrees(np.arccos(np.clip(m @ n, -1.0, 1.0)))))
        )
    return out


def one_to_one(found, reference) -> bool:
    """Whether no two reference contacts have the same nearest found contact."""
    nearest = {int(np.argmin([np.linalg.norm(q - p) for q, _ in found])) for p, _ in reference}
    return len(nearest) == len(reference)


def checks(path, capsys, *extra):
    """The scene's checks (JSON results by id)."""
    assert main(["check", str(path), "--format", "json", "-j", "1", *extra]) in (0, 1)
    scene = json.loads(capsys.readouterr().out)["scenes"][0]
    return {c["id"]: c for c in scene["checks"]}


def assert_same_checks(got, want):
    """The same checks, verdicts and margins; the analytical check's margins (deg; analytical-3d
    for a spatial scene, analytical-2d for a planar one), whichever the scene's load reports."""
    assert got.keys() == want.keys()
    for check_id in want:
        assert got[check_id]["status"] == want[check_id]["status"], check_id
        # Each margin: the force-angle margin (deg), the least holding friction over the
        # design friction (jamming: the friction limit), Maxwell's least cos.
        if "margin" in want[check_id]:
            assert got[check_id]["margin"]["value"] == pytest.approx(
                want[check_id]["margin"]["value"], rel=1e-3
            ), check_id
    margins = ("design_margin_deg", "robust_margin_deg", "sweep_design_margin_deg")
    ran = "analytical-3d" if want["analytical-3d"]["status"] != "skipped" else "analytical-2d"
    reported = [k for k in margins if want[ran].get(k) is not None]
    assert reported == [k for k in margins if got[ran].get(k) is not None]
    # A spatial scene reports one always; a planar one none when no angle is safe, and then
    # the retractions' outcomes and safe ranges say it (the supports' names may differ: in
    # order of outcome and range).
    assert reported or ran == "analytical-2d", want[ran]

    def cases(result):
        out = [(c["outcome"], list(np.ravel(c["safe_ranges_deg"]))) for c in result["cases"]]
        return sorted(out, key=lambda c: (c[0], c[1]))

    if ran == "analytical-2d":
        mine, theirs = cases(got[ran]), cases(want[ran])
        assert [c[0] for c in mine] == [c[0] for c in theirs]
        for (_, a), (_, b) in zip(mine, theirs, strict=True):
            assert a == pytest.approx(b, abs=0.05)
    for key in reported:
        assert got[ran][key] == pytest.approx(want[ran][key], abs=0.05)
