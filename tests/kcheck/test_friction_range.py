"""Friction ranges (kcheck.mechanics.friction_range, kcheck.analysis.friction_ranges) against dense
brute force.

The brute force solves the equations of motion directly at many coefficients of the range —
one LU solve per coefficient (``K(t) x = b0 + B d``), the outcome rule on the solution, the
effective masses from determinants — and intersects over them. It shares with the code under
test only the system matrices of :mod:`kcheck.mechanics.dynamics`; the code under test never solves
at a sampled coefficient (Cramer polynomials, real roots, envelopes).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from kcheck.analysis.friction_ranges import design_margins, failing_intervals, worst_parameter
from kcheck.mechanics.arcs import TAU
from kcheck.mechanics.caps import region
from kcheck.mechanics.dynamics import Problem, analyse_cases, build_problem, friction_matrices
from kcheck.mechanics.friction import friction_intervals
from kcheck.mechanics.friction_range import FrictionPath, range_arcs, range_caps, range_cases
from kcheck.mechanics.outcomes import safe_arcs
from kcheck.mechanics.sphere import fibonacci_sphere


def random_problem(rng: np.random.Generator, dim: int, far_load: bool = False) -> Problem:
    """A random coupling: normals roughly towards the supports' centroid, a compact body, the
    load somewhere around (or far outside: friction then moves the range ends most)."""
    k = 3 if dim == 2 else 6
    points = np.zeros((k, 3))
    points[:, :dim] = rng.uniform(-1, 1, (k, dim))
    normals = np.zeros((k, 3))
    normals[:, :dim] = -points[:, :dim] + rng.normal(size=(k, dim)) * 0.8
    cloud = rng.normal(size=(8, 3)) * 0.3
    cloud -= cloud.mean(axis=0)
    inertia = sum(np.dot(x, x) * np.eye(3) - np.outer(x, x) for x in cloud) / 8
    load = np.zeros(3)
    load[:dim] = rng.uniform(-1, 1, dim) * (3.0 if far_load else 1.0)
    com = np.zeros(3)
    com[:dim] = rng.uniform(-0.3, 0.3, dim)
    return build_problem(
        points=points,
        normals=normals,
        friction=np.zeros(k),
        names=tuple(f"s{j}" for j in range(k)),
        dim=dim,
        mass=1.0,
        com=com,
        inertia=inertia,
        gravity=np.zeros(3),
        load_magnitude=1.0,
        load_point=load,
        torque=np.zeros(3),
    )


def random_path(
    rng: np.random.Generator, k: int, uniform: bool, wide: bool = False
) -> FrictionPath:
    low = rng.uniform(0.0, 0.3, 1 if uniform else k) * np.ones(k)
    high = low + rng.uniform(0.05, 1.5 if wide else 0.8, 1 if uniform else k) * np.ones(k)
    return FrictionPath(low, high)


def brute_closes(
    problem: Problem, r: int, path: FrictionPath, ts: np.ndarray, dirs: np.ndarray
) -> np.ndarray:
    """(t, q): whether case ``r`` closes at each coefficient ``t`` and direction, by direct
    solves: forward lambda > 0 and every normal force > 0, effective masses positive."""
    case = analyse_cases(problem, [r])[0]
    f_low = friction_matrices(problem, [case], path.low)[0]
    f_span = friction_matrices(problem, [case], path.high - path.low)[0]
    k0 = case.k0
    b0, big_b = problem.load_basis()
    forward = k0 + f_low + ts[:, None, None] * f_span
    backward = k0 - f_low - ts[:, None, None] * f_span
    x = np.linalg.solve(
        forward,
        np.broadcast_to(np.column_stack([b0, big_b]), forward.shape[:2] + (1 + problem.dim,)),
    )
    values = x[:, None, :, 0] + dirs @ np.swapaxes(x[:, :, 1:], 1, 2)  # (t, q, k)
    sign0 = np.sign(np.linalg.det(k0))
    painleve = (np.sign(np.linalg.det(forward)) != sign0) | (
        np.sign(np.linalg.det(backward)) != sign0
    )
    return np.all(values > 0, axis=2) & ~painleve[:, None]


def inside(arcs, angles: np.ndarray) -> np.ndarray:
    ok = np.zeros(len(angles), bool)
    for s, e in arcs:
        ok |= ((angles - s) % TAU) <= (e - s)
    return ok


def _probe_ends(problem, r, path, arcs) -> np.ndarray:
    """Brute-force decisions at 1e-7 rad inside and outside every bounded arc end, with 4001
    coefficients: ``[True, False, True, False]`` per arc when the ends are right."""
    bounded = [arc for arc in arcs if arc[1] - arc[0] < TAU]
    probes = np.array([[s + 1e-7, s - 1e-7, e - 1e-7, e + 1e-7] for s, e in bounded]).ravel()
    dirs = np.stack([np.cos(probes), np.sin(probes)], axis=1)
    return np.all(brute_closes(problem, r, path, np.linspace(0, 1, 4001), dirs), axis=0)


def _tag(tags: dict[float, float], end: float) -> float:
    return min(tags.items(), key=lambda kv: abs((kv[0] - end + np.pi) % TAU - np.pi))[1]


def test_range_arcs_are_the_intersection_over_the_range():
    """100 random planar scenes (half with coefficients that differ per support, half with the
    load far out and wide ranges): the exact arcs against 201 coefficients x 720 angles, and
    every arc end against 4001 coefficients just inside and just outside it (1e-7 rad)."""
    rng = np.random.default_rng(7)
    e1, e2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    angles = (np.arange(720) + 0.5) * TAU / 720
    dirs = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    coarse = np.linspace(0, 1, 201)
    compared = ends = 0
    for trial in range(100):
        problem = random_problem(rng, 2, far_load=trial % 2 == 1)
        path = random_path(rng, 3, uniform=trial % 4 < 2, wide=trial % 2 == 1)
        cases = analyse_cases(problem)
        for r, rc in enumerate(range_cases(problem, cases, path)):
            if rc is None or not cases[r].well_conditioned:
                continue
            arcs, _ = range_arcs(rc, e1, e2)
            expected = np.all(brute_closes(problem, r, path, coarse, dirs), axis=0)
            got = inside(arcs, angles)
            near = np.zeros(len(angles), bool)
            for s, e in arcs:
                for end in (s, e):
                    near |= np.abs((angles - end + np.pi) % TAU - np.pi) < 1e-3
            # far from the ends: identical; near them only the grid of coefficients may be off
            assert np.array_equal(got[~near], expected[~near]), (trial, r)
            compared += int(np.count_nonzero(~near))
            bounded = [arc for arc in arcs if arc[1] - arc[0] < TAU]
            if bounded:
                decided = _probe_ends(problem, r, path, arcs)
                assert decided.tolist() == [True, False, True, False] * len(bounded), (trial, r)
                ends += 2 * len(bounded)
    assert compared > 100_000 and ends > 200


def test_envelope_ends_inside_the_range():
    """Arc ends that bind at a coefficient inside the range (an envelope: the end turns back),
    found among random scenes with the load far out: each is right to 1e-7 rad against 4001
    coefficients, and the ends of the range alone would have put it elsewhere."""
    rng = np.random.default_rng(17)
    e1, e2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    found = 0
    for _ in range(3000):
        problem = random_problem(rng, 2, far_load=True)
        path = random_path(rng, 3, uniform=bool(rng.uniform() < 0.5), wide=True)
        cases = analyse_cases(problem)
        for r, rc in enumerate(range_cases(problem, cases, path)):
            if rc is None or not cases[r].well_conditioned:
                continue
            arcs, tags = range_arcs(rc, e1, e2)
            bounded = [arc for arc in arcs if arc[1] - arc[0] < TAU]
            # an end binding inside the range, and the direction just outside it
            inner = [
                (end, end + sign * 1e-7)
                for arc in bounded
                for end, sign in zip(arc, (-1.0, 1.0), strict=True)
                if 0.0 < _tag(tags, end) < 1.0
            ]
            if not inner:
                continue
            decided = _probe_ends(problem, r, path, arcs)
            assert decided.tolist() == [True, False, True, False] * len(bounded)
            out = np.array([o for _, o in inner])
            out_dirs = np.stack([np.cos(out), np.sin(out)], axis=1)
            # just outside: it still closes at both ends of the range, not throughout
            at_ends = brute_closes(problem, r, path, np.array([0.0, 1.0]), out_dirs)
            assert np.all(at_ends)
            found += len(inner)
        if found >= 12:
            break
    assert found >= 12


def test_uniform_range_verdict_is_the_friction_intervals():
    """With one common coefficient the range closes throughout exactly when it lies inside one
    of the case's friction intervals (kcheck.mechanics.friction, an independent exact computation),
    and it fails exactly on the rest of the range. The design direction is one that closes at the
    middle of the range, so both verdicts occur."""
    rng = np.random.default_rng(11)
    checked = failing = 0
    for _ in range(200):
        problem = random_problem(rng, int(rng.choice([2, 3])))
        k = len(problem.names)
        lo, hi = sorted(rng.uniform(0.0, 1.0, 2))
        path = FrictionPath(np.full(k, lo), np.full(k, hi))
        scaled = dataclasses.replace(problem, friction=np.full(k, hi))
        cases = analyse_cases(scaled)
        for r, rc in enumerate(range_cases(problem, cases, path)):
            if rc is None or not cases[r].well_conditioned:
                continue
            tries = rng.normal(size=(64, problem.dim))
            tries /= np.linalg.norm(tries, axis=1, keepdims=True)
            good = np.flatnonzero(rc.closing_at(tries, np.array([0.0]))[:, 0])
            if not len(good):
                continue
            design = tries[good[0]]
            intervals = friction_intervals(scaled, cases[r], design).intervals
            # the part of [lo, hi] the intervals do not cover
            rest, start = [], lo
            for a, b in intervals:
                if b < lo or a > hi:
                    continue
                if a > start:
                    rest.append((start, a))
                start = max(start, b)
            if start < hi:
                rest.append((start, hi))
            fails = [
                (lo + a * (hi - lo), lo + b * (hi - lo)) for a, b in failing_intervals(rc, design)
            ]
            assert bool(rc.closes(design)[0]) == (not rest)
            assert len(fails) == len(rest), (fails, rest)
            for (a, b), (c, d) in zip(fails, rest, strict=True):
                assert a == pytest.approx(c, abs=1e-9) and b == pytest.approx(d, abs=1e-9)
            checked += 1
            failing += bool(rest)
    assert checked > 150 and 0.2 * checked < failing < 0.8 * checked


def test_worst_margin_is_the_margin_to_the_range_arcs():
    """Where the design direction closes throughout, its least margin over the range (closed
    form, golden section) equals its exact distance to the range arcs' nearest end."""
    rng = np.random.default_rng(5)
    e1, e2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    compared = 0
    for trial in range(120):
        problem = random_problem(rng, 2, far_load=trial % 2 == 1)
        path = random_path(rng, 3, uniform=True)
        cases = analyse_cases(problem)
        for rc in range_cases(problem, cases, path):
            if rc is None:
                continue
            arcs, _ = range_arcs(rc, e1, e2)
            for s, e in arcs:
                if e - s >= TAU:
                    continue
                angle = s + rng.uniform(0.1, 0.9) * (e - s)
                design = np.array([np.cos(angle), np.sin(angle)])
                t, margin = worst_parameter(rc, design)
                exact = min(angle - s, e - angle)
                assert margin == pytest.approx(exact, abs=1e-9)
                assert design_margins(rc, design, np.array([2 * t - 1]))[0] == pytest.approx(margin)
                compared += 1
    assert compared > 100


