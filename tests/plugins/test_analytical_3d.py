"""The `analytical-3d` check: published numbers, closed forms, 2D agreement, invariances.

Reference values and where they come from:

* Patti & Vogels, "Self-alignment of kinematic couplings: effects of deformations", Precision
  Engineering 60 (2019), Figure 6 ("without deformations"), as quoted in issue 4: limiting
  friction 0.337 0.365 0.354 0.317 0.262 0.195 for beta = 15 ... 65 deg. Their public MATLAB
  script solves, per removed contact k, the generalised eigenproblem (A_k + mu B_k) x = 0 of
  *static* equilibrium of the five remaining contacts (normal force plus mu times friction
  against the contact's sliding direction under the free motion) and the load, and takes the
  smallest positive real mu over k. That is the jamming onset: the mu at which friction can
  hold the body still, i.e. where kcheck's acceleration lambda of the retracted case crosses
  zero. Inertia plays no part at lambda = 0 and the six cases are equivalent by symmetry, so
  kcheck's per-case limiting friction (largest mu that still closes) equals theirs when
  jamming, not contact loss, ends closing. The tests check all three facts.
* Maxwell's criterion for a ball in a V-groove whose flank normals are tilted beta from the
  horizontal: removing one flank frees the ball to slide along the other flank, at
  |90 - 2 beta| deg from the removed normal (the two normals are 180 - 2 beta apart).
* Planar agreement and the frictionless work criterion: methods.md §3 (exact by construction,
  compared to rounding); the closed form of methods.md §7 for the embedded block.
"""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from kcheck_checks.analytical_2d import Analytical2D, AnalyticalOptions
from kcheck_checks.analytical_3d import Analytical3D, Analytical3DOptions, sphere_map
from kcheck_checks.maxwell import Maxwell, MaxwellOptions

from kcheck.analysis import analyse
from kcheck.body.mass import body_mass_properties
from kcheck.cli.expand import expanded_text
from kcheck.mechanics.outcomes import outcome
from kcheck.plugin import Inputs
from kcheck.result import CheckResult, Status
from kcheck.scene import Scene, load_scene

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "fixtures"
PATTI_VOGELS = {15: 0.337, 25: 0.365, 35: 0.354, 45: 0.317, 55: 0.262, 65: 0.195}
# Their values are read to three decimals from a plot: agreement within half a unit of the
# last digit is all that can be asked.
PATTI_TOL = 0.0005


