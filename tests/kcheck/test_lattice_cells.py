"""Coarse-to-fine lattice tests (issue 24): the cells decide exactly what every direction's
own evaluation decides, and the sparse matrices handed to clarabel are scipy's."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.arcs import TAU, intersect, intersect_single
from kcheck.mechanics.csc import Csc
from kcheck.mechanics.lattice_cells import bounded_slack, lattice_cells, lattice_slack
from kcheck.mechanics.sphere import fibonacci_sphere


def test_cells_cover_the_lattice_with_their_largest_chord():
    cells = lattice_cells(2000)
    fine = fibonacci_sphere(2000)
    assert np.array_equal(cells.fine, fine)
    # Independent: each direction's nearest coarse direction by brute force.
    nearest = np.argmin(np.linalg.norm(fine[:, None, :] - cells.coarse[None], axis=2), axis=1)
    chord = np.linalg.norm(fine - cells.coarse[nearest], axis=1)
    assert np.allclose(np.linalg.norm(fine - cells.coarse[cells.owner], axis=1), chord)
    for cell in range(len(cells.coarse)):
        members = cells.owner == cell
        if np.any(members):
            assert cells.radius[cell] == pytest.approx(chord[members].max())


@pytest.mark.parametrize("seed", range(6))
def test_bounded_slack_decides_as_every_direction_does(seed):
    rng = np.random.default_rng(seed)
    cells = lattice_cells(4000)
    # A spherical polygon: caps about nearby axes, as a held set's facets.
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    c = axis + 0.6 * rng.normal(size=(40, 3))
    a = -np.linalg.norm(c, axis=1) * np.cos(rng.uniform(0.2, 1.2, 40))
    exact = np.min(a + cells.fine @ c.T, axis=1)  # every direction, every facet
    tol = 1e-9
    slack, open_, _ = bounded_slack(a, c, cells, -tol, tol)
    decided = np.setdiff1d(np.arange(len(exact)), open_)
    assert np.all(np.isnan(slack[open_]))
    for threshold in (-tol, 0.0, tol):
        assert np.array_equal(slack[decided] >= threshold, exact[decided] >= threshold)
    # Cells decide most of the sphere: only directions near the boundary stay open.
    assert len(open_) < 0.5 * len(exact)


@pytest.mark.parametrize("seed", range(6))
def test_lattice_slack_is_every_facets_least_where_the_map_compares_it(seed):
    """lattice_slack against the least slack over every facet at every direction (numpy,
    no cells): the same comparisons with the floor, 0 and the ceiling everywhere, the same
    value within rounding wherever it lies between floor and ceiling; with ``where``, the
    same for the wanted directions and NaN or a bound elsewhere."""
    rng = np.random.default_rng(10 + seed)
    cells = lattice_cells(4000)
    # A spherical polygon about ``axis``: caps that each hold it by 0.1-0.5 rad.
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    centres = axis + 0.3 * rng.normal(size=(60, 3))
    centres /= np.linalg.norm(centres, axis=1, keepdims=True)
    radius = np.arccos(centres @ axis) + rng.uniform(0.1, 0.5, 60)
    c = centres * rng.uniform(0.5, 2.0, (60, 1))
    a = -np.linalg.norm(c, axis=1) * np.cos(radius)
    exact = np.min(a + cells.fine @ c.T, axis=1)
    tol = 0.05  # wide, so that many directions lie in the band
    for where in (None, exact >= -tol):
        slack = lattice_slack(a, c, cells, -tol, tol, where)
        wanted = np.ones(len(exact), bool) if where is None else where
        for threshold in (-tol, 0.0, tol):
            assert np.array_equal(slack[wanted] >= threshold, exact[wanted] >= threshold)
        band = wanted & (exact >= -tol) & (exact < tol)
        assert np.count_nonzero(band) > 10
        assert np.allclose(slack[band], exact[band], rtol=0, atol=1e-14)


def test_intersect_single_is_intersect():
    rng = np.random.default_rng(3)
    for trial in range(2000):
        k = int(rng.integers(2, 10))
        start = rng.uniform(0, TAU, k) if trial % 2 else rng.choice(rng.uniform(0, TAU, 3), k)
        end = start + 2.0 * rng.choice([0.5, 1.5, 2.9, rng.uniform(0, np.pi)], k)
        reference = intersect(*(((float(s), float(e)),) for s, e in zip(start, end, strict=True)))
        assert intersect_single(start, end) == reference


def test_intersect_single_is_intersect_where_ends_coincide():
    """Ends shared by several arcs, arcs ending where another starts, and full turns whose
    end - 2 pi rounds past their start (start + 2 pi in floating point): the elementary
    intervals one ulp wide there are inside or outside as :func:`intersect` finds them."""
    rng = np.random.default_rng(7)
    for _ in range(4000):
        k = int(rng.integers(2, 12))
        pool = rng.uniform(0, TAU, 4)
        start = rng.choice(pool, k)
        kind = rng.integers(0, 4, k)
        touching = (rng.choice(pool, k) - start) % TAU
        length = np.select(
            [kind == 0, kind == 1, kind == 2],
            [touching, np.full(k, TAU), rng.uniform(0, TAU, k)],
            2 * np.arccos(rng.uniform(-1, 1, k)),  # as affine_arcs builds them
        )
        end = start + np.where(length > 0, length, TAU)
        reference = intersect(*(((float(s), float(e)),) for s, e in zip(start, end, strict=True)))
        assert intersect_single(start, end) == reference


def test_csc_matches_scipy():
    sparse = pytest.importorskip("scipy.sparse")
    dense = np.random.default_rng(1).normal(size=(9, 13))
    dense[dense < 0.4] = 0.0
    ours, theirs = Csc.of(dense), sparse.csc_matrix(dense)
    assert np.array_equal(ours.indptr, theirs.indptr)
    assert np.array_equal(ours.indices, theirs.indices)
    assert np.array_equal(ours.data, theirs.data)
    assert ours.shape == theirs.shape and ours.nnz == theirs.nnz
