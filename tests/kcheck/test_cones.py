"""Polyhedral cones: a direction inside the image of a cone, and the essential rows found
with it, against independent computations (a linear programme for membership, brute force
and NNLS for the rows)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import linprog, nnls

from kcheck.mechanics import cones
from kcheck.mechanics.cones import balanced_image, cone_facets, essential_rows, inside_image


def _combines(generators: np.ndarray, y: np.ndarray) -> bool:
    """Whether ``y`` is a non-negative combination of the rows of ``generators``: a
    feasibility programme (HiGHS), independent of kcheck's cones. (scipy 1.13's NNLS, the
    declared lower bound, fails to converge on these cones.)"""
    combination = linprog(np.zeros(len(generators)), A_eq=generators.T, b_eq=y, bounds=(0, None))
    return combination.status == 0 and np.allclose(
        generators.T @ combination.x, y, atol=1e-9 * np.linalg.norm(y)
    )


def test_inside_image_lies_strictly_inside_the_cone() -> None:
    """Random six-dimensional cones (30 generators) and random four-column images: the ``x``
    found puts ``image @ x`` strictly inside every facet (facets from qhull), and a programme
    writes it as a non-negative combination of the generators (residual ~0)."""
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(20):
        generators = rng.normal(size=(30, 6)) + np.array([3.0, 0, 0, 0, 0, 0])
        image = rng.normal(size=(6, 4))
        x = inside_image(generators, image)
        facets = cone_facets(generators)
        assert not isinstance(facets, str)
        if x is None:
            continue
        y = image @ x
        assert np.all(facets @ y > 0)
        assert _combines(generators, y)
        checked += 1
    assert checked >= 10


def test_inside_image_is_none_where_the_image_misses_the_cone() -> None:
    """A cone in the half-space ``x_0 > 0`` and an image in ``x_0 = 0``: only the apex is
    shared, so no direction lies inside."""
    rng = np.random.default_rng(3)
    generators = np.abs(rng.normal(size=(20, 6)))
    generators[:, 0] += 1.0
    image = np.vstack([np.zeros((1, 4)), rng.normal(size=(5, 4))])
    assert inside_image(generators, image) is None


def test_balanced_image_lies_strictly_inside_the_cone() -> None:
    """The least-squares balance (no programme): where it answers, ``image @ x`` is strictly
    inside every facet (qhull's) and a linear programme writes it as a non-negative
    combination of the generators. Where the image's first column is the sum of the
    generators, all ones is the nearest balance, so ``x`` is the first unit vector; None
    where the image misses the cone (the half-space example below)."""
    rng = np.random.default_rng(7)
    checked = 0
    for trial in range(40):
        generators = rng.normal(size=(30, 6)) + np.array([3.0, 0, 0, 0, 0, 0])
        image = rng.normal(size=(6, 4))
        if trial % 2:
            image[:, 0] = generators.sum(axis=0)
        x = balanced_image(generators, image)
        if trial % 2:
            assert x is not None
            assert np.allclose(x, [1.0, 0.0, 0.0, 0.0], atol=1e-9)
        if x is None:
            continue
        facets = cone_facets(generators)
        assert not isinstance(facets, str)
        y = image @ x
        assert np.all(facets @ y > 0)
        assert _combines(generators, y)
        checked += 1
    assert checked >= 20
    generators = np.abs(rng.normal(size=(20, 6)))
    generators[:, 0] += 1.0
    image = np.vstack([np.zeros((1, 4)), rng.normal(size=(5, 4))])
    assert balanced_image(generators, image) is None


def test_essential_rows_do_not_depend_on_the_inside_direction(monkeypatch) -> None:
    """The rows kept with a caller's inside direction (no perceptron step before it, so that
    it is used every time) are those kept without it, and every row left out is a
    non-negative combination of the kept ones (NNLS residual ~0): the extreme rays, by brute
    force."""
    monkeypatch.setattr(cones, "GUESS_AFTER", 0)
    rng = np.random.default_rng(11)
    compared = 0
    for _ in range(10):
        generators = rng.normal(size=(24, 6)) + np.array([2.5, 0, 0, 0, 0, 0])
        image = rng.normal(size=(6, 4))
        facets = cone_facets(generators)
        assert not isinstance(facets, str)
        rows = facets @ image
        plain = essential_rows(rows)
        guided = essential_rows(rows, lambda g=generators, i=image: inside_image(g, i))
        cheap = essential_rows(
            rows,
            lambda g=generators, i=image: balanced_image(g, i),
            lambda g=generators, i=image: inside_image(g, i),
        )
        if plain is None:
            continue
        assert guided is not None
        compared += 1
        assert np.array_equal(plain, guided)
        assert np.array_equal(plain, cheap)
        for r in np.setdiff1d(np.arange(len(rows)), plain):
            _, residual = nnls(rows[plain].T, rows[r])
            assert residual < 1e-7 * np.linalg.norm(rows[r])
    assert compared >= 5


def test_planar_facets_are_numpys_bits():
    """Three-dimensional cones' facets in plain float arithmetic are, bit for bit and in the
    same row order, those of the numpy formulation they replaced (cross products of pairs,
    normalised, kept where every generator is on one side, rounded to FACET_DECIMALS and
    deduplicated), written out here as the independent reference; random cones of three to
    six generators and cones with parallel or coinciding generators."""
    from kcheck.numerics.arrays import unique_rounded_rows
    from kcheck.numerics.thresholds import FACET_DECIMALS, FACET_TOL

    def reference(g: np.ndarray) -> np.ndarray | str:
        if np.linalg.matrix_rank(g, tol=FACET_TOL) < 3:
            return "flat"
        i, j = np.triu_indices(len(g), 1)
        normals = np.cross(g[i], g[j])
        size = np.linalg.norm(normals, axis=1)
        normals = normals[size > FACET_TOL] / size[size > FACET_TOL, None]
        side = normals @ g.T
        upper = np.all(side >= -FACET_TOL, axis=1)
        lower = np.all(side <= FACET_TOL, axis=1)
        facets = np.vstack([normals[upper], -normals[lower & ~upper]])
        return unique_rounded_rows(facets, FACET_DECIMALS) if len(facets) else "everywhere"

    rng = np.random.default_rng(24)
    for _ in range(1500):
        g = rng.normal(size=(int(rng.integers(3, 7)), 3))
        if rng.random() < 0.3:
            g[-1] = g[0] * rng.choice([1.0, -1.0, 2.0])
        if rng.random() < 0.3:
            g = np.round(g)
            g[np.all(g == 0, axis=1)] = (0.0, 0.0, 1.0)
        expected = reference(g)
        got = cone_facets(g)
        if isinstance(expected, str):
            assert got == expected
        else:
            assert isinstance(got, np.ndarray)
            assert got.tobytes() == expected.tobytes()
            assert got.shape == expected.shape


def test_rank_three_by_minor_never_contradicts_the_singular_values():
    """Where three generators' determinant settles the planar cone's rank
    (``_rank_three_by_minor``), the SVD's count (``_flat``, the rank test it stands in for)
    says rank 3 as well: random unit generators, coplanar ones and ones tilted off a plane by
    1e-12 to 1e-6 (either side of the rank test's 1e-10), three to six rows. Both the settled
    and the undecided sides are exercised, and every coplanar set stays undecided."""
    rng = np.random.default_rng(7)
    settled = undecided = 0
    for _ in range(6000):
        count = int(rng.integers(3, 7))
        g = rng.normal(size=(count, 3))
        if rng.random() < 0.6:  # near a plane: the third coordinate small
            g[:, 2] = rng.normal(size=count) * 10.0 ** rng.uniform(-13, -5)
            if rng.random() < 0.3:
                g[:, 2] = 0.0
        g /= np.linalg.norm(g, axis=1, keepdims=True)
        g = np.round(g, 14)
        if cones._rank_three_by_minor(g.tolist()):
            settled += 1
            assert not cones._flat(g)
            assert np.linalg.matrix_rank(g, tol=cones.FACET_TOL) == 3
        else:
            undecided += 1
        if not np.any(g[:, 2]):
            assert not cones._rank_three_by_minor(g.tolist())
    assert settled > 1000 and undecided > 1000
