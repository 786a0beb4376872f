"""Assemblies as CAD exports them: parts with their own units and transforms, point masses,
preloads, STEP files, vertex merging, open meshes located, opt-in repair."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

from kcheck.body.mass import body_mass_properties, load_mesh, mesh_mass_properties, step_length_unit
from kcheck.errors import MeshError, SceneError
from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.scene import load_scene
from tests.conftest import FIXTURES

STL = 1e-6  # float32 coordinates in binary STL
SIX = "".join(
    f"  - {{name: s{i}, position: [{x}, {y}, 0], normal: [0, 0, 1]}}\n"
    for i, (x, y) in enumerate([(0, 0), (100, 0), (0, 50), (10, 10), (90, 10), (50, 45)])
)


def _scene(write_scene, body: str, extra: str = "") -> Path:
    return write_scene(f"version: 1\nunits: mm\nbody:\n{body}supports:\n{SIX}{extra}")


def _box(path: Path, extents, corner=(0.0, 0.0, 0.0)) -> None:
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(np.asarray(corner) + np.asarray(extents) / 2)
    mesh.export(path)


def test_parts_units_transform_and_point_masses_against_closed_form(write_scene, tmp_path):
    """A 100 x 60 x 20 mm steel box (in mm), a 2 x 2 x 2 cm steel cube (in cm, rotated 90 deg
    about z and moved), and a 0.5 kg point mass: mass, centre of mass and the inertia by the
    parallel-axis theorem written out by hand."""
    _box(tmp_path / "plate.stl", (100, 60, 20))
    _box(tmp_path / "cube.stl", (2, 2, 2), corner=(-1, -1, -1))  # cm, centred on its origin
    body = (
        "  parts:\n"
        "    - {mesh: plate.stl, material: steel}\n"
        "    - {mesh: cube.stl, material: steel, units: cm,\n"
        "       transform: {rotate: {axis: [0, 0, 1], angle: 90}, translate: [50, 30, 30]}}\n"
        "  point_masses: [{name: magnet, mass: 0.5, point: [0, 0, 10]}]\n"
    )
    scene = load_scene(_scene(write_scene, body))
    cube_part = scene.body.parts[1]
    assert cube_part.scale == 0.01 and cube_part.units == "cm"
    assert cube_part.translation == pytest.approx((0.05, 0.03, 0.03))
    props = body_mass_properties(scene.body)

    rho = 7850.0
    m1, c1 = rho * 0.1 * 0.06 * 0.02, np.array([0.05, 0.03, 0.01])
    i1 = m1 / 12 * np.diag([0.06**2 + 0.02**2, 0.1**2 + 0.02**2, 0.1**2 + 0.06**2])
    m2, c2 = rho * 0.02**3, np.array([0.05, 0.03, 0.03])
    i2 = m2 * 0.02**2 / 6 * np.eye(3)  # a cube is isotropic: rotation changes nothing
    m3, c3 = 0.5, np.array([0.0, 0.0, 0.01])
    mass = m1 + m2 + m3
    com = (m1 * c1 + m2 * c2 + m3 * c3) / mass
    inertia = i1 + i2
    for m, c in ((m1, c1), (m2, c2), (m3, c3)):
        r = c - com
        inertia = inertia + m * (r @ r * np.eye(3) - np.outer(r, r))
    assert props.mass == pytest.approx(mass, rel=STL)
    np.testing.assert_allclose(props.center_of_mass, com, rtol=STL, atol=1e-9)
    np.testing.assert_allclose(props.inertia, inertia, rtol=1e-5, atol=1e-10)
    np.testing.assert_allclose(props.bounds, [[0, 0, 0], [0.1, 0.06, 0.04]], atol=1e-8)
    assert any("point mass" in n for n in props.notes)


def test_rotation_matrix_moves_inertia(write_scene, tmp_path):
    """A 100 x 20 x 10 mm bar rotated 90 deg about z by a matrix: I_xx and I_yy swap."""
    _box(tmp_path / "bar.stl", (100, 20, 10), corner=(-50, -10, -5))
    body = (
        "  parts:\n    - {mesh: bar.stl, density: 1000, transform: {rotate: "
        "[[0, -1, 0], [1, 0, 0], [0, 0, 1]]}}\n"
    )
    props = body_mass_properties(load_scene(_scene(write_scene, body)).body)
    m = 1000 * 0.1 * 0.02 * 0.01
    expected = m / 12 * np.diag([0.1**2 + 0.01**2, 0.02**2 + 0.01**2, 0.1**2 + 0.02**2])
    np.testing.assert_allclose(props.inertia, expected, rtol=1e-5, atol=1e-12)


def test_tool_changer_fixture_turns_its_plate_over():
    scene = load_scene(FIXTURES / "tool-changer" / "tool.kcheck.yaml")
    props = body_mass_properties(scene.body)
    # The plate was exported upside down (z -11 .. -5 mm); rotated about x it rests on the
    # balls' tops (z 5 .. 11 mm).
    plate = props.part_bounds[0]
    np.testing.assert_allclose(plate[:, 2], [0.005, 0.011], atol=1e-9)
    assert [p.name for p in scene.preloads] == ["magnet"]
    np.testing.assert_allclose(scene.preloads[0].force, [0, 0, -40])
    np.testing.assert_allclose(scene.preloads[0].point, [0, 0, 0.005])


def test_preloads_are_validated(write_scene):
    body = "  mass: 1\n  center_of_mass: [0, 0, 0]\n  inertia: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n"
    for preload, fragment in [
        ("[{name: a, point: [0, 0, 0], force: [0, 0, .inf]}]", "finite"),
        ("[{name: a, point: [0, 0, 0], force: [0, 0, 1e9]}]", "1e+07 N"),
        (
            "[{name: a, point: [0, 0, 0], force: [0, 0, 1]}, {name: a, point: [0, 0, 0], "
            "force: [0, 0, 1]}]",
            "used twice",
        ),
    ]:
        with pytest.raises(SceneError) as info:
            load_scene(_scene(write_scene, body, f"preloads: {preload}\n"))
        assert any(
            fragment in e.message and e.field.startswith("preloads") for e in info.value.all()
        ), str(info.value)


# --- meshes ---------------------------------------------------------------------------------


def _open_box(path: Path) -> None:
    """A 100 mm cube with one face (two triangles) missing: a hole of 100 mm at x = 100."""
    mesh = trimesh.creation.box(extents=(100, 100, 100))
    mesh.apply_translation([50, 50, 50])
    keep = [i for i, n in enumerate(mesh.face_normals) if not np.allclose(n, [1, 0, 0])]
    trimesh.Trimesh(mesh.vertices, mesh.faces[keep], process=False).export(path)


def test_open_mesh_error_says_how_many_edges_and_where(tmp_path):
    path = tmp_path / "open.stl"
    _open_box(path)
    mesh = load_mesh(path, 1e-3, "mesh")
    with pytest.raises(MeshError) as info:
        mesh_mass_properties(mesh, 2700, path, "mesh", scale=1e-3, units="mm")
    message = info.value.message
    assert "4 open edge(s) in 1 hole(s)" in message
    assert "centred at (100, 50, 50) mm" in message and "141.4 mm across" in message
    assert "repair: true" in message


def test_repair_closes_a_small_hole_with_a_warning(write_scene, tmp_path):
    _open_box(tmp_path / "open.stl")
    body = "  mesh: open.stl\n  material: aluminium\n  repair: true\n"
    result = check_scene(_scene(write_scene, body, "load: {magnitude: 1}\n"), load_checks())
    assert result.mass_properties.mass == pytest.approx(2700 * 1e-3, rel=STL)
    assert [w.code for w in result.warnings] == ["mesh-repaired"]
    assert result.warnings[0].field == ("body", "mesh") and result.warnings[0].line == 4
    assert result.status.value != "error"
    # Without `repair` the same scene is an input error naming the hole.
    result = check_scene(
        _scene(write_scene, body.replace("  repair: true\n", ""), "load: {magnitude: 1}\n"),
        load_checks(),
    )
    assert result.status.value == "error" and "1 hole" in result.error


def test_unmerged_stl_vertices_are_merged(tmp_path):
    """An ASCII STL whose shared corners differ by noise (up to 3e-7 of the size) is not
    watertight to trimesh's own merge (1e-8 absolute); kcheck's merge at 1e-6 of the size
    closes it."""
    box = trimesh.creation.box(extents=(0.1, 0.05, 0.02))
    rng = np.random.default_rng(0)
    lines = ["solid noisy"]
    for tri in box.triangles:
        lines.append("facet normal 0 0 0\nouter loop")
        for v in tri + rng.uniform(-3e-8, 3e-8, 3):
            lines.append("vertex " + " ".join(f"{x:.17g}" for x in v))
        lines.append("endloop\nendfacet")
    lines.append("endsolid noisy")
    path = tmp_path / "noisy.stl"
    path.write_text("\n".join(lines))
    assert not trimesh.load_mesh(path).is_watertight
    props = mesh_mass_properties(load_mesh(path, 1.0, "mesh"), 1000, path, "mesh")
    assert props.mass == pytest.approx(1000 * 0.1 * 0.05 * 0.02, rel=1e-5)  # noise ~ 1e-6
    assert any("duplicate vertices merged" in n for n in props.notes)


def _generator():
    spec = importlib.util.spec_from_file_location("generate", FIXTURES / "generate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


HAVE_CASCADIO = importlib.util.find_spec("cascadio") is not None


@pytest.mark.skipif(not HAVE_CASCADIO, reason="the `step` extra (cascadio) is not installed")
@pytest.mark.parametrize(("unit", "metres"), [("mm", 1e-3), ("in", 0.0254), ("m", 1.0)])
def test_step_files_honour_their_declared_unit(write_scene, tmp_path, unit, metres):
    """A 4 x 2 x 1 box in each declared unit: OpenCASCADE converts to metres, kcheck merges
    the per-face vertices and gets the closed-form mass."""
    (tmp_path / "box.step").write_text(_generator().step_box((4.0, 2.0, 1.0), unit))
    assert step_length_unit(tmp_path / "box.step") == unit
    body = "  parts: [{mesh: box.step, density: 1000}]\n"
    scene = load_scene(_scene(write_scene, body))
    assert scene.body.parts[0].scale == 1.0
    props = body_mass_properties(scene.body)
    volume = 8.0 * metres**3
    assert props.mass == pytest.approx(1000 * volume, rel=1e-6)
    np.testing.assert_allclose(props.center_of_mass, np.array([2.0, 1.0, 0.5]) * metres, rtol=1e-6)
    assert any(f"declared unit {unit}" in n for n in props.notes)


def test_step_units_field_is_refused(write_scene, tmp_path):
    (tmp_path / "box.step").write_text(_generator().step_box((4.0, 2.0, 1.0), "mm"))
    with pytest.raises(SceneError, match="declares its own length unit"):
        load_scene(_scene(write_scene, "  parts: [{mesh: box.step, density: 1000, units: mm}]\n"))


def test_missing_step_extra_names_the_install_command(tmp_path, monkeypatch):
    import kcheck.body.meshio

    (tmp_path / "box.step").write_text(_generator().step_box((4.0, 2.0, 1.0), "mm"))
    real = importlib.util.find_spec
    monkeypatch.setattr(
        kcheck.body.meshio.importlib.util,
        "find_spec",
        lambda name: None if name == "cascadio" else real(name),
    )
    with pytest.raises(MeshError, match=r"pip install 'kcheck\[step\]'"):
        load_mesh(tmp_path / "box.step", 1.0, "mesh")


def test_rotation_angle_is_right_handed():
    from kcheck.scene.load import rotation_matrix

    r = rotation_matrix(np.array([0.0, 0.0, 1.0]), 90.0)
    np.testing.assert_allclose(r @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    assert np.linalg.det(rotation_matrix(np.array([1.0, 2, 3]) / math.sqrt(14), 33.0)) == (
        pytest.approx(1.0)
    )
