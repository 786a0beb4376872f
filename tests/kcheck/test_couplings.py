"""Coupling shorthands: each expansion against points and normals derived by hand (1e-12),
the curvatures of the touching surfaces, the loader's errors, and `kcheck expand`."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.optimize import brentq

from kcheck.errors import SceneError
from kcheck.scene import couplings, load_scene
from tests.conftest import FIXTURES

S2 = math.sqrt(0.5)
TOL = 1e-12


def _close(actual: np.ndarray, expected: Any) -> None:
    np.testing.assert_allclose(actual, expected, rtol=0, atol=TOL)


# --- expansions against hand-derived geometry ----------------------------------------------


def test_ball_vee_by_hand():
    # Groove along x, up z, flanks at 45 deg: normals (0, ±1, 1)/sqrt2; the first leans
    # towards up × axis = z × x = +y. `up` need not be perpendicular to the axis.
    c = np.array([1.0, 2.0, 3.0])
    got = couplings.ball_vee(c, 0.5, np.array([2.0, 0, 0]), np.array([0.3, 0, 1.0]), 45.0)
    for contact, n in zip(got, ([0, S2, S2], [0, -S2, S2]), strict=True):
        _close(contact.normal, n)
        _close(contact.point, c - 0.5 * np.array(n))
        assert contact.mate.radii == (math.inf, math.inf)


def test_ball_cylinders_by_hand():
    # Two pins along y at x = ±4.2, 5.6 below the ball centre; r + R = 5 + 2 = 7 (a 3-4-5
    # triangle): normals (∓4.2, 0, 5.6) / 7.
    c = np.array([0.0, 30.0, 0.0])
    pins = [
        (np.array([4.2, 0.0, -5.6]), np.array([0.0, 3.0, 0.0]), 2.0),
        (np.array([-4.2, 100.0, -5.6]), np.array([0.0, -1.0, 0.0]), 2.0),
    ]
    got = couplings.ball_cylinders(c, 5.0, pins)
    for contact, n in zip(got, ([-0.6, 0, 0.8], [0.6, 0, 0.8]), strict=True):
        _close(contact.normal, n)
        _close(contact.point, c - 5.0 * np.array(n))
        # Flat along the pin's axis (first radius, `direction`), its radius across.
        assert contact.mate.radii == (math.inf, 2.0)
        _close(abs(contact.mate.direction), [0, 1, 0])


def test_ball_spheres_by_hand():
    c = np.array([0.0, 0.0, 4.0])
    spheres = [(np.array([3.0, 0.0, 0.0]), 2.0), (np.array([0.0, -3.0, 0.0]), 2.0)]
    got = couplings.ball_spheres(c, 3.0, spheres)  # centre distances 5 = 3 + 2
    for contact, n in zip(got, ([-0.6, 0, 0.8], [0, 0.6, 0.8]), strict=True):
        _close(contact.normal, n)
        _close(contact.point, c - 3.0 * np.array(n))
        assert contact.mate.radii == (2.0, 2.0)


@pytest.mark.parametrize("kind", ["ball-trihedral", "ball-cone"])
def test_ring_of_three_by_hand(kind):
    # up z, half angle 30 deg, first contact towards +x, then 120 and 240 deg ccw about z:
    # n_k = cos30 z - sin30 (cos t_k, sin t_k, 0).
    c = np.array([1.0, -1.0, 0.5])
    function = couplings.ball_trihedral if kind == "ball-trihedral" else couplings.ball_cone
    got = function(c, 2.0, np.array([0, 0, 5.0]), 30.0, np.array([1.0, 0, 0.4]))
    for k, contact in enumerate(got):
        t = math.radians(120 * k)
        n = [-0.5 * math.cos(t), -0.5 * math.sin(t), math.sqrt(3) / 2]
        _close(contact.normal, n)
        _close(contact.point, c - 2.0 * np.array(n))


def test_ball_flat_by_hand():
    got = couplings.ball_flat(np.array([0.0, 0, 1]), 1.0, np.array([0.0, 0, -7]))
    _close(got[0].normal, [0, 0, -1])
    _close(got[0].point, [0, 0, 2])


def test_cone_curvature_by_meusnier_and_numerically():
    """The seat's circumferential radius -rho/sin(h), checked against the normal section of
    the actual cone: points P + s T + w(s) n on the cone, curvature w''(0)."""
    c, r, h = np.array([0.0, 0.0, 0.0]), 3.0, 50.0
    contact = couplings.ball_cone(c, r, np.array([0, 0, 1.0]), h, np.array([1.0, 0, 0]))[0]
    p, n, g = contact.point, contact.normal, contact.mate.direction
    rho = math.hypot(p[0], p[1])
    assert contact.mate.radii[0] == math.inf
    assert contact.mate.radii[1] == pytest.approx(-rho / math.sin(math.radians(h)), rel=1e-14)
    assert contact.mate.radii[1] == pytest.approx(-r, rel=1e-12)  # conforms with the ball

    # The cone: radius about the z axis grows along the generator g (in the rz-plane).
    slope = math.hypot(g[0], g[1]) / g[2] * np.sign(g[0])

    def cone(x: np.ndarray) -> float:
        return math.hypot(x[0], x[1]) - (rho + (x[2] - p[2]) * slope)

    tangent = np.cross(n, g)  # along the circle
    for t in (-1.0, 0.5, 2.0):  # the generator lies in the surface: zero curvature along it
        assert abs(cone(p + t * g)) < 1e-12

    def w(s: float) -> float:
        return brentq(lambda w_: cone(p + s * tangent + w_ * n), -1.0, 1.0, xtol=1e-15)

    ds = 1e-3
    kappa = (w(ds) + w(-ds) - 2 * w(0.0)) / ds**2  # > 0: bends towards the ball (concave)
    assert kappa > 0
    assert -1 / kappa == pytest.approx(contact.mate.radii[1], rel=1e-5)


def test_supports_flip_normals_with_the_ball_on_the_base():
    contacts = couplings.ball_vee(
        np.array([0.0, 0, 10]), 2.0, np.array([1.0, 0, 0]), np.array([0, 0, -1.0]), 45.0
    )
    on_body = couplings.supports(
        "v", "ball-vee", np.array([0, 0, 10.0]), 2.0, contacts, "body", 0.1, 1e-3
    )
    on_base = couplings.supports(
        "v", "ball-vee", np.array([0, 0, 10.0]), 2.0, contacts, "base", 0.1, 1e-3
    )
    assert [s.name for s in on_base] == ["v.1", "v.2"]
    for a, b in zip(on_body, on_base, strict=True):
        _close(b.normal, -a.normal)
        _close(b.position, a.position)  # the contact point does not move
        assert a.geometry.body.radii == (0.002, 0.002) and a.geometry.base.radii[0] == math.inf
        assert b.geometry.base.radii == (0.002, 0.002) and b.geometry.body.radii[0] == math.inf
    # Grooves opening downwards, ball on the base: the supports push the body upwards.
    assert all(s.normal[2] > 0 for s in on_base)


def test_unit_is_a_fixed_point():
    rng = np.random.default_rng(3)
    for v in rng.normal(size=(2000, 3)):
        n = couplings.unit(v)
        assert couplings.unit(n) is n


# --- through the loader ---------------------------------------------------------------------

COUPLED = """
version: 1
units: mm
body: {mass: 1, center_of_mass: [0, 0, 10], inertia: [[1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]]}
couplings:
  - {name: a, type: ball-vee, ball: {center: [0, 50, 0], radius: 6},
     groove: {axis: [0, 1, 0], up: [0, 0, 1], half_angle: 45}, friction: 0.2}
  - {name: b, type: ball-sphere, ball: {center: [-40, -25, 0], radius: 6},
     spheres: [{center: [-40, -25, -10], radius: 4}]}
  - {name: c, type: ball-cone, ball: {center: [40, -25, 0], radius: 6}, up: [0, 0, 1],
     half_angle: 45}
