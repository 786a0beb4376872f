"""Twist kinematics: constraint rows, free twists, poles at infinity, Maxwell's measure."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.kinematics import (
    free_twist,
    layout_singular_values,
    maxwell_cos,
    point_velocity,
    wrenches,
)


def test_row_times_twist_is_normal_velocity():
    rng = np.random.default_rng(1)
    for dim, n in ((2, 3), (3, 6)):
        p, nrm, twist = rng.normal(size=(5, dim)), rng.normal(size=(5, dim)), rng.normal(size=n)
        np.testing.assert_allclose(
            wrenches(p, nrm) @ twist, np.sum(nrm * point_velocity(twist, p), axis=1), atol=1e-12
        )


def test_planar_free_twist_is_rotation_about_the_pole():
    # Normals of supports 0 and 1 meet at (1, 1): retracting 2 leaves a rotation about it.
    p = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, -0.5]])
    n = np.array([[0.0, 1.0], [1.0, 0.0], [1.0, 1.0]]) / np.array([[1], [1], [np.sqrt(2)]])
    free = free_twist(p, n, 2)
    assert np.linalg.norm(point_velocity(free.twist, np.array([1.0, 1.0]))) < 1e-12
    assert n[2] @ point_velocity(free.twist, p[2]) < 0  # oriented to close the gap


def test_parallel_normals_give_a_translation_without_special_case():
    p = np.array([[0.2, 0.0], [0.8, 0.0], [0.0, 0.3]])
    n = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
    free = free_twist(p, n, 2)
    np.testing.assert_allclose(free.twist, [0, -1, 0], atol=1e-15)  # w = 0, v = -x
    assert free.closing == pytest.approx(1.0)


def test_concurrent_normals_are_rank_deficient():
    # Three normals through the origin: a rotation about it stays free with all supports.
    angles = np.radians([90, 210, 330])
    p = np.column_stack([np.cos(angles), np.sin(angles)])
    s = layout_singular_values(p, -p)
    assert s[-1] / s[0] < 1e-15
    assert free_twist(p, -p, 0).closing < 1e-12  # retracting frees nothing that closes it


def test_maxwell_cos_is_one_for_a_square_block_corner():
    p = np.array([[0.2, 0.0], [0.8, 0.0], [0.0, 0.3]])
    n = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]])
    assert maxwell_cos(free_twist(p, n, 2), p[2], n[2]) == pytest.approx(1.0)


def test_planar_point_velocity_is_v_plus_w_cross_p_bit_for_bit():
    # The closed form u = v + w (-y, x), written with np.stack as before the in-place fill,
    # on single and stacked twists (broadcast against the points).
    rng = np.random.default_rng(7)
    points = rng.normal(size=(4, 5, 2))
    for twist in (rng.normal(size=3), rng.normal(size=(4, 1, 3))):
        w, v = twist[..., :1], twist[..., 1:]
        expected = v + w * np.stack([-points[..., 1], points[..., 0]], axis=-1)
        got = point_velocity(twist, points)
        assert got.shape == expected.shape
        assert np.array_equal(got, expected)


def test_wrenches_of_one_force_at_many_points_repeat_it():
    # (p x f, f): one force given once or repeated per point gives the same rows, bit for bit,
    # in 2D and 3D; the force part is the force itself.
    rng = np.random.default_rng(3)
    for dim in (2, 3):
        points, force = rng.normal(size=(6, dim)), rng.normal(size=dim)
        once, repeated = wrenches(points, force), wrenches(points, np.tile(force, (6, 1)))
        assert np.array_equal(once, repeated)
        assert np.array_equal(once[:, -dim:], np.tile(force, (6, 1)))


def test_cross3_of_two_vectors_is_np_cross_bit_for_bit():
    """``cross3``'s two-3-vector shortcut (Python floats) gives ``np.cross``'s bits, signed
    zeros, infinities and NaN included; other shapes and dtypes take the array path."""
    from kcheck.mechanics.kinematics import cross3

    rng = np.random.default_rng(3)
    special = [0.0, -0.0, 1.0, -1.0, np.inf, -np.inf, np.nan, 1e-310, 1e300]
    vectors = [*rng.normal(size=(400, 3)) * 10.0 ** rng.integers(-8, 8, (400, 1))]
    vectors += [np.array(rng.choice(special, 3)) for _ in range(400)]
    for a, b in zip(vectors, vectors[1:] + vectors[:1], strict=True):
        with np.errstate(invalid="ignore", over="ignore"):  # inf - inf, inf * 0: NaN, as said
            got, want = cross3(a, b), np.cross(a, b)
        assert got.dtype == want.dtype and got.shape == want.shape
        assert got.tobytes() == want.tobytes()
    rows = rng.normal(size=(5, 3))
    assert cross3(rows, rows[::-1]).tobytes() == np.cross(rows, rows[::-1]).tobytes()
    small = rng.normal(size=3).astype(np.float32)
    assert cross3(small, small[::-1]).dtype == np.result_type(small, float)
