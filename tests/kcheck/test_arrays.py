"""kcheck.numerics.arrays against numpy's own ``np.unique`` (the reference), on random arrays with
repeated rows, zeros of both signs and empty inputs."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.numerics.arrays import row_lengths, unique, unique_rounded_rows, unique_rows


def test_unique_and_unique_rows_equal_numpy() -> None:
    rng = np.random.default_rng(5)
    for _ in range(500):
        rows = np.round(rng.normal(size=(int(rng.integers(0, 12)), 3)), 1)
        rows[rng.uniform(size=rows.shape) < 0.3] = 0.0
        if len(rows) and rng.uniform() < 0.5:
            rows = np.vstack([rows, rows[:3], -0.0 * rows[:1]])
        expected = np.unique(rows, axis=0) if len(rows) else rows
        assert np.array_equal(unique_rows(rows), expected)
        assert np.array_equal(unique(rows.ravel()), np.unique(rows.ravel()))


def test_unique_rounded_rows_equal_numpy_bit_for_bit() -> None:
    """The integer-key path gives numpy's rows in numpy's order, bit for bit (the sign of a
    zero included: the first of equal rows is kept), for six and for three columns, values
    in and beyond the range where the keys fit."""
    rng = np.random.default_rng(6)
    for _ in range(300):
        columns = int(rng.choice([3, 6]))
        rows = rng.normal(size=(int(rng.integers(0, 40)), columns)) * float(rng.choice([0.3, 3]))
        rows[rng.uniform(size=rows.shape) < 0.2] = 0.0
        if len(rows) and rng.uniform() < 0.5:
            rows = np.vstack([rows, rows[:5] + 1e-12, -0.0 * rows[:2], rows[:4]])
        decimals = int(rng.choice([3, 9, 12]))
        rounded = np.round(rows, decimals)
        expected = np.unique(rounded, axis=0) if len(rows) else rounded
        found = unique_rounded_rows(rows, decimals)
        assert found.shape == expected.shape
        assert np.array_equal(found, expected)
        assert found.tobytes() == unique_rows(rounded).tobytes()


def test_row_lengths_are_numpys_bits() -> None:
    """``row_lengths`` gives ``np.linalg.norm(..., axis=1, keepdims=True)`` bit for bit (the
    cones' facet normalisation and the perceptron's unit rows depend on it), for the widths
    the cones use and magnitudes over forty decades, zeros included."""
    rng = np.random.default_rng(12)
    for columns in (3, 4, 5, 6):
        rows = rng.normal(size=(20_000, columns)) * np.exp(rng.uniform(-45, 45, (20_000, 1)))
        rows[rng.uniform(size=rows.shape) < 0.05] = 0.0
        found = row_lengths(rows)
        assert found.shape == (20_000, 1)
        assert found.tobytes() == np.linalg.norm(rows, axis=1, keepdims=True).tobytes()


def test_unique_rounded_rows_refuses_negative_decimals() -> None:
    """Negative decimals would round by another operation than numpy's (a division), so they
    are refused rather than given other bits."""
    with pytest.raises(ValueError, match="decimals"):
        unique_rounded_rows(np.ones((3, 3)), -1)


def test_rint_shift_is_numpy_rint() -> None:
    """``copysign((y + RINT_SHIFT) - RINT_SHIFT, y)`` is ``np.rint(y)`` (half to even, a
    zero's sign kept) and the former ``copysign(float(round(y)), y)``, bit for bit, for
    ``|y| <= 2^51``: random values at every scale, ties, their neighbours, signed zeros."""
    import math

    from kcheck.numerics.arrays import RINT_SHIFT

    rng = np.random.default_rng(11)
    values = rng.uniform(-1, 1, 200_000) * 10.0 ** rng.integers(-3, 16, 200_000)
    ties = np.arange(-4000, 4000) + 0.5
    edges = np.array([0.0, -0.0, 2.0**51, -(2.0**51), 2.0**51 - 0.5, 1e13, -1e13, 4.9e-324])
    values = np.concatenate(
        [values, ties, np.nextafter(ties, np.inf), np.nextafter(ties, -np.inf), edges]
    )
    assert np.all(np.abs(values) <= 2.0**51)
    want = np.rint(values)
    for y, w in zip(values.tolist(), want.tolist(), strict=True):
        got = math.copysign((y + RINT_SHIFT) - RINT_SHIFT, y)
        assert got.hex() == w.hex() == math.copysign(float(round(y)), y).hex(), y


def test_rounding_helper_is_numpys_round() -> None:
    """``round3_like_numpy`` (the plain-float twins' one rounding) gives ``np.round(v, d)``'s
    bits for unit-sized parts at the decimals the callers use (13: facets and edge wrenches),
    signed zeros and ties included."""
    from kcheck.numerics.arrays import round3_like_numpy

    rng = np.random.default_rng(12)
    parts = rng.uniform(-1, 1, (30_000, 3)) * 10.0 ** rng.integers(-16, 1, (30_000, 1))
    parts[rng.random(parts.shape) < 0.1] = 0.0
    parts[rng.random(parts.shape) < 0.05] *= -0.0
    parts[:50] = (np.arange(150).reshape(50, 3) + 0.5) / 10.0**13  # ties at the 13th decimal
    for d in (13, 6, 0):
        scale = 10.0**d
        want = np.round(parts, d)
        for (x, y, z), w in zip(parts.tolist(), want.tolist(), strict=True):
            got = round3_like_numpy(x, y, z, scale)
            assert [v.hex() for v in got] == [v.hex() for v in w]
