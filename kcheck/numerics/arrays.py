"""Small array helpers that spare numpy's own a cost, with numpy's results bit for bit.

``np.unique`` looks up ``np.ma`` on every call, and so imports ``numpy.ma`` (about 8 ms, once
per process) in runs that use nothing else of it; these give the same results without it.
:func:`row_lengths` spares ``np.linalg.norm``'s reduction along short rows its cost a row.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "RINT_SHIFT",
    "round3_like_numpy",
    "row_lengths",
    "sorted_unique_tuples",
    "unique",
    "unique_rows",
    "unique_rounded_rows",
]


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


def unique_rounded_rows(rows: np.ndarray, decimals: int) -> np.ndarray:
    """``unique_rows(np.round(rows, decimals))``, sorting integer keys where they fit: each
    rounded value is ``K / 10^decimals`` with an integer ``K`` that orders and identifies it
    exactly, and two ``K`` below ``2^30`` in size share one int64 key (half the sort keys of
    floats, and integer comparisons); rows sorted by the first key, ties by the others.
    ``decimals`` >= 0: ``np.round`` divides by ``10^-decimals`` for negative ones, other
    bits."""
    if decimals < 0:
        raise ValueError(f"decimals must be >= 0, got {decimals}")
    scale = 10.0**decimals
    whole = np.rint(rows * scale)  # np.round's own steps: rint(x 10^d) / 10^d
    rounded = whole / scale
    if len(rounded) < 2 or not np.all(np.abs(whole) < 2.0**30 - 1):
        return unique_rows(rounded)
    k = whole.astype(np.int64) + 2**30
    if k.shape[1] % 2:
        k = np.column_stack([k, np.zeros(len(k), np.int64)])
    keys = k[:, 0::2] * 2**31 + k[:, 1::2]
    # One stable sort by the first key; only the runs it leaves tied (a few per cent of a
    # hull's facets) by all of them: lexsort's order, at a third of its cost.
    order = np.argsort(keys[:, 0], kind="stable")
    first = keys[order, 0]
    tied = first[1:] == first[:-1]
    if tied.any():
        run = np.flatnonzero(np.concatenate([[False], tied]) | np.concatenate([tied, [False]]))
        members = order[run]
        order[run] = members[np.lexsort(keys[members].T[::-1])]
    keys = keys[order]
    # A row differing from the one before in some key, column by column (np.any along the
    # rows' two or three keys cost a call per row).
    new = np.ones(len(keys), bool)
    new[1:] = keys[1:, 0] != keys[:-1, 0]
    for j in range(1, keys.shape[1]):
        new[1:] |= keys[1:, j] != keys[:-1, j]
    return rounded[order[new]]


def row_lengths(vectors: np.ndarray) -> np.ndarray:
    """``np.linalg.norm(vectors, axis=1, keepdims=True)`` of rows (r, n), the same bits: numpy
    sums a short row's squares left to right, done here column by column over all rows at
    once (numpy's reduction along short rows costs a call per row: 25 against 5-10 µs for
    690 rows)."""
    squares = vectors * vectors
    total = squares[:, 0].copy()
    for j in range(1, vectors.shape[1]):
        total += squares[:, j]
    return np.sqrt(total)[:, None]


#: ``(y + RINT_SHIFT) - RINT_SHIFT`` is ``rint(y)`` (round half to even) for ``|y| <= 2^51``:
#: the sum's unit in the last place is 1, so adding rounds away the fraction as rint does,
#: and the subtraction is exact. ``math.copysign`` of it with ``y`` keeps a zero's sign as
#: ``np.rint`` does; the same float as ``math.copysign(float(round(y)), y)``, without the
#: integer (the unit facets and wrenches rounded to 13 decimals are far inside the bound).
RINT_SHIFT = 1.5 * 2.0**52


def round3_like_numpy(x: float, y: float, z: float, scale: float) -> tuple[float, float, float]:
    """``np.round(v, d)`` of each part of a 3-vector (a unit facet or wrench), ``scale`` =
    10^d, each ``|part scale| <= 2^51``: ``rint(part scale) / scale`` with the sign of a zero
    kept, the same bits, in plain floats (for the plain-float twins of numpy code, where a
    scene rounds thousands of rows and numpy's per-call overhead is most of the time). The
    one place the shift ``copysign((y + RINT_SHIFT) - RINT_SHIFT, y)`` is written."""
    shift = RINT_SHIFT
    x, y, z = x * scale, y * scale, z * scale
    return (
        math.copysign((x + shift) - shift, x) / scale,
        math.copysign((y + shift) - shift, y) / scale,
        math.copysign((z + shift) - shift, z) / scale,
    )


def sorted_unique_tuples(rows: list[tuple[float, ...]]) -> np.ndarray:
    """:func:`unique_rows` of rows given as tuples (at least one): sorted, duplicates
    dropped, as a float array."""
    rows = sorted(rows)
    out = [rows[0]]
    for row in rows[1:]:
        if row != out[-1]:
            out.append(row)
    return np.array(out, dtype=float)
