"""Explicit mass properties in the wrong unit (issue 21): the warning names the field and the
unit it was probably typed in. References are closed forms of a uniform box (mass = volume ×
density, I_zz = m (a² + b²) / 12) and the thesis block's published values
(fixtures/thesis-block-5-2)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import trimesh

from kcheck.analysis.sanity import scene_warnings
from kcheck.body.mass import body_mass_properties
from kcheck.scene import load_scene
from kcheck.scene.materials import density_of
from tests.conftest import FIXTURES

A, B, C = 0.100, 0.060, 0.020  # m: the planar block
DENSITY = density_of("aluminium")
assert DENSITY is not None
MASS = A * B * C * DENSITY
IZZ = MASS * (A**2 + B**2) / 12

PLANAR = """
version: 1
units: mm
body:
  mesh: block.stl
{material}  mass: {mass}
  center_of_mass: {com}
  inertia: {izz}
supports:
  - {{name: y1, position: [20, 0, 10], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 10], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 10], normal: [1, 0, 0]}}
friction: 0.1
load: {{magnitude: 1, angle: 225}}
"""


def _warnings(folder: Path, material: bool = True, **values: object):
    box = trimesh.creation.box(extents=(100, 60, 20))
    box.apply_translation((50, 30, 10))
    box.export(folder / "block.stl")
    fields = {"mass": MASS, "com": "[50, 30, 10]", "izz": IZZ, **values}
    text = PLANAR.format(material="  material: aluminium\n" if material else "", **fields)
    path = folder / "s.kcheck.yaml"
    path.write_text(textwrap.dedent(text).lstrip())
    scene = load_scene(path)
    assert scene.body is not None
    return scene_warnings(scene, body_mass_properties(scene.body))


def _codes(warnings) -> dict[str, object]:
    return {w.code: w for w in warnings}


def test_right_values_give_no_unit_warning(tmp_path):
    assert not _warnings(tmp_path)


def test_mass_in_grams(tmp_path):
    (w,) = _warnings(tmp_path, mass=MASS * 1e3)
    assert w.code == "mass-units" and w.field == ("body", "mass")
    assert "typed in g?" in w.hint and f"{MASS:.4g}" in w.hint


def test_inertia_in_kg_mm2(tmp_path):
    (w,) = _warnings(tmp_path, izz=IZZ * 1e6)
    assert w.code == "inertia-units" and w.field == ("body", "inertia")
    assert "kg·mm²" in w.hint and "I_zz" in w.message


def test_inertia_in_g_mm2_without_a_density(tmp_path):
    """Without `material` only the radius of gyration is compared: I / m, density-free."""
    (w,) = _warnings(tmp_path, material=False, izz=IZZ * 1e9)
    assert w.code == "inertia-units" and "g·mm²" in w.hint


def test_centre_of_mass_in_metres_in_a_mm_scene(tmp_path):
    w = _codes(_warnings(tmp_path, com="[0.05, 0.03, 0.01]"))["center-of-mass-units"]
    assert w.field == ("body", "center_of_mass") and "typed in m?" in w.hint


def test_a_density_off_by_less_than_a_unit_is_no_slip(tmp_path):
    """A hollow part (a third of the mesh's mass) is not a unit mix-up."""
    assert not _warnings(tmp_path, mass=MASS / 3, izz=IZZ / 3)


def _block_5_2(tmp_path: Path, old: str, new: str):
    text = (FIXTURES / "thesis-block-5-2" / "block.kcheck.yaml").read_text()
    assert old in text
    path = tmp_path / "b.kcheck.yaml"
    path.write_text(text.replace(old, new))
    scene = load_scene(path)
    assert scene.body is not None
    return scene_warnings(scene, body_mass_properties(scene.body))


INERTIA_5_2 = "inertia: [[17.4e-3, 0, 0], [0, 27.8e-3, 0], [0, 0, 36.8e-3]]"


def test_without_a_mesh_the_inertia_slip_is_told_from_a_mass_slip(tmp_path):
    """The thesis block (6.948 kg, no mesh): its inertia typed in kg·mm² is named as the
    inertia; its mass typed in g as the mass. Each moves the radius of gyration and the
    equivalent box's density differently, so the two are not confused."""
    assert not _block_5_2(tmp_path, "mass: 6.948", "mass: 6.948")
    inertia = _block_5_2(
        tmp_path, INERTIA_5_2, "inertia: [[17.4e3, 0, 0], [0, 27.8e3, 0], [0, 0, 36.8e3]]"
    )
    assert [w.code for w in inertia] == ["inertia-units"]
    assert "kg·mm²" in (inertia[0].hint or "")
    mass = _block_5_2(tmp_path, "mass: 6.948", "mass: 6948")
    assert [w.code for w in mass] == ["mass-units"]
    assert "typed in g?" in (mass[0].hint or "") and "6.948" in (mass[0].hint or "")


def test_without_a_mesh_a_far_centre_of_mass_in_another_unit(tmp_path):
    """The thesis block's centre of mass typed in µm (95.94 mm = 95940 µm) in a mm scene."""
    found = _block_5_2(
        tmp_path, "center_of_mass: [95.94, 70.50, 37.41]", "center_of_mass: [95940, 70500, 37410]"
    )
    w = _codes(found)["center-of-mass-units"]
    assert "typed in um?" in (w.hint or "")


def test_the_fixtures_have_no_unit_warning():
    """Every bundled fixture with explicit values (thesis blocks, the potato, the grooves)."""
    for path in sorted(FIXTURES.glob("*/*.kcheck.yaml")):
        scene = load_scene(path)
        if scene.body is None or scene.body.explicit is None:
            continue
        codes = {w.code for w in scene_warnings(scene, body_mass_properties(scene.body))}
        assert not codes & {"mass-units", "inertia-units", "center-of-mass-units"}, path
        assert np.isfinite(scene.body.explicit.mass)
