"""The checks with uncertain and two-valued friction, through real scene files.

* A range ``{min, max}``: a case passes only if it closes for every coefficient in it. The
  symmetric three-groove couplings of Patti & Vogels (2019) close up to their limiting friction
  (0.195–0.365 for beta = 65...25 deg, reproduced by analytical-3d, tests/plugins/
  test_analytical_3d.py), so ``friction: {min: 0.1, max: 0.3}`` must fail exactly for the
  grooves whose limiting friction lies inside it.
* ``{static, kinetic}``: the dynamics (analytical-2d/3d) slide with the kinetic coefficient;
  holding (jamming) and Koster's construction (graphical-2d) are about the start of motion and
  take the static one. Each check must give exactly its answer for that plain coefficient.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from kcheck_checks.analytical_2d import Analytical2D
from kcheck_checks.analytical_3d import Analytical3D
from kcheck_checks.graphical_2d import Graphical2D
from kcheck_checks.jamming import Jamming

from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.arcs import TAU
from kcheck.mechanics.dynamics import friction_directions
from kcheck.mechanics.kinematics import cross3, point_velocity, wrenches
from kcheck.mechanics.koster import construct_case, friction_over_range
from kcheck.plugin import Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene, load_scene
from tests.conftest import FIXTURES

BETAS = (15, 25, 35, 45, 55, 65)


#: The marginal bands switched off: these tests are about the failure line itself.
NO_BAND = {"marginal_deg": 0.0, "marginal_friction_ratio": 1.0}


def run(check, scene: Scene) -> CheckResult:
    mass = body_mass_properties(scene.body, scene.scale) if scene.body is not None else None
    options = check.options()
    band = {k: v for k, v in NO_BAND.items() if k in type(options).model_fields}
    return check.run(Inputs(scene, mass, options.model_copy(update=band)))


def with_friction(write_scene, fixture: str, friction: str, name: str = "s.kcheck.yaml") -> Scene:
    """A fixture with its `friction:` line replaced (meshes copied next to it when needed)."""
    folder = FIXTURES / fixture
    source = next(folder.glob("*.kcheck.yaml"))
    text = source.read_text()
    lines = [ln for ln in text.splitlines() if ln.startswith("friction:")]
    assert len(lines) == 1
    path = write_scene(text.replace(lines[0], f"friction: {friction}"), name)
    for mesh in folder.glob("*.stl"):
        (path.parent / mesh.name).write_bytes(mesh.read_bytes())
    return load_scene(path)


def limiting(result: CheckResult) -> float:
    return min(float(c.limiting_friction) for c in result.cases)


@pytest.mark.parametrize("beta", BETAS)
def test_three_groove_range_fails_where_its_limiting_friction_lies_inside(write_scene, beta):
    plain = run(Analytical3D(), with_friction(write_scene, f"three-groove-beta-{beta}", "0.1"))
    mu_limit = limiting(plain)  # 0.195 ... 0.365 (Patti & Vogels)
    ranged = run(
        Analytical3D(),
        with_friction(write_scene, f"three-groove-beta-{beta}", "{min: 0.1, max: 0.3}"),
    )
    inside = 0.1 < mu_limit < 0.3
    assert (ranged.status == "fail") == inside
    summary = ranged.details["friction_range"]
    assert summary["closes_throughout"] == (not inside)
    for case in ranged.cases:
        span = case.details["friction_range"]
        if inside:
            # it fails from the case's own limiting friction to the top of the range
            ((lo, hi),) = span["fails_for"]
            assert lo == pytest.approx(case_limit(plain, case.retracted), abs=1e-9)
            assert hi == pytest.approx(0.3)
            assert case.outcome == "jams" and span["worst_mu"] == pytest.approx(0.3)
        else:
            assert span["fails_for"] == [] and case.outcome == "closes"
    if inside:
        assert "the worst of the friction range 0.1–0.3" in ranged.findings[0].message


def case_limit(result: CheckResult, name: str) -> float:
    return float(next(c.limiting_friction for c in result.cases if c.retracted == name))


def test_range_end_just_below_and_above_the_limiting_friction(write_scene):
    """Exactly: a range ending 1e-6 below the limiting friction passes, 1e-6 above fails."""
    plain = run(Analytical3D(), with_friction(write_scene, "three-groove-beta-55", "0.1"))
    mu = limiting(plain)
    below = with_friction(write_scene, "three-groove-beta-55", f"{{min: 0.1, max: {mu - 1e-6}}}")
    above = with_friction(write_scene, "three-groove-beta-55", f"{{min: 0.1, max: {mu + 1e-6}}}")
    assert run(Analytical3D(), below).status == "pass"
    assert run(Analytical3D(), above).status == "fail"


def _same(a: CheckResult, b: CheckResult) -> None:
    """Two results of one check agree on everything the verdict rests on."""
    assert a.status == b.status and a.message == b.message
    np.testing.assert_allclose(np.array(a.safe_ranges_deg), np.array(b.safe_ranges_deg))
    assert [c.outcome for c in a.cases] == [c.outcome for c in b.cases]


@pytest.mark.parametrize(
    ("fixture", "checks"),
    [
        ("three-groove-beta-65", (Analytical3D, Jamming)),
        ("planar-block", (Analytical2D, Graphical2D, Jamming)),
    ],
)
def test_static_and_kinetic_are_each_used_where_the_docs_say(write_scene, fixture, checks):
    """The groove's limiting friction is 0.195 and the block's 0.26 (retract y1): a static
    coefficient above it and a kinetic one below split the verdicts — the dynamics pass with
    the kinetic one, holding and Koster's construction fail with the static one."""
    static, kinetic = (0.2, 0.15) if "groove" in fixture else (0.3, 0.2)
    pair = with_friction(write_scene, fixture, f"{{static: {static}, kinetic: {kinetic}}}")
    only_static = with_friction(write_scene, fixture, str(static), "static.kcheck.yaml")
    only_kinetic = with_friction(write_scene, fixture, str(kinetic), "kinetic.kcheck.yaml")
    for check in checks:
        kind = "kinetic" if check.id.startswith("analytical") else "static"
        got = run(check(), pair)
        expected = run(check(), only_kinetic if kind == "kinetic" else only_static)
        if got.findings:  # the dynamics say which coefficient they slid with
            assert ("kinetic μ" in got.findings[0].message) == (kind == "kinetic")
            got = dataclasses.replace(got, findings=expected.findings, message=expected.message)
        _same(got, expected)
        assert got.details["friction_range"]["kind"] == kind
        assert got.status == ("pass" if kind == "kinetic" else "fail")