friction: 0.1
load: {magnitude: 10, direction: [0, 0, -1]}
"""


def test_loader_expands_in_si_with_names_and_provenance(write_scene):
    scene = load_scene(write_scene(COUPLED))
    assert [s.name for s in scene.supports] == ["a.1", "a.2", "b.1", "c.1", "c.2", "c.3"]
    assert scene.kind == "spatial"
    a1 = scene.supports[0]
    _close(a1.normal, [-S2, 0, S2])  # up × axis = z × y = -x
    _close(a1.position, (np.array([0, 50, 0]) - 6 * np.array([-S2, 0, S2])) * 1e-3)
    assert a1.friction == 0.2 and scene.supports[2].friction == 0.1
    assert a1.geometry.coupling == "a" and a1.geometry.index == 1
    assert a1.geometry.ball_radius == pytest.approx(0.006)
    _close(scene.supports[2].normal, [0, 0, 1])
    assert scene.supports[3].geometry.line_contact
    assert any("line contact" in note for note in scene.notes)
    assert a1.to_json()["coupling"] == "a" and a1.to_json()["kind"] == "ball-vee"


@pytest.mark.parametrize(
    ("old", "new", "field", "fragment"),
    [
        (
            "spheres: [{center: [-40, -25, -10], radius: 4}]",
            "spheres: [{center: [-40, -25, -20], radius: 4}]",
            "couplings[1].spheres[0]",
            "does not touch",
        ),
        (
            "axis: [0, 1, 0], up: [0, 0, 1]",
            "axis: [0, 0, 2], up: [0, 0, 1]",
            "couplings[0].groove.up",  # it was couplings[0].up, a field a ball-vee has not
            "parallel to the groove's `axis`",
        ),
        (
            "half_angle: 45}, friction",
            "half_angle: 90}, friction",
            "couplings[0].groove.half_angle",
            "0 < half_angle < 90 deg",
        ),
        ("type: ball-cone", "type: ball-cones", "couplings[2].type", "ball-cone"),
        ("radius: 6}, up", "radius: 60000}, up", "couplings[2].ball.radius", "radius"),
        ("name: b,", "name: a,", "couplings[1].name", "used twice"),
    ],
)
def test_coupling_errors_are_located(write_scene, old, new, field, fragment):
    assert old in COUPLED
    with pytest.raises(SceneError) as info:
        load_scene(write_scene(COUPLED.replace(old, new)))
    errors = info.value.all()
    assert any(e.field == field and fragment in e.message for e in errors), [str(e) for e in errors]


# --- fixtures -------------------------------------------------------------------------------


def _generator() -> Any:
    spec = importlib.util.spec_from_file_location("generate", FIXTURES / "generate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _limiting_friction(path: Path) -> np.ndarray:
    from kcheck_checks.analytical_3d import Analytical3D

    from kcheck.body.mass import body_mass_properties
    from kcheck.plugin import Inputs

    scene = load_scene(path)
    check = Analytical3D()
    result = check.run(Inputs(scene, body_mass_properties(scene.body), check.options()))
    return np.array([c.limiting_friction for c in result.cases], dtype=float)


@pytest.mark.parametrize("beta", [15, 25, 35, 45, 55, 65])
def test_ball_vee_fixtures_match_the_explicit_contacts(beta, tmp_path):
    """The `ball-vee` fixture against the explicit scene the fixture was before (contacts
    derived by hand from Patti & Vogels' geometry): the same limiting friction."""
    explicit = tmp_path / "explicit.kcheck.yaml"
    explicit.write_text(_generator().explicit_scene_text(beta))
    shorthand = FIXTURES / f"three-groove-beta-{beta}" / "coupling.kcheck.yaml"
    np.testing.assert_allclose(
        _limiting_friction(shorthand), _limiting_friction(explicit), rtol=1e-9
    )


SHORTHAND_FIXTURES = [
    "three-groove-beta-35/coupling.kcheck.yaml",
    "kelvin/coupling.kcheck.yaml",
    "maxwell-three-vee/coupling.kcheck.yaml",
    "block-321-balls/block.kcheck.yaml",
    "tool-changer/tool.kcheck.yaml",
]


def _comparable(doc: dict) -> dict:
    """A result without timings, paths and coupling provenance, and without the checks that
    need the contact geometry only shorthands carry (explicit supports have no ball or groove
    radii: `hertz` is skipped on them, with that reason)."""
    scene = doc["scenes"][0]
    scene.pop("path"), scene.pop("runtime_s")
    scene["notes"] = [n for n in scene.get("notes", []) if "line contact" not in n]
    for s in scene.get("supports", []):
        s.pop("coupling"), s.pop("kind")
    scene["checks"] = [c for c in scene["checks"] if c["id"] != "hertz"]
    for check in scene["checks"]:
        check.pop("runtime_s")
    return doc


def _leaves(doc: object, where: str = "") -> dict[str, object]:
    """Every leaf of a JSON document by its path (numbers as floats, the rest as they are)."""
    if isinstance(doc, dict):
        return {
            k: v for key, value in doc.items() for k, v in _leaves(value, f"{where}/{key}").items()
        }
    if isinstance(doc, list):
        return {
            k: v for i, value in enumerate(doc) for k, v in _leaves(value, f"{where}/{i}").items()
        }
    return {
        where: float(doc) if isinstance(doc, (int, float)) and not isinstance(doc, bool) else doc
    }


@pytest.mark.parametrize("fixture", SHORTHAND_FIXTURES)
def test_expand_checks_identically(fixture, cli, tmp_path):
    source = FIXTURES / fixture
    for mesh in source.parent.glob("*.stl"):  # expanded output next to its meshes
        (tmp_path / mesh.name).write_bytes(mesh.read_bytes())
    code, text, err = cli("expand", str(source))
    assert code == 0, err
    assert "couplings" not in text and "type: ball" not in text
    expanded = tmp_path / "expanded.kcheck.yaml"
    expanded.write_text(text)
    assert all(s.geometry is None for s in load_scene(expanded).supports)
    docs = []
    for path in (source, expanded):
        code, out, _ = cli("check", "--format", "json", str(path))
        docs.append(_comparable(json.loads(out)))
    # The same result: every word equal, every number to 6 digits (expand writes 12
    # significant digits, not the float noise of the last ones: kcheck.fmt.COMPUTED_DIGITS).
    original, expanded_leaves = _leaves(docs[0]), _leaves(docs[1])
    assert expanded_leaves.keys() == original.keys()
    for key, value in original.items():
        if isinstance(value, float):
            # Error estimates (conditioning times the input's rounding, the polyhedral error)
            # move with the last digits themselves: 6 digits, above the 4 the reports show.
            assert expanded_leaves[key] == pytest.approx(value, rel=1e-6, abs=1e-9), key
        else:
            assert expanded_leaves[key] == value, key
    # expanded supports carry their `contact` (radii, materials): hertz says the same
    hertz = []
    for path in (source, expanded):
        code, out, _ = cli("check", "--format", "json", "--select", "hertz", str(path))
        (check,) = json.loads(out)["scenes"][0]["checks"]
        hertz.append(check)
    assert hertz[0]["status"] == hertz[1]["status"]
    line_contact = "line contact" in hertz[0]["message"]
    if hertz[0]["status"] == "skipped" and not line_contact:
        assert all(h["message"].startswith("not checked: material of") for h in hertz)


def test_json_result_says_where_each_support_came_from(cli_json):
    code, doc = cli_json(str(FIXTURES / "tool-changer" / "tool.kcheck.yaml"))
    supports = doc["scenes"][0]["supports"]
    assert code == 0 and [s["name"] for s in supports][:2] == ["b1.1", "b1.2"]
    assert {(s["coupling"], s["kind"]) for s in supports} == {
        ("b1", "ball-cylinders"),
        ("b2", "ball-cylinders"),
        ("b3", "ball-cylinders"),
    }
    # b1.1 rests on the pin at x = +4.2 mm: the normal (-4.2, 0, 5.6) / 7, the contact point
    # 5 mm from the ball centre (0, 30, 0) mm along -n.
    assert supports[0]["normal"] == pytest.approx([-0.6, 0, 0.8], abs=1e-15)
    assert supports[0]["position"] == pytest.approx([0.003, 0.03, -0.004], abs=1e-15)
    _, doc = cli_json(str(FIXTURES / "block-321" / "block.kcheck.yaml"))
    assert {(s["coupling"], s["kind"]) for s in doc["scenes"][0]["supports"]} == {
        (None, "explicit")
    }
