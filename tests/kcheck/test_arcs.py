"""Exact arc sets on the circle and caps on the sphere, against dense sampling."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.arcs import FULL, TAU, cap_margins, contains, intersect, margin, positive_arc

ANGLES = np.linspace(0, TAU, 200_001)


def _member(arcs, angles=ANGLES):
    return np.array([contains(arcs, a) for a in angles[::50]])


@pytest.mark.parametrize("seed", range(20))
def test_positive_arc_matches_sampling(seed):
    rng = np.random.default_rng(seed)
    a, b, c = rng.normal(size=3)
    arcs = positive_arc(a, b, c)
    sampled = (a + b * np.cos(ANGLES[::50]) + c * np.sin(ANGLES[::50])) > 0
    mismatch = np.count_nonzero(_member(arcs) != sampled)
    assert mismatch <= 2  # only samples within rounding of an arc end may differ
    for start, end in arcs:
        assert 0 <= start < TAU and start < end <= start + TAU


def test_degenerate_arcs():
    assert positive_arc(1.0, 0.0, 0.0) == FULL
    assert positive_arc(-1.0, 0.0, 0.0) == ()
    assert positive_arc(2.0, 1.0, 0.0) == FULL  # never reaches zero
    assert positive_arc(-2.0, 1.0, 0.0) == ()
    (arc,) = positive_arc(0.0, 1.0, 0.0)  # cos > 0: (-90, 90) deg, wrapping through 0
    assert np.degrees(arc) == pytest.approx([270.0, 450.0])


def test_intersection_across_zero_and_splitting():
    wrap = ((np.radians(300), np.radians(400)),)  # 300..40 deg
    band = ((np.radians(20), np.radians(320)),)
    got = np.degrees(intersect(wrap, band))
    assert got == pytest.approx(np.array([[20, 40], [300, 320]]))
    assert intersect(wrap, ((np.radians(100), np.radians(200)),)) == ()
    np.testing.assert_allclose(intersect(FULL, wrap), wrap)
    # Two arcs meeting across 0 merge into one arc that wraps.
    merged = intersect(((np.radians(350), np.radians(370)),), FULL)
    np.testing.assert_allclose(np.degrees(merged), [[350, 370]])


def test_margin_inside_and_outside():
    arcs = ((np.radians(100), np.radians(160)),)
    assert np.degrees(margin(arcs, np.radians(120))) == pytest.approx(20)
    assert np.degrees(margin(arcs, np.radians(170))) == pytest.approx(-10)
    assert np.degrees(margin(arcs, np.radians(-170))) == pytest.approx(-30)
    assert margin(FULL, 1.0) == pytest.approx(np.pi) and margin((), 1.0) == pytest.approx(-np.pi)


def test_cap_margin_against_great_circle_geometry():
    # Condition d_z > cos(60 deg): a cap of angular radius 60 deg about +z (closed form).
    a = np.array([-0.5])
    c = np.array([[0.0, 0.0, 1.0]])
    dirs = np.array([[0, 0, 1.0], [1, 0, 0.0], [np.sin(0.5), 0, np.cos(0.5)]])
    np.testing.assert_allclose(
        np.degrees(cap_margins(a, c, dirs)), [60, -30, 60 - np.degrees(0.5)], atol=1e-9
    )
    # A condition that always holds adds no boundary; one that never holds empties the map.
    always = cap_margins(np.array([-0.5, 5.0]), np.array([[0, 0, 1.0], [1, 0, 0]]), dirs)
    np.testing.assert_allclose(always, cap_margins(a, c, dirs))
    never = cap_margins(np.array([-5.0]), np.array([[1.0, 0, 0]]), dirs)
    assert np.all(never < 0)


def test_margin_outside_is_the_distance_to_the_set():
    """Outside an arc set the margin is minus the distance to the nearest member angle: brute
    force over 3.6e4 angles (0.01° apart) finds none nearer, and one within a step."""
    rng = np.random.default_rng(9)
    grid = np.linspace(0, TAU, 360_000, endpoint=False)[::10]
    step = TAU / 36_000
    outside = 0
    for _ in range(20):
        arcs = intersect(
            *(positive_arc(*rng.normal(size=3)) for _ in range(int(rng.integers(1, 4))))
        )
        if not arcs or arcs == FULL:
            continue
        members = grid[np.array([contains(arcs, g) for g in grid])]
        for angle in rng.uniform(0, TAU, 5):
            m = margin(arcs, angle)
            if m >= 0:
                continue
            gap = np.abs((members - angle + np.pi) % TAU - np.pi).min()
            assert -m <= gap + 1e-12 and gap <= -m + step
            outside += 1
    assert outside >= 20


def test_complement_shift_equals_numpy_floor() -> None:
    """The gaps' shift by whole turns in plain float arithmetic (``_shifted``) is the
    ``np.floor`` form it replaced, bit for bit, on gaps starting anywhere from -3 to 1e17
    turns (signed zeros, exact multiples of 2 pi and quotients past 2^52 included)."""
    from kcheck.mechanics.arcs import _shifted

    rng = np.random.default_rng(7)
    starts = np.concatenate(
        [
            rng.uniform(-3, 3, 2000) * TAU,
            rng.uniform(0, 1, 500) * TAU,
            np.arange(-4, 5) * TAU,
            [0.0, -0.0, 1e-300, -1e-300, 2.0**52 * TAU, 2.0**53 * TAU, 1e17, 7.5 * TAU],
            np.nextafter(TAU, 0) * np.arange(1, 5),
        ]
    )
    for s in starts.tolist():
        e = s + 1.25
        shift = np.floor(s / TAU) * TAU
        want = (float(s - shift), float(e - shift))
        got = _shifted(s, e)
        assert [x.hex() for x in got] == [x.hex() for x in want], s
        assert all(type(x) is float for x in got)
