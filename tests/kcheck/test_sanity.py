"""Sanity warnings: every bundled fixture is warning-free and keeps its verdict; a units slip,
reversed normals and a part in the wrong unit each give a warning naming the culprit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from kcheck.analysis.sanity import body_box
from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import MassProperties, Status
from tests.conftest import FIXTURES, PLANAR_SCENE

# The verdict each fixture is meant to have (some thesis fixtures fail on purpose: see their
# comments and docs/validation.md).
VERDICTS = {
    "block-321": "pass",
    "block-321-balls": "pass",
    "kelvin": "pass",
    "aspe-kc-design-script": "pass",
    "mostly-printed-probe": "warn",  # only maxwell: its inclined pin pairs give cos θ 0.50
    "maxwell-three-vee": "pass",
    "planar-block": "pass",
    "thesis-appendix-a": "fail",
    "thesis-block-4-2": "pass",
    "thesis-block-5-2": "pass",
    "thesis-potato": "warn",  # only maxwell (severity warning) fails
    "three-groove": "pass",
    "three-groove-beta-15": "warn",  # only maxwell (|90° - 2β| = 60°): it still closes
    "three-groove-beta-25": "pass",
    "three-groove-beta-35": "pass",
    "three-groove-beta-45": "pass",
    "three-groove-beta-55": "pass",
    "three-groove-beta-65": "pass",
    "tool-changer": "pass",
    "voron-kinematic-bed": "pass",
}


@pytest.fixture(scope="module")
def checks():
    return load_checks()


def test_every_fixture_is_listed():
    assert sorted(p.parent.name for p in FIXTURES.glob("*/*.kcheck.yaml")) == sorted(VERDICTS)


@pytest.mark.parametrize("fixture", sorted(VERDICTS))
def test_fixtures_are_warning_free_and_keep_their_verdict(fixture, checks):
    path = next((FIXTURES / fixture).glob("*.kcheck.yaml"))
    result = check_scene(path, checks)
    assert result.warnings == (), [w.message for w in result.warnings]
    assert result.status.value == VERDICTS[fixture], result.error


def _box_mesh(path: Path, extents, corner=(0.0, 0.0, 0.0)) -> None:
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(np.asarray(corner, dtype=float) + np.asarray(extents) / 2)
    mesh.export(path)


def test_units_slip_names_the_supports(write_scene, tmp_path, checks):
    """The new user's scene: a 20 cm body in metres, supports typed in millimetres. Each
    support is off the body's mesh: an input error naming it, and the unit that fits."""
    _box_mesh(tmp_path / "block.stl", (0.2, 0.15, 0.085))
    text = (FIXTURES / "block-321" / "block.kcheck.yaml").read_text()
    text = text.replace("units: mm", "units: m").replace("[100, 75, 85]", "[0.1, 0.075, 0.085]")
    result = check_scene(write_scene(text), checks)
    assert result.status is Status.ERROR
    assert {e.field for e in result.errors} == {("supports", i, "position") for i in range(6)}
    x1 = next(e for e in result.errors if e.field == ("supports", 0, "position"))
    # x1 at (0, 75, 42.5) m against a 0.2 x 0.15 x 0.085 m box at the origin: the nearest
    # point is its corner (0, 0.15, 0.085), sqrt(74.85² + 42.415²) = 86.03 m away.
    assert "support `x1` is 86.03 m from the body's surface" in x1.message
    assert "scene's coordinates in mm (`units: mm` and `units: m` on the meshes)" in x1.message
    assert x1.line is not None


def test_units_slip_the_other_way(write_scene, tmp_path, checks):
    """Supports typed in metres in a millimetre scene: all within a hundredth of the body."""
    _box_mesh(tmp_path / "block.stl", (200, 150, 85))
    text = (FIXTURES / "block-321" / "block.kcheck.yaml").read_text()
    for old, new in [
        ("[0, 75, 42.5]", "[0, 0.075, 0.0425]"),
        ("[40, 0, 42.5]", "[0.04, 0, 0.0425]"),
        ("[160, 0, 42.5]", "[0.16, 0, 0.0425]"),
        ("[30, 30, 0]", "[0.03, 0.03, 0]"),
        ("[170, 30, 0]", "[0.17, 0.03, 0]"),
        ("[100, 130, 0]", "[0.1, 0.13, 0]"),
    ]:
        text = text.replace(old, new)
    result = check_scene(write_scene(text), checks)
    assert "supports-tiny" in {w.code for w in result.warnings}


