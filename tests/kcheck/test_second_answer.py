"""The rigid model's second answer (kcheck.mechanics.second_answer) against an independent
computation: planar contact modes enumerated one by one (tests/kcheck/test_lift_off.py), and
the recorded cases of the `reseat` agreement test (tests/plugins/data/reseat_disagreements.json)
where `jamming` says friction holds the body and the simulation moves."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from kcheck.mechanics.kinematics import point_velocity, wrenches
from kcheck.mechanics.lift_off import LIFT_EDGES, LiftOff, _edges
from kcheck.mechanics.second_answer import Body, SecondAnswer, second_answers, subsets
from kcheck.numerics.thresholds import LIFT_SHARE
from tests.kcheck.test_lemke import full_tableau
from tests.kcheck.test_lift_off import _modes


def test_subsets_are_tried_largest_first() -> None:
    """5 remaining contacts: 31 subsets, all five first; 2: 3."""
    five = subsets(5)
    assert len(five) == 31 and five[0] == (0, 1, 2, 3, 4) and len(set(five)) == 31
    assert subsets(2) == [(0, 1), (0,), (1,)]


def test_planar_second_answer_is_an_enumerated_moving_mode() -> None:
    """Random planar bodies on two remaining contacts under random wrenches where an
    equilibrium exists (rest is an enumerated mode): a second answer found is one of the
    enumerated consistent modes, moving, with the same contacts separating; where the
    enumeration has a moving mode the search finds one in most cases (measured: 63 held,
    17 with a moving mode, 16 found; Lemke's method returns one solution per subset, and
    where rest is one on a subset it may return rest)."""
    rng = np.random.default_rng(27)
    held = found = missed = 0
    for _ in range(3000):
        points = rng.uniform(-1, 1, (3, 2))
        angles = rng.uniform(0, 2 * np.pi, 3)
        normals = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        com = rng.uniform(-0.5, 0.5, 2)
        inertia = np.array([[rng.uniform(0.05, 0.5)]])
        mu = rng.uniform(0.2, 1.0, 2)
        wrench = rng.normal(size=3)
        kept = (points[1:], normals[1:])
        modes = _modes(*kept, mu, com, inertia, wrench)
        if not any(np.all(a == 0) or np.abs(a).max() < 1e-12 for a, _ in modes):
            continue  # no equilibrium: not a case friction holds
        held += 1
        moving = [(a, up) for a, up in modes if np.abs(a).max() > 1e-9]
        body = Body(*kept, mu, com, inertia, wrench)
        answer = second_answers(body, [((points[0], normals[0]), np.arange(2))])[0]
        if answer is None:
            missed += bool(moving)
            continue
        scale = 1 + float(np.abs(wrench).max())
        assert any(
            np.allclose(a, answer.motion.acceleration, atol=1e-7 * scale)
            and np.array_equal(up, answer.lifted)
            for a, up in moving
        ), (answer, modes)
        found += 1
    assert held > 50 and found > 5
    assert missed <= 0.1 * (found + missed)


def test_recorded_held_cases_that_move(tmp_path: Path) -> None:
    """The agreement test's generated scenes (seed 26): random-3d-3391 retracting s4, which
    `jamming` says friction holds and the simulation moves keeping s1 and s6 (measured with
    kcheck.analysis.reseat.simulate at the agreement test's settings), has the second answer
    that keeps s1 and s6 and lifts s2, s3 and s5. random-3d-1667 retracting s1, recorded as
    a second rigid answer too, has none: the lift-off problem on the contacts its simulation
    keeps (s2, s3, s4, s6) returns rest, not a motion, which the recorded evidence
    (`rigid_motion`) counted."""
    from tests.plugins.contact_modes import retraction_case
    from tests.plugins.reseat_agreement import generated

    paths = {p.name: p for p in generated(tmp_path, 100)}
    for name, retracted, lifted in (
        ("random-3d-3391.kcheck.yaml", "s4", ["s2", "s3", "s5"]),
        ("random-3d-1667.kcheck.yaml", "s1", None),
    ):
        c = retraction_case(paths, name, retracted)
        names, r, rest, points, normals = c.names, c.retracted, c.rest, c.points, c.normals
        body = Body(*c.arrays)
        answer = second_answers(body, [((points[r], normals[r]), np.arange(len(rest)))])[0]
        if lifted is None:
            assert answer is None
            continue
        assert answer is not None
        assert [names[rest[i]] for i in np.flatnonzero(answer.lifted)] == lifted
        # Independently: the kept contacts do not accelerate along their normals, the lifted
        # ones separate, and the body moves.
        lever = points[rest] - c.center_of_mass
        normal_accel = wrenches(lever, normals[rest]) @ answer.motion.acceleration
        scale = float(np.abs(answer.motion.acceleration).max())
        assert scale > 0
        assert np.all(np.abs(normal_accel[answer.kept]) <= 1e-6 * scale)
        assert np.all(normal_accel[answer.lifted] > 0)


def _reference_lift_off(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    com: np.ndarray,
    inertia: np.ndarray,
    wrench: np.ndarray,
    retracted: tuple[np.ndarray, np.ndarray],
    edges: int = LIFT_EDGES,
) -> LiftOff | None:
    """c5f8237's kcheck.mechanics.lift_off.lift_off, verbatim but for Lemke's method: the
    full-tableau one kept in tests/kcheck/test_lemke.py."""
    c, dim = points.shape
    nw = 1 if dim == 2 else 3
    lever = points - com
    directions = _edges(normals, edges)
    m = directions.shape[1]
    g_n = wrenches(lever, normals)  # (c, n)
    g_d = wrenches(np.repeat(lever, m, axis=0), directions.reshape(c * m, dim))  # (c m, n)
    mass = np.zeros((nw + dim, nw + dim))
    mass[:nw, :nw] = inertia
    mass[nw:, nw:] = np.eye(dim)
    inv = np.linalg.inv(mass)
    g = np.vstack([g_n, g_d])
    block = np.zeros((c * m, c))
    block[np.arange(c * m), np.repeat(np.arange(c), m)] = 1.0
    size = c + c * m + c
    a = np.zeros((size, size))
    a[: c + c * m, : c + c * m] = g @ inv @ g.T
    a[c : c + c * m, c + c * m :] = block
    a[c + c * m :, :c] = np.diag(mu)
    a[c + c * m :, c : c + c * m] = -block.T
    q = np.concatenate([g @ inv @ wrench, np.zeros(c)])
    z = full_tableau(a, q)
    if z is None:
        return None
    forces = z[:c]
    accel = inv @ (wrench + g.T @ z[: c + c * m])
    # Rounding noise is measured against the free body's acceleration under the wrench.
    free = inv @ wrench
    scale = float(np.max(np.abs(free))) + float(np.max(np.abs(point_velocity(free, lever))))
    if float(np.max(np.abs(accel))) <= LIFT_SHARE * scale:
        accel = np.zeros_like(accel)
    contact = point_velocity(accel, lever)
    normal_accel = np.einsum("ij,ij->i", contact, normals)
    lifted = normal_accel > LIFT_SHARE * scale
    point, normal = retracted
    closing = -float(point_velocity(accel, point - com) @ normal)
    return LiftOff(accel, forces, lifted, closing)


def _reference_second_answer(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    com: np.ndarray,
    inertia: np.ndarray,
    wrench: np.ndarray,
    retracted: tuple[np.ndarray, np.ndarray],
    edges: int = LIFT_EDGES,
) -> SecondAnswer | None:
    """c5f8237's kcheck.mechanics.second_answer.second_answer, verbatim (one subset at a time,
    each its own lift-off problem), over :func:`_reference_lift_off`: the reference the
    batched search must answer as, bit for bit."""
    c = len(points)
    lever = points - com
    nw = 1 if points.shape[1] == 2 else 3
    mass = np.eye(nw + points.shape[1])
    mass[:nw, :nw] = inertia
    free = np.linalg.solve(mass, wrench)
    scale = float(np.max(np.abs(free))) + float(np.max(np.abs(point_velocity(free, lever))))
    rows = wrenches(lever, normals)  # normal acceleration of each contact per twist (c, n)
    for k in subsets(c):
        keep = np.zeros(c, dtype=bool)
        keep[list(k)] = True
        motion = _reference_lift_off(
            points[keep], normals[keep], mu[keep], com, inertia, wrench, retracted, edges
        )
        if motion is None or not motion.moves or np.any(motion.lifted):
            continue
        if np.all(rows[~keep] @ motion.acceleration >= -LIFT_SHARE * scale):
            return SecondAnswer(keep, motion)
    return None


def _same_answers(body: Body, cases: list, together: list) -> int:
    """Each case's answer equal to the reference's, kept contacts, motion (acceleration,
    forces, lifted) and closing bit for bit; how many have one."""
    answered = 0
    for (retracted, rest), got in zip(cases, together, strict=True):
        alone = _reference_second_answer(
            body.points[rest],
            body.normals[rest],
            body.mu[rest],
            body.com,
            body.inertia,
            body.wrench,
            retracted,
        )
        assert (got is None) == (alone is None)
        if got is not None and alone is not None:
            assert np.array_equal(got.kept, alone.kept)
            assert np.array_equal(got.motion.acceleration, alone.motion.acceleration)
            assert np.array_equal(got.motion.forces, alone.motion.forces)
            assert np.array_equal(got.motion.lifted, alone.motion.lifted)
            assert got.motion.closing == alone.motion.closing
            answered += 1
    return answered


def test_spatial_cases_answer_as_the_one_subset_at_a_time_reference() -> None:
    """second_answers solves each distinct subset of supports once for all cases, in padded
    batches: every case's answer is the reference's (c5f8237's one-subset-at-a-time search
    over the full-tableau Lemke), bit for bit (random spatial bodies on six supports, every
    support retracted in turn, wrenches pressing them in)."""
    rng = np.random.default_rng(24)
    answered = 0
    for _ in range(6):
        points = rng.uniform(-1, 1, (6, 3))
        normals = -points + rng.normal(0, 0.3, (6, 3))  # roughly inward: the body is seated
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        mu = rng.uniform(0.1, 0.6, 6)
        cloud = rng.normal(0, 0.3, (6, 3))
        inertia = np.sum(cloud**2) * np.eye(3) - cloud.T @ cloud
        com = rng.uniform(-0.2, 0.2, 3)
        wrench = np.r_[rng.normal(0, 0.2, 3), rng.normal(0, 1, 3)]
        body = Body(points, normals, mu, com, inertia, wrench)
        cases = [((points[r], normals[r]), np.delete(np.arange(6), r)) for r in range(6)]
        answered += _same_answers(body, cases, second_answers(body, cases))
    assert answered > 10  # measured: 26 of 36 cases have a second answer


def test_planar_held_cases_answer_as_the_one_subset_at_a_time_reference() -> None:
    """Random planar bodies on three supports, each retracted in turn, the cases where rest is
    a consistent mode of the remaining two (friction holds; enumerated independently by
    tests/kcheck/test_lift_off.py's _modes): second_answers answers each as the reference, bit
    for bit (a planar case's three subsets are solved one by one, several cases' in padded
    batches)."""
    rng = np.random.default_rng(31)
    held = answered = 0
    for _ in range(1000):
        points = rng.uniform(-1, 1, (3, 2))
        angles = rng.uniform(0, 2 * np.pi, 3)
        normals = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        com = rng.uniform(-0.5, 0.5, 2)
        inertia = np.array([[rng.uniform(0.05, 0.5)]])
        mu = rng.uniform(0.2, 1.0, 3)
        wrench = rng.normal(size=3)
        body = Body(points, normals, mu, com, inertia, wrench)
        cases = []
        for r in range(3):
            rest = np.delete(np.arange(3), r)
            modes = _modes(points[rest], normals[rest], mu[rest], com, inertia, wrench)
            if any(np.abs(a).max() < 1e-12 for a, _ in modes):  # rest: friction holds
                cases.append(((points[r], normals[r]), rest))
        held += len(cases)
        if cases:
            answered += _same_answers(body, cases, second_answers(body, cases))
    assert held > 50 and answered > 10  # measured: 73 held cases, 15 with a second answer
