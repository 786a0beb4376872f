"""The rigid model's second answer (kcheck.mechanics.second_answer) against an independent
computation: planar contact modes enumerated one by one (tests/kcheck/test_lift_off.py), and
the recorded cases of the `reseat` agreement test (tests/plugins/data/reseat_disagreements.json)
where `jamming` says friction holds the body and the simulation moves."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from kcheck.mechanics.kinematics import wrenches
from kcheck.mechanics.second_answer import second_answer, subsets
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
        answer = second_answer(*kept, mu, com, inertia, wrench, (points[0], normals[0]))
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
    from kcheck.analysis.reseat import _wrench
    from kcheck.body.mass import body_mass_properties
    from kcheck.scene import load_scene
    from tests.plugins.reseat_agreement import generated

    paths = {p.name: p for p in generated(tmp_path, 100)}
    for name, retracted, lifted in (
        ("random-3d-3391.kcheck.yaml", "s4", ["s2", "s3", "s5"]),
        ("random-3d-1667.kcheck.yaml", "s1", None),
    ):
        scene = load_scene(paths[name])
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        names = [s.name for s in scene.supports]
        r = names.index(retracted)
        rest = [i for i in range(len(names)) if i != r]
        points = np.array([s.position for s in scene.supports])
        normals = np.array([s.normal / np.linalg.norm(s.normal) for s in scene.supports])
        load = _wrench(scene, mass.center_of_mass, 1.0) + np.r_[mass.mass * scene.gravity, 0, 0, 0]
        answer = second_answer(
            points[rest],
            normals[rest],
            np.asarray(scene.friction_range("kinetic")[1])[rest],
            mass.center_of_mass,
            mass.inertia / mass.mass,
            np.r_[load[3:], load[:3]] / mass.mass,
            (points[r], normals[r]),
        )
        if lifted is None:
            assert answer is None
            continue
        assert answer is not None
        assert [names[rest[i]] for i in np.flatnonzero(answer.lifted)] == lifted
        # Independently: the kept contacts do not accelerate along their normals, the lifted
        # ones separate, and the body moves.
        lever = points[rest] - mass.center_of_mass
        normal_accel = wrenches(lever, normals[rest]) @ answer.motion.acceleration
        scale = float(np.abs(answer.motion.acceleration).max())
        assert scale > 0
        assert np.all(np.abs(normal_accel[answer.kept]) <= 1e-6 * scale)
        assert np.all(normal_accel[answer.lifted] > 0)


def test_cases_together_answer_as_each_alone() -> None:
    """second_answers solves each distinct subset of supports once for all cases: every case's
    answer is the one second_answer gives it alone, motion bit for bit (random spatial bodies
    on six supports, every support retracted in turn, wrenches pressing them in)."""
    from kcheck.mechanics.second_answer import Body, second_answers

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
        together = second_answers(body, cases)
        for (retracted, rest), got in zip(cases, together, strict=True):
            alone = second_answer(
                points[rest], normals[rest], mu[rest], com, inertia, wrench, retracted
            )
            assert (got is None) == (alone is None)
            if got is not None and alone is not None:
                assert np.array_equal(got.kept, alone.kept)
                assert np.array_equal(got.motion.acceleration, alone.motion.acceleration)
                assert got.motion.closing == alone.motion.closing
                answered += 1
    assert answered > 10  # measured: 26 of 36 cases have a second answer
