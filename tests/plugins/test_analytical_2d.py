"""The `analytical-2d` check against closed forms, brute force and bisection.

Every reference value says where it comes from: a closed form derived in the test (methods.md
§7 and §1.1 of the thesis), or an independent brute-force computation (sweeping ``outcome`` or
solving the linear system angle by angle) that does not use the closed-form arc formulas.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from kcheck_checks.analytical_2d import Analytical2D, AnalyticalOptions

from kcheck.body.mass import body_mass_properties
from kcheck.cli import main
from kcheck.mechanics.arcs import TAU, contains
from kcheck.mechanics.dynamics import analyse_case, build_problem, solve_affine, system_matrix
from kcheck.mechanics.friction import friction_intervals, limiting_friction
from kcheck.mechanics.outcomes import outcome, safe_arcs
from kcheck.plugin import Inputs
from kcheck.result import CheckResult, Status
from kcheck.scene import load_scene

# methods.md §7: block 100 x 60 mm, 1 kg, y1 (20, 0), y2 (80, 0) normal +y, x1 (0, 30) normal
# +x, unit force at the centre of mass (50, 30). Inertia of a uniform 100 x 60 mm plate.
BLOCK_INERTIA = 1.0 * (0.1**2 + 0.06**2) / 12


def block_scene(**changes: Any) -> dict[str, Any]:
    """The methods.md §7 block as a scene mapping (mm), with top-level fields replaced."""
    scene: dict[str, Any] = {
        "version": 1,
        "name": "methods 7 block",
        "units": "mm",
        "body": {"mass": 1.0, "center_of_mass": [50, 30, 0], "inertia": BLOCK_INERTIA},
        "supports": [
            {"name": "y1", "position": [20, 0, 0], "normal": [0, 1, 0]},
            {"name": "y2", "position": [80, 0, 0], "normal": [0, 1, 0]},
            {"name": "x1", "position": [0, 30, 0], "normal": [1, 0, 0]},
        ],
        "friction": 0.1,
        "load": {"magnitude": 1.0, "angle": 225.0},
    }
    scene.update(changes)
    return scene


def write_scene(directory: Path, data: dict[str, Any], name: str = "scene") -> Path:
    """Write a scene mapping as a real ``*.kcheck.yaml`` file."""
    path = directory / f"{name}.kcheck.yaml"
    plain = json.loads(json.dumps(data, default=float))  # numpy scalars to plain floats
    path.write_text(yaml.safe_dump(plain, sort_keys=False), encoding="utf-8")
    return path


def run_check(path: Path) -> CheckResult:
    """Load a scene file with the real loader and run `analytical-2d` on it."""
    scene = load_scene(path)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    options = AnalyticalOptions.model_validate(scene.check_options.get("analytical-2d", {}))
    return Analytical2D().run(Inputs(scene, mass, options))


def case(result: CheckResult, name: str) -> Any:
    """The case result for one retracted support."""
    return next(c for c in result.cases if c.retracted == name)


def block_closed_form(
    alpha_deg: float, mu1: float, mu2: float, torque: float = 0.0, mass: float = 1.0
) -> tuple[float, float, float]:
    """methods.md §7, x1 retracted, derived by hand: N1, N2 (N) and a (m/s^2, along -x).

    Translation along -x, friction ``+mu_j N_j`` along +x. Forces in y: ``N1 + N2 = -F_y``;
    moments about the centre of mass (m): ``N1 (-0.03 + 0.03 mu1) + N2 (0.03 + 0.03 mu2) + M
    = 0``; along -x: ``m a = -(F_x + mu1 N1 + mu2 N2)``. Solved by Cramer's rule.
    """
    fx, fy = np.cos(np.radians(alpha_deg)), np.sin(np.radians(alpha_deg))
    k1, k2 = -0.03 + 0.03 * mu1, 0.03 + 0.03 * mu2
    det = 1.0 * k2 - 1.0 * k1
    n1 = (-fy * k2 - (-torque) * 1.0) / det
    n2 = (1.0 * (-torque) - k1 * (-fy)) / det
    return n1, n2, -(fx + mu1 * n1 + mu2 * n2) / mass


# --- methods.md §7 --------------------------------------------------------------------------


def test_block_methods_7_through_yaml_and_check(tmp_path: Path) -> None:
    """methods.md §7 gives N1 = 0.388909 N, N2 = 0.318198 N, a = 0.636396 m/s^2 at 225 deg."""
    result = run_check(write_scene(tmp_path, block_scene()))
    x1 = case(result, "x1")
    assert x1.outcome == "closes"
    assert x1.normal_forces["y1"] == pytest.approx(0.388909, abs=1e-6)
    assert x1.normal_forces["y2"] == pytest.approx(0.318198, abs=1e-6)
    assert x1.acceleration == pytest.approx(0.636396, abs=1e-6)
    assert x1.details["motion"] == "translation"
    # Same numbers from the closed form in full precision.
    n1, n2, a = block_closed_form(225.0, 0.1, 0.1)
    assert (x1.normal_forces["y1"], x1.normal_forces["y2"], x1.acceleration) == pytest.approx(
        (n1, n2, a), rel=1e-12
    )


def test_block_methods_7_through_cli_json(tmp_path: Path) -> None:
    """The CLI's JSON carries the same methods.md §7 numbers."""
    scene = write_scene(tmp_path, block_scene())
    out = tmp_path / "out.json"
    code = main(
        ["check", str(scene), "--select", "analytical-2d", "--format", "json", "-o", str(out)]
    )
    assert code == 0
    doc = json.loads(out.read_text())
    check = doc["scenes"][0]["checks"][0]
    assert check["id"] == "analytical-2d" and check["status"] == "pass"
    x1 = next(c for c in check["cases"] if c["retracted"] == "x1")
    assert x1["normal_forces"]["y1"] == pytest.approx(0.388909, abs=1e-6)
    assert x1["normal_forces"]["y2"] == pytest.approx(0.318198, abs=1e-6)
    assert x1["acceleration"] == pytest.approx(0.636396, abs=1e-6)


