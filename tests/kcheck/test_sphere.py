"""The lattice count of safe directions (kcheck.mechanics.sphere), the oracle of
kcheck.mechanics.caps, against closed forms.

References: the area of a spherical cap of angular radius r is 2 pi (1 - cos r), a fraction
(1 - cos r) / 2 of the sphere; three orthogonal hemispheres meet in an octant (1/8), whose
deepest point (1, 1, 1)/sqrt(3) lies arcsin(1/sqrt(3)) = 35.26 deg from each bounding plane.
"""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.arcs import cap_margin_matrix, cap_margins
from kcheck.mechanics.deepest import most_robust_direction
from kcheck.mechanics.sphere import (
    cap_fraction,
    fibonacci_chunks,
    fibonacci_sphere,
    grid_spacing,
    lattice_best,
    safe_fraction,
)

OCTANT_A = np.zeros(3)
OCTANT_C = np.eye(3)


def test_fibonacci_sphere_is_uniform() -> None:
    points = fibonacci_sphere(5000)
    assert points.shape == (5000, 3)
    np.testing.assert_allclose(np.linalg.norm(points, axis=1), 1.0, rtol=1e-14)
    # A uniform set has zero mean and second moment I/3.
    np.testing.assert_allclose(points.mean(axis=0), 0.0, atol=1e-3)
    np.testing.assert_allclose(points.T @ points / len(points), np.eye(3) / 3, atol=1e-3)


@pytest.mark.parametrize("n", [1000, 10000, 100000])
@pytest.mark.parametrize("a", [-0.9, -0.3, 0.0, 0.5, 0.95])
def test_single_cap_fraction_within_its_error_estimate(n: int, a: float) -> None:
    c = np.array([0.3, -0.4, 0.5]) / np.linalg.norm([0.3, -0.4, 0.5])
    result = safe_fraction(np.array([a]), c[None], n)
    exact = cap_fraction(a, c)
    assert exact == pytest.approx((1 - (-a)) / 2)
    assert abs(result.fraction - exact) <= result.error
    # One cell is 1/n of the sphere; the band estimate shrinks like n^-1/2.
    assert result.error < 3.0 / np.sqrt(n)


def test_octant_fraction() -> None:
    for n in (2000, 20000, 200000):
        result = safe_fraction(OCTANT_A, OCTANT_C, n)
        assert abs(result.fraction - 0.125) <= result.error


def test_empty_and_full_regions() -> None:
    c = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
    assert safe_fraction(np.array([-0.1, -0.1]), c, 5000).fraction == 0.0  # disjoint caps
    assert safe_fraction(np.array([2.0]), c[:1], 5000).fraction == 1.0  # holds everywhere
    assert safe_fraction(np.array([-2.0]), c[:1], 5000).fraction == 0.0  # holds nowhere


def test_margin_matrix_reduces_to_cap_margins() -> None:
    rng = np.random.default_rng(3)
    a, c = rng.normal(size=7), rng.normal(size=(7, 3))
    a[0], c[1] = 5.0, 0.0  # one condition everywhere true, one with no direction term
    d = fibonacci_sphere(300)
    np.testing.assert_array_equal(cap_margin_matrix(a, c, d).min(axis=1), cap_margins(a, c, d))


def test_chunks_are_the_whole_lattice() -> None:
    """The chunked lattice is the same point set, so counts do not depend on the chunk size."""
    whole = fibonacci_sphere(1000)
    np.testing.assert_array_equal(np.concatenate(list(fibonacci_chunks(1000, 128))), whole)
    rng = np.random.default_rng(4)
    a, c = rng.normal(size=5), rng.normal(size=(5, 3))
    margins = cap_margins(a, c, whole)
    best, value = lattice_best(a, c, 1000)
    assert value == margins.max()
    np.testing.assert_array_equal(best, whole[int(np.argmax(margins))])


def test_most_robust_direction_of_an_octant() -> None:
    direction, margin = most_robust_direction(OCTANT_A, OCTANT_C)
    np.testing.assert_allclose(direction, np.ones(3) / np.sqrt(3), atol=1e-12)
    assert margin == pytest.approx(np.arcsin(1 / np.sqrt(3)), abs=1e-12)


def test_most_robust_direction_of_one_cap_is_its_axis() -> None:
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    direction, margin = most_robust_direction(np.array([-0.5]), 2.0 * axis[None])
    np.testing.assert_allclose(direction, axis, atol=1e-12)
    assert margin == pytest.approx(np.arccos(0.25), abs=1e-12)  # radius arccos(-a / |c|)


def test_exact_robust_direction_beats_every_lattice_point() -> None:
    """The exact deepest point is at least as deep as the best of 2e5 lattice points, and at
    most one lattice spacing deeper (the margin changes by at most the distance moved)."""
    rng = np.random.default_rng(7)
    for _ in range(5):
        c = rng.normal(size=(12, 3))
        a = 0.8 * np.linalg.norm(c, axis=1)  # generous caps: a region of safe directions exists
        _, exact = most_robust_direction(a, c)
        _, lattice = lattice_best(a, c, 200_000)
        assert lattice <= exact + 1e-12
        assert exact <= lattice + grid_spacing(200_000)
