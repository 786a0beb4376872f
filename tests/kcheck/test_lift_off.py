"""The first motion with contacts free to lift off (kcheck.mechanics.lift_off) against an
independent computation: planar contact modes enumerated one by one (every kept contact
lifts, sticks or slides either way; each mode is a linear system, kept when its signs are
consistent), and Lemke's method against the complementarity conditions themselves."""

from __future__ import annotations

import itertools

import numpy as np

from kcheck.mechanics.kinematics import point_velocity, wrenches
from kcheck.mechanics.lift_off import lift_off
from kcheck.numerics.lemke import lemke

TOL = 1e-9


def test_lemke_solves_positive_definite_problems() -> None:
    """A positive definite LCP has exactly one solution: z >= 0, w = A z + q >= 0, z . w = 0."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        n = int(rng.integers(1, 10))
        b = rng.normal(size=(n, n))
        a = b @ b.T + 0.1 * np.eye(n)
        q = rng.normal(size=n)
        z = lemke(a, q)
        assert z is not None
        w = a @ z + q
        assert z.min() >= -1e-9 and w.min() >= -1e-9
        assert abs(z @ w) <= 1e-8 * (1 + np.abs(q).max())


def _modes(points, normals, mu, com, inertia, wrench):
    """Every consistent planar first motion from rest, by enumeration: (acceleration, lifted)."""
    c = len(points)
    lever = points - com
    tangents = np.stack([-normals[:, 1], normals[:, 0]], axis=-1)
    mass = np.diag([inertia[0, 0], 1.0, 1.0])
    rows_n = wrenches(lever, normals)  # n_j . a(p_j) = rows_n[j] @ a
    rows_t = wrenches(lever, tangents)
    found = []
    for states in itertools.product(("lift", "stick", "+", "-"), repeat=c):
        # Unknowns: a (3), then per contact N_j and a tangential force T_j.
        size = 3 + 2 * c
        m = np.zeros((size, size))
        rhs = np.zeros(size)
        m[:3, :3] = mass
        rhs[:3] = wrench
        for j in range(c):
            m[:3, 3 + 2 * j] = -rows_n[j]
            m[:3, 4 + 2 * j] = -rows_t[j]
            r0, r1 = 3 + 2 * j, 4 + 2 * j
            if states[j] == "lift":
                m[r0, 3 + 2 * j] = 1.0  # N = 0
                m[r1, 4 + 2 * j] = 1.0  # T = 0
            else:
                m[r0, :3] = rows_n[j]  # no normal acceleration
                if states[j] == "stick":
                    m[r1, :3] = rows_t[j]
                else:  # sliding with tangential acceleration of sign s: T = -s mu N
                    s = 1.0 if states[j] == "+" else -1.0
                    m[r1, 4 + 2 * j] = 1.0
                    m[r1, 3 + 2 * j] = s * mu[j]
        try:
            x = np.linalg.solve(m, rhs)
        except np.linalg.LinAlgError:
            continue
        a = x[:3]
        ok = True
        for j in range(c):
            n_j, t_j = x[3 + 2 * j], x[4 + 2 * j]
            an, at = rows_n[j] @ a, rows_t[j] @ a
            if states[j] == "lift":
                ok &= an > TOL
            else:
                ok &= n_j >= -TOL
                if states[j] == "stick":
                    ok &= abs(t_j) <= mu[j] * n_j + TOL
                else:
                    ok &= (at > TOL) if states[j] == "+" else (at < -TOL)
        if ok:
            found.append((a, np.array([s == "lift" for s in states])))
    return found


def test_planar_first_motion_is_one_of_the_enumerated_modes() -> None:
    """Random planar bodies on two kept contacts under random wrenches: whenever no
    equilibrium exists (no enumerated mode at rest), lift_off's motion is one of the consistent
    modes the enumeration finds, with the same lifted contacts and the same acceleration."""
    rng = np.random.default_rng(26)
    compared = lifted = 0
    for _ in range(400):
        points = rng.uniform(-1, 1, (3, 2))
        angles = rng.uniform(0, 2 * np.pi, 3)
        normals = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        com = rng.uniform(-0.5, 0.5, 2)
        inertia = np.array([[rng.uniform(0.05, 0.5)]])
        mu = rng.uniform(0, 0.6, 2)
        wrench = rng.normal(size=3)
        kept = (points[1:], normals[1:])
        modes = _modes(*kept, mu, com, inertia, wrench)
        if not modes:
            continue  # no consistent mode at all (Painlevé inconsistency): nothing to compare
        motion = lift_off(*kept, mu, com, inertia, wrench, (points[0], normals[0]))
        assert motion is not None
        scale = 1 + float(np.abs(wrench).max())
        match = [
            (a, up)
            for a, up in modes
            if np.allclose(a, motion.acceleration, atol=1e-7 * scale)
            and np.array_equal(up, motion.lifted)
        ]
        assert match, (motion, modes)
        compared += 1
        lifted += bool(motion.lifted.any())
        u = point_velocity(motion.acceleration, points[0] - com)
        assert np.isclose(motion.closing, -(u @ normals[0]))
    assert compared > 300 and lifted > 50
