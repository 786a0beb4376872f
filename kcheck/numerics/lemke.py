"""Lemke's complementary pivoting for a linear complementarity problem: find ``z >= 0`` with
``w = A z + q >= 0`` and ``z . w = 0`` (Cottle, Pang & Stone, *The Linear Complementarity
Problem*, 1992, §4.4), on a dense condensed tableau.

The tableau keeps only the nonbasic variables' columns (n + 1 of them, and the right-hand
side): a basic variable's column is a unit vector the method never reads. A pivot exchanges
the entering variable's column for the leaving one's, computed with the same floating-point
operations the full tableau ``[I, -A, -e, q]`` would use for it (its unit column divided and
eliminated), so the pivots and the answer are those of the full tableau, at half the work.
"""

from __future__ import annotations

import numpy as np

from kcheck.numerics.thresholds import LEMKE_PIVOT_RTOL

__all__ = ["lemke", "lemke_batch", "lemke_padded"]

#: Pivots allowed per unknown before giving up (cycling on a degenerate problem).
PIVOTS_PER_UNKNOWN = 50


def _start(a: np.ndarray, q: np.ndarray, cover: np.ndarray | None = None) -> np.ndarray:
    """The condensed tableaus (..., n, n + 2) of ``w - A z - d z0 = q``: columns z (n), the
    artificial z0, the right-hand side; the covering vector ``d`` is ``cover`` (..., n) or
    ones."""
    n = q.shape[-1]
    tableau = np.empty(q.shape[:-1] + (n, n + 2))
    tableau[..., :n] = -a
    tableau[..., n] = -1.0 if cover is None else -cover
    tableau[..., n + 1] = q
    return tableau


def lemke(a: np.ndarray, q: np.ndarray) -> np.ndarray | None:
    """A solution ``z`` (n,) of LCP(q, A) for ``a`` (n, n), ``q`` (n,); None when the method
    ends on a ray (the problem may have no solution) or cycles."""
    n = len(q)
    if np.all(q >= 0):
        return np.zeros(n)
    # Variables: w 0..n-1, z n..2n-1, the artificial 2n.
    tableau = _start(a, q.astype(float))
    rhs = tableau[:, -1]
    basis = list(range(n))
    column_of = [-1] * n + list(range(n + 1))  # a nonbasic variable's column
    artificial = 2 * n
    row = int(np.argmin(q))
    entering = artificial
    for _ in range(PIVOTS_PER_UNKNOWN * n + 1):
        col = column_of[entering]
        _pivot(tableau, row, col)
        leaving, basis[row] = basis[row], entering
        column_of[leaving], column_of[entering] = col, -1
        if leaving == artificial:
            z = np.zeros(n)
            for r, var in enumerate(basis):
                if n <= var < 2 * n:
                    z[var - n] = rhs[r]
            return z
        if entering == artificial:
            art_row = row  # where the artificial variable stays basic until it leaves
        entering = leaving + n if leaving < n else leaving - n
        column = tableau[:, column_of[entering]]
        high, low_entry = float(column.max()), float(column.min())
        scale = max(high, -low_entry) or 1.0
        if not high > LEMKE_PIVOT_RTOL * scale:
            return None  # no candidate row: a ray
        rows = np.flatnonzero(column > LEMKE_PIVOT_RTOL * scale)
        ratios = rhs[rows] / column[rows]
        low = float(ratios.min())
        best = rows[ratios <= low + LEMKE_PIVOT_RTOL * max(1.0, abs(low))]
        # Among ties, let the artificial variable leave: the method then ends.
        row = art_row if art_row in best else int(best[0])
    return None


def _pivot(tableau: np.ndarray, row: int, column: int) -> None:
    """Exchange the basic variable of ``row`` for the nonbasic one of ``column``; the column
    becomes the leaving variable's (its unit column divided and eliminated, as in the full
    tableau)."""
    pivot = tableau[row, column]
    factors = tableau[:, column].copy()
    factors[row] = 0.0
    tableau[:, column] = 0.0
    tableau[row, column] = 1.0
    tableau[row] /= pivot
    tableau -= factors[:, None] * tableau[row][None, :]


