"""Supports checked against the body's mesh (issue 21): a support off the surface, or a
normal pointing out of the body, is a located input error (exit 2) naming the support and the
distance or the corrected normal, with the unit mix-up that explains it where one does; where
the mesh cannot tell, a warning. Meshes are trimesh primitives written as STL, scenes real
YAML; reference values are the boxes' own geometry."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import trimesh

from kcheck.analysis.placement import SURFACE_RTOL, support_placement
from kcheck.body.surface import (
    Surface,
    body_surface,
    closest_on_segments,
    closest_on_triangles,
    closest_point,
    inside,
    section_segments,
    winding_numbers,
)
from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import Status
from kcheck.scene import load_scene
from tests.conftest import FIXTURES

# --- the geometry, against independent computations -----------------------------------------


def test_closest_points_match_dense_sampling():
    """Closest points on random triangles against the nearest of 5,151 barycentric samples
    per triangle: never farther than the samples, and within their spacing of them."""
    rng = np.random.default_rng(7)
    triangles = rng.normal(size=(20, 3, 3))
    points = rng.normal(size=(15, 3)) * 2
    q, d, face = closest_on_triangles(triangles, points)
    n = 100
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    keep = i + j <= n
    u, v = i[keep] / n, j[keep] / n
    w = 1 - u - v
    samples = (
        u[None, :, None] * triangles[:, None, 0]
        + v[None, :, None] * triangles[:, None, 1]
        + w[None, :, None] * triangles[:, None, 2]
    ).reshape(-1, 3)
    sampled = np.linalg.norm(points[:, None] - samples[None], axis=2).min(axis=1)
    longest = np.linalg.norm(triangles - np.roll(triangles, 1, axis=1), axis=2).max()
    assert np.all(d <= sampled + 1e-12)
    assert np.all(sampled - d <= longest / n)
    assert np.allclose(np.linalg.norm(q - points, axis=1), d)


def test_winding_numbers_of_a_box():
    box = trimesh.creation.box(extents=(2.0, 3.0, 4.0))
    points = np.array([[0, 0, 0], [0.9, 1.4, 1.9], [1.1, 0, 0], [0, 0, 2.5], [5, 5, 5]])
    w = winding_numbers(np.asarray(box.triangles), points)
    assert np.allclose(w, [1, 1, 0, 0, 0], atol=1e-9)


def test_the_culled_queries_agree_with_the_brute_force_ones():
    """closest_point (bounding-box culling) against closest_on_triangles over every face, and
    inside (ray parity) against the winding number, on a sphere of 5,120 faces."""
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    triangles = np.asarray(sphere.triangles)
    rng = np.random.default_rng(3)
    points = rng.normal(size=(40, 3))
    points *= rng.uniform(0.5, 1.5, size=(40, 1)) / np.linalg.norm(points, axis=1, keepdims=True)
    _, fast, _ = closest_point(triangles, points)
    _, slow, _ = closest_on_triangles(triangles, points)
    np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(
        inside(triangles, points), winding_numbers(triangles, points) > 0.5
    )


def test_a_section_and_its_closest_points():
    """The section of a 2 × 3 box is its rectangle: a point 1 outside its long side is 1 from
    it, the nearest point is on the side."""
    box = trimesh.creation.box(extents=(2.0, 3.0, 4.0))
    segments = section_segments(np.asarray(box.triangles), 0.3)
    ends = segments.reshape(-1, 2)
    assert np.allclose(np.abs(ends).max(axis=0), [1.0, 1.5])
    q, d = closest_on_segments(segments, np.array([[2.0, 0.5], [0.0, 0.0]]))
    assert np.allclose(d, [1.0, 1.0]) and np.allclose(q[0], [1.0, 0.5])


# --- scenes -------------------------------------------------------------------------------

BLOCK_MM = (200.0, 150.0, 85.0)


def _block(folder: Path, name: str = "block.stl", extents=BLOCK_MM, open_top=False) -> None:
    """A box with a corner at the origin, written as STL in the file's own numbers."""
    box = trimesh.creation.box(extents=extents)
    box.apply_translation(np.asarray(extents) / 2)
    if open_top:
        keep = box.face_normals[:, 2] < 0.5
        box = trimesh.Trimesh(box.vertices, box.faces[keep], process=False)
    box.export(folder / name)


SPATIAL = """
version: 1
units: mm
body:
  parts:
    - {{mesh: block.stl, material: aluminium{mesh_units}}}
supports:
  - {{name: x1, position: [0, 75, 42.5], normal: [1, 0, 0]}}
  - {{name: y1, position: [40, 0, 42.5], normal: [0, 1, 0]}}
  - {{name: y2, position: [160, 0, 42.5], normal: [0, 1, 0]}}
  - {{name: z1, position: [30, 30, 0], normal: [0, 0, 1]}}
  - {{name: z2, position: [170, 30, 0], normal: [0, 0, 1]}}
  - {{name: z3, position: [100, 130, {z3}], normal: [0, 0, {z3n}]}}
friction: 0.11
gravity: [0, 0, -9.81]
load:
  point: [100, 75, 85]
  magnitude: 50
  direction: [-0.57, -0.82, 0.04]
"""

