"""A Fibonacci lattice grouped into the cells of a coarser one, for exact coarse-to-fine tests.

Every fine direction ``d`` belongs to its nearest coarse direction ``p``; the cell's radius
``r`` is the largest chord ``|d - p|`` over its members. An affine slack ``a + c . d`` then
lies within ``|c| r`` of its value at ``p`` for every member (Cauchy-Schwarz), so a coarse
evaluation decides whole cells far from a boundary and only the cells a boundary may cross
are evaluated direction by direction: the same classification as every fine direction, for
a fraction of the work. Nondimensional.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from kcheck.records import dataclass

__all__ = ["LatticeCells", "lattice_cells", "bounded_slack", "lattice_slack"]

#: Fine directions per coarse cell (about): more cells cost more coarse products, fewer
#: leave more fine directions near a boundary undecided.
PER_CELL = 24
#: Relative guard on the cell bounds against rounding of the products (far above 1e-16).
GUARD = 1e-12
#: Facets every cell meets first (chosen on SAMPLE cells); the rest only the cells these
#: leave undecided. (12 on 100 cells before the bounds became one product each: choosing
#: them then cost more than the few cells more they decide.)
FIRST = 4
SAMPLE = 50
# Fine times coarse directions compared at once when the cells are built.
CHUNK = 4_000_000


@dataclass(frozen=True)
class LatticeCells:
    """``fine`` (n, 3) directions; ``coarse`` (m, 3); ``owner`` (n,) each fine direction's
    cell; ``radius`` (m,) the largest chord from a cell's centre to a member."""

    fine: np.ndarray
    coarse: np.ndarray
    owner: np.ndarray
    radius: np.ndarray


@lru_cache(maxsize=4)
def lattice_cells(points: int) -> LatticeCells:
    """The ``points``-direction Fibonacci lattice in cells of a lattice ``PER_CELL`` times
    coarser (computed once per size)."""
    # Imported here: jamming imports this module for planar scenes too, which need no sphere.
    from kcheck.mechanics.sphere import fibonacci_sphere

    fine = fibonacci_sphere(points)
    coarse = fibonacci_sphere(max(1, points // PER_CELL))
    owner = np.empty(points, int)
    step = max(1, CHUNK // len(coarse))
    for i in range(0, points, step):
        owner[i : i + step] = np.argmax(fine[i : i + step] @ coarse.T, axis=1)
    chord = np.linalg.norm(fine - coarse[owner], axis=1)
    radius = np.zeros(len(coarse))
    np.maximum.at(radius, owner, chord)
    for array in (fine, coarse, owner, radius):
        array.flags.writeable = False
    return LatticeCells(fine, coarse, owner, radius)


def bounded_slack(
    a: np.ndarray,
    c: np.ndarray,
    cells: LatticeCells,
    floor: float,
    ceiling: float,
    where: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per fine direction, ``min_f (a_f + c_f . d)`` as far as its comparison with ``floor``
    and ``ceiling`` goes, the fine indices left for the caller to evaluate exactly, and the
    facets that can bring their least slack below ``ceiling`` (the others cannot).

    Returned values: a lower bound that is ``>= ceiling`` in cells wholly above it, an upper
    bound ``< floor`` in cells wholly below it, NaN elsewhere (the undecided directions,
    returned as indices); ``where`` (n,) bool limits the answer to those directions (only
    their cells are bounded; the others' values are NaN and not returned as undecided).
    ``a`` (f,), ``c`` (f, 3), at least one facet.
    """
    size = np.linalg.norm(c, axis=1)
    guard = GUARD * (np.abs(a) + size)
    m = len(cells.coarse)
    value = np.full(m, np.nan)
    if where is None:
        # Most cells lie outside the set: a few facets, chosen on a sample of the cells, put
        # them wholly below the floor; only the others meet every facet.
        first = _outside_facets(a, c, size, guard, cells, floor)
        high = _bound(cells, slice(None), a[first], c[first], size[first], guard[first]).min(0)
        value = np.where(high < floor, high, np.nan)
        rest = np.flatnonzero(~(high < floor))
    else:
        # Only the cells that hold a wanted direction (a few percent of them): every facet.
        wanted = np.zeros(m, bool)
        wanted[cells.owner[where]] = True
        rest = np.flatnonzero(wanted)
    facets = np.zeros(0, int)
    if len(rest):
        lows = _bound(cells, rest, a, c, -size, -guard)  # (f, rest)
        low = lows.min(axis=0)
        high = _bound(cells, rest, a, c, size, guard).min(axis=0)
        value[rest] = np.where(low >= ceiling, low, np.where(high < floor, high, np.nan))
        # Facets above the ceiling at every member of every undecided cell cannot bring a
        # member's least slack below it: the exact values need only the others.
        facets = np.flatnonzero(np.any(lows[:, np.isnan(value[rest])] < ceiling, axis=1))
    slack = value[cells.owner]
    open_ = np.isnan(slack)
    if where is not None:
        open_ &= where
    return slack, np.flatnonzero(open_), facets


def _bound(
    cells: LatticeCells,
    which: np.ndarray | slice,
    a: np.ndarray,
    c: np.ndarray,
    size: np.ndarray,
    guard: np.ndarray,
) -> np.ndarray:
    """``a_f + c_f . p_i + r_i size_f + guard_f`` at the centres ``p_i`` (radius ``r_i``) of
    the cells ``which``, (facets, cells), as one matrix product (its rounding, about 1e-16
    of the terms, far inside ``guard``). With ``size`` and ``guard`` negated: the lower
    bound."""
    centres = np.column_stack(
        [cells.coarse[which], cells.radius[which], np.ones(len(cells.radius[which]))]
    )
    return np.column_stack([c, size, a + guard]) @ centres.T


def _outside_facets(
    a: np.ndarray,
    c: np.ndarray,
    size: np.ndarray,
    guard: np.ndarray,
    cells: LatticeCells,
    floor: float,
) -> np.ndarray:
    """Up to FIRST facet indices chosen greedily on a sample of the cells: each the one that
    puts most of the sample's cells not yet below ``floor`` wholly below it."""
    sample = slice(None, None, max(1, len(cells.coarse) // SAMPLE))
    below = _bound(cells, sample, a, c, size, guard) < floor  # (f, s)
    alive = np.ones(below.shape[1], bool)
    chosen: list[int] = []
    for _ in range(min(FIRST, len(a))):
        out = np.count_nonzero(below[:, alive], axis=1)
        best = int(np.argmax(out))
        if out[best] == 0:
            break
        chosen.append(best)
        alive &= ~below[best]
    return np.array(chosen or [0], dtype=int)


def lattice_slack(
    a: np.ndarray,
    c: np.ndarray,
    cells: LatticeCells,
    floor: float,
    ceiling: float,
    where: np.ndarray | None = None,
) -> np.ndarray:
    """Per fine direction, ``min_f (a_f + c_f . d)``, exact wherever it lies in ``[floor,
    ceiling)``; elsewhere a value on the same side (``where``: NaN outside those directions).
    Whole cells beyond the band are decided by :func:`bounded_slack`; the undecided
    directions meet only the facets that can bring them below ``ceiling``."""
    slack, open_, facets = bounded_slack(a, c, cells, floor, ceiling, where)
    if len(open_):
        a, c = a[facets], c[facets]
        step = max(1, CHUNK // (4 * len(facets)))
        for i in range(0, len(open_), step):
            which = open_[i : i + step]
            # (facets, directions): the least over the first axis is the faster reduction.
            values = c @ cells.fine[which].T
            values += a[:, None]
            slack[which] = values.min(axis=0)
    return slack
