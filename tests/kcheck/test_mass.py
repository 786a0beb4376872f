"""Mass properties from real mesh files through trimesh, against closed forms."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from kcheck.body.mass import body_volumes, combine, load_mesh, mesh_mass_properties
from kcheck.errors import MeshError
from kcheck.gate.runner import check_scene
from kcheck.plugin import load_checks
from kcheck.result import MassProperties

RHO = 2700.0
# Binary STL stores coordinates as float32: a relative precision of about 1e-7 per coordinate,
# so mesh-derived values agree with closed forms to about 1e-6, not to double rounding.
STL = 1e-6


def _props(tmp_path, mesh: trimesh.Trimesh, scale: float = 1.0, name: str = "m.stl"):
    path = tmp_path / name
    mesh.export(path)
    return mesh_mass_properties(load_mesh(path, scale, "mesh"), RHO, path, "mesh")


def test_box_closed_form(tmp_path):
    a, b, c = 0.2, 0.15, 0.085
    props = _props(tmp_path, trimesh.creation.box(extents=(a, b, c)))
    m = RHO * a * b * c  # closed form: m = rho a b c, I_xx = m (b^2 + c^2) / 12, ...
    assert props.mass == pytest.approx(m, rel=STL)
    expected = m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    np.testing.assert_allclose(props.inertia, expected, rtol=STL, atol=1e-12)
    np.testing.assert_allclose(props.center_of_mass, 0, atol=1e-12)


@pytest.mark.parametrize("sections", [16, 64, 256])
def test_cylinder_at_several_tessellations(tmp_path, sections):
    r, h = 0.05, 0.12
    props = _props(tmp_path, trimesh.creation.cylinder(radius=r, height=h, sections=sections))
    # Exact for the tessellated prism: a regular n-gon of circumradius r has area
    # (n/2) r^2 sin(2 pi / n).
    prism = RHO * sections / 2 * r * r * np.sin(2 * np.pi / sections) * h
    assert props.mass == pytest.approx(prism, rel=STL)
    # Against the smooth cylinder (m = rho pi r^2 h, I_zz = m r^2 / 2): the error falls as
    # (2 pi^2 / 3) / n^2 for the area; allow twice that for I_zz.
    cylinder = RHO * np.pi * r * r * h
    rel = 2 * np.pi**2 / 3 / sections**2
    assert abs(props.mass / cylinder - 1) <= 1.01 * rel
    assert abs(props.inertia[2, 2] / (cylinder * r * r / 2) - 1) <= 2.5 * rel
    i_xx = cylinder * (3 * r * r + h * h) / 12
    assert abs(props.inertia[0, 0] / i_xx - 1) <= 2.5 * rel


def test_sphere_converges(tmp_path):
    r = 0.03
    errors = []
    for subdivisions in (2, 3, 4):
        props = _props(tmp_path, trimesh.creation.icosphere(subdivisions=subdivisions, radius=r))
        m = RHO * 4 / 3 * np.pi * r**3  # closed form; I = 2/5 m r^2
        errors.append(abs(props.mass / m - 1))
        assert np.allclose(np.diag(props.inertia), 0.4 * props.mass * r * r, rtol=0.03)
    # Each subdivision halves the edge length: second-order convergence divides the error by 4.
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.5) & (ratios < 4.5)) and errors[2] < 2.5e-3


def test_units_scale_mass_by_cube_and_inertia_by_fifth_power(tmp_path):
    mesh_mm = trimesh.creation.box(extents=(200.0, 150.0, 85.0))
    mesh_m = trimesh.creation.box(extents=(0.2, 0.15, 0.085))
    in_mm = _props(tmp_path, mesh_mm, scale=1e-3, name="mm.stl")
    in_m = _props(tmp_path, mesh_m, name="m.stl")
    assert in_mm.mass == pytest.approx(in_m.mass, rel=STL)
    np.testing.assert_allclose(in_mm.inertia, in_m.inertia, rtol=STL, atol=1e-12)


def test_parallel_axis_composition(tmp_path):
    # Two boxes side by side combined by kcheck equal one box of their union (closed form).
    left = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    right = left.copy()
    right.apply_translation([0.1, 0, 0])
    whole = trimesh.creation.box(extents=(0.2, 0.1, 0.1))
    whole.apply_translation([0.05, 0, 0])
    parts = combine([_props(tmp_path, left, name="l.stl"), _props(tmp_path, right, name="r.stl")])
    one = _props(tmp_path, whole, name="w.stl")
    assert parts.mass == pytest.approx(one.mass, rel=STL)
    np.testing.assert_allclose(parts.center_of_mass, one.center_of_mass, atol=1e-9)
    np.testing.assert_allclose(parts.inertia, one.inertia, rtol=STL, atol=1e-12)


def test_rotation_keeps_principal_moments(tmp_path):
    box = trimesh.creation.box(extents=(0.3, 0.2, 0.1))
    rotated = box.copy()
    rotated.apply_transform(trimesh.transformations.random_rotation_matrix(np.random.rand(3)))
    a = np.linalg.eigvalsh(_props(tmp_path, box, name="a.stl").inertia)
    b = np.linalg.eigvalsh(_props(tmp_path, rotated, name="b.stl").inertia)
    np.testing.assert_allclose(a, b, rtol=STL)


def test_disconnected_bodies_are_combined_and_reported(tmp_path):
    a = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    b = a.copy()
    b.apply_translation([1, 0, 0])
    props = _props(tmp_path, trimesh.util.concatenate([a, b]))
    assert props.mass == pytest.approx(2 * RHO * 1e-3, rel=STL)
    assert props.center_of_mass[0] == pytest.approx(0.5, rel=STL)
    assert any("2 disconnected closed bodies" in n for n in props.notes)


def test_a_scene_file_of_moved_parts_is_baked_with_its_transforms(tmp_path):
    """A glTF file whose two boxes are placed by node transforms (not in their vertices) is
    read as one mesh with the transforms applied; a lone unmoved mesh (an STL) is taken as
    it is. Closed form: two 0.1 m cubes at x = 0 and x = 0.3, centre of mass at x = 0.15."""
    scene = trimesh.Scene()
    cube = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    scene.add_geometry(cube, node_name="a")
    scene.add_geometry(
        cube, node_name="b", transform=trimesh.transformations.translation_matrix([0.3, 0, 0])
    )
    path = tmp_path / "two.glb"
    scene.export(path)
    props = mesh_mass_properties(load_mesh(path, 1.0, "mesh"), RHO, path, "mesh")
    assert props.mass == pytest.approx(2 * RHO * 1e-3, rel=STL)  # float32 in the file
    np.testing.assert_allclose(props.center_of_mass, [0.15, 0, 0], atol=1e-7)


def test_body_volumes_match_trimesh_split(tmp_path):
    """Per-body signed volumes from face labels equal those of the meshes ``split`` builds
    (an independent computation in trimesh), cavity included."""
    outer = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    cavity = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    cavity.invert()
    apart = trimesh.creation.icosphere(2, radius=0.05)
    apart.apply_translation([1, 0, 0])
    mesh = trimesh.util.concatenate([outer, cavity, apart])
    expected = sorted(b.volume for b in mesh.split(only_watertight=False))
    np.testing.assert_allclose(sorted(body_volumes(mesh)), expected, rtol=1e-12)


def test_hollow_body_keeps_its_cavity(tmp_path):
    outer = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    cavity = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    cavity.invert()  # an inward-wound shell: a cavity, which validate=True would fill
    props = _props(tmp_path, trimesh.util.concatenate([outer, cavity]))
    assert props.mass == pytest.approx(RHO * (0.008 - 0.001), rel=STL)
    assert any("cavities" in n for n in props.notes)


@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda: _inverted(), "inverted"),
        (lambda: _open(), "not watertight"),
        (lambda: _flat(), "no volume"),
    ],
)
def test_bad_meshes_are_refused(tmp_path, make, fragment):
    with pytest.raises(MeshError, match=fragment):
        _props(tmp_path, make())


def _inverted() -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    mesh.invert()
    return mesh


def _open() -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=(0.1, 0.1, 0.1))
    return trimesh.Trimesh(mesh.vertices, mesh.faces[:-1], process=False)


def _flat() -> trimesh.Trimesh:
    # Two triangles back to back: closed, consistent, but encloses nothing.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    return trimesh.Trimesh(v, [[0, 1, 2], [0, 2, 1]], process=False)


def test_empty_and_unreadable_files(tmp_path):
    empty = tmp_path / "e.stl"
    empty.write_text("solid e\nendsolid e\n")
    with pytest.raises(MeshError, match="empty"):
        load_mesh(empty, 1.0, "mesh")
    junk = tmp_path / "j.obj"
    junk.write_text("this is not a mesh\n")
    with pytest.raises(MeshError):
        load_mesh(junk, 1.0, "mesh")


def test_explicit_values_win_over_the_mesh(write_scene, tmp_path):
    box = trimesh.creation.box(extents=(100.0, 60.0, 20.0))
    box.apply_translation((50, 30, 0))  # the supports on its faces (checked against the mesh)
    box.export(tmp_path / "b.stl")
    path = write_scene(
        """
        version: 1
        units: mm
        body: {mesh: b.stl, material: steel, mass: 2, center_of_mass: [1, 2, 0], inertia: 0.01}
        supports:
          - {name: a, position: [0, 0, 0], normal: [0, 1, 0]}
          - {name: b, position: [10, 0, 0], normal: [0, 1, 0]}
          - {name: c, position: [0, 5, 0], normal: [1, 0, 0]}
        load: {magnitude: 1, angle: 225}
        """
    )
    result = check_scene(path, load_checks())
    assert result.mass_properties.source == "explicit" and result.mass_properties.mass == 2
    assert any("win over the mesh" in n for n in result.notes)


def test_mass_properties_json_form():
    props = MassProperties(2.0, np.zeros(3), np.eye(3), "mesh", 1e-3, ("n",))
    doc = json.loads(json.dumps(props.to_json()))
    assert doc["mass"] == 2.0 and doc["source"] == "mesh" and doc["inertia"][1][1] == 1.0


def test_mass_command(cli, tmp_path):
    path = tmp_path / "block.stl"
    trimesh.creation.box(extents=(200.0, 150.0, 85.0)).export(path)
    code, out, _ = cli("mass", str(path), "--units", "mm", "--material", "aluminium")
    assert code == 0
    assert "mass 6.885 kg" in out  # 2700 kg/m^3 x 0.2 x 0.15 x 0.085 m^3 = 6.885 kg
    assert "principal moments" in out
    assert "lengths in mm" in out and "kg mm^2" in out
    code, out, _ = cli("mass", str(path), "--units", "mm", "--density", "2700", "--format", "json")
    doc = json.loads(out)
    mesh = doc["meshes"][0]
    assert code == 0 and mesh["mass"] == pytest.approx(6.885)
    assert doc["units"] == {"length": "mm", "mass": "kg", "inertia": "kg mm^2"}
    # I_zz = m (a^2 + b^2) / 12 with a = 200 mm, b = 150 mm, in kg mm^2
    assert mesh["principal_moments"][2] == pytest.approx(6.885 * (200**2 + 150**2) / 12)
    np.testing.assert_allclose(mesh["bounds"], [[-100, -75, -42.5], [100, 75, 42.5]], rtol=1e-6)
    # The same in metres when asked for.
    code, out, _ = cli(
        "mass",
        str(path),
        "--units",
        "mm",
        "--density",
        "2700",
        "--report-units",
        "m",
        "--format",
        "json",
    )
    mesh = json.loads(out)["meshes"][0]
    assert mesh["principal_moments"][2] == pytest.approx(6.885 * (0.2**2 + 0.15**2) / 12)


def test_mass_command_bad_input(cli, tmp_path):
    assert cli("mass", str(tmp_path / "none.stl"), "--units", "mm", "--density", "1")[0] == 2
    path = tmp_path / "inv.stl"
    _inverted().export(path)
    code, _, err = cli("mass", str(path), "--units", "m", "--material", "steel")
    assert code == 2 and "inverted" in err and "Traceback" not in err
    code, _, err = cli("mass", str(path), "--units", "m", "--material", "cheese")
    assert code == 2 and "unknown material" in err


def test_units_are_never_guessed_from_the_file_name(tmp_path):
    # trimesh would read "in" (inches) out of this name if asked to convert units
    # (ecosystem notes, trimesh/units.py); kcheck scales by the declared unit only.
    mesh = trimesh.creation.box(extents=(100.0, 100.0, 100.0))
    props = _props(tmp_path, mesh, scale=1e-3, name="bracket_in_housing.stl")
    assert props.mass == pytest.approx(RHO * 1e-3, rel=STL)  # a 0.1 m cube