PLANAR = """
version: 1
units: mm
body:
  mesh: block.stl
  material: aluminium
supports:
  - name: y1
    position: [20, 0, 10]
    normal: [0, {y1n}, 0]
  - name: y2
    position: [80, 0, 10]
    normal: [0, 1, 0]
  - name: x1
    position: [0, 30, 10]
    normal: [1, 0, 0]
friction: 0.1
load:
  magnitude: 1
  angle: 225
"""


def _scene(folder: Path, text: str, **values: str) -> Path:
    defaults = {"mesh_units": "", "z3": "0", "z3n": "1", "y1n": "1"}
    path = folder / "scene.kcheck.yaml"
    path.write_text(textwrap.dedent(text.format(**{**defaults, **values})).lstrip())
    return path


def _placement(path: Path):
    scene = load_scene(path)
    assert scene.body is not None
    surface = body_surface(scene.body)
    assert surface is not None
    return support_placement(scene, surface)


def test_a_right_block_is_clean(tmp_path):
    _block(tmp_path)
    found = _placement(_scene(tmp_path, SPATIAL))
    assert not found.errors and not found.warnings


def test_one_reversed_normal_is_named_with_its_correction(tmp_path):
    """Issue 21: z3 flipped in the 3-2-1 block; y1 flipped in the planar block (checked in
    the body's section)."""
    _block(tmp_path)
    (error,) = _placement(_scene(tmp_path, SPATIAL, z3n="-1")).errors
    assert error.field == ("supports", 5, "normal") and error.code == "support-normal-outward"
    assert "`z3`" in error.message and "inward normal there is (0, 0, 1)" in error.message
    _block(tmp_path, extents=(100.0, 60.0, 20.0))
    (error,) = _placement(_scene(tmp_path, PLANAR, y1n="-1")).errors
    assert error.field == ("supports", 0, "normal")
    assert "`y1`" in error.message and "(0, 1, 0)" in error.message


def test_a_support_30_m_away_is_an_error_and_exit_2(tmp_path):
    _block(tmp_path)
    path = _scene(tmp_path, SPATIAL, z3="30000")
    (error,) = _placement(path).errors
    assert error.field == ("supports", 5, "position") and error.code == "support-off-surface"
    # 30 m above the bottom, 85 mm above the top
    assert "`z3`" in error.message and "2.992e+04 mm" in error.message
    assert error.hint is not None and "unit mix-up" not in error.hint  # one support, no slip
    result = check_scene(path, load_checks())
    assert result.status is Status.ERROR
    assert [e.field for e in result.errors] == [("supports", 5, "position")]
    z3_line = 1 + path.read_text().splitlines().index(
        "  - {name: z3, position: [100, 130, 30000], normal: [0, 0, 1]}"
    )
    assert result.errors[0].line == z3_line
    run = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert run.returncode == 2 and "Traceback" not in run.stdout + run.stderr
    assert f"scene.kcheck.yaml:{z3_line}:" in run.stdout


def test_supports_in_another_unit_get_the_unit_named(tmp_path):
    """The mesh in mm, the scene in m with its coordinates written in mm: every support is
    hundreds of metres off, and reading the mesh in m would put each on its surface."""
    _block(tmp_path)
    text = SPATIAL.replace("units: mm", "units: m").replace("[100, 75, 85]", "[0.1, 0.075, 0.085]")
    found = _placement(_scene(tmp_path, text, mesh_units=", units: mm"))
    assert len(found.errors) == 6
    assert all(
        e.hint is not None and "scene's coordinates in mm (`units: mm`)" in e.hint
        for e in found.errors
    )


def test_a_mesh_in_another_unit_gets_the_unit_named(tmp_path):
    """The block 1 m from the origin, its mesh declared in cm while its numbers are mm: the
    mesh is read ten times too large and ten times too far, every support off it."""
    box = trimesh.creation.box(extents=BLOCK_MM)
    box.apply_translation(np.asarray(BLOCK_MM) / 2 + [1000, 0, 0])
    box.export(tmp_path / "block.stl")
    text = SPATIAL.replace("[0, 75, 42.5]", "[1000, 75, 42.5]")
    for x in ("40", "160", "30", "170", "100"):
        text = text.replace(f"position: [{x}, ", f"position: [{1000 + float(x):g}, ")
    text = text.replace("[100, 75, 85]", "[1100, 75, 85]")
    assert not _placement(_scene(tmp_path, text)).errors  # the right unit
    found = _placement(_scene(tmp_path, text, mesh_units=", units: cm"))
    assert len(found.errors) == 6
    assert all(
        e.hint is not None and "mesh read in mm (`units: mm` on it)" in e.hint for e in found.errors
    )


