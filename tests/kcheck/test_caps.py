"""Exact geometry of intersections of spherical caps (kcheck.mechanics.caps) against closed forms,
identities and brute force.

References:

* one cap of angular radius r: area 2 pi (1 - cos r);
* Girard's theorem: a spherical triangle (three hemispheres) has area = sum of its angles - pi;
* a lens (two caps, radii r1, r2, axes gamma apart) by Gauss–Bonnet written out by hand:
  ``2 pi - 2 phi1 cos r1 - 2 phi2 cos r2 - 2 beta`` with the half-arc angles ``phi_i`` and the
  corner's exterior angle ``beta`` from the spherical law of cosines in the triangle of the
  two axes and a corner — corner angles, which kcheck's Stokes form never computes;
* the 2^k cells cut by k circles tile the sphere: their areas add up to 4 pi;
* brute force: a Fibonacci lattice (kcheck.mechanics.sphere) for areas, distances and the deepest
point.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kcheck.mechanics.arcs import cap_margins
from kcheck.mechanics.caps import FOUR_PI, angle_between, region, signed_distance
from kcheck.mechanics.deepest import deepest_point
from kcheck.mechanics.sphere import fibonacci_sphere, grid_spacing, safe_fraction

LATTICE = 200_000


def caps_about(axes: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Conditions ``a + c . d > 0`` of caps with unit ``axes`` and angular ``radii``."""
    return -np.cos(radii), np.asarray(axes, float)


def unit(v: list[float]) -> np.ndarray:
    return np.asarray(v, float) / np.linalg.norm(v)


@pytest.mark.parametrize("radius_deg", [0.5, 30.0, 89.0, 90.0, 135.0, 179.0])
def test_single_cap_closed_form(radius_deg: float) -> None:
    r = np.radians(radius_deg)
    a, c = caps_about(unit([0.3, -0.4, 0.5])[None], np.array([r]))
    got = region(2.5 * a, 2.5 * c)  # scaling a condition changes nothing
    assert got.area == pytest.approx(2 * np.pi * (1 - np.cos(r)), rel=1e-13, abs=1e-15)
    assert got.perimeter == pytest.approx(2 * np.pi * np.sin(r), rel=1e-13)


def test_triangle_of_three_hemispheres_is_girard() -> None:
    """Hemispheres about three axes: a spherical triangle whose angles are pi minus the angles
    between the axes; Girard: area = sum of angles - pi."""
    axes = np.array([unit([1, 0.2, 0.1]), unit([0.1, 1, -0.3]), unit([0.2, 0.3, 1])])
    angles = [np.pi - angle_between(axes[i], axes[j]) for i, j in ((0, 1), (1, 2), (0, 2))]
    got = region(np.zeros(3), axes)
    assert got.area == pytest.approx(sum(angles) - np.pi, rel=1e-13)


def lens_area(r1: float, r2: float, gamma: float) -> float:
    """Two overlapping caps by Gauss–Bonnet with corners (independent of kcheck's Stokes form)."""
    phi1 = np.arccos((np.cos(r2) - np.cos(r1) * np.cos(gamma)) / (np.sin(r1) * np.sin(gamma)))
    phi2 = np.arccos((np.cos(r1) - np.cos(r2) * np.cos(gamma)) / (np.sin(r2) * np.sin(gamma)))
    beta = np.arccos((np.cos(gamma) - np.cos(r1) * np.cos(r2)) / (np.sin(r1) * np.sin(r2)))
    return 2 * np.pi - 2 * phi1 * np.cos(r1) - 2 * phi2 * np.cos(r2) - 2 * beta


@pytest.mark.parametrize(
    ("r1", "r2", "gamma"), [(40, 50, 60), (20, 30, 45), (100, 60, 90), (100, 110, 120)]
)
def test_lens_closed_form(r1: float, r2: float, gamma: float) -> None:
    r1, r2, gamma = np.radians([r1, r2, gamma])
    axes = np.array([[0, 0, 1.0], [np.sin(gamma), 0, np.cos(gamma)]])
    got = region(*caps_about(axes, np.array([r1, r2])))
    assert got.area == pytest.approx(lens_area(r1, r2, gamma), rel=1e-12)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(seed=st.integers(0, 10**6), k=st.integers(1, 5))
def test_cells_of_k_circles_tile_the_sphere(seed: int, k: int) -> None:
    """Every cap or its complement (also a cap): the 2^k intersections partition the sphere,
    so their exact areas add up to 4 pi — caps larger than a hemisphere, several pieces and
    holes included."""
    rng = np.random.default_rng(seed)
    c = rng.normal(size=(k, 3))
    a = rng.uniform(-1.2, 1.2, k) * np.linalg.norm(c, axis=1)
    total = 0.0
    for signs in itertools.product((1.0, -1.0), repeat=k):
        s = np.array(signs)
        total += region(a * s, c * s[:, None]).area
    assert total == pytest.approx(FOUR_PI, abs=1e-12)


def random_caps(rng: np.random.Generator, k: int) -> tuple[np.ndarray, np.ndarray]:
    """k random caps, radii from small to larger than a hemisphere."""
    c = rng.normal(size=(k, 3))
    a = rng.uniform(-0.6, 1.0, k) * np.linalg.norm(c, axis=1)
    return a, c


def test_area_equals_the_lattice_count() -> None:
    """The lattice oracle: exact area within the lattice's own error estimate."""
    rng = np.random.default_rng(31)
    for _ in range(8):
        a, c = random_caps(rng, int(rng.integers(1, 9)))
        exact = region(a, c).fraction
        lattice = safe_fraction(a, c, LATTICE)
        assert abs(exact - lattice.fraction) <= lattice.error + 1e-12