def _generator() -> Any:
    spec = importlib.util.spec_from_file_location("generate", FIXTURES / "generate.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_scene(directory: Path, data: dict[str, Any], name: str = "scene") -> Path:
    """Write a scene mapping as a real scene file."""
    path = directory / f"{name}.kcheck.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def run(check: Any, scene: Scene, options: Any = None) -> CheckResult:
    """Run a check the way the runner does (mass properties through kcheck.body.mass)."""
    mass = body_mass_properties(scene.body, scene.scale) if check.needs_mass else None
    opts = options if options is not None else check.options()
    return check.run(Inputs(scene, mass, opts))


def groove_scene(beta: int) -> Scene:
    return load_scene(FIXTURES / f"three-groove-beta-{beta}" / "coupling.kcheck.yaml")


def scene_dict(path: Path, explicit: bool = False) -> dict[str, Any]:
    """A scene file as a mapping (coupling shorthands expanded into supports); ``explicit``
    replaces a mesh by its mass properties."""
    data = yaml.safe_load(expanded_text(path))
    if explicit and "mesh" in data["body"]:
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        data["body"] = {
            "mass": mass.mass,
            "center_of_mass": (mass.center_of_mass / scene.scale).tolist(),
            "inertia": mass.inertia.tolist(),
        }
    return data


# --- Patti & Vogels -------------------------------------------------------------------------


@pytest.mark.parametrize("beta", sorted(PATTI_VOGELS))
def test_patti_vogels_limiting_friction(beta: int) -> None:
    result = run(Analytical3D(), groove_scene(beta))
    mus = np.array([c.limiting_friction for c in result.cases], dtype=float)
    # The six retractions are equivalent by the coupling's symmetry.
    np.testing.assert_allclose(mus, mus[0], rtol=1e-9)
    assert abs(mus.min() - PATTI_VOGELS[beta]) <= PATTI_TOL


@pytest.mark.parametrize("beta", [15, 45, 65])
def test_patti_vogels_mu_is_the_jamming_onset(beta: int, tmp_path: Path) -> None:
    path = FIXTURES / f"three-groove-beta-{beta}" / "coupling.kcheck.yaml"
    mu = run(Analytical3D(), load_scene(path)).cases[0].limiting_friction
    assert mu is not None
    for factor, expected in ((0.99, "closes"), (1.01, "jams")):
        data = scene_dict(path)
        data["friction"] = factor * mu
        scene = load_scene(write_scene(tmp_path, data, f"mu{factor}"))
        assert run(Analytical3D(), scene).cases[0].outcome == expected
    # Static balance: neither the body's mass nor its inertia moves the onset.
    data = scene_dict(path)
    data["body"] = {
        "mass": 123.0,
        "center_of_mass": [10, -20, 30],
        "inertia": [[5.0, 0.3, 0], [0.3, 4.0, 0.1], [0, 0.1, 7.0]],
    }
    heavy = run(Analytical3D(), load_scene(write_scene(tmp_path, data, "heavy")))
    assert heavy.cases[0].limiting_friction == pytest.approx(mu, rel=1e-9)


# --- Maxwell --------------------------------------------------------------------------------


@pytest.mark.parametrize("beta", [5, 15, 25, 30, 35, 45, 55, 65, 80])
def test_maxwell_angle_of_a_ball_in_a_groove(beta: int, tmp_path: Path) -> None:
    generator = _generator()
    # point balls: each contact at its ball's centre
    text = generator.explicit_scene_text(beta, ball_mm=0.0)
    path = tmp_path / "groove.kcheck.yaml"
    path.write_text(text)
    result = run(Maxwell(), load_scene(path), MaxwellOptions(min_cos=0.0))
    for case in result.cases:
        assert case.details["theta_deg"] == pytest.approx(abs(90 - 2 * beta), abs=1e-7)


def test_generated_fixtures_are_current() -> None:
    generator = _generator()
    for beta in generator.BETAS_DEG:
        path = FIXTURES / f"three-groove-beta-{beta}" / "coupling.kcheck.yaml"
        assert path.read_text() == generator.scene_text(beta)


# --- planar configuration embedded in space -------------------------------------------------

BLOCK_INERTIA = 1.0 * (0.1**2 + 0.06**2) / 12  # 100 x 60 mm plate, 1 kg (methods.md §7)
IN_PLANE = [
    {"name": "y1", "position": [20, 0, 10], "normal": [0, 1, 0]},
    {"name": "y2", "position": [80, 0, 10], "normal": [0, 1, 0]},
    {"name": "x1", "position": [0, 30, 10], "normal": [1, 0, 0]},
]
# The table: frictionless supports normal to the plane carry the weight and nothing of the
# in-plane force: exactly the plane of motion a planar scene assumes (it ignores gravity z).
TABLE = [
    {"name": "z1", "position": [20, 10, 0], "normal": [0, 0, 1], "friction": 0.0},
    {"name": "z2", "position": [80, 10, 0], "normal": [0, 0, 1], "friction": 0.0},
    {"name": "z3", "position": [50, 50, 0], "normal": [0, 0, 1], "friction": 0.0},
]


def embedded_pair(tmp_path: Path, angle: float) -> tuple[Scene, Scene]:
    common = {
        "version": 1,
        "units": "mm",
        "friction": 0.1,
        "gravity": [0, 0, -9.81],
        "load": {"magnitude": 1.0, "angle": angle},
    }
    planar = dict(
        common,
        name="planar",
        body={"mass": 1.0, "center_of_mass": [50, 30, 10], "inertia": BLOCK_INERTIA},
        supports=IN_PLANE,
    )
    # A 100 x 60 x 20 mm 1 kg block, with a product of inertia the table has to carry.
    inertia = [[3.3333e-4, 1e-5, 2e-5], [1e-5, 8.6667e-4, 0], [2e-5, 0, BLOCK_INERTIA]]
    spatial = dict(
        common,
        name="spatial",
        body={"mass": 1.0, "center_of_mass": [50, 30, 10], "inertia": inertia},
        supports=IN_PLANE + TABLE,
        # The planar scene's plane (a spatial scene without `sweep` would get the plane through
        # the design and most robust directions).
        sweep={"normal": [0, 0, 1], "zero": [1, 0, 0]},
    )
    return (
        load_scene(write_scene(tmp_path, planar, "planar")),
        load_scene(write_scene(tmp_path, spatial, "spatial")),
    )


@pytest.mark.parametrize("angle", [190.0, 225.0, 260.0, 300.0])
def test_planar_configuration_in_space_agrees_with_2d(angle: float, tmp_path: Path) -> None:
    planar, spatial = embedded_pair(tmp_path, angle)
    r2 = run(Analytical2D(), planar, AnalyticalOptions())
    r3 = run(Analytical3D(), spatial, Analytical3DOptions(sphere_points=2000))
    cases3 = {c.retracted: c for c in r3.cases}
    for c2 in r2.cases:
        c3 = cases3[c2.retracted]
        assert c3.outcome == c2.outcome
        if c2.acceleration is None:  # jammed: no motion, no sliding solution to report
            assert c3.acceleration is None and c3.normal_forces is None
            continue
        assert c3.acceleration == pytest.approx(c2.acceleration, rel=1e-9, abs=1e-12)
        if c2.limiting_friction is None:  # the case does not close even without friction
            assert c3.limiting_friction is None
        else:
            assert c3.limiting_friction == pytest.approx(c2.limiting_friction, rel=1e-9)
        assert c2.normal_forces is not None and c3.normal_forces is not None
        for name, force in c2.normal_forces.items():
            assert c3.normal_forces[name] == pytest.approx(force, rel=1e-9, abs=1e-12)
        np.testing.assert_allclose(c3.safe_ranges_deg, c2.safe_ranges_deg, rtol=0, atol=1e-9)
    if angle == 225.0:  # methods.md §7 closed form, x1 retracted
        x1 = cases3["x1"]
        assert x1.normal_forces["y1"] == pytest.approx(0.388909, abs=1e-6)
        assert x1.normal_forces["y2"] == pytest.approx(0.318198, abs=1e-6)
        assert x1.acceleration == pytest.approx(0.636396, abs=1e-6)


# --- random layouts: work criterion and rigid-motion invariance -----------------------------


def random_layout(rng: np.random.Generator) -> dict[str, Any]:
    """Six supports at random on a 100 mm box, normals roughly into it, a random load."""
    points = rng.uniform(0, 100, size=(6, 3))
    normals = rng.normal(size=(6, 3))
    # Inertia of a random cloud of point masses: always a physical tensor.
    cloud = rng.normal(size=(8, 3)) * 0.05
    cloud -= cloud.mean(axis=0)
    inertia = sum(np.dot(r, r) * np.eye(3) - np.outer(r, r) for r in cloud) / 8
    return {
        "version": 1,
        "name": "random",
        "units": "mm",
        "body": {
            "mass": float(rng.uniform(0.5, 5)),
            "center_of_mass": rng.uniform(20, 80, 3).tolist(),
            "inertia": inertia.tolist(),
        },
        "supports": [
            {"name": f"s{i}", "position": p.tolist(), "normal": n.tolist()}
            for i, (p, n) in enumerate(zip(points, normals, strict=True))
        ],
        "friction": 0.0,
        "gravity": (rng.normal(size=3) * 3).tolist(),
        "load": {
            "point": rng.uniform(0, 100, 3).tolist(),
            "magnitude": float(rng.uniform(1, 20)),
            "direction": rng.normal(size=3).tolist(),
        },
    }


@pytest.mark.parametrize("seed", range(12))
def test_frictionless_sign_is_the_virtual_power(seed: int, tmp_path: Path) -> None:
    scene = load_scene(write_scene(tmp_path, random_layout(np.random.default_rng(seed))))
    assert scene.body is not None and scene.load is not None
    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
    p = analysis.problem
    checked = 0
    for case in analysis.cases:
        if not case.determined or not case.well_conditioned:
            continue
        w, v = case.free.twist[:3], case.free.twist[3:]
        # Virtual power of load, gravity and torque along the free twist (nondimensional).
        power = (
            p.load_scale * scene.load.direction @ (v + np.cross(w, p.load_point))
            + p.gravity @ (v + np.cross(w, p.com))
            + p.torque @ w
        )
        _, x = outcome(case, scene.load.direction)
        assert x is not None
        if abs(power) > 1e-9:
            assert np.sign(x[0]) == np.sign(power)
            checked += 1
    assert checked >= 1


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def transformed(data: dict[str, Any], rot: np.ndarray, shift: np.ndarray) -> dict[str, Any]:
    """The same scene moved rigidly: points x -> R x + t, vectors -> R v, inertia R I R^T."""
    out = yaml.safe_load(yaml.safe_dump(data))
    out["supports"] = [
        dict(
            s, position=(rot @ s["position"] + shift).tolist(), normal=(rot @ s["normal"]).tolist()
        )
        for s in data["supports"]
    ]
    body = data["body"]
    out["body"] = {
        "mass": body["mass"],
        "center_of_mass": (rot @ body["center_of_mass"] + shift).tolist(),
        "inertia": (rot @ np.array(body["inertia"]) @ rot.T).tolist(),
    }
    out["gravity"] = (rot @ data["gravity"]).tolist()
    out["load"] = dict(
        data["load"],
        point=(rot @ data["load"]["point"] + shift).tolist(),
        direction=(rot @ data["load"]["direction"]).tolist(),
    )
    return out


@pytest.mark.parametrize("fixture", ["block-321", "three-groove-beta-35", "random"])
def test_rigid_motion_of_the_scene_changes_nothing(fixture: str, tmp_path: Path) -> None:
    rng = np.random.default_rng(11)
    if fixture == "random":
        data = random_layout(rng)
        data["friction"] = 0.15
    else:
        path = next((FIXTURES / fixture).glob("*.kcheck.yaml"))
        data = scene_dict(path, explicit=True)  # the mesh's inertia, to be rotated
        data["gravity"] = data.get("gravity", [0, 0, 0])
        data["load"].setdefault("point", data["body"]["center_of_mass"])
    data.pop("sweep", None)
    rot, shift = _rotation(rng), rng.uniform(-500, 500, 3)
    before = load_scene(write_scene(tmp_path, data, "before"))
    after = load_scene(write_scene(tmp_path, transformed(data, rot, shift), "after"))
    options = Analytical3DOptions(sphere_points=4000)
    r0, r1 = run(Analytical3D(), before, options), run(Analytical3D(), after, options)
    assert r1.status == r0.status
    for c0, c1 in zip(r0.cases, r1.cases, strict=True):
        assert c1.outcome == c0.outcome
        if c0.limiting_friction is not None:
            assert c1.limiting_friction == pytest.approx(c0.limiting_friction, rel=1e-8)
        if c0.normal_forces is not None:
            assert c1.normal_forces is not None
            for name, force in c0.normal_forces.items():
                assert c1.normal_forces[name] == pytest.approx(force, rel=1e-8, abs=1e-10)
            assert c1.acceleration == pytest.approx(c0.acceleration, rel=1e-8, abs=1e-10)
    if "design_margin_deg" in r0.details:
        assert r1.details["design_margin_deg"] == pytest.approx(
            r0.details["design_margin_deg"], abs=1e-7
        )
        robust0 = np.array(r0.details["most_robust_direction"])
        robust1 = np.array(r1.details["most_robust_direction"])
        # Refined only where safe directions exist; elsewhere it is the grid's best point.
        if r0.details["robust_margin_deg"] > 0:
            assert r1.details["robust_margin_deg"] == pytest.approx(
                r0.details["robust_margin_deg"], abs=1e-4
            )
            np.testing.assert_allclose(robust1, rot @ robust0, atol=1e-4)


# --- the sphere map -------------------------------------------------------------------------


def test_sphere_map_against_case_by_case_outcomes() -> None:
    """Cap signs equal `outcome` evaluated direction by direction (no caps involved)."""
    scene = load_scene(FIXTURES / "block-321" / "block.kcheck.yaml")
    assert scene.body is not None
    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
    smap = sphere_map(scene, analysis, 2000)
    assert smap is not None
    rng = np.random.default_rng(5)
    directions = rng.normal(size=(400, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    from kcheck.mechanics.arcs import cap_margins

    margins = cap_margins(smap.a, smap.c, directions)
    for d, m in zip(directions, margins, strict=True):
        every = all(outcome(case, d)[0] == "closes" for case in analysis.cases)
        if abs(m) > 1e-9:
            assert every == (m > 0)
    assert np.any(margins > 0) and np.any(margins < 0)


def test_three_groove_fixture_passes_with_a_robust_design() -> None:
    scene = load_scene(FIXTURES / "three-groove" / "coupling.kcheck.yaml")
    result = run(Analytical3D(), scene, Analytical3DOptions(min_margin_deg=10))
    assert result.status == Status.PASS
    d = result.details
    # By the three-fold symmetry with mirror planes, straight down is the deepest direction.
    np.testing.assert_allclose(d["most_robust_direction"], [0, 0, -1], atol=1e-6)
    assert d["design_margin_deg"] == pytest.approx(d["robust_margin_deg"], abs=1e-6)
    assert 0 < d["safe_solid_angle_fraction"] < 1
    # The sweep plane holds the design direction: its in-plane margin cannot be smaller than
    # the distance to the nearest boundary anywhere on the sphere.
    ((start, end),) = result.safe_ranges_deg
    assert min(360 - start, end - 360) >= d["design_margin_deg"] - 1e-9
    assert d["sweep_design_margin_deg"] >= d["design_margin_deg"] - 1e-9


def test_required_margin_decides(tmp_path: Path) -> None:
    path = FIXTURES / "three-groove" / "coupling.kcheck.yaml"
    scene = load_scene(path)
    margin = run(Analytical3D(), scene).details["design_margin_deg"]
    strict = run(Analytical3D(), scene, Analytical3DOptions(min_margin_deg=margin + 0.5))
    assert strict.status == Status.FAIL and "required" in strict.message
    # Without a design direction the verdict is whether a safe direction exists.
    data = scene_dict(path, explicit=True)
    del data["load"]["direction"]
    free = run(Analytical3D(), load_scene(write_scene(tmp_path, data)))
    assert free.status == Status.PASS and "design_margin_deg" not in free.details
    # 1 N against the plate's 14.4 N weight: the weight closes every case whatever the load's
    # direction, so every direction is safe and no margin (no boundary) is reported.
    data["load"]["magnitude"] = 1.0
    weak = run(Analytical3D(), load_scene(write_scene(tmp_path, data, "weak")))
    assert weak.status == Status.PASS and weak.details["safe_solid_angle_fraction"] == 1.0
    assert "robust_margin_deg" not in weak.details
    assert weak.message.startswith("every force direction closes every retraction")


def test_gravity_map_of_the_thesis_block(tmp_path: Path) -> None:
    """Without a load the map is over gravity directions; check it by re-tilting the block."""
    path = FIXTURES / "thesis-block-5-2" / "block.kcheck.yaml"
    result = run(Analytical3D(), load_scene(path))
    assert result.status == Status.PASS
    assert result.details["swept_direction"] == "gravity"
    assert all(c.outcome == "closes" for c in result.cases)
    data = scene_dict(path)
    robust = np.array(result.details["most_robust_direction"])
    # Tilted into a direction just outside the map's safe region, some case must fail.
    for direction, expected in ((robust, Status.PASS), (-robust, Status.FAIL)):
        data["gravity"] = (9.81 * direction).tolist()
        scene = load_scene(write_scene(tmp_path, data, f"tilt{expected.value}"))
        tilted = run(Analytical3D(), scene, Analytical3DOptions(min_margin_deg=0))
        assert tilted.status == expected
        closes = all(c.outcome == "closes" for c in tilted.cases)
        assert closes == (expected == Status.PASS)


def test_plots_are_written(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    from kcheck.pictures.plotting import formats

    check = Analytical3D()
    for scene_path in (FIXTURES / "three-groove" / "coupling.kcheck.yaml",):
        scene = load_scene(scene_path)
        assert scene.body is not None
        options = Analytical3DOptions(sphere_points=2000)
        inputs = Inputs(scene, body_mass_properties(scene.body, scene.scale), options)
        result = check.run(inputs)
        with formats(("png", "svg")):
            files = check.plot(inputs, result, tmp_path)
        names = {Path(f).name for f in files}
        for kind in ("scene", "sphere", "forces"):
            for ext in ("png", "svg"):
                assert any(n.endswith(f"-analytical-3d-{kind}.{ext}") for n in names)
        for f in files:
            assert Path(f).stat().st_size > 1000


def test_result_is_immutable_json() -> None:
    result = run(Analytical3D(), groove_scene(45), Analytical3DOptions(sphere_points=1000))
    out = result.to_json()
    assert out["sphere_points"] == 1000
    assert 0 <= out["safe_solid_angle_fraction_error"] < out["safe_solid_angle_fraction"]
    assert all("closing_solid_angle_fraction" in c for c in out["cases"])
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.status = Status.FAIL  # type: ignore[misc]


def test_gravity_only_scene_still_estimates_its_error(cli_json) -> None:
    # With no load to sweep there are no range ends; the error estimate then comes from the
    # sphere map's cap boundaries (coefficient error over the slope), never a bare zero.
    scene = Path(__file__).resolve().parents[2] / "fixtures" / "thesis-block-5-2"
    code, doc = cli_json(str(scene))
    check = next(c for c in doc["scenes"][0]["checks"] if c["id"] == "analytical-3d")
    assert code == 0 and 0 < check["error_estimate"] < 1e-9


# --- Painlevé-type case in space -----------------------------------------------------------


def test_painleve_case_in_space_agrees_with_2d(tmp_path: Path) -> None:
    """The long light body of tests/kcheck/test_dynamics.py on a frictionless table (as the
    planar block above): analytical-3d finds the same Painlevé onset for y1 as the planar
    check, mu* = 0.46305 derived by hand, and fails there."""
    from tests.plugins.test_analytical_2d import ROD_MU_STAR, rod_scene

    data = rod_scene(0.6)
    for support in data["supports"]:
        support["position"][2] = 0.01
    data["supports"] += [
        {"name": "z1", "position": [-0.5, 0.0, 0], "normal": [0, 0, 1], "friction": 0.0},
        {"name": "z2", "position": [0.5, 0.0, 0], "normal": [0, 0, 1], "friction": 0.0},
        {"name": "z3", "position": [0.0, 0.2, 0], "normal": [0, 0, 1], "friction": 0.0},
    ]
    data["body"] = {
        "mass": 1.0,
        "center_of_mass": [0, 0.1, 0.01],
        "inertia": [[0.02, 0, 0], [0, 0.02, 0], [0, 0, 0.01]],
    }
    data["gravity"] = [0, 0, -9.81]
    result = run(Analytical3D(), load_scene(write_scene(tmp_path, data)))
    y1 = next(c for c in result.cases if c.retracted == "y1")
    assert y1.outcome == "ambiguous"
    assert y1.details["painleve_from_mu"] == pytest.approx(ROD_MU_STAR, rel=1e-9)
    assert result.status is Status.FAIL
    assert any(f.code == "ambiguous" and f.field == ("supports", 0) for f in result.findings)


def test_scene_views_of_a_far_load_point_stay_a_picture(tmp_path):
    """Fuzz finding (campaign seed 4242, mutation-4242-1517): block-321's load point moved from
    z = 85 mm to 85 m (inside the documented 1000 m) made the scene views' figure 386 million
    pixels tall-and-wide: 1.7 GB and a minute to encode a PNG. The panels are now at most
    MAX_PANEL_RATIO times as tall as wide."""
    pytest.importorskip("matplotlib")
    from kcheck_checks.pictures.spatial import MAX_PANEL_RATIO, scene_views

    text = (FIXTURES / "block-321" / "block.kcheck.yaml").read_text()
    assert "point: [100, 75, 85]" in text
    folder = tmp_path / "far"
    folder.mkdir()
    (folder / "block.stl").write_bytes((FIXTURES / "block-321" / "block.stl").read_bytes())
    (folder / "block.kcheck.yaml").write_text(text.replace("[100, 75, 85]", "[100, 75, 85000]"))
    scene = load_scene(folder / "block.kcheck.yaml")
    check = Analytical3D()
    result = run(check, scene)
    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
    width, height = scene_views(scene, analysis, result).get_size_inches()
    # Two rows (six supports, three a row) of a plan over an elevation, each at most
    # MAX_PANEL_RATIO times a panel's width (about 3.8 in): under 50 in (it was ~1,700 in).
    assert MAX_PANEL_RATIO == 3.0 and width == pytest.approx(13.8) and height < 50


@pytest.mark.parametrize("fixture", ["tool-changer/tool", "kelvin/coupling"])
def test_scene_views_draw_preloads_and_fit_long_titles(fixture):
    """A new user's picture left out the scene's preload, and a rotation axis's three
    components ran a panel title into the next one. The tool changer's magnet is drawn
    (labelled by its name), and the Kelvin coupling's long titles ("socket.3 retracted:
    closes — pure rotation about (-0.632, 0.000, -0.775)") stay inside their panels."""
    pytest.importorskip("matplotlib")
    from kcheck_checks.pictures.spatial import scene_views
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    scene = load_scene(FIXTURES / f"{fixture}.kcheck.yaml")
    assert scene.body is not None
    result = run(Analytical3D(), scene)
    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
    fig = scene_views(scene, analysis, result)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    for preload in scene.preloads:
        assert any(preload.name in t for t in texts)
    renderer = FigureCanvasAgg(fig).get_renderer()
    from matplotlib.text import Text

    titles = [
        (t, ax)
        for ax in fig.axes
        if ax.get_title(loc="left")
        for t in ax.get_children()
        if isinstance(t, Text) and t.get_text() == ax.get_title(loc="left")
    ]
    assert len(titles) == len(scene.supports)
    for title, ax in titles:
        box = title.get_window_extent(renderer)
        panel = ax.get_window_extent(renderer)
        # No wider than its own panel plus the gap to the next (wspace 0.2 of a panel).
        assert box.width <= 1.2 * panel.width, title.get_text()


@pytest.mark.parametrize("sweep", [None, {"normal": [0, -1, 0], "zero": [0, 0, -1]}])
def test_gravity_swept_ranges_agree_with_the_dynamics_at_each_tilt(
    sweep: dict | None, tmp_path: Path
) -> None:
    """Gravity the only swept force (fixtures/kelvin without its load, a spring preload): the
    check reports `sweep_plane`, `safe_ranges_deg` and `sweep_design_margin_deg` (before, none
    of them: the sweep was of a load that is not there). Reference, an independent computation:
    the dynamics evaluated directly with the scene's gravity turned to each angle (the
    fixed-wrench path of `analyse`, no swept form): every case closes just inside each range
    end and some case fails just outside it."""
    from kcheck.fmt import normalise_range
    from tests.couplings import tilted_kelvin

    scene = load_scene(tilted_kelvin(tmp_path, 0.1, sweep))
    assert scene.load is None
    mass = body_mass_properties(scene.body, scene.scale)
    result = run(Analytical3D(), scene)
    plane = result.details["sweep_plane"]
    e1, normal = np.array(plane["zero"]), np.array(plane["normal"])
    e2 = np.cross(normal, e1)
    np.testing.assert_allclose(e1, [0, 0, -1], atol=1e-12)  # the design gravity direction at 0°
    if sweep is None:
        assert plane["chosen"] == "through the design and most robust directions"
        assert abs(normal @ result.details["most_robust_direction"]) < 1e-12
    else:
        assert plane["chosen"] == "the scene's sweep"
        np.testing.assert_allclose(normal, [0, -1, 0])
    ranges = [normalise_range(s, e) for s, e in result.safe_ranges_deg or ()]
    assert ranges and all(0 < (e - s) % 360 < 360 for s, e in ranges)  # bounded ranges
    assert result.details["case_ranges_label"] == "safe gravity angles"
    g = float(np.linalg.norm(scene.gravity))

    def closes(angle_deg: float) -> bool:
        t = np.radians(angle_deg)
        tilted = dataclasses.replace(scene, gravity=g * (np.cos(t) * e1 + np.sin(t) * e2))
        return analyse(tilted, mass).every_case_closes

    step = 0.01  # deg; the range ends are exact to rounding (error_estimate)
    assert result.error_estimate is not None and result.error_estimate < 1e-6
    for start, end in ranges:
        assert closes(start + step) and not closes(start - step)
        assert closes(end - step) and not closes(end + step)
    # The design gravity direction (0°) inside a range, its margin the distance to the ends.
    inside = [(s, e) for s, e in ranges if s > e or s == 0]
    assert len(inside) == 1 and closes(0.0)
    s, e = inside[0]
    assert result.details["sweep_design_margin_deg"] == pytest.approx(min(360 - s, e), abs=1e-9)


def test_the_drawn_mesh_is_placed_like_the_mass_properties():
    """The scene views drew each part's raw file coordinates: the tool changer's plate is
    turned 180° about x by its `transform`, and was drawn unturned. The drawn triangles now
    lie in the body's bounds as the mass properties compute them (transforms applied)."""
    from kcheck_checks.pictures.spatial import _mesh_triangles

    scene = load_scene(FIXTURES / "tool-changer" / "tool.kcheck.yaml")
    assert scene.body is not None and scene.body.parts[0].rotation is not None
    bounds = body_mass_properties(scene.body).bounds / scene.scale
    triangles = _mesh_triangles(scene)
    assert triangles is not None and 0 < len(triangles) <= 6000
    points = triangles.reshape(-1, 3)
    assert np.all(points >= bounds[0] - 1e-6) and np.all(points <= bounds[1] + 1e-6)
    assert np.allclose(points.min(axis=0), bounds[0], atol=0.5)  # reaches the box's corners
