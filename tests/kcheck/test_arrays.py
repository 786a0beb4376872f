"""kcheck.numerics.arrays against numpy's own ``np.unique`` (the reference), on random arrays with
repeated rows, zeros of both signs and empty inputs."""

from __future__ import annotations

import numpy as np

from kcheck.numerics.arrays import unique, unique_rounded_rows, unique_rows


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