def test_degenerate_sets() -> None:
    axis = np.array([[0.0, 0.0, 1.0]])
    assert region(np.array([-0.1, -0.1]), np.vstack([axis, -axis])).empty  # disjoint caps
    assert region(np.array([2.0, 1.5]), np.vstack([axis, -axis])).full  # both hold everywhere
    assert region(np.array([-2.0]), axis).empty  # a condition that never holds
    once = region(np.array([-0.5]), axis).area
    assert region(np.array([-0.5, -1.0]), np.vstack([axis, 2 * axis])).area == pytest.approx(once)
    # A cap and its complement meet only on their circle: nothing of positive area.
    assert region(np.array([-0.5, 0.5]), np.vstack([axis, -axis])).area == 0.0


def boundary_samples(a: np.ndarray, c: np.ndarray, per_circle: int) -> np.ndarray:
    """Points of every cap's circle (``per_circle`` each) that lie in every cap: a dense
    sample of the region's boundary, corners included to within the sample spacing."""
    size = np.linalg.norm(c, axis=1)
    live = np.abs(a / size) < 1
    out = []
    t = np.linspace(0, 2 * np.pi, per_circle, endpoint=False)
    for ak, ck, nk in zip(a[live], c[live], size[live], strict=True):
        u = ck / nk
        e1 = np.cross(u, [1.0, 0, 0] if abs(u[0]) < 0.9 else [0, 1.0, 0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(u, e1)
        cos_r = -ak / nk
        sin_r = np.sqrt(1 - cos_r**2)
        out.append(cos_r * u + sin_r * (np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2)))
    points = np.concatenate(out)
    return points[cap_margins(a, c, points) > -1e-12]


def test_signed_distance_against_brute_force() -> None:
    """Inside: the distance to the nearest circle (as cap_margins). Outside: minus the exact
    distance to the region — brute force: the nearest of 2e4 samples per circle of the
    region's boundary (where the nearest point of a region lies) is at most one sample
    spacing farther — and the nearest safe direction lies on the region at that distance."""
    rng = np.random.default_rng(5)
    per_circle = 20_000
    spacing = 2 * np.pi / per_circle
    outside = 0
    for _ in range(20):
        a, c = random_caps(rng, int(rng.integers(1, 8)))
        reg = region(a, c)
        if reg.empty:
            assert not np.any(cap_margins(a, c, fibonacci_sphere(LATTICE)) > 0)
            continue
        boundary = boundary_samples(a, c, per_circle)
        for d in rng.normal(size=(4, 3)):
            d /= np.linalg.norm(d)
            margin, nearest = signed_distance(reg, d)
            assert margin is not None and nearest is not None
            own = float(cap_margins(a, c, d[None])[0])
            if own >= 0:
                assert margin == pytest.approx(own, abs=1e-12)
                continue
            outside += 1
            brute = float(angle_between(boundary, d).min())
            assert -margin <= brute + 1e-12 and brute <= -margin + spacing
            assert float(cap_margins(a, c, nearest[None])[0]) > -1e-10
            assert float(angle_between(nearest, d)) == pytest.approx(-margin, abs=1e-12)
    assert outside > 20


def test_deepest_point_against_the_lattice() -> None:
    """At least as deep as every lattice point, and at most one spacing deeper; also where
    nothing is safe (the least violating direction)."""
    rng = np.random.default_rng(8)
    points = fibonacci_sphere(LATTICE)
    h = grid_spacing(LATTICE)
    for _ in range(10):
        a, c = random_caps(rng, int(rng.integers(1, 10)))
        reg = region(a, c)
        best, depth = deepest_point(reg)
        assert best is not None and depth is not None
        assert float(cap_margins(a, c, best[None])[0]) == pytest.approx(depth, abs=1e-12)
        lattice = float(cap_margins(a, c, points).max())
        assert lattice <= depth + 1e-12 and depth <= lattice + h
        assert (depth > 0) == (not reg.empty)


def test_deepest_point_of_an_octant() -> None:
    best, depth = deepest_point(region(np.zeros(3), np.eye(3)))
    np.testing.assert_allclose(best, np.ones(3) / np.sqrt(3), atol=1e-14)
    assert depth == pytest.approx(np.arcsin(1 / np.sqrt(3)), abs=1e-14)


@pytest.mark.parametrize("seed", range(6))
def test_deepest_point_of_many_caps_by_active_set(seed: int) -> None:
    """Sixty caps (more than the active set starts with): the active set's answer equals the
    full enumeration of every single, pair and triple of caps (independent: no subset), for
    regions empty and not, and no lattice direction is deeper."""
    from kcheck.mechanics.deepest import _deepest_among

    rng = np.random.default_rng(100 + seed)
    a, c = random_caps(rng, 60)
    if seed % 2:  # a non-empty region: every cap holds at a common direction
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        a = np.maximum(a, -(c @ d) + 0.05 * np.linalg.norm(c, axis=1))
    reg = region(a, c)
    best, depth = deepest_point(reg)
    _, full = _deepest_among(reg.caps, np.arange(len(reg.caps.radius)))
    assert depth == pytest.approx(full, abs=1e-12)
    lattice = fibonacci_sphere(20_000)
    assert cap_margins(a, c, lattice).max() <= depth + 1e-12
    assert cap_margins(a, c, best[None])[0] == pytest.approx(depth, abs=1e-12)