@pytest.mark.parametrize("alpha", [190.0, 200.0, 225.0, 250.0, 260.0])
def test_block_closed_form_over_angles(tmp_path: Path, alpha: float) -> None:
    """Closed form of methods.md §7 (derived in ``block_closed_form``) at several angles."""
    result = run_check(write_scene(tmp_path, block_scene(load={"magnitude": 1.0, "angle": alpha})))
    x1 = case(result, "x1")
    n1, n2, a = block_closed_form(alpha, 0.1, 0.1)
    assert x1.normal_forces["y1"] == pytest.approx(n1, rel=1e-12)
    assert x1.normal_forces["y2"] == pytest.approx(n2, rel=1e-12)
    assert x1.acceleration == pytest.approx(a, rel=1e-12)


def test_per_support_friction_override(tmp_path: Path) -> None:
    """Per-support coefficients enter each contact's friction: closed form with mu1 != mu2."""
    data = block_scene()
    data["supports"][0]["friction"] = 0.3
    data["supports"][1]["friction"] = 0.05
    x1 = case(run_check(write_scene(tmp_path, data)), "x1")
    n1, n2, a = block_closed_form(225.0, 0.3, 0.05)
    assert x1.normal_forces["y1"] == pytest.approx(n1, rel=1e-12)
    assert x1.normal_forces["y2"] == pytest.approx(n2, rel=1e-12)
    assert x1.acceleration == pytest.approx(a, rel=1e-12)
    # Differs from the common-coefficient answer, so the override was really used.
    assert abs(x1.normal_forces["y1"] - 0.388909) > 1e-3


def test_torque_in_the_load(tmp_path: Path) -> None:
    """A torque M_z enters the moment balance: closed form with M = 0.004 N m."""
    load = {"magnitude": 1.0, "angle": 225.0, "torque": [0, 0, 0.004]}
    x1 = case(run_check(write_scene(tmp_path, block_scene(load=load))), "x1")
    n1, n2, a = block_closed_form(225.0, 0.1, 0.1, torque=0.004)
    assert x1.normal_forces["y1"] == pytest.approx(n1, rel=1e-12)
    assert x1.normal_forces["y2"] == pytest.approx(n2, rel=1e-12)
    assert x1.acceleration == pytest.approx(a, rel=1e-12)
    assert n1 > 0.388909 + 0.01  # a ccw torque loads y1 more


# --- thesis §1.1: block on a plane slides iff tan(theta) > mu ---------------------------------


