"""kcheck.mechanics.holding_certificates against the conic programme, on thousands of
random contact sets (seeded).

The reference is built here, independently of kcheck's statics: forces in world
coordinates (three per contact), the balance of force and moment about the origin, each
force in its exact circular cone ``mu (n . f) >= |f - (n . f) n|`` written with tangents from
an SVD, solved by clarabel with scipy's sparse matrices. The screen's columns are built here
too, from the same SVD tangents (its answer must not depend on which tangents).
"""

from __future__ import annotations

from pathlib import Path

import clarabel
import numpy as np
import pytest
from scipy import sparse

from kcheck.mechanics.holding_certificates import holding_certified


def _tangents(normal: np.ndarray) -> np.ndarray:
    """Two orthonormal tangents (2, 3) of a unit normal: the SVD's null space."""
    return np.linalg.svd(normal[None, :])[2][1:]


def _cross(p: np.ndarray, f: np.ndarray) -> np.ndarray:
    return np.array(
        [p[1] * f[2] - p[2] * f[1], p[2] * f[0] - p[0] * f[2], p[0] * f[1] - p[1] * f[0]]
    )


def _reference_holds(points, normals, mu, moment, force) -> bool | None:
    """Whether forces in the exact cones balance the wrench (clarabel); None when clarabel
    reaches no verdict."""
    k = len(points)
    # Equilibrium: sum f_j = -force, sum p_j x f_j = -moment (unknowns f_j, world frame).
    eq = np.zeros((6, 3 * k))
    for j, p in enumerate(points):
        for a in range(3):
            e = np.zeros(3)
            e[a] = 1.0
            eq[:3, 3 * j + a] = _cross(p, e)
            eq[3:, 3 * j + a] = e
    rows = [eq]
    for j, n in enumerate(normals):
        t = _tangents(n)
        cone = np.zeros((3, 3 * k))
        cone[0, 3 * j : 3 * j + 3] = -mu[j] * n
        cone[1:, 3 * j : 3 * j + 3] = -t
        rows.append(cone)
    push = np.zeros((k, 3 * k))
    for j, n in enumerate(normals):
        push[j, 3 * j : 3 * j + 3] = -n
    rows.append(push)
    a = sparse.csc_matrix(np.vstack(rows))
    b = np.concatenate([-moment, -force, np.zeros(3 * k + k)])
    cones = [
        clarabel.ZeroConeT(6),
        *[clarabel.SecondOrderConeT(3)] * k,
        clarabel.NonnegativeConeT(k),
    ]
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    p = sparse.csc_matrix((3 * k, 3 * k))
    status = str(clarabel.DefaultSolver(p, np.zeros(3 * k), a, b, cones, settings).solve().status)
    if status in ("Solved", "AlmostSolved"):
        return True
    if status in ("PrimalInfeasible", "AlmostPrimalInfeasible"):
        return False
    return None