def test_reversed_normals(write_scene, checks):
    """planar-block's layout with every normal pointing out of the body."""
    text = PLANAR_SCENE.replace("normal: [0, 1, 0]", "normal: [0, -1, 0]").replace(
        "normal: [1, 0, 0]", "normal: [-1, 0, 0]"
    )
    result = check_scene(write_scene(text), checks)
    codes = [w.code for w in result.warnings]
    assert codes == ["normals-reversed"]
    warning = result.warnings[0]
    assert "the support normals may be reversed" in warning.message
    assert warning.field == ("supports",) and warning.line == 8
    # The right way round: no warning.
    assert check_scene(write_scene(PLANAR_SCENE, "ok.kcheck.yaml"), checks).warnings == ()


def test_reversed_normals_of_a_spatial_coupling(write_scene, checks):
    text = (FIXTURES / "three-groove-beta-45" / "coupling.kcheck.yaml").read_text()
    text = text.replace("up: [0, 0, 1]", "up: [0, 0, -1]")  # grooves upside down
    result = check_scene(write_scene(text), checks)
    assert [w.code for w in result.warnings] == ["normals-reversed"]
    assert result.warnings[0].field == ("couplings",)


def test_part_in_cm_in_a_mm_assembly(write_scene, tmp_path, checks):
    """A base plate and a cover in mm, and a handle exported in cm (40 x 20 x 20 mm written
    as 4 x 2 x 2) but read as mm: the handle is named."""
    _box_mesh(tmp_path / "plate.stl", (100, 100, 10))
    _box_mesh(tmp_path / "cover.stl", (80, 80, 10), corner=(10, 10, 10))
    _box_mesh(tmp_path / "handle.stl", (4, 2, 2), corner=(3, 4, 2))
    text = PLANAR_SCENE.replace(
        "body:\n  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n",
        "body:\n  parts:\n    - {mesh: plate.stl, material: aluminium}\n"
        "    - {mesh: cover.stl, material: aluminium}\n"
        "    - {mesh: handle.stl, material: steel}\n",
    )
    for x, y in ((20, 0), (80, 0), (0, 30)):
        text = text.replace(f"position: [{x}, {y}, 0]", f"position: [{x}, {y}, 5]")
    result = check_scene(write_scene(text), checks)
    outliers = [w for w in result.warnings if w.code == "part-size-outlier"]
    assert [w.field for w in outliers] == [("body", "parts", 2)]
    assert "part 3 (handle.stl)" in outliers[0].message and outliers[0].line == 8
    assert "another unit than mm" in outliers[0].hint


def test_load_point_far_outside(write_scene, tmp_path, checks):
    _box_mesh(tmp_path / "block.stl", (100, 60, 10))
    text = PLANAR_SCENE.replace(
        "  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n",
        "  mesh: block.stl\n  material: aluminium\n",
    ).replace("  angle: 225\n", "  angle: 225\n  point: [5000, 30, 0]\n")
    result = check_scene(write_scene(text), checks)
    assert [w.code for w in result.warnings] == ["point-far-from-body"]
    assert result.warnings[0].field == ("load", "point")


def test_equivalent_box_of_explicit_inertia():
    """A uniform 0.2 x 0.15 x 0.085 box's inertia gives back its sides."""
    m, a, b, c = 6.0, 0.2, 0.15, 0.085
    inertia = m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    box = body_box(MassProperties(m, np.zeros(3), inertia, "explicit"))
    np.testing.assert_allclose(sorted(2 * box.half), sorted([a, b, c]), rtol=1e-12)


def test_a_planar_scene_with_i_zz_alone_is_checked_against_its_radius_of_gyration(
    write_scene, checks
):
    """A new user's planar scene typed in mm but declared `units: m` passed silently: with a
    lone I_zz there is no body box to compare the supports with. The radius of gyration is a
    size the body must reach: methods.md §7's block (1 kg, I_zz = 0.001 kg·m²) has
    sqrt(I_zz / m) = 31.62 mm; its supports span sqrt(80² + 30²) = 85.44 mm (ratio 2.7, no
    warning) — or 85.44 m when the same numbers are read in metres (ratio 2,700: warning)."""
    fine = check_scene(write_scene(PLANAR_SCENE), checks)
    assert "supports-vs-inertia" not in {w.code for w in fine.warnings}
    slip = check_scene(write_scene(PLANAR_SCENE.replace("units: mm", "units: m")), checks)
    (warning,) = [w for w in slip.warnings if w.code == "supports-vs-inertia"]
    assert "span 85.44 m" in warning.message and "is only 0.03162 m" in warning.message
    assert warning.field == ("supports",) and warning.line is not None