def lemke_padded(problems: list[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray | None]:
    """:func:`lemke_batch` on problems of different sizes: each padded to the largest with
    rows ``w_d = 1`` that touch nothing (zero in A, in q's place 1, in the covering vector 0).
    Such a row stays as it is through every pivot (its entry in every pivot column is 0, so it
    is never a candidate and its update subtracts zeros), its ``z_d`` never enters (``w_d``
    never leaves), and the problem's own rows come first, so ties break as before; each problem
    is given up after its own size's pivot limit, not the padded one's: each takes its own
    pivots, bit for bit."""
    n = max(len(q) for _, q in problems)
    a = np.zeros((len(problems), n, n))
    q = np.ones((len(problems), n))
    cover = np.zeros((len(problems), n))
    for i, (ai, qi) in enumerate(problems):
        m = len(qi)
        a[i, :m, :m] = ai
        q[i, :m] = qi
        cover[i, :m] = 1.0
    solved = lemke_batch(a, q, cover, np.array([len(qi) for _, qi in problems]))
    return [
        None if z is None else z[: len(qi)] for z, (_, qi) in zip(solved, problems, strict=True)
    ]


def lemke_batch(
    a: np.ndarray,
    q: np.ndarray,
    cover: np.ndarray | None = None,
    sizes: np.ndarray | None = None,
) -> list[np.ndarray | None]:
    """:func:`lemke` on ``b`` problems of one size at once: ``a`` (b, n, n), ``q`` (b, n); each
    problem's solution or None. Every problem takes the same pivots as alone, with the same
    floating-point operations on its own tableau (elementwise in numpy either way), so the
    answers are bit for bit :func:`lemke`'s; the batch pays numpy's per-call cost once a pivot
    step instead of once a problem. ``cover`` (b, n): the covering vector (default ones; zero
    on :func:`lemke_padded`'s padding rows). ``sizes`` (b,): each problem's own size before
    padding (default n), which sets its pivot limit ``PIVOTS_PER_UNKNOWN * size + 1`` as
    alone."""
    b, n = q.shape
    out: list[np.ndarray | None] = [None] * b
    start = np.all(q >= 0, axis=1)
    for i in np.flatnonzero(start):
        out[i] = np.zeros(n)
    idx = np.flatnonzero(~start)  # the problems still pivoting
    if len(idx) == 0:
        return out
    k = len(idx)
    tableau = _start(a[idx], q[idx].astype(float), None if cover is None else cover[idx])
    basis = np.tile(np.arange(n), (k, 1))
    column_of = np.full((k, 2 * n + 1), -1)
    column_of[:, n:] = np.arange(n + 1)
    artificial = 2 * n
    row = np.argmin(q[idx], axis=1)
    entering = np.full(k, artificial)
    buffer = np.empty_like(tableau)  # the rank-one update, allocated once
    # The artificial variable enters at the first pivot and stays in that row until it leaves.
    artificial_row = row.copy()
    at = np.arange(k)
    # Each problem gives up after its own limit of pivots, as alone.
    limit = PIVOTS_PER_UNKNOWN * (np.full(b, n) if sizes is None else np.asarray(sizes))[idx] + 1
    first_limit = int(limit.min())
    for step in range(1, int(limit.max()) + 1):
        col = column_of[at, entering]
        pivot = tableau[at, row, col]
        factors = tableau[at, :, col]
        factors[at, row] = 0.0
        tableau[at, :, col] = 0.0
        tableau[at, row, col] = 1.0
        pivot_row = tableau[at, row] / pivot[:, None]
        tableau[at, row] = pivot_row
        # Each entry one product, as the full tableau's broadcast (einsum is the faster outer).
        np.einsum("ij,ik->ijk", factors, pivot_row, out=buffer)
        tableau -= buffer
        leaving = basis[at, row]
        basis[at, row] = entering
        column_of[at, leaving] = col
        column_of[at, entering] = -1
        done = leaving == artificial
        for j in np.flatnonzero(done):
            z = np.zeros(n)
            held = basis[j] >= n
            z[basis[j, held] - n] = tableau[j, held, -1]
            out[int(idx[j])] = z
        entering = np.where(leaving < n, leaving + n, leaving - n)
        column = tableau[at, :, column_of[at, entering]]
        scale = np.max(np.abs(column), axis=1)
        scale[scale == 0] = 1.0
        ok = column > LEMKE_PIVOT_RTOL * scale[:, None]
        ratios = np.full(column.shape, np.inf)
        np.divide(tableau[:, :, -1], column, out=ratios, where=ok)
        low = ratios.min(axis=1)
        best = ok & (ratios <= (low + LEMKE_PIVOT_RTOL * np.maximum(1.0, np.abs(low)))[:, None])
        # Among ties, let the artificial variable leave: the method then ends.
        row = np.where(best[at, artificial_row], artificial_row, np.argmax(best, axis=1))
        going = ~done & ok.any(axis=1)  # no candidate row: a ray, None
        if step >= first_limit:  # out of pivots (rare: only then the arrays' compare)
            going &= limit > step
        if not going.all():
            if not going.any():
                break
            idx, tableau, basis = idx[going], tableau[going], basis[going]
            column_of, row, entering = column_of[going], row[going], entering[going]
            artificial_row, limit = artificial_row[going], limit[going]
            first_limit = int(limit.min())
            buffer = buffer[: len(idx)]
            at = np.arange(len(idx))
    return out
