"""Lemke's complementary pivoting for a linear complementarity problem: find ``z >= 0`` with
``w = A z + q >= 0`` and ``z . w = 0`` (Cottle, Pang & Stone, *The Linear Complementarity
Problem*, 1992, §4.4), on a dense tableau."""

from __future__ import annotations

import numpy as np

from kcheck.numerics.thresholds import LEMKE_PIVOT_RTOL

__all__ = ["lemke"]

#: Pivots allowed per unknown before giving up (cycling on a degenerate problem).
PIVOTS_PER_UNKNOWN = 50


def lemke(a: np.ndarray, q: np.ndarray) -> np.ndarray | None:
    """A solution ``z`` (n,) of LCP(q, A) for ``a`` (n, n), ``q`` (n,); None when the method
    ends on a ray (the problem may have no solution) or cycles."""
    n = len(q)
    if np.all(q >= 0):
        return np.zeros(n)
    # Columns: w (n), z (n), the artificial z0, right-hand side; rows say w - A z - e z0 = q.
    tableau = np.hstack([np.eye(n), -a, -np.ones((n, 1)), q[:, None]]).astype(float)
    basis = list(range(n))
    artificial = 2 * n
    row = int(np.argmin(q))
    entering = artificial
    for _ in range(PIVOTS_PER_UNKNOWN * n + 1):
        _pivot(tableau, row, entering)
        leaving, basis[row] = basis[row], entering
        if leaving == artificial:
            z = np.zeros(n)
            for r, var in enumerate(basis):
                if n <= var < 2 * n:
                    z[var - n] = tableau[r, -1]
            return z
        entering = leaving + n if leaving < n else leaving - n
        column = tableau[:, entering]
        scale = float(np.max(np.abs(column))) or 1.0
        rows = np.flatnonzero(column > LEMKE_PIVOT_RTOL * scale)
        if len(rows) == 0:
            return None
        ratios = tableau[rows, -1] / column[rows]
        best = rows[ratios <= ratios.min() + LEMKE_PIVOT_RTOL * max(1.0, abs(float(ratios.min())))]
        # Among ties, let the artificial variable leave: the method then ends.
        ends = [r for r in best if basis[r] == artificial]
        row = int(ends[0] if ends else best[0])
    return None


def _pivot(tableau: np.ndarray, row: int, column: int) -> None:
    tableau[row] /= tableau[row, column]
    factors = tableau[:, column].copy()
    factors[row] = 0.0
    tableau -= factors[:, None] * tableau[row][None, :]
