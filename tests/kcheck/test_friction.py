"""Friction intervals (kcheck.mechanics.friction) against 50-digit polynomial roots and closed
forms.

The reference: ``det(A0 + mu A1)`` as a polynomial, interpolated from mpmath determinants at
n + 1 points (50 digits), and its roots from ``mpmath.polyroots`` — no eigenvalues, no numpy.
The pencils are the same double-precision matrices kcheck builds, so the comparison measures
kcheck's root finding (numpy only: shifted eigenvalues) and the interval logic.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest
from mpmath import mp, mpf

from kcheck.mechanics.dynamics import analyse_cases, build_problem
from kcheck.mechanics.friction import (
    FrictionIntervals,
    _pencils,
    describe_friction,
    friction_intervals,
    pencil_roots,
)


@pytest.fixture(autouse=True)
def _fifty_digits():
    """The 50-digit references of this module, whatever another module set (mpmath's
    precision is global)."""
    with mp.workdps(50):
        yield


def mp_roots(a0: np.ndarray, a1: np.ndarray) -> list[Any]:
    """Real roots of det(A0 + mu A1), 50 digits: interpolation at mu = 0..n, polyroots."""
    n = a0.shape[0]
    xs = [mpf(k) for k in range(n + 1)]
    ys = [mp.det(mp.matrix(a0.tolist()) + x * mp.matrix(a1.tolist())) for x in xs]
    vander = mp.matrix([[x**j for j in range(n + 1)] for x in xs])
    coef = mp.lu_solve(vander, mp.matrix(ys))
    coeffs = [coef[j] for j in range(n + 1)]  # ascending powers
    scale = max(abs(c) for c in coeffs)
    while coeffs and abs(coeffs[-1]) <= mpf(10) ** -40 * scale:
        coeffs = coeffs[:-1]  # degree drops when A1 is singular
    if len(coeffs) < 2:
        return []
    roots = mp.polyroots(coeffs, maxsteps=200, extraprec=200, asc=True)
    return [r.real for r in roots if abs(mp.im(r)) <= mpf(10) ** -25 * (1 + abs(r))]


def test_pencil_roots_equal_polynomial_roots() -> None:
    rng = np.random.default_rng(12)
    compared = 0
    for n in (3, 6):
        for _ in range(15):
            a0, a1 = rng.normal(size=(n, n)), rng.normal(size=(n, n))
            if rng.uniform() < 0.3:
                a1[:, 0] = 0.0  # a column without friction: A1 singular, roots at infinity
            ours = pencil_roots(a0[None], a1[None])[0]
            ours = np.sort(ours[np.isfinite(ours)])
            ref = sorted(float(r) for r in mp_roots(a0, a1))
            assert len(ours) == len(ref), (ours, ref)
            for x, y in zip(ours, ref, strict=True):
                assert x == pytest.approx(y, rel=1e-9, abs=1e-12)
                compared += 1
    assert compared > 40


def test_singular_pencil_has_no_roots() -> None:
    """An unknown that is zero for every mu (its Cramer matrix singular for every mu)."""
    a0 = np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [3.0, 1.0, 0.0]])
    a1 = np.array([[0.5, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 2.0, 0.0]])
    assert np.all(np.isnan(pencil_roots(a0[None], a1[None])))


def random_spatial(rng: np.random.Generator):
    points = rng.uniform(-1, 1, (6, 3))
    cloud = rng.normal(size=(8, 3)) * 0.3
    cloud -= cloud.mean(axis=0)
    inertia = sum(np.dot(x, x) * np.eye(3) - np.outer(x, x) for x in cloud) / 8
    return build_problem(
        points=points,
        normals=rng.normal(size=(6, 3)),
        friction=np.full(6, rng.uniform(0.05, 0.8)),
        names=tuple("abcdef"),
        dim=3,
        mass=1.0,
        com=rng.normal(size=3) * 0.3,
        inertia=inertia,
        gravity=rng.normal(size=3) * 3,
        load_magnitude=10.0,
        load_point=rng.normal(size=3) * 0.5,
        torque=np.zeros(3),
    )


def test_spatial_interval_ends_are_50_digit_roots() -> None:
    """Every finite end of every friction interval (and of every Painlevé interval) of random
    six-support cases is a real root of one of the case's determinant polynomials (K, or K
    with a column replaced by the right-hand side; for backward sliding at -mu), to 1e-9."""
    rng = np.random.default_rng(3)
    ends = 0
    for _ in range(3):
        problem = random_spatial(rng)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        for case in analyse_cases(problem):
            if not (case.determined and case.well_conditioned):
                continue
            found = friction_intervals(problem, case, direction)
            finite = [x for lo, hi in (*found.intervals, *found.painleve) for x in (lo, hi)]
            finite = [x for x in finite if 0 < x < np.inf]
            if not finite:
                continue
            assert case.k0 is not None and case.k_friction is not None
            a0, a1 = _pencils(case.k0, case.k_friction, problem.wrench(direction))
            roots = [abs(float(r)) for k in range(len(a0)) for r in mp_roots(a0[k], a1[k])]
            for x in finite:
                assert min(abs(x - r) for r in roots) <= 1e-9 * x, (x, sorted(roots))
                ends += 1
    assert ends > 10


@pytest.mark.parametrize(
    ("intervals", "mu", "closes", "text"),
    [
        (((0.0, 0.122),), 0.6, False, "closes for μ ≤ 0.122"),
        (((0.08, np.inf),), 0.2, True, "needs μ ≥ 0.08"),
        (((0.08, 0.5),), 0.2, True, "needs μ ≥ 0.08 and closes up to μ = 0.5"),
        (((0.0, 0.3),), 0.1, True, "closes for μ ≤ 0.3"),
        (((0.0, np.inf),), 0.1, True, "closes for every μ"),
        ((), 0.1, False, "closes for no μ"),
        (((0.0, 0.05), (0.3, np.inf)), 0.1, False, "closes for μ ≤ 0.05 or μ ≥ 0.3"),
        (((0.05, 0.2),), 0.5, False, "closes for 0.05 ≤ μ ≤ 0.2"),
    ],
)
def test_friction_in_words(
    intervals: tuple[tuple[float, float], ...], mu: float, closes: bool, text: str
) -> None:
    found = FrictionIntervals(intervals, mu, closes)
    assert describe_friction(found) == text
    if closes:
        assert found.limiting == found.containing[1]  # type: ignore[index]
    else:
        assert found.limiting is None


def test_no_scipy_in_the_per_scene_path(write_scene) -> None:
    """Friction intervals, the sphere's exact geometry and the most robust direction use numpy
    alone: a planar scene with a design direction and a spatial one (explicit mass properties,
    so no mesh library either) import neither scipy nor trimesh (issue 8: 0.2-0.4 s per run)."""
    import subprocess
    import sys

    from tests.conftest import FIXTURES, PLANAR_SCENE

    probe = (
        "import json, sys\nfrom kcheck.cli import main\ncode = main(sys.argv[1:])\n"
        "print(json.dumps(sorted(m for m in ('scipy', 'trimesh') if m in sys.modules)),"
        " file=sys.stderr)\n"
    )
    for scene in (write_scene(PLANAR_SCENE), FIXTURES / "three-groove-beta-45"):
        proc = subprocess.run(
            [sys.executable, "-c", probe, "check", str(scene), "--format", "json"],
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 0, proc.stderr
        assert json.loads(proc.stderr.strip().splitlines()[-1]) == []


def test_a_limit_next_to_the_scene_coefficient_is_not_rounded_onto_it() -> None:
    """A new user read "jams at μ = 0.15; it closes for μ ≤ 0.15" (the limit was 0.14977):
    a limit that would read as the scene's coefficient gets the digits that tell them apart;
    others keep 3 significant digits."""
    near = FrictionIntervals(((0.0, 0.14977),), mu=0.15, closes=False)
    assert describe_friction(near) == "closes for μ ≤ 0.1498"
    far = FrictionIntervals(((0.0, 0.12219),), mu=0.15, closes=False)
    assert describe_friction(far) == "closes for μ ≤ 0.122"
    at = FrictionIntervals(((0.0, 0.15),), mu=0.15, closes=True)
    assert describe_friction(at) == "closes for μ ≤ 0.15"