def test_a_fixed_path_gives_the_single_coefficient_arcs():
    rng = np.random.default_rng(3)
    e1, e2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    for _ in range(30):
        problem = random_problem(rng, 2)
        mu = rng.uniform(0, 0.6)
        path = FrictionPath(np.full(3, mu), np.full(3, mu))
        cases = analyse_cases(dataclasses.replace(problem, friction=np.full(3, mu)))
        for case, rc in zip(cases, range_cases(problem, cases, path), strict=True):
            if rc is None or not case.well_conditioned:
                continue
            single, _ = safe_arcs(case, e1, e2)
            ranged, _ = range_arcs(rc, e1, e2)
            assert len(single) == len(ranged)
            for (a, b), (c, d) in zip(single, ranged, strict=True):
                assert (a % TAU, (b - a)) == pytest.approx((c % TAU, (d - c)), abs=1e-9)


def test_range_caps_on_the_sphere_against_brute_force():
    """Spatial: directions classified by the range caps against direct solves at 201
    coefficients; they may differ only within the stated boundary error of the caps (plus
    what the grid of coefficients misses), and the area agrees with a lattice count."""
    rng = np.random.default_rng(2)
    dirs = fibonacci_sphere(4000)
    ts = np.linspace(0, 1, 201)
    nonempty = 0
    for _ in range(25):
        problem = random_problem(rng, 3)
        path = random_path(rng, 6, uniform=True)
        cases = analyse_cases(problem)
        for r, rc in enumerate(range_cases(problem, cases, path)):
            if rc is None or not cases[r].well_conditioned:
                continue
            a, c, error = range_caps(rc)
            margin = (
                np.min(
                    np.arccos(np.clip(-a / np.linalg.norm(c, axis=1), -1, 1))[None]
                    - np.arccos(np.clip(dirs @ c.T / np.linalg.norm(c, axis=1), -1, 1)),
                    axis=1,
                )
                if np.any(np.linalg.norm(c, axis=1) > 0)
                else np.full(len(dirs), -np.pi)
            )
            expected = np.all(brute_closes(problem, r, path, ts, dirs), axis=0)
            differ = (margin > 0) != expected
            assert not np.any(differ & (np.abs(margin) > error + 2e-3)), (r, error)
            share = region(a, c).fraction
            assert share == pytest.approx(expected.mean(), abs=0.02)
            nonempty += share > 0
    assert nonempty >= 10