def test_a_mesh_in_cm_is_suspected(tmp_path):
    """Issue 21: the block's mesh given `units: cm` leaves every support on a face through
    the origin, crowded into one corner: a warning names mm."""
    _block(tmp_path)
    found = _placement(_scene(tmp_path, SPATIAL, mesh_units=", units: cm"))
    assert not found.errors
    (warning,) = found.warnings
    assert warning.code == "mesh-units-suspect" and "`units: mm`" in (warning.hint or "")
    assert warning.field == ("body", "parts", 0, "mesh")


def test_a_support_inside_the_body_is_off_its_surface(tmp_path):
    _block(tmp_path)
    (error,) = _placement(_scene(tmp_path, SPATIAL, z3="40")).errors
    # (100, 130, 40) in a 200 × 150 × 85 box: nearest is the face y = 150, 20 mm away
    assert "inside the body" in error.message and " 20 mm " in error.message


def test_within_the_tolerance_is_on_the_surface(tmp_path):
    """A support half the tolerance off the bottom face is on it; twice it, off."""
    _block(tmp_path)
    diagonal = float(np.linalg.norm(BLOCK_MM))
    half = f"{-0.5 * SURFACE_RTOL * diagonal:.6f}"
    assert not _placement(_scene(tmp_path, SPATIAL, z3=half)).errors
    twice = f"{-2 * SURFACE_RTOL * diagonal:.6f}"
    (error,) = _placement(_scene(tmp_path, SPATIAL, z3=twice)).errors
    assert error.code == "support-off-surface"


def test_an_open_mesh_cannot_tell_a_normal(tmp_path):
    """Without a closed mesh there is no inside: a warning per support, no error."""
    _block(tmp_path)
    scene = load_scene(_scene(tmp_path, SPATIAL, z3n="-1"))
    box = trimesh.creation.box(extents=BLOCK_MM)
    box.apply_translation(np.asarray(BLOCK_MM) / 2)
    keep = box.face_normals[:, 0] > -0.5  # the x = 0 face removed
    triangles = np.asarray(box.vertices)[box.faces[keep]] * 1e-3
    found = support_placement(scene, Surface(triangles, closed=False))
    assert not found.errors
    assert {w.code for w in found.warnings} == {"support-unchecked"}


@pytest.mark.parametrize(
    "fixture", sorted(FIXTURES.glob("*/*.kcheck.yaml")), ids=lambda p: p.parent.name
)
def test_every_bundled_fixture_is_clean(fixture):
    """Explicit supports, balls in grooves and balls carried by the body: none is reported."""
    scene = load_scene(fixture)
    if scene.body is None or not scene.body.parts:
        pytest.skip("no mesh")
    surface = body_surface(scene.body)
    assert surface is not None
    found = support_placement(scene, surface)
    assert not found.errors and not found.warnings


COUPLINGS = """
version: 1
units: mm
body: {mesh: plate.stl, material: aluminium}
couplings:
  - {name: t, type: ball-trihedral, ball: {center: [0, 50, 0], radius: 6}, up: [0, 0, 1],
     half_angle: 54.7356, reference: [1, 0, 0]}
  - {name: v, type: ball-vee, ball: {center: [-43.3, -25, 0], radius: 6},
     groove: {axis: [-0.866, -0.5, 0], up: [0, 0, 1], half_angle: 45}}
  - {name: f, type: ball-flat, ball: {center: [43.3, -25, 0], radius: 6}, normal: [0, 0, 1]}
friction: 0.1
gravity: [0, 0, -9.81]
"""


def test_balls_left_out_of_a_simplified_mesh_are_a_warning(tmp_path):
    """A plate mesh without its balls (the balls on the body, their centres on its lower
    face): the contacts lie up to a ball's diameter off the plate, so the mesh cannot tell.
    30 mm off is past that: an error."""
    plate = trimesh.creation.box(extents=(120, 120, 20))
    plate.apply_translation((0, 0, 10))
    plate.export(tmp_path / "plate.stl")
    path = tmp_path / "c.kcheck.yaml"
    path.write_text(textwrap.dedent(COUPLINGS).lstrip())
    found = _placement(path)
    assert not found.errors
    assert found.warnings and {w.code for w in found.warnings} == {"support-unchecked"}
    path.write_text(path.read_text().replace("[43.3, -25, 0]", "[43.3, -25, -30]"))
    found = _placement(path)
    assert {e.field for e in found.errors} == {("couplings", 2)}
