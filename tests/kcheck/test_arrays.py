"""kcheck.numerics.arrays against numpy's own ``np.unique`` (the reference), on random arrays with
repeated rows, zeros of both signs and empty inputs."""

from __future__ import annotations

import numpy as np

from kcheck.numerics.arrays import unique, unique_rows


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
