"""Lemke's method (kcheck.numerics.lemke): the condensed tableau and the batch take the pivots
of the textbook full tableau ``[I, -A, -e, q]`` (Cottle, Pang & Stone 1992, §4.4), written
out again here as the reference, bit for bit, on random problems and on the lift-off problems
of random spatial bodies (degenerate: many zeros in q, ties in the ratio test)."""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.mechanics.lift_off import contact_rows, lcp
from kcheck.numerics.lemke import PIVOTS_PER_UNKNOWN, lemke, lemke_batch, lemke_padded
from kcheck.numerics.thresholds import LEMKE_PIVOT_RTOL


def full_tableau(a: np.ndarray, q: np.ndarray) -> np.ndarray | None:
    """The full-tableau Lemke (the implementation before the condensed one, kept verbatim as
    the reference): every column of w, z, z0 and the right-hand side, updated every pivot."""
    n = len(q)
    if np.all(q >= 0):
        return np.zeros(n)
    tableau = np.hstack([np.eye(n), -a, -np.ones((n, 1)), q[:, None]]).astype(float)
    basis = list(range(n))
    artificial = 2 * n
    row = int(np.argmin(q))
    entering = artificial
    for _ in range(PIVOTS_PER_UNKNOWN * n + 1):
        tableau[row] /= tableau[row, entering]
        factors = tableau[:, entering].copy()
        factors[row] = 0.0
        tableau -= factors[:, None] * tableau[row][None, :]
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
        ends = [r for r in best if basis[r] == artificial]
        row = int(ends[0] if ends else best[0])
    return None


def _same(x: np.ndarray | None, y: np.ndarray | None) -> bool:
    return (x is None) == (y is None) and (x is None or np.array_equal(x, y))


def _lift_off_problems(rng: np.random.Generator, count: int) -> list[tuple[np.ndarray, ...]]:
    """Lift-off LCPs (kcheck.mechanics.lift_off.lcp) of random spatial bodies on 1 to 3
    contacts under random wrenches, 16-edge pyramids."""
    out = []
    for _ in range(count):
        c = int(rng.integers(1, 4))
        points = rng.uniform(-1, 1, (c, 3))
        normals = rng.normal(size=(c, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        cloud = rng.normal(0, 0.3, (6, 3))
        inertia = np.sum(cloud**2) * np.eye(3) - cloud.T @ cloud
        rows = contact_rows(points, normals, rng.uniform(0.05, 0.5, c), np.zeros(3), inertia)
        out.append(lcp(rows, rng.normal(size=6)))
    return out


def test_condensed_tableau_pivots_as_the_full_one() -> None:
    rng = np.random.default_rng(24)
    problems = _lift_off_problems(rng, 40)
    for _ in range(150):
        n = int(rng.integers(1, 12))
        a = rng.normal(size=(n, n))
        q = rng.normal(size=n) * (rng.random(n) < 0.7)  # zeros: degenerate ties
        problems.append((a, q))
    solved = 0
    for a, q in problems:
        expected = full_tableau(a, q)
        assert _same(lemke(a, q), expected)
        solved += expected is not None
    assert solved > 60  # measured 91 of 190; rays (None) agree too


def test_batch_solves_each_problem_as_alone() -> None:
    """Problems of one size in one batch: each the solution lemke gives alone, bit for bit,
    including problems that end on a ray (None) or start solved (q >= 0)."""
    rng = np.random.default_rng(26)
    lifts = _lift_off_problems(rng, 30)
    by_size: dict[int, list[tuple[np.ndarray, np.ndarray]]] = {}
    for a, q in lifts:
        by_size.setdefault(len(q), []).append((a, q))
    for n in (3, 7):
        for _ in range(20):
            a = rng.normal(size=(n, n))
            by_size.setdefault(n, []).append((a, rng.normal(size=n) * (rng.random(n) < 0.7)))
        by_size[n].append((np.eye(n), np.ones(n)))  # solved at the start: z = 0
    kinds = set()
    for group in by_size.values():
        got = lemke_batch(np.stack([a for a, _ in group]), np.stack([q for _, q in group]))
        for (a, q), z in zip(group, got, strict=True):
            expected = lemke(a, q)
            assert _same(z, expected)
            kinds.add("ray" if z is None else "rest" if not z.any() else "solved")
    assert kinds == {"ray", "rest", "solved"}


def test_padded_batch_solves_each_problem_as_alone() -> None:
    """Problems of different sizes padded to the largest (rows that touch nothing): each the
    solution lemke gives it alone, bit for bit."""
    rng = np.random.default_rng(27)
    problems = _lift_off_problems(rng, 20)
    for n in (2, 5, 9):
        for _ in range(5):
            problems.append((rng.normal(size=(n, n)), rng.normal(size=n) * (rng.random(n) < 0.7)))
    got = lemke_padded(problems)
    assert len({len(q) for _, q in problems}) > 3
    for (a, q), z in zip(problems, got, strict=True):
        assert _same(z, lemke(a, q))


def test_padded_batch_gives_up_at_each_problems_own_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    """With the pivot limit shrunk to one pivot per unknown, small random problems padded
    beside a large one give up after their own ``n + 1`` pivots, as alone: each the answer
    lemke gives it alone, bit for bit. Some of them would solve within the padded size's
    limit (the batch of the same padded problems given the padded size's limit answers
    them), so the test tells the two limits apart."""
    import kcheck.numerics.lemke as module

    monkeypatch.setattr(module, "PIVOTS_PER_UNKNOWN", 1)
    rng = np.random.default_rng(28)
    problems = [(rng.normal(size=(12, 12)), rng.normal(size=12))]
    for _ in range(1000):
        n = int(rng.integers(2, 5))
        problems.append((rng.normal(size=(n, n)), rng.normal(size=n)))
    alone = [lemke(a, q) for a, q in problems]
    for z, expected in zip(lemke_padded(problems), alone, strict=True):
        assert _same(z, expected)
    # The same padding with every problem given the padded size's limit (sizes left out).
    a = np.zeros((len(problems), 12, 12))
    q, cover = np.ones((len(problems), 12)), np.zeros((len(problems), 12))
    for i, (ai, qi) in enumerate(problems):
        m = len(qi)
        a[i, :m, :m], q[i, :m], cover[i, :m] = ai, qi, 1.0
    longer = lemke_batch(a, q, cover)
    pairs = zip(longer[1:], alone[1:], strict=True)
    cut = sum(expected is None and z is not None for z, expected in pairs)
    assert cut > 0  # measured: 5 of 1000 solve with 13 pivots, not with their own n + 1
