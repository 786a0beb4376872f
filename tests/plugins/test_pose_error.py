"""Issue 28: the seated pose error from manufacturing tolerances (`pose-error`).

References computed here, independently of the check's linear algebra:

* a symmetric three-vee whose first ball grows by ``dr``: that ball's centre rises by
  ``dr / cos(b)`` (``b`` the flank normals' angle from up), the other two stay put, so the
  body tilts about the line through their centres by ``dr / (cos(b) 1.5 R)`` (closed form);
* a full nonlinear re-solve of the seated pose (rotation and translation that keep every ball
  at its radius from its seat plane, scipy's least_squares) with perturbed balls and seats —
  the linear answer must agree to second order;
* a shift of every seat by one vector moves the body by that vector (or by its opposite when
  the seats are on the body), without rotation;
* for Gaussian errors the pose error is Gaussian with covariance ``T S Sigma S^T T^T`` (``T``
  the pose map, ``S`` the sensitivities): the Monte Carlo bounds must cover its exact mean
  square and quantiles in about the stated share of seeds.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from kcheck_checks.pose_error import (
    PoseError,
    PoseErrorOptions,
    load_sensitivities,
    sensitivities,
)
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation
from scipy.stats import norm

from kcheck.gate.runner import Settings, check_scene
from kcheck.mechanics.pose_error import (
    draw,
    mean_bounds,
    pose_errors,
    pose_map,
    quantile_bounds,
    sobol_draws,
)
from kcheck.plugin import Inputs, load_checks
from kcheck.result import Status
from tests.conftest import FIXTURES
from tests.couplings import ball_vee, coupling_scene, kelvin, three_vee

R, BALL, HALF = 0.05, 6e-3, 45.0
POINT_MM = [10.0, -20.0, 30.0]


def _scene(tmp_path, contacts, **options):
    return coupling_scene(tmp_path, contacts, {"checks": {"pose-error": options}})


def _arrays(scene):
    p = np.array([s.position for s in scene.supports])
    n = np.array([s.normal for s in scene.supports])
    return p, n


def _delta(scene, opts, values):
    """Contact separations for given error values per source (name -> vector)."""
    total = np.zeros(len(scene.supports))
    for name, matrix, _ in sensitivities(scene, opts):
        total += matrix @ values[name]
    return total


def test_three_vee_ball_radius_closed_form(tmp_path):
    scene = _scene(tmp_path, three_vee(R, BALL, HALF), ball_radius_um=1.0)
    opts = PoseErrorOptions(ball_radius_um=1.0)
    p, n = _arrays(scene)
    q = np.array(POINT_MM) * 1e-3
    pose = pose_map(p, n, q)
    dr = 1e-6
    delta = _delta(scene, opts, {"ball radius": np.array([dr, 0.0, 0.0])})
    trans, rot = pose_errors(pose, delta[None])
    # g1's ball is at (0, R, 0); the axis through g2 and g3 is the line y = -R/2, z = 0 along x.
    phi = dr / np.cos(np.radians(HALF)) / (1.5 * R)
    expected_rot = np.array([phi, 0.0, 0.0])
    expected_trans = phi * np.array([0.0, -q[2], q[1] + R / 2])
    np.testing.assert_allclose(rot[0], expected_rot, atol=1e-12 * phi)
    np.testing.assert_allclose(trans[0], expected_trans, atol=1e-12 * dr)
    assert pose.condition < 100


def _rot(w):
    return Rotation.from_rotvec(w).as_matrix()


def _pivot(normals, points, i):
    """The point of the seat's planes' intersection nearest contact ``i``: a vee's root (the
    two planes plus the plane through p_i across the root line), a trihedral's apex, a flat's
    own contact point."""
    if len(normals) == 1:
        return points[0]
    if len(normals) == 2:
        d = np.cross(normals[0], normals[1])
        a = np.array([normals[0], normals[1], d])
        b = np.array([normals[0] @ points[0], normals[1] @ points[1], d @ points[i]])
        return np.linalg.solve(a, b)
    return np.linalg.solve(
        np.array(normals[:3]), [m @ x for m, x in zip(normals, points, strict=True)]
    )


def _nonlinear_pose(scene, q, ball_shift, radius, seat_shift, seat_turn):
    """The seated pose's displacement of body point ``q`` (and rotation vector), solved
    exactly: each ball at its radius from its (moved) seat plane. Errors per coupling name."""
    groups: dict[str, list[int]] = {}
    for i, s in enumerate(scene.supports):
        groups.setdefault(s.geometry.coupling, []).append(i)
    contacts = []
    for name, idx in groups.items():
        g0 = scene.supports[idx[0]].geometry
        # the seat plane's normal towards the ball centre (in the seat's own frame)
        towards = [scene.supports[i].normal * (1 if g0.ball_on == "body" else -1) for i in idx]
        pts = [scene.supports[i].position for i in idx]
        for k in range(len(idx)):
            pivot = _pivot(towards, pts, k)
            turn = _rot(seat_turn[name])
            m = turn @ towards[k]
            a = pivot + turn @ (pts[k] - pivot) + seat_shift[name]
            c = g0.ball_center + ball_shift[name]
            contacts.append((g0.ball_on, c, g0.ball_radius + radius[name], m, a))

    def residual(x):
        rot, t = _rot(x[:3]), x[3:] * R
        out = []
        for on, c, r, m, a in contacts:
            if on == "body":
                c = rot @ c + t
            else:
                m, a = rot @ m, rot @ a + t
            out.append((m @ (c - a) - r) / R)
        return out

    sol = least_squares(residual, np.zeros(6), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    rot, t = _rot(sol.x[:3]), sol.x[3:] * R
    return rot @ q + t - q, sol.x[:3]


@pytest.mark.parametrize("layout", ["kelvin", "vee-on-base"])
def test_linear_pose_matches_the_nonlinear_seat(tmp_path, layout):
    if layout == "kelvin":
        contacts = kelvin(R, BALL, HALF)
    else:  # balls on the base, grooves on the body
        contacts = []
        for k in range(3):
            phi = np.radians(90 + 120 * k)
            c = R * np.array([np.cos(phi), np.sin(phi), 0.0])
            contacts += ball_vee(f"g{k + 1}", c, BALL, c, HALF, ball_on="base")
    scene = _scene(tmp_path, contacts)
    names = list(dict.fromkeys(s.geometry.coupling for s in scene.supports))
    rng = np.random.default_rng(3)
    size = 1e-6
    ball_shift = {n: rng.normal(0, size, 3) for n in names}
    radius = {n: rng.normal(0, size) for n in names}
    seat_shift = {n: rng.normal(0, size, 3) for n in names}
    seat_turn = {n: rng.normal(0, size / R, 3) for n in names}
    opts = PoseErrorOptions(
        ball_position_um=1, ball_radius_um=1, seat_position_um=1, seat_angle_urad=1
    )
    values = {
        "ball position": np.concatenate([ball_shift[n] for n in names]),
        "ball radius": np.array([radius[n] for n in names]),
        "seat position": np.concatenate([seat_shift[n] for n in names]),
        "seat angle": np.concatenate([seat_turn[n] for n in names]),
    }
    q = np.array(POINT_MM) * 1e-3
    p, n = _arrays(scene)
    trans, rot = pose_errors(pose_map(p, n, q), _delta(scene, opts, values)[None])
    exact, exact_rot = _nonlinear_pose(scene, q, ball_shift, radius, seat_shift, seat_turn)
    # second-order residue: (size / R) of the first-order answer, with room
    assert np.linalg.norm(trans[0]) > 0.3 * size
    np.testing.assert_allclose(trans[0], exact, atol=1e-3 * size)
    np.testing.assert_allclose(rot[0], exact_rot, atol=1e-3 * size / R)


@pytest.mark.parametrize("ball_on", ["body", "base"])
def test_group_shift_is_a_pure_translation(tmp_path, ball_on):
    contacts = []
    for k in range(3):
        phi = np.radians(90 + 120 * k)
        c = R * np.array([np.cos(phi), np.sin(phi), 0.0])
        contacts += ball_vee(f"g{k + 1}", c, BALL, c, HALF, ball_on=ball_on)
    scene = _scene(tmp_path, contacts)
    group = {"name": "mill", "couplings": ["g1", "g2", "g3"], "position_um": 1.0}
    opts = PoseErrorOptions.model_validate({"groups": [group]})
    d = np.array([1.0, -2.0, 0.5]) * 1e-6
    p, n = _arrays(scene)
    for q in (np.zeros(3), np.array([0.3, -0.1, 0.2])):
        trans, rot = pose_errors(
            pose_map(p, n, q), _delta(scene, opts, {"group mill position": d})[None]
        )
        sign = 1.0 if ball_on == "body" else -1.0  # seats on the body carry the body back
        np.testing.assert_allclose(trans[0], sign * d, atol=1e-15)
        np.testing.assert_allclose(rot[0], 0.0, atol=1e-12)


def test_monte_carlo_bounds_cover_the_gaussian_truth(tmp_path):
    scene = _scene(tmp_path, kelvin(R, BALL, HALF))
    opts = PoseErrorOptions(ball_radius_um=1.0, seat_position_um=2.0, seat_angle_urad=30.0)
    q = np.array(POINT_MM) * 1e-3
    p, n = _arrays(scene)
    pose = pose_map(p, n, q)
    sources = sensitivities(scene, opts)
    cov = sum(tol**2 * m @ m.T for _, m, tol in sources)
    c_t = pose.translation @ cov @ pose.translation.T
    mean_square = np.trace(c_t)  # E|e|^2, exact
    q95 = np.sqrt(c_t[0, 0]) * norm.ppf(0.9)  # the exact 0.9 quantile of e_x
    z = norm.ppf(0.975)
    covered_mean = covered_q = 0
    seeds = 40
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        delta = sum(
            draw(rng, 4000, np.full(m.shape[1], tol), "normal") @ m.T for _, m, tol in sources
        )
        trans, _ = pose_errors(pose, delta)
        _, _, lo, hi = mean_bounds(np.sum(trans**2, axis=1), z)
        covered_mean += lo <= mean_square <= hi
        _, qlo, qhi = quantile_bounds(trans[:, 0], 0.9, 0.95)
        covered_q += qlo <= q95 <= qhi
    # 95% bounds: 38 of 40 expected; fewer than 34 has probability below 1% (binomial)
    assert covered_mean >= 34
    assert covered_q >= 34


def _run(scene, **options):
    return PoseError().run(Inputs(scene, None, PoseErrorOptions.model_validate(options)))


def test_check_reports_and_judges(tmp_path):
    base = {"point": POINT_MM, "ball_radius_um": 1.0, "seat_position_um": 2.0, "samples": 2000}
    scene = _scene(tmp_path, kelvin(R, BALL, HALF), **base)
    assert PoseError().skip_reason(scene) is None
    unjudged = _run(scene, **base)
    assert unjudged.status is Status.SKIPPED and "not judged" in unjudged.message
    t = unjudged.details["translation_um"]
    assert t["quantile_bounds"][0] <= t["quantile"] <= t["quantile_bounds"][1]
    assert t["mean_bounds"][0] <= t["mean"] <= t["mean_bounds"][1]
    assert unjudged.error_estimate is not None and unjudged.error_estimate > 0
    loose = _run(scene, **base, allowed_translation_um=10 * t["quantile"])
    assert loose.status is Status.PASS
    tight = _run(scene, **base, allowed_translation_um=0.5 * t["quantile"])
    assert tight.status is Status.FAIL and tight.findings[0].code == "pose-error"
    # the same seed repeats
    assert _run(scene, **base).details["translation_um"] == t


def _kelvin_fixture(folder: Path, checks: str = "") -> Path:
    """fixtures/kelvin (real mesh) with a `checks:` block appended."""
    source = FIXTURES / "kelvin"
    shutil.copy(source / "top-plate.stl", folder / "top-plate.stl")
    text = (source / "coupling.kcheck.yaml").read_text(encoding="utf-8") + checks
    path = folder / "coupling.kcheck.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def _ids(path: Path, settings: Settings | None = None) -> dict[str, Status]:
    result = check_scene(path, load_checks(), settings=settings)
    return {c.id: c.status for c in result.checks}


def test_check_is_opt_in(tmp_path):
    plain = _kelvin_fixture(tmp_path)
    assert "pose-error" not in _ids(plain)  # not asked for: not run, not listed
    assert _ids(plain, Settings(named=frozenset({"pose-error"})))["pose-error"] is Status.SKIPPED
    configured = Settings(check_options={"pose-error": {"point": POINT_MM}})
    assert _ids(plain, configured)["pose-error"] is Status.SKIPPED  # no tolerance given
    asked = _kelvin_fixture(
        tmp_path, "checks:\n  pose-error: {point: [0, 0, 50], ball_radius_um: 1, samples: 500}\n"
    )
    assert _ids(asked)["pose-error"] is Status.SKIPPED  # numbers, not judged
    judged = _kelvin_fixture(
        tmp_path,
        "checks:\n  pose-error: {point: [0, 0, 50], ball_radius_um: 1, samples: 500, "
        "allowed_translation_um: 100, allowed_rotation_urad: 1000}\n",
    )
    assert _ids(judged)["pose-error"] is Status.PASS


def test_check_says_what_is_missing(tmp_path):
    scene = _scene(tmp_path, kelvin(R, BALL, HALF), ball_radius_um=1.0)
    no_point = _run(scene, ball_radius_um=1.0)
    assert no_point.status is Status.SKIPPED and "point" in no_point.message
    nothing = _run(scene, point=POINT_MM)
    assert nothing.status is Status.SKIPPED and "no tolerance" in nothing.message
    bad = _run(scene, point=POINT_MM, groups=[{"name": "x", "couplings": ["nope"]}])
    assert bad.status is Status.SKIPPED and "nope" in bad.message


def test_load_tolerance_sinks_a_three_vee_by_the_hertz_closed_form(tmp_path):
    """A three-vee under a central vertical load F: each of the six contacts carries
    N0 = F / (6 cos b); a ball on a flat has k = dN/d(approach) = 2 E* a with
    a = (3 N0 r / (4 E*))^(1/3) (Johnson §4.2, circular contact); one per cent more load sinks
    every contact by 0.01 N0 / k, the body straight down by that over cos b, without turning.
    52100 on 52100: E = 210 GPa, nu = 0.30 (docs/materials.md)."""
    force = 100.0
    load = {"point": [0, 0, 0], "magnitude": force, "direction": [0, 0, -1]}
    scene = coupling_scene(
        tmp_path, three_vee(R, BALL, HALF), {"load": load, "checks": {"pose-error": {}}}
    )
    opts = PoseErrorOptions(load_percent=1.0, ball_material="52100", seat_material="52100")
    sources, why = load_sensitivities(scene, None, opts)
    assert why is None and [s[0] for s in sources] == ["load"]
    _, matrix, tol = sources[0]
    e_star = 210e9 / (2 * (1 - 0.30**2))
    cos_b = np.cos(np.radians(HALF))
    n0 = force / (6 * cos_b)
    k = 2 * e_star * np.cbrt(3 * n0 * BALL / (4 * e_star))
    p, n = _arrays(scene)
    trans, rot = pose_errors(pose_map(p, n, np.array([0.01, 0.02, 0.03])), tol * matrix.T)
    np.testing.assert_allclose(trans[0], [0, 0, -0.01 * n0 / (k * cos_b)], rtol=1e-9, atol=1e-18)
    np.testing.assert_allclose(rot[0], 0.0, atol=1e-15)
    result = _run(scene, point=[0, 0, 0], **opts.model_dump(exclude_defaults=True))
    assert result.status is Status.SKIPPED and "load" in result.details["sources"]
    # |translation| = |z| ~ |N(0, s^2)|: its mean is s sqrt(2 / pi) (within the CLT bounds)
    s = 0.01 * n0 / (k * cos_b) / 1e-6
    lo, hi = result.details["translation_um"]["mean_bounds"]
    assert lo <= s * np.sqrt(2 / np.pi) <= hi


def test_load_tolerance_needs_materials(tmp_path):
    load = {"point": [0, 0, 0], "magnitude": 100.0, "direction": [0, 0, -1]}
    scene = coupling_scene(tmp_path, three_vee(R, BALL, HALF), {"load": load})
    result = _run(scene, point=[0, 0, 0], load_percent=1.0)
    assert result.status is Status.SKIPPED and "material" in result.message
    no_weight = _run(
        scene, point=[0, 0, 0], mass_percent=1.0, ball_material="52100", seat_material="52100"
    )
    assert no_weight.status is Status.SKIPPED and "weight" in no_weight.message


def test_select_names_an_opt_in_check_on_the_command_line(tmp_path):
    import json
    import subprocess
    import sys

    plain = _kelvin_fixture(tmp_path)
    args = [sys.executable, "-m", "kcheck", "check", str(plain), "--format", "json", "-j", "1"]

    def ids(*extra: str) -> list[str]:
        run = subprocess.run([*args, *extra], capture_output=True, text=True, timeout=120)
        return [c["id"] for c in json.loads(run.stdout)["scenes"][0]["checks"]]

    assert "pose-error" not in ids()
    assert ids("--select", "pose-error") == ["pose-error"]


def test_sobol_draws_reach_the_gaussian_truth(tmp_path):
    """Scrambled Sobol points (samples rounded up to 2^k) estimate the exact mean square
    tr(T S Sigma S^T T^T) closely, and the reported bounds (those of independent draws)
    cover it."""
    base = {"point": POINT_MM, "ball_radius_um": 1.0, "seat_angle_urad": 30.0}
    scene = _scene(tmp_path, kelvin(R, BALL, HALF), **base)
    result = _run(scene, **base, samples=5000, sampler="sobol")
    assert result.details["samples"] == 8192
    opts = PoseErrorOptions.model_validate(base)
    pose = pose_map(*_arrays(scene), np.array(POINT_MM) * 1e-3)
    sources = sensitivities(scene, opts)
    cov = sum(tol**2 * m @ m.T for _, m, tol in sources)
    exact = np.trace(pose.translation @ cov @ pose.translation.T)
    scale = np.concatenate([np.full(m.shape[1], tol) for _, m, tol in sources])
    x, count = sobol_draws(1, 4096, scale, "normal")
    delta = x @ np.hstack([m for _, m, _ in sources]).T
    trans, _ = pose_errors(pose, delta)
    _, _, lo, hi = mean_bounds(np.sum(trans**2, axis=1), norm.ppf(0.975))
    assert count == 4096 and lo <= exact <= hi
    assert abs(np.mean(np.sum(trans**2, axis=1)) / exact - 1) < 0.02