def test_block_on_plane_slide_threshold(tmp_path: Path) -> None:
    """Thesis §1.1 / Figure 1.1: slides iff tan(theta) > mu; mu = 0.1 gives 5.7106 deg.

    The force makes angle theta with the normal of the plane, tilted towards x1: alpha = 270 -
    theta. The x1 case's safe arc must end exactly at 270 - atan(0.1) deg.
    """
    threshold = np.degrees(np.arctan(0.1))
    assert threshold == pytest.approx(5.7106, abs=1e-4)
    result = run_check(write_scene(tmp_path, block_scene()))
    ends = [e for _, e in case(result, "x1").safe_ranges_deg]
    assert ends == [pytest.approx(270.0 - threshold, abs=1e-9)]
    for theta, expected in [(threshold - 1e-6, "jams"), (threshold + 1e-6, "closes")]:
        load = {"magnitude": 1.0, "angle": 270.0 - theta}
        x1 = case(run_check(write_scene(tmp_path, block_scene(load=load))), "x1")
        assert x1.outcome == expected


# --- every outcome from a real scene ----------------------------------------------------------


@pytest.mark.parametrize(
    ("alpha", "expected", "why"),
    [
        (225.0, "closes", "into the corner (methods.md §7)"),
        (315.0, "opens", "pushes away from x1 and down: lambda < 0 under backward friction"),
        (45.0, "opens_loses_contact", "pushes away from x1 and up: N1 + N2 = -F_y < 0"),
        (268.0, "jams", "2 deg from the normal < atan(0.1): friction holds it (§1.1)"),
        (135.0, "loses_contact", "pulls up: N1 + N2 = -F_y < 0 while moving towards x1"),
    ],
)
def test_outcomes(tmp_path: Path, alpha: float, expected: str, why: str) -> None:
    """Each outcome of the x1 case, from the closed form's sign reasoning in ``why``."""
    result = run_check(write_scene(tmp_path, block_scene(load={"magnitude": 1.0, "angle": alpha})))
    assert case(result, "x1").outcome == expected, why
    assert result.status is (Status.PASS if expected == "closes" else Status.FAIL)


# --- min_margin_deg -----------------------------------------------------------------------------


def test_min_margin_pass_fail(tmp_path: Path) -> None:
    """The design margin is the distance to the nearest end of the combined range; the option
    fails a design closer than required and passes one farther away."""
    result = run_check(write_scene(tmp_path, block_scene()))
    margin = result.details["design_margin_deg"]
    ends = [x for arc in result.safe_ranges_deg for x in arc]
    assert margin == pytest.approx(min(abs(225.0 - x) for x in ends), abs=1e-12)
    for required, status in [(margin - 0.01, Status.PASS), (margin + 0.01, Status.FAIL)]:
        data = block_scene(checks={"analytical-2d": {"min_margin_deg": required}})
        assert run_check(write_scene(tmp_path, data)).status is status


# --- limiting friction by bisection on mu -------------------------------------------------------


def _closes_with(problem: Any, retracted: int, mu: float, direction: np.ndarray) -> bool:
    """Whether the case closes with friction ``mu`` times the scene's pattern (supports keep
    their shares of the largest coefficient), by a fresh analysis of the case."""
    pattern, _ = problem.friction_pattern()
    trial = dataclasses.replace(problem, friction=pattern * mu)
    return outcome(analyse_case(trial, retracted), direction)[0] == "closes"


def _bisect(problem: Any, r: int, lo: float, hi: float, direction: np.ndarray) -> float:
    """Where ``closes`` changes between ``lo`` and ``hi`` (it differs at the two ends)."""
    state = _closes_with(problem, r, lo, direction)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _closes_with(problem, r, mid, direction) == state else (lo, mid)
    return 0.5 * (lo + hi)