def test_koster_friction_arcs_over_a_static_range_against_brute_force():
    """graphical-2d over a static range: the friction arcs that hold for every coefficient
    (exact: ends of the range and envelope points) against 401 coefficients x 1800 angles
    (the friction pole's moment sense evaluated directly), on 180 random cases. The arcs of
    the top coefficient alone differ in most of them: the friction pole moves, and its half
    circle of directions turns with it."""
    rng = np.random.default_rng(4)
    e1, e2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    angles = (np.arange(1800) + 0.5) * TAU / 1800
    ts = np.linspace(0, 1, 401)

    def inside(arcs) -> np.ndarray:
        ok = np.zeros(len(angles), bool)
        for s, e in arcs:
            ok |= ((angles - s) % TAU) <= (e - s)
        return ok

    compared = differs_from_top = 0
    for _ in range(60):
        points = rng.uniform(-1, 1, (3, 2))
        normals = -points + rng.normal(size=(3, 2)) * 0.8
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        q = rng.uniform(-3, 3, 2)
        low = np.full(3, rng.uniform(0, 0.3))
        high = low + rng.uniform(0.1, 1.5)
        for r in range(3):
            top = construct_case(points, normals, high, r, q, 0.0, e1, e2)
            if top.tilted is None:
                continue
            ranged = friction_over_range(top, points, normals, low, high, q, 0.0, e1, e2)
            # brute force: the friction pole's moment condition at every coefficient, directly
            keep = top.keep
            t_dir, _ = friction_directions(top.free.twist, points[keep], +1)
            mu = low[None, keep, None] + ts[:, None, None] * (high - low)[None, keep, None]
            rows = wrenches(points[keep][None], normals[keep][None] + mu * t_dir[None])
            tilted = cross3(rows[:, 0], rows[:, 1])
            plain = wrenches(points[keep], normals[keep])
            tilted *= np.sign(cross3(plain[0], plain[1]) @ top.free.twist)
            power = point_velocity(tilted, q)  # (t, 2): the load point's velocity
            dirs = np.stack([np.cos(angles), np.sin(angles)], axis=1)
            expected = np.all(power @ dirs.T > 0, axis=0)
            got = inside(ranged.friction)
            near = np.zeros(len(angles), bool)
            for s, e in ranged.friction:
                for end in (s, e):
                    near |= np.abs((angles - end + np.pi) % TAU - np.pi) < 2e-3
            assert np.array_equal(got[~near], expected[~near])
            assert np.array_equal(inside(ranged.safe), inside(ranged.funnel) & got)
            compared += 1
            differs_from_top += not np.array_equal(inside(top.friction), expected)
    assert compared > 150 and differs_from_top > compared // 2


def test_pictures_against_friction(write_scene, tmp_path):
    """One picture against μ per check (a real PNG; analytical-2d's through its `plot`, as
    `--plots` calls it), and the bands are the check's own ranges at each coefficient."""
    pytest.importorskip("matplotlib")
    from kcheck_checks.pictures.friction import friction_axis, plot_friction, scene_at

    scene = with_friction(write_scene, "planar-block", "{min: 0.05, max: 0.3}")
    mass = body_mass_properties(scene.body, scene.scale)
    check = Analytical2D()
    inputs = Inputs(scene, mass, check.options())
    files = [Path(f).name for f in check.plot(inputs, check.run(inputs), tmp_path)]
    assert "planar-rectangular-block-analytical-2d-friction.png" in files
    for check in (Graphical2D(), Jamming()):
        inputs = Inputs(scene, mass, check.options())
        (png,) = plot_friction(  # PNG only by default (`--plot-format`)
            check.id, inputs, check.run(inputs), tmp_path
        )
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    mus, pattern, low, high = friction_axis(scene, "kinetic", 5)
    assert (low, high) == (0.05, 0.3) and mus[-1] == pytest.approx(0.45)
    at = scene_at(scene, pattern * 0.3)
    assert [s.coefficients.plain for s in at.supports] == [True] * 3
    plain = with_friction(write_scene, "planar-block", "0.3", "plain.kcheck.yaml")
    assert run(Analytical2D(), at).safe_ranges_deg == run(Analytical2D(), plain).safe_ranges_deg
    spatial = with_friction(
        write_scene, "three-groove-beta-45", "{min: 0.1, max: 0.3}", "g.kcheck.yaml"
    )
    check = Analytical3D()
    inputs = Inputs(spatial, body_mass_properties(spatial.body, spatial.scale), check.options())
    (png,) = plot_friction(check.id, inputs, check.run(inputs), tmp_path)
    assert png.name.endswith("-analytical-3d-friction.png") and png.stat().st_size > 10_000
