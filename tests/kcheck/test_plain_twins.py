"""Plain-float twins of numpy helpers (written where numpy's per-call overhead on three or
six elements was most of the time, issue 24) against the numpy functions they copy: the
3-vector helpers bit for bit, the few-condition arcs within the ends' stated error."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.fmt import clean, clean3
from kcheck.mechanics import arcs
from kcheck.mechanics.kinematics import norm3, row_norms, unit3, unit_rows


def _vectors(rng: np.random.Generator, count: int) -> np.ndarray:
    """Random 3-vectors across magnitudes, with exact zeros and rounding-noise entries."""
    v = rng.normal(size=(count, 3)) * 10.0 ** rng.integers(-300, 300, size=(count, 1))
    v[rng.random((count, 3)) < 0.15] = 0.0
    noisy = rng.random((count, 3)) < 0.1
    v[noisy] *= 1e-17
    return v


def test_three_vector_helpers_equal_their_numpy_twins_bit_for_bit():
    rng = np.random.default_rng(24)
    for v in _vectors(rng, 5000):
        values = [float(x) for x in v]
        assert np.array_equal(np.array(clean3(values)), clean(v))
        assert np.array_equal(np.array(clean3(values, 2.5)), clean(v, 2.5))
        if np.any(v):
            assert norm3(values) == row_norms(v)
            assert np.array_equal(np.array(unit3(values)), unit_rows(v))


@pytest.mark.parametrize("k", [2, 3, 6, 12])
def test_few_condition_arcs_equal_numpys_within_their_error(k, monkeypatch):
    """The same arc structure; each end within the error the arcs state (at least eps of
    2 pi), numpy's path (FEW_CONDITIONS = 0) against the plain-float one."""
    rng = np.random.default_rng(k)
    e1, e2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    compared = 0
    for _ in range(400):
        a = rng.uniform(0.0, 1.5, size=k)  # mostly wide arcs, so 12 still overlap
        c = rng.normal(size=(k, 3))
        error = np.abs(a) * 1e-12 + 1e-15
        few, few_err = arcs.affine_arcs(a, c, e1, e2, error)
        with monkeypatch.context() as m:
            m.setattr(arcs, "FEW_CONDITIONS", 0)
            many, many_err = arcs.affine_arcs(a, c, e1, e2, error)
        assert len(few) == len(many)
        if few_err is None:
            assert many_err is None and few == many
            continue
        assert many_err is not None
        bound = max(few_err, many_err)
        assert np.allclose(np.array(few), np.array(many), rtol=0, atol=bound)
        compared += 1
    assert compared > 100  # a good share of the draws have arcs with ends


def test_largest_friction_ratio_equals_its_numpy_twin_bit_for_bit():
    """sliding_limit.largest_ratio (plain floats, a handful of contacts) against the numpy
    version it copies: forces across magnitudes, pulling and unpressed contacts, frictionless
    supports (scale 0)."""
    from kcheck.mechanics.sliding_limit import _largest_ratio_numpy, largest_ratio

    rng = np.random.default_rng(26)
    for trial in range(20000):
        k = int(rng.integers(1, 7))
        local = rng.normal(size=(k, 3)) * 10.0 ** rng.uniform(-8, 8)
        if trial % 3:
            local[:, 0] = np.abs(local[:, 0])
        if trial % 7 == 0:
            local[rng.integers(0, k), 0] = 0.0
        scale = np.where(rng.random(k) < 0.2, 0.0, rng.uniform(0.1, 2.0, k))
        assert largest_ratio(local, scale) == _largest_ratio_numpy(local, scale)


def _former_row_norms(vectors: np.ndarray) -> np.ndarray:
    """``row_norms`` as it was, numpy only."""
    v = np.asarray(vectors, dtype=float)
    big = np.abs(v).max(axis=-1, keepdims=True)
    safe = np.where(big > 0, big, 1.0)
    return np.sqrt(np.sum((v / safe) ** 2, axis=-1)) * big[..., 0]


@pytest.mark.parametrize("n", [1, 2, 3])
def test_row_norms_of_one_vector_in_plain_floats_bit_for_bit(n):
    """``row_norms`` of one finite vector of 1-3 parts (Python floats) is its numpy form's
    numpy float, bit for bit, at every magnitude, with zeros and rounding noise; non-finite
    vectors and other shapes take the numpy form."""
    rng = np.random.default_rng(n)
    vectors = [v[:n] for v in _vectors(rng, 20_000)]
    vectors += [np.zeros(n), np.full(n, 5e-324), np.full(n, 1e308), -np.zeros(n)]
    vectors += [np.array([np.inf, *[1.0] * (n - 1)]), np.array([*[1.0] * (n - 1), np.nan])]
    vectors += [rng.normal(size=4), rng.normal(size=(3, n)), [1, 2, 3][:n]]
    for v in vectors:
        with np.errstate(invalid="ignore", over="ignore"):  # inf / inf: NaN, as meant
            got, want = row_norms(v), _former_row_norms(v)
        assert type(got) is type(want)
        assert np.asarray(got).tobytes() == np.asarray(want).tobytes(), v
    for f in (row_norms, _former_row_norms):  # no parts: no largest magnitude, as before
        with pytest.raises(ValueError):
            f(np.zeros(0))


def _former_frame(points: np.ndarray) -> tuple[np.ndarray, float]:
    """``Frame.for_points``' origin and length as they were, numpy only."""
    points = np.asarray(points, dtype=float)
    big = float(np.abs(points).max()) if points.size else 0.0
    scale = big if big > 0 and np.isfinite(big) else 1.0
    origin = (points / scale).mean(axis=0) * scale
    length = float(_former_row_norms(points - origin).max()) if len(points) else 0.0
    if not (length > 0 and np.isfinite(length)):
        length = 1.0
    return origin, length


def test_frame_of_a_few_points_in_plain_floats_bit_for_bit():
    """``Frame.for_points`` of up to FEW_POINTS finite points (Python floats) has its numpy
    form's origin and length, bit for bit: 1-12 points in 2 and 3 dimensions at every
    magnitude, coincident points, zeros; non-finite points take the numpy form, and so do
    column-major points (numpy's mean adds a column-major array's 8 or more rows in another
    order: another origin in most draws)."""
    from kcheck.mechanics.kinematics import FEW_POINTS, Frame

    rng = np.random.default_rng(8)
    sets = []
    for _ in range(6000):
        k, d = int(rng.integers(1, FEW_POINTS + 3)), int(rng.integers(2, 4))
        p = rng.normal(size=(k, d)) * 10.0 ** rng.integers(-200, 200)
        p[rng.random((k, d)) < 0.1] = 0.0
        if rng.random() < 0.1:
            p[:] = p[0]  # every point the same: no length
        sets.append(p)
    sets += [np.array([[np.inf, 0.0], [1.0, 2.0]]), np.array([[np.nan, 0.0, 1.0]])]
    sets += [np.asfortranarray(p) for p in sets[:3000] if len(p) > 1]
    for p in sets:
        with np.errstate(invalid="ignore", over="ignore"):
            frame = Frame.for_points(p, p.shape[1], 1.0)
            origin, length = _former_frame(p)
        assert frame.origin.dtype == origin.dtype and frame.origin.shape == origin.shape
        assert frame.origin.tobytes() == origin.tobytes() and type(frame.length) is float
        assert np.float64(frame.length).tobytes() == np.float64(length).tobytes()
