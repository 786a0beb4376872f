"""Placing the closing force: the caps in closed form over points, the symmetric optimum,
reproducibility and the friction range.

Reference values: the caps at a point must equal those kcheck's dynamics computes with the load
moved there (an independent path: a new problem and a new solve per point); the symmetric
three-groove coupling's optimum lies on its axis of symmetry and points into the coupling (the
3-fold symmetry makes the axis a critical line, and the margin falls off it: measured below).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from kcheck.analysis.candidates import BoxSampler, SurfaceSampler
from kcheck.analysis.cases import problem_for
from kcheck.analysis.suggest import (
    caps_at,
    point_caps,
    point_margins,
    search,
    with_load,
)
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.arcs import cap_margins
from kcheck.mechanics.deepest import most_robust_direction
from kcheck.mechanics.dynamics import analyse_case
from kcheck.mechanics.sphere import fibonacci_sphere
from kcheck.scene import load_scene
from tests.conftest import FIXTURES, PLANAR_SCENE

THREE_GROOVE = FIXTURES / "three-groove" / "coupling.kcheck.yaml"


@pytest.fixture(scope="module")
def three_groove():
    scene = load_scene(THREE_GROOVE)
    return scene, body_mass_properties(scene.body, scene.scale)


def test_caps_at_points_equal_a_fresh_solve(three_groove):
    scene, mass = three_groove
    caps = point_caps(problem_for(scene, mass))
    rng = np.random.default_rng(3)
    points = rng.uniform(-0.08, 0.08, (4, 3))
    coefficients = caps_at(caps, points)
    for point, c in zip(points, coefficients, strict=True):
        moved = problem_for(with_load(scene, point, np.array([0.0, 0.0, -1.0])), mass)
        fresh_a, fresh_c = [], []
        for r in range(6):
            case = analyse_case(moved, r)
            fresh_a.append(case.forward.a)
            fresh_c.append(case.forward.c)
        np.testing.assert_allclose(caps.a, np.concatenate(fresh_a), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(c, np.vstack(fresh_c), rtol=1e-10, atol=1e-12)


def test_point_margins_equal_one_point_at_a_time(three_groove):
    scene, mass = three_groove
    caps = point_caps(problem_for(scene, mass))
    points = np.random.default_rng(4).uniform(-0.05, 0.05, (7, 3))
    grid = fibonacci_sphere(300)
    best, index = point_margins(caps, points, grid)
    for p, m, i in zip(points, best, index, strict=True):
        each = cap_margins(caps.a, caps_at(caps, p[None])[0], grid)
        assert m == each.max() and each[i] == m


def test_symmetric_three_groove_optimum_is_on_the_axis(three_groove):
    scene, mass = three_groove
    found = search(scene, mass, SurfaceSampler(scene, seed=1), 400, directions=300, keep=3)
    best = found.best[0]
    # on the axis (the bottom face's centre, 6.5 mm up), pointing down into the coupling
    assert np.hypot(*best.point[:2]) < 1e-6 and best.point[2] == pytest.approx(6.5e-3)
    assert best.direction @ np.array([0.0, 0.0, -1.0]) > np.cos(np.radians(0.01))
    # its margin is the exact optimum over directions there, and 3 mm off the axis is worse
    caps = point_caps(problem_for(scene, mass))

    def robust(point):
        return most_robust_direction(caps.a, caps_at(caps, np.array([point]))[0])[1]

    assert best.margin == pytest.approx(robust([0, 0, 6.5e-3]), abs=1e-8)
    assert robust([3e-3, 0, 6.5e-3]) < best.margin - np.radians(1)
    assert robust([0, 3e-3, 6.5e-3]) < best.margin - np.radians(1)
    assert 0 < best.limiting_friction < 1 and best.pushes is False  # pulls the bottom face
    # distinct candidates, best first
    assert [c.margin for c in found.best] == sorted((c.margin for c in found.best), reverse=True)


def test_box_grid_through_the_axis_finds_it(three_groove):
    scene, mass = three_groove
    sampler = BoxSampler(np.array([-0.02, -0.02, 0.03]), np.array([0.02, 0.02, 0.03]), 81, 0)
    found = search(scene, mass, sampler, 81, directions=300, keep=1, rounds=0)
    assert np.hypot(*found.best[0].point[:2]) < 1e-12
    assert found.best[0].direction[2] == pytest.approx(-1.0, abs=1e-8)


def test_seeded_and_parallel_runs_agree(three_groove):
    scene, mass = three_groove
    runs = [
        search(scene, mass, SurfaceSampler(scene, seed=7), 200, directions=100, keep=2, jobs=j)
        for j in (1, 2, 1)
    ]
    for other in runs[1:]:
        np.testing.assert_array_equal(runs[0].points, other.points)
        np.testing.assert_array_equal(runs[0].margins, other.margins)
        assert runs[0].best[0].margin == other.best[0].margin


def test_friction_range_is_safe_at_every_sampled_coefficient(three_groove):
    scene, mass = three_groove
    problem = problem_for(scene, mass)
    values = [0.05, 0.1, 0.2]
    sets = [np.full(6, v) for v in values]
    both = point_caps(problem, sets)
    point, direction = np.array([0.0, 0.0, 0.0065]), np.array([0.0, 0.0, -1.0])
    joint = cap_margins(both.a, caps_at(both, point[None])[0], direction[None])[0]
    singles = []
    for mu in sets:
        caps = point_caps(dataclasses.replace(problem, friction=mu))
        singles.append(cap_margins(caps.a, caps_at(caps, point[None])[0], direction[None])[0])
    assert joint == pytest.approx(min(singles), abs=1e-12)
    assert sorted(set(both.friction)) == values


def test_planar_caps_at_points_equal_a_fresh_solve(write_scene):
    """A planar scene is searched too: its arcs at each point are those kcheck's dynamics
    computes with the load moved there (a new problem and a new solve per point)."""
    scene = load_scene(write_scene(PLANAR_SCENE))
    mass = body_mass_properties(scene.body, scene.scale)
    caps = point_caps(problem_for(scene, mass))
    points = np.random.default_rng(5).uniform(-0.05, 0.1, (4, 3))
    for point, c in zip(points, caps_at(caps, points), strict=True):
        moved = problem_for(with_load(scene, point, np.array([0.0, -1.0, 0.0])), mass)
        fresh = [analyse_case(moved, r).forward for r in range(3)]
        np.testing.assert_allclose(caps.a, np.concatenate([f.a for f in fresh]), atol=1e-12)
        np.testing.assert_allclose(c, np.vstack([f.c for f in fresh]), rtol=1e-10, atol=1e-12)


def _closes_anywhere(scene, mass, magnitude: float, radius: float) -> float:
    """Convex relaxation, independent of suggest's search: the best scaled slack of the closing
    conditions of every case over ALL wrenches whose force has at most ``magnitude`` (400
    Fibonacci half-spaces around the unit ball: a superset of it) and whose moment about the
    centre of mass is at most ``radius`` (nondimensional) per component — every force acting
    within that distance of the centre of mass is among them. Negative: none closes."""
    from scipy.optimize import linprog

    loaded = with_load(scene, scene.load.point, scene.load.direction, magnitude)
    # Every case's conditions a + g . (r x d) + h . d > 0 for a force along d at r from the
    # centre of mass (the caps, tested against fresh solves above): a + g . M + h . F with
    # (M, F) the load's wrench about the centre of mass, per unit of ``magnitude``.
    cap = point_caps(problem_for(loaded, mass))
    wrench = np.hstack([cap.g, cap.h])  # condition a + g . (r x d) + h . d: M = r x d
    norm = np.linalg.norm(wrench, axis=1)
    ball = fibonacci_sphere(400)
    a_ub = np.vstack(
        [
            np.hstack([-wrench, norm[:, None]]),
            np.hstack([np.zeros((len(ball), 3)), ball, np.zeros((len(ball), 1))]),
        ]
    )
    b_ub = np.concatenate([cap.a, np.ones(len(ball))])
    bounds = [(-radius, radius)] * 3 + [(None, None)] * 3 + [(None, 1.0)]
    res = linprog(np.r_[np.zeros(6), -1.0], A_ub=a_ub, b_ub=b_ub, bounds=bounds)
    assert res.status == 0
    return float(-res.fun)


def test_no_force_of_10_newtons_closes_the_block_anywhere():
    """Issue 12's 3-2-1 block, 10 N (weight 67.5 N, μ = 0.11): not only does suggest find no
    safe placement on the surface — no force of at most 10 N acting anywhere within the
    block's bounding sphere closes every retraction (the relaxation above is infeasible), and
    not even of 15 N; the least force suggest reports (about 17 N) lies above that bound."""
    scene = load_scene(FIXTURES / "block-321" / "block.kcheck.yaml")
    mass = body_mass_properties(scene.body, scene.scale)
    problem = problem_for(scene, mass)
    corners = np.array(
        [[x, y, z] for x in (0, 0.2) for y in (0, 0.15) for z in (0, 0.085)]
    )  # the 200 x 150 x 85 mm block
    radius = max(np.linalg.norm(problem.frame.point(p) - problem.com) for p in corners)
    assert _closes_anywhere(scene, mass, 10.0, radius) < 0
    assert _closes_anywhere(scene, mass, 15.0, radius) < 0
    assert _closes_anywhere(scene, mass, 20.0, radius) > 0  # the relaxation is not vacuous


def test_surface_samples_lie_on_the_placed_body():
    """Review of issue 13's picture fix: `kcheck suggest` sampled each part's raw file
    coordinates, in the scene's units, like the scene views did. The tool changer's plate is
    turned 180° about x by its `transform`; the samples now lie in the body's bounds as the
    mass properties compute them (transforms applied), and reach its top face."""
    scene = load_scene(FIXTURES / "tool-changer" / "tool.kcheck.yaml")
    assert scene.body is not None and scene.body.parts[0].rotation is not None
    lo, hi = body_mass_properties(scene.body).bounds
    points, _ = SurfaceSampler(scene, seed=1).initial(2000)
    assert np.all(points >= lo - 1e-9) and np.all(points <= hi + 1e-9)
    assert points[:, 2].max() == pytest.approx(hi[2], abs=1e-6)