def test_friction_intervals_by_brute_force() -> None:
    """``friction_intervals`` equals a scan of ``outcome`` over mu with fresh analyses: inside
    and outside agree on a grid, and every finite interval end is a change found by bisection
    (1e-9 relative). ``limiting_friction`` is the upper end of the interval holding the scene's
    mu, None when the case does not close there."""
    rng = np.random.default_rng(7)
    checked = ends = 0
    for problem in random_problems(rng, 20):
        _, mu_scene = problem.friction_pattern()
        for r in range(3):
            case_ = analyse_case(problem, r)
            if not (case_.determined and case_.well_conditioned):
                continue
            direction = unit(rng.uniform(0, TAU))
            found = friction_intervals(problem, case_, direction)
            limit = limiting_friction(problem, case_, direction)
            closes_here = outcome(case_, direction)[0] == "closes"
            assert found.closes == closes_here and (limit is None) == (not closes_here)
            grid = np.linspace(0.0, 3.0, 61)
            for mu in grid:
                gaps = [abs(mu - x) for lo, hi in found.intervals for x in (lo, hi)]
                if min(gaps, default=1.0) < 1e-6:
                    continue
                inside = any(lo <= mu <= hi for lo, hi in found.intervals)
                assert inside == _closes_with(problem, r, mu, direction), (r, mu, found)
            for lo, hi in found.intervals:
                for end in (lo, hi):
                    if 0 < end < np.inf:
                        a, b = end * (1 - 1e-7), end * (1 + 1e-7)
                        assert _closes_with(problem, r, a, direction) != _closes_with(
                            problem, r, b, direction
                        )
                        assert _bisect(problem, r, a, b, direction) == pytest.approx(end, rel=1e-9)
                        ends += 1
            if closes_here:
                assert found.containing is not None
                assert found.containing[0] <= mu_scene <= found.containing[1]
                assert limit == found.containing[1]
            checked += 1
    assert checked > 20 and ends > 10


def test_limiting_friction_block_closed_form() -> None:
    """x1 of the §7 block at 225 deg: a = -(F_x + mu (N1 + N2)) = 0 at mu = -F_x / -F_y = 1,
    and N1 > 0 needs -0.03 + 0.03 mu < 0, i.e. mu < 1 too: the limit is exactly 1."""
    problem = block_problem(0.1)
    direction = unit(np.radians(225.0))
    assert limiting_friction(problem, analyse_case(problem, 2), direction) == pytest.approx(1.0)


# --- closed-form ranges against a brute-force sweep ---------------------------------------------


def unit(angle: float) -> np.ndarray:
    """Unit vector at an angle (rad) from +x."""
    return np.array([np.cos(angle), np.sin(angle)])


def block_problem(mu: float) -> Any:
    """The methods.md §7 block as a :class:`Problem` (SI)."""
    return build_problem(
        points=np.array([[0.02, 0, 0], [0.08, 0, 0], [0, 0.03, 0]]),
        normals=np.array([[0, 1.0, 0], [0, 1.0, 0], [1.0, 0, 0]]),
        friction=np.full(3, mu),
        names=("y1", "y2", "x1"),
        dim=2,
        mass=1.0,
        com=np.array([0.05, 0.03, 0]),
        inertia=np.diag([np.nan, np.nan, BLOCK_INERTIA]),
        gravity=np.zeros(3),
        load_magnitude=1.0,
        load_point=None,
        torque=np.zeros(3),
    )


def random_problems(rng: np.random.Generator, count: int) -> list[Any]:
    """Random planar couplings: supports on a unit-ish outline with inward-ish normals,
    random mass, inertia, friction per support, load point and torque."""
    out = []
    while len(out) < count:
        phi = np.sort(rng.uniform(0, TAU, 3))
        points = np.column_stack([np.cos(phi), np.sin(phi), np.zeros(3)]) * rng.uniform(0.5, 2)
        inward = -points[:, :2] / np.linalg.norm(points[:, :2], axis=1, keepdims=True)
        tilt = rng.uniform(-1.0, 1.0, 3)
        c, s = np.cos(tilt), np.sin(tilt)
        normals = np.column_stack(
            [c * inward[:, 0] - s * inward[:, 1], s * inward[:, 0] + c * inward[:, 1], np.zeros(3)]
        )
        mass = 10 ** rng.uniform(-1, 1)
        out.append(
            build_problem(
                points=points,
                normals=normals,
                friction=rng.uniform(0, 0.6, 3),
                names=("a", "b", "c"),
                dim=2,
                mass=mass,
                com=np.append(rng.normal(0, 0.3, 2), 0),
                inertia=np.diag([np.nan, np.nan, mass * 10 ** rng.uniform(-2, 0.5)]),
                gravity=np.append(rng.normal(0, 0.3, 2), 0) * (rng.uniform() < 0.3),
                load_magnitude=1.0,
                load_point=np.append(rng.normal(0, 0.5, 2), 0),
                torque=np.array([0, 0, rng.normal(0, 0.2)]),
            )
        )
    return out


def _closes(case_: Any, angle: float) -> bool:
    return outcome(case_, unit(angle))[0] == "closes"


