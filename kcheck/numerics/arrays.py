"""Small array helpers that spare numpy's own a cost at start-up.

``np.unique`` looks up ``np.ma`` on every call, and so imports ``numpy.ma`` (about 8 ms, once
per process) in runs that use nothing else of it; these give the same results without it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["unique", "unique_rows"]


def unique(values: np.ndarray) -> np.ndarray:
    """Sorted distinct values of a 1-D array (``np.unique(values)``)."""
    s = np.sort(np.asarray(values).ravel())
    if len(s) < 2:
        return s
    return s[np.concatenate([[True], s[1:] != s[:-1]])]


def unique_rows(rows: np.ndarray) -> np.ndarray:
    """Distinct rows (r, n), sorted lexicographically (``np.unique(rows, axis=0)``)."""
    if len(rows) < 2:
        return rows.copy()
    s = rows[np.lexsort(rows.T[::-1])]
    return s[np.concatenate([[True], np.any(s[1:] != s[:-1], axis=1)])]
