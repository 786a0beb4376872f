"""Friction in scene files: a number, a range ``{min, max}`` or ``{static, kinetic}`` (each a
number or a range), per scene, support and coupling; located errors; ``tolerances:``."""

from __future__ import annotations

import pytest

from kcheck.errors import SceneErrors
from kcheck.scene import Friction, load_scene, scene_json_schema
from tests.conftest import FIXTURES, PLANAR_SCENE

GROOVE = (FIXTURES / "three-groove-beta-35" / "coupling.kcheck.yaml").read_text()


def _edit(old: str, new: str, text: str = PLANAR_SCENE) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def test_the_three_forms_per_scene_and_support(write_scene):
    text = _edit("friction: 0.1", "friction: {min: 0.1, max: 0.3}")
    text = _edit(
        "normal: [0, 1, 0]}",
        "normal: [0, 1, 0], friction: {static: 0.25, kinetic: {min: 0.1, max: 0.2}}}",
        text,
    )
    text = _edit("normal: [1, 0, 0]}", "normal: [1, 0, 0], friction: 0.05}", text)
    scene = load_scene(write_scene(text))
    y1, y2, x1 = scene.supports
    assert y1.coefficients == Friction((0.25, 0.25), (0.1, 0.2))
    assert y2.coefficients == Friction((0.1, 0.3), (0.1, 0.3))  # the scene's range
    assert x1.coefficients == Friction.of(0.05) and x1.friction_spec is None
    # `friction` is the largest coefficient a support may have
    assert [s.friction for s in scene.supports] == [0.25, 0.3, 0.05]
    low, high = scene.friction_range("kinetic")
    assert low.tolist() == [0.1, 0.1, 0.05] and high.tolist() == [0.2, 0.3, 0.05]
    low, high = scene.friction_range("static")
    assert low.tolist() == [0.25, 0.1, 0.05] and high.tolist() == [0.25, 0.3, 0.05]
    # JSON: the ranges appear only where friction is more than one number
    assert y1.to_json()["friction_static"] == [0.25, 0.25]
    assert y1.to_json()["friction_kinetic"] == [0.1, 0.2]
    assert "friction_static" not in x1.to_json()


def test_coupling_friction_forms_reach_their_supports(write_scene):
    text = _edit("friction: 0.1", "friction: {min: 0.1, max: 0.3}", GROOVE)
    text = _edit(
        "name: g2, type: ball-vee,",
        "name: g2, type: ball-vee, friction: {static: 0.2, kinetic: 0.15},",
        text,
    )
    scene = load_scene(write_scene(text))
    by_name = {s.name: s.coefficients for s in scene.supports}
    assert by_name["g1.1"] == by_name["g3.2"] == Friction((0.1, 0.3), (0.1, 0.3))
    assert by_name["g2.1"] == by_name["g2.2"] == Friction((0.2, 0.2), (0.15, 0.15))


BAD = {
    "min above max": (
        "friction: {min: 0.3, max: 0.1}",
        "friction",
        "min ≤ max, got min 0.3 > max 0.1",
    ),
    "static below kinetic": (
        "friction: {static: 0.1, kinetic: 0.2}",
        "friction",
        "static 0.1 below kinetic 0.2; swap them?",
    ),
    "static range below kinetic": (
        "friction: {static: {min: 0.1, max: 0.3}, kinetic: 0.2}",
        "friction",
        "static 0.1–0.3 below kinetic 0.2",
    ),
    "nested out of range": (
        "friction: {static: 0.2, kinetic: {min: -1, max: 0.1}}",
        "friction.kinetic.min",
        "expected 0 ≤ min ≤ 100, got -1",
    ),
    "number out of range": ("friction: -0.2", "friction", "0 ≤ friction ≤ 100"),
    "max missing": ("friction: {min: 0.1}", "friction.max", "required field is missing"),
    "half a pair": ("friction: {static: 0.2}", "friction.kinetic", "required field is missing"),
    "unknown key in a range": (
        "friction: {min: 0.1, max: 0.2, mean: 0.15}",
        "friction.mean",
        "unknown field",
    ),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_friction_is_a_located_error(write_scene, name):
    new, field, words = BAD[name]
    path = write_scene(_edit("friction: 0.1", new))
    with pytest.raises(SceneErrors) as info:
        load_scene(path)
    errors = info.value.all()
    match = [e for e in errors if e.field == field]
    assert match, [str(e) for e in errors]
    assert words in match[0].message
    assert match[0].line == 12  # the scene's `friction:` line


def test_bad_support_friction_names_the_support(write_scene):
    text = _edit("normal: [1, 0, 0]}", "normal: [1, 0, 0], friction: {min: 0.5, max: 0.4}}")
    with pytest.raises(SceneErrors) as info:
        load_scene(write_scene(text))
    (error,) = info.value.all()
    assert error.field == "supports[2].friction" and error.line == 11


def test_tolerances_in_scene_units(write_scene):
    text = PLANAR_SCENE + "tolerances: {position: 0.05, normal: 0.5, load_direction: 1}\n"
    scene = load_scene(write_scene(text))
    assert scene.tolerances is not None
    assert scene.tolerances.position == pytest.approx(5e-5)  # 0.05 mm in m
    assert (scene.tolerances.normal_deg, scene.tolerances.load_direction_deg) == (0.5, 1)
    assert load_scene(write_scene(PLANAR_SCENE)).tolerances is None
    for bad, field, words in [
        ("{position: 2000}", "tolerances.position", "± position ≤ 1 m, got 2000 (2 m)"),
        ("{normal: 45}", "tolerances.normal", "0 ≤ normal ≤ 30 deg, got 45"),
    ]:
        with pytest.raises(SceneErrors) as info:
            load_scene(write_scene(PLANAR_SCENE + f"tolerances: {bad}\n"))
        (error,) = info.value.all()
        assert error.field == field and words in error.message, str(error)


def test_schema_has_the_new_forms():
    schema = scene_json_schema()
    definitions = schema["definitions"]
    assert {"FrictionRangeModel", "FrictionPairModel", "TolerancesModel"} <= set(definitions)
    forms = schema["properties"]["friction"]["oneOf"]
    assert {"type": "number", "minimum": 0.0, "maximum": 100.0}.items() <= forms[0].items()
    assert [f.get("$ref") for f in forms[1:]] == [
        "#/definitions/FrictionRangeModel",
        "#/definitions/FrictionPairModel",
    ]


def test_expand_writes_the_forms_back(cli, write_scene, tmp_path):
    text = _edit("friction: 0.1", "friction: {min: 0.1, max: 0.3}", GROOVE)
    text = _edit(
        "name: g2, type: ball-vee,",
        "name: g2, type: ball-vee, friction: {static: 0.2, kinetic: {min: 0.1, max: 0.15}},",
        text,
    )
    original = write_scene(text)
    code, out, err = cli("expand", str(original))
    assert code == 0, err
    assert "friction: {static: 0.2, kinetic: {min: 0.1, max: 0.15}}" in out
    expanded = write_scene(out, "expanded.kcheck.yaml")
    a, b = load_scene(original), load_scene(expanded)
    assert [s.coefficients for s in a.supports] == [s.coefficients for s in b.supports]