def brute_force_ends(case_: Any, samples: int = 1440) -> np.ndarray:
    """Angles (rad) where ``outcome`` switches into or out of "closes": a sweep, then 60
    bisection steps at every sign change (~1e-16 rad)."""
    angles = np.linspace(0, TAU, samples, endpoint=False)
    state = np.array([_closes(case_, a) for a in angles])
    ends = []
    for i in np.flatnonzero(state != np.roll(state, -1)):
        lo, hi = angles[i], angles[i] + TAU / samples
        inside = state[i]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if _closes(case_, mid) == inside else (lo, mid)
        ends.append(0.5 * (lo + hi) % TAU)
    return np.sort(np.array(ends))


def test_closed_form_ranges_equal_brute_force() -> None:
    """Arc ends from the closed form (methods.md §4) equal a brute-force sweep of ``outcome``
    with bisection to 1e-9 deg, on many random planar scenes."""
    rng = np.random.default_rng(2003)
    worst, compared = 0.0, 0
    for problem in random_problems(rng, 30):
        for r in range(3):
            case_ = analyse_case(problem, r)
            if not (case_.determined and case_.well_conditioned):
                continue
            arcs, _ = safe_arcs(case_, np.array([1.0, 0]), np.array([0, 1.0]))
            closed = np.sort(np.array([x % TAU for arc in arcs for x in arc if arc != (0, TAU)]))
            brute = brute_force_ends(case_)
            # An arc narrower than the sweep step can hide between samples; the sweep has 0.25
            # deg steps and no random case here comes that close (asserted by equal counts).
            assert len(brute) == len(closed)
            if len(closed):
                diff = np.abs((brute - closed + np.pi) % TAU - np.pi)
                worst = max(worst, float(np.degrees(diff.max())))
                compared += len(closed)
            # Inside/outside agree everywhere on a finer independent grid.
            for a in np.linspace(0, TAU, 97, endpoint=False) + 1e-3:
                if min(np.abs((a - closed + np.pi) % TAU - np.pi), default=1.0) > 1e-6:
                    assert contains(arcs, a) == _closes(case_, a)
    assert compared > 50
    assert worst < 1e-9
    print(f"brute force: {compared} arc ends, worst deviation {worst:.2e} deg")


def test_affine_form_equals_direct_solve() -> None:
    """The affine coefficients reproduce a direct solve of the Newton–Euler system per angle."""
    rng = np.random.default_rng(11)
    for problem in random_problems(rng, 10):
        for r in range(3):
            case_ = analyse_case(problem, r)
            if not (case_.determined and case_.well_conditioned):
                continue
            k = system_matrix(
                problem, case_.free.twist, case_.keep, problem.friction[case_.keep], 1
            )
            for a in rng.uniform(0, TAU, 5):
                direct = np.linalg.solve(k, problem.wrench(unit(a)))
                np.testing.assert_allclose(case_.forward.at(unit(a)), direct, rtol=1e-9, atol=1e-12)
                b0, big_b = problem.load_basis()
                single = solve_affine(k, b0 + big_b @ unit(a), np.zeros((3, 0)))
                np.testing.assert_allclose(single.a, direct, rtol=1e-9, atol=1e-12)


# --- partial ranges and pictures ----------------------------------------------------------------


def test_partial_ranges_block(tmp_path: Path) -> None:
    """x1 of the §7 block: lambda > 0 iff -cos(a) + mu sin(a) > 0, i.e. 90 - atan(mu) to
    270 - atan(mu) deg; both normal forces positive iff F_y < 0 (180-360 deg), since the
    moment balance fixes N1 / N2 = (0.03 + 0.03 mu) / (0.03 - 0.03 mu) > 0."""
    x1 = case(run_check(write_scene(tmp_path, block_scene())), "x1")
    t = np.degrees(np.arctan(0.1))
    assert x1.details["desired_motion_deg"] == [[pytest.approx(90 - t), pytest.approx(270 - t)]]
    assert x1.details["contacts_kept_deg"] == [[pytest.approx(180.0), pytest.approx(360.0)]]
    assert "diagnostic" not in run_check(write_scene(tmp_path, block_scene())).details


def test_plots_are_written(tmp_path: Path) -> None:
    """`kcheck check --plots` writes the analytical-2d PNG and SVG for a planar scene, and its
    picture against friction (kcheck_checks.pictures.friction)."""
    scene = write_scene(tmp_path, block_scene(name="Block §7"))
    plots = tmp_path / "plots"
    out = tmp_path / "out.json"
    args = ["check", str(scene), "--select", "analytical-2d", "--plots", str(plots)]
    args += ["--plot-format", "png,svg"]
    assert main([*args, "--format", "json", "-o", str(out)]) == 0
    png, svg = plots / "block-7-analytical-2d.png", plots / "block-7-analytical-2d.svg"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    assert "<svg" in svg.read_text()[:2000]
    against = [plots / f"block-7-analytical-2d-friction.{ext}" for ext in ("png", "svg")]
    written = sorted(json.loads(out.read_text())["scenes"][0]["plots"])
    assert written == sorted([str(png), str(svg), *map(str, against)])


