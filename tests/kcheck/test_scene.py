"""Scene loading: SI conversion, planar/spatial detection, and a clear error for bad input."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from kcheck.errors import SceneError
from kcheck.scene import load_scene, scene_json_schema
from tests.conftest import FIXTURES, PLANAR_SCENE


def test_planar_scene_in_si(write_scene):
    scene = load_scene(write_scene(PLANAR_SCENE))
    assert scene.kind == "planar" and scene.dim == 2
    np.testing.assert_allclose(scene.supports[0].position, [0.02, 0, 0])
    assert scene.supports[2].friction == 0.1
    assert scene.body.explicit.mass == 1
    np.testing.assert_allclose(scene.body.explicit.center_of_mass, [0.05, 0.03, 0])
    np.testing.assert_allclose(scene.load.direction, [-np.sqrt(0.5), -np.sqrt(0.5), 0])
    assert scene.design_angle_deg == pytest.approx(225)


def test_spatial_fixture_and_per_support_friction(write_scene):
    scene = load_scene(FIXTURES / "block-321" / "block.kcheck.yaml")
    assert scene.kind == "spatial" and len(scene.supports) == 6
    assert scene.body.parts[0].density == 2700
    text = PLANAR_SCENE.replace("normal: [1, 0, 0]}", "normal: [2, 0, 0], friction: 0.3}")
    scene = load_scene(write_scene(text))
    assert [s.friction for s in scene.supports] == [0.1, 0.1, 0.3]
    np.testing.assert_allclose(scene.supports[2].normal, [1, 0, 0])  # normalised


def _edit(old: str, new: str) -> str:
    assert old in PLANAR_SCENE, old
    return PLANAR_SCENE.replace(old, new, 1)


# Lines are 1-based; in PLANAR_SCENE line 1 is `version: 1` and line 14 `magnitude: 1`.
BAD = {
    "wrong type": (
        _edit("magnitude: 1", "magnitude: strong"),
        "load.magnitude",
        14,
        "expected a number, got 'strong'",
    ),
    "negative": (_edit("magnitude: 1", "magnitude: -1"), "load.magnitude", 14, "0 ≤ magnitude"),
    "missing": (_edit("version: 1\n", ""), "version", 1, "missing"),
    "typo": (_edit("friction: 0.1", "fricton: 0.1"), "fricton", 12, "unknown field"),
    "short vector": (
        _edit("position: [20, 0, 0]", "position: [20, 0]"),
        "supports[0].position",
        9,
        "3 numbers",
    ),
    "units": (
        _edit("units: mm", "units: furlong"),
        "units",
        3,
        "expected one of 'm', 'cm', 'mm', 'um', 'in', got 'furlong'",
    ),
    "version": (_edit("version: 1", "version: 2"), "version", 1, "expected 1, got 2"),
    "zero normal": (
        _edit("normal: [1, 0, 0]", "normal: [0, 0, 0]"),
        "supports[2].normal",
        11,
        "non-zero",
    ),
    "planar normal out of plane": (
        _edit("normal: [1, 0, 0]", "normal: [1, 0, 1]"),
        "supports[2].normal",
        11,
        "xy-plane",
    ),
    "planar z differs": (_edit("[0, 30, 0]", "[0, 30, 5]"), "supports", 8, "same z"),
    "four supports": (
        _edit(
            "friction: 0.1",
            "  - {name: x2, position: [0, 50, 0], normal: [1, 0, 0]}\nfriction: 0.1",
        ),
        "supports",
        8,
        "3 supports (planar) or 6",
    ),
    "duplicate name": (_edit("name: y2", "name: y1"), "supports[1].name", 10, "used twice"),
    "direction and angle": (
        _edit("angle: 225", "angle: 225\n  direction: [1, 0, 0]"),
        "load",
        13,
        "not both",
    ),
    "partial explicit": (_edit("  inertia: 0.001\n", ""), "body.inertia", 4, "together"),
    "duplicate key": (
        _edit("friction: 0.1", "friction: 0.1\nfriction: 0.2"),
        "friction",
        13,
        "duplicate",
    ),
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_input_names_file_field_and_line(write_scene, name):
    text, field, line, fragment = BAD[name]
    path = write_scene(text)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    err = info.value
    assert err.path == str(path)
    assert err.field == field
    assert err.line == line
    assert fragment in err.message
    assert str(path) in str(err) and f"`{field}`" in str(err)


def test_unknown_material_is_named(write_scene, tmp_path):
    (tmp_path / "m.stl").write_text("solid x\nendsolid x\n")
    text = _edit(
        "  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n",
        "  mesh: m.stl\n  material: unobtainium\n",
    )
    with pytest.raises(SceneError) as info:
        load_scene(write_scene(text))
    assert info.value.field == "body.material" and "unobtainium" in info.value.message
    assert "aluminium" in info.value.message  # lists what is known


def test_mesh_may_not_leave_the_folder(write_scene, tmp_path):
    outside = tmp_path.parent / f"{tmp_path.name}-outside.stl"
    outside.write_text("solid x\nendsolid x\n")
    text = _edit(
        "  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n",
        f"  mesh: ../{outside.name}\n  density: 1000\n",
    )
    path = write_scene(text)
    with pytest.raises(SceneError, match="leaves the scene's folder"):
        load_scene(path)
    assert load_scene(path, allow_outside=True).body.parts[0].mesh == outside.resolve()


def test_mesh_without_density_is_refused(write_scene, tmp_path):
    (tmp_path / "m.stl").write_text("solid x\nendsolid x\n")
    text = _edit("  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n", "  mesh: m.stl\n")
    with pytest.raises(SceneError, match="trimesh would assume 1"):
        load_scene(write_scene(text))


def test_spatial_needs_full_inertia(write_scene):
    text = textwrap.dedent(
        """
        version: 1
        body: {mass: 1, center_of_mass: [0, 0, 0], inertia: 0.1}
        supports:
        """
    ) + "".join(f"  - {{name: s{i}, position: [{i}, 0, 0], normal: [0, 0, 1]}}\n" for i in range(6))
    with pytest.raises(SceneError) as info:
        load_scene(write_scene(text))
    assert info.value.field == "body.inertia" and "3x3" in info.value.message


@pytest.mark.parametrize(
    ("tensor", "fragment"),
    [
        ("[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]", "symmetric"),
        ("[[1, 0, 0], [0, -1, 0], [0, 0, 1]]", "positive definite"),
        ("[[1, 0, 0], [0, 1, 0], [0, 0, 5]]", "triangle inequality"),
    ],
)
def test_inertia_must_be_physical(write_scene, tensor, fragment):
    text = _edit("inertia: 0.001", f"inertia: {tensor}")
    with pytest.raises(SceneError, match=fragment):
        load_scene(write_scene(text))


def test_schema_is_draft07_and_lists_fields():
    schema = scene_json_schema()
    assert schema["$schema"].startswith("http://json-schema.org/draft-07")
    assert {"version", "supports", "body", "load", "sweep"} <= set(schema["properties"])
    assert "$defs" not in schema and "SupportModel" in schema["definitions"]
    assert schema["additionalProperties"] is False


def test_shipped_schema_is_current():
    # docs/kcheck-scene.schema.json is what editors point at; regenerate with
    # `kcheck schema > docs/kcheck-scene.schema.json` when the format changes.
    import json

    from tests.conftest import ROOT

    shipped = json.loads((ROOT / "docs" / "kcheck-scene.schema.json").read_text())
    assert shipped == scene_json_schema()


def test_sweep_third_axis_is_np_cross(tmp_path):
    """A scene's sweep ``e2`` (``normal x e1``, written out in the loader) is ``np.cross``'s,
    bit for bit, for the default sweep and given zero directions (either normal sense)."""
    rng = np.random.default_rng(5)
    texts = [PLANAR_SCENE]
    texts += [
        PLANAR_SCENE.replace("version: 1", f"version: 1\nsweep: {{normal: {n}, zero: {z}}}")
        for n, z in [
            ("[0, 0, 1]", "[1, 0.3, 0]"),
            ("[0, 0, -1]", "[-0.2, 1, 0]"),
            ("[0, 0, 1]", str(rng.normal(size=2).round(6).tolist() + [0.0])),
        ]
    ]
    for k, text in enumerate(texts):
        path = tmp_path / f"s{k}.kcheck.yaml"
        path.write_text(text)
        sweep = load_scene(path).sweep
        assert sweep.e2.tobytes() == np.cross(sweep.normal, sweep.e1).tobytes()