def _columns(points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Unit wrenches (moment about the origin, force) of each contact's normal and tangents,
    (3k, 6)."""
    out = []
    for p, n in zip(points, normals, strict=True):
        for axis in (n, *_tangents(n)):
            out.append(np.concatenate([_cross(p, axis), axis]))
    return np.array(out)


def _random_sets(count: int, seed: int):
    """Contact sets of 3-5 contacts on a body around the origin, normals roughly inwards,
    coefficients 0.02-0.8, random wrenches; every seventh with a frictionless contact, every
    eleventh with its contacts on one line (their wrenches span 5 of the 6 dimensions)."""
    rng = np.random.default_rng(seed)
    for i in range(count):
        k = int(rng.integers(3, 6))
        points = rng.uniform(-1, 1, (k, 3))
        if i % 11 == 0:
            points = rng.uniform(-1, 1, (k, 1)) * rng.normal(0, 1, 3) + rng.uniform(-1, 1, 3)
        normals = -points + rng.normal(0, 0.8, (k, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        mu = rng.uniform(0.02, 0.8, k)
        if i % 7 == 0:
            mu[0] = 0.0
        moment, force = rng.normal(0, 0.3, 3), rng.normal(0, 1, 3)
        yield points, normals, mu, moment, force


@pytest.mark.parametrize("seed", [1, 2])
def test_certificates_agree_with_the_conic_programme(seed: int) -> None:
    """Every question the certificates decide, on 1500 random sets, has the reference's
    answer; most (90 %) are decided, both ways."""
    sets = list(_random_sets(1500, seed))
    answers = holding_certified(
        [_columns(p, n) for p, n, _, _, _ in sets],
        [np.concatenate([m, f]) for _, _, _, m, f in sets],
        [mu for _, _, mu, _, _ in sets],
    )
    decided = {True: 0, False: 0}
    for (points, normals, mu, moment, force), answer in zip(sets, answers, strict=True):
        if answer is None:
            continue
        assert answer == _reference_holds(points, normals, mu, moment, force)
        decided[answer] += 1
    assert decided[True] + decided[False] >= 0.9 * len(sets)
    assert min(decided.values()) >= 0.1 * len(sets)


def test_certificates_stay_undecided_on_the_boundary() -> None:
    """A block on a plane with its weight exactly at the friction angle (methods.md §7: held
    iff tan(theta) <= mu) is on the boundary: no certificate clears the margin either way;
    a little inside or outside it is decided, and as the closed form says."""
    points = np.array([[1.0, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]])
    normals = np.tile([0, 0, 1.0], (3, 1))
    mu = np.full(3, 0.3)
    columns = _columns(points, normals)
    answers = []
    for tilt in (0.3 * (1 - 1e-3), 0.3, 0.3 * (1 + 1e-3)):
        force = np.array([tilt, 0.0, -1.0])  # weight down, sideways at tan(theta) = tilt
        moment = np.zeros(3)
        answers.append(holding_certified([columns], [np.concatenate([moment, force])], [mu])[0])
    assert answers == [True, None, False]


def test_no_wrench_and_no_contacts_are_left_undecided() -> None:
    """Degenerate questions (no wrench; a non-finite one) go to the programme."""
    points = np.array([[1.0, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]])
    columns = _columns(points, np.tile([0, 0, 1.0], (3, 1)))
    mu = np.full(3, 0.3)
    wrenches = [np.zeros(6), np.full(6, np.nan)]
    assert holding_certified([columns] * 2, wrenches, [mu] * 2) == [None, None]


def test_analyse_many_with_certificates_equals_the_programmes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``analyse_many`` of the fixtures and 60 generated spatial scenes: the same results
    (every outcome, force, ``friction_may_hold``, lift-off) with the chunk's equilibrium
    questions decided by certificates as with every one asked of its conic programme; and
    the certificates were asked (and decided most)."""
    import sys

    from kcheck.analysis import analyse_many
    from kcheck.analysis import cases as cases_module
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene

    tests = Path(__file__).resolve().parents[1]
    sys.path.insert(0, str(tests))
    from spatial_scenes import write_spatial_scenes  # type: ignore[import-not-found]

    paths = sorted((tests.parent / "fixtures").glob("*/*.kcheck.yaml"))
    scenes = [load_scene(p) for p in [*paths, *write_spatial_scenes(tmp_path, range(60))]]
    bodies = [(s, s.body) for s in scenes if s.dim == 3]
    scenes = [s for s, body in bodies if body is not None]
    masses = [body_mass_properties(body, s.scale) for s, body in bodies if body is not None]
    asked: list[bool | None] = []

    def counted(*args: list[np.ndarray]) -> list[bool | None]:
        answers = holding_certified(*args)
        asked.extend(answers)
        return answers

    monkeypatch.setattr(cases_module, "holding_certified", counted)
    screened = analyse_many(scenes, masses)
    monkeypatch.setattr(cases_module, "HOLDING_CERTIFICATE_BATCH", 10**9)
    programmes = analyse_many(scenes, masses)
    assert [a.results for a in screened] == [a.results for a in programmes]
    assert len(asked) >= 100
    assert sum(a is not None for a in asked) >= 0.9 * len(asked)


def test_nearly_dependent_contacts_certify_nothing() -> None:
    """Three contacts nearly on one line (the third 1e-7 off it), the weight through their
    centroid: the set's unit wrenches are nearly dependent (reach ``|C| |(C^T C)^-1|`` about
    5e14, computed here), so the least-norm correction's rounding is not bounded and no
    forces certify holding; the question goes to the programme, which (the reference) says
    it holds, as the closed form does (the weight inside the triangle, tan(theta) = 0.1 <
    mu). The twist side is unaffected: at tan(theta) = 0.5 > mu it is still decided."""
    points = np.array([[1.0, 0, 0], [-1.0, 0, 0], [0.0, 1e-7, 0]])
    normals = np.tile([0, 0, 1.0], (3, 1))
    mu = np.full(3, 0.3)
    columns = _columns(points, normals)
    reach = np.linalg.norm(columns) * np.linalg.norm(np.linalg.inv(columns.T @ columns))
    assert reach > 1e12
    answers = []
    for tilt in (0.1, 0.5):
        force = np.array([tilt, 0.0, -1.0])
        moment = _cross(points.mean(axis=0), force)
        answers.append(holding_certified([columns], [np.concatenate([moment, force])], [mu])[0])
        if tilt == 0.1:
            assert _reference_holds(points, normals, mu, moment, force) is True
    assert answers == [None, False]