# --- Painlevé-type cases (tests/kcheck/test_dynamics.py derives the onset by hand) -----------

ROD_MU_STAR = (-0.1 + np.sqrt(0.96)) / 1.9  # 0.46305: a = 0.2, b = 1, h = 0.1, k^2 = 0.01


def rod_scene(mu: float) -> dict[str, Any]:
    """The long light body of tests/kcheck/test_dynamics.py as a scene file (m)."""
    return {
        "version": 1,
        "name": "long light body",
        "units": "m",
        "body": {"mass": 1.0, "center_of_mass": [0, 0.1, 0], "inertia": 0.01},
        "supports": [
            {"name": "y1", "position": [-0.2, 0, 0], "normal": [0, 1, 0]},
            {"name": "y2", "position": [0.2, 0, 0], "normal": [0, 1, 0]},
            {"name": "x1", "position": [-1.0, 0.1, 0], "normal": [1, 0, 0]},
        ],
        "friction": mu,
        "load": {"magnitude": 1.0, "angle": 280.0},
    }


def test_painleve_case_is_ambiguous_and_fails(tmp_path: Path) -> None:
    """Below the hand-derived onset the y1 case has an ordinary outcome; above it the check
    reports `ambiguous` from that mu on, fails, and locates the finding at y1."""
    below = case(run_check(write_scene(tmp_path, rod_scene(0.4), "below")), "y1")
    assert below.outcome != "ambiguous" and "painleve_from_mu" not in below.details
    result = run_check(write_scene(tmp_path, rod_scene(0.6), "above"))
    y1 = case(result, "y1")
    assert y1.outcome == "ambiguous"
    assert y1.details["painleve_from_mu"] == pytest.approx(ROD_MU_STAR, rel=1e-12)
    assert y1.safe_ranges_deg == () and y1.limiting_friction is None
    assert result.status is Status.FAIL
    (finding,) = [f for f in result.findings if f.code == "ambiguous"]
    assert finding.field == ("supports", 0)
    assert finding.message.startswith("retract y1 → ambiguous")
    assert "from μ = 0.463 on (Painlevé)" in finding.message


def _batch_scenes() -> list[dict[str, Any]]:
    """Planar scenes of every kind `run_many` meets in a chunk: passing and failing loads,
    friction ranges (analysed one by one), gravity alone (the tolerated tilt), a torque,
    no friction, a design angle that fails."""
    out = [block_scene(load={"magnitude": 1.0, "angle": a}) for a in (200.0, 225.0, 250.0, 45.0)]
    out.append(block_scene(friction={"min": 0.05, "max": 0.15}))
    out.append(block_scene(friction=0.0))
    gravity = block_scene(gravity=[-4, -9, 0])
    del gravity["load"]
    out.append(gravity)
    out.append(block_scene(load={"magnitude": 1.0, "angle": 230.0, "torque": [0, 0, 0.004]}))
    moved = block_scene()
    moved["supports"][2]["position"] = [0, 45, 0]
    out.append(moved)
    return out


def test_run_many_equals_each_scene_alone(tmp_path: Path) -> None:
    """A worker's chunk checked at once (`run_many`: the cases' algebra of all its scenes
    stacked) gives each scene exactly the result it gets alone, bit for bit (run times
    aside); the stacking is the batch of tests/kcheck/test_batch.py."""
    inputs = []
    for i, data in enumerate(_batch_scenes()):
        scene = load_scene(write_scene(tmp_path, data, f"s{i}"))
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        options = AnalyticalOptions.model_validate({})
        inputs.append(Inputs(scene, mass, options))
    check = Analytical2D()
    together = check.run_many(inputs)
    alone = [check.run_many([each])[0] for each in inputs]
    assert {r.status for r in alone} >= {Status.PASS, Status.FAIL}
    for a, b in zip(together, alone, strict=True):
        assert repr(dataclasses.replace(a, runtime_s=0.0)) == repr(
            dataclasses.replace(b, runtime_s=0.0)
        )
