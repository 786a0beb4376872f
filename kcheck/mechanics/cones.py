"""Polyhedral convex cones: facets from generators, pointedness, essential inequalities.

Small numpy functions on cones ``{sum lambda_i g_i : lambda >= 0}`` and on their inequality
form ``{x : F x >= 0}``, for the statics of :mod:`kcheck.mechanics.statics`. Three dimensions are
handled exactly (cross products); more with qhull on a section of the cone (scipy, imported
only then) and small linear programmes solved by clarabel.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Literal

import numpy as np

from kcheck.numerics.arrays import (
    round3_like_numpy,
    row_lengths,
    sorted_unique_tuples,
    unique,
    unique_rounded_rows,
)
from kcheck.numerics.thresholds import (
    FACET_DECIMALS,
    FACET_TOL,
    HULL_FACET_DECIMALS,
    HULL_FACET_TOL,
    IMAGE_RANK_RTOL,
    LP_EQUALITY_SLACK,
    LP_POSITIVE,
    RANK_MINOR_MARGIN,
    WELL_INSIDE,
)

__all__ = [
    "FACET_TOL",
    "cone_facets",
    "planar_cone_holds",
    "pointing",
    "essential_rows",
    "inside_image",
    "balanced_image",
]

PERCEPTRON_STEPS = 50
#: Perceptron steps before a caller's guess (:func:`pointing`): most cones that have a
#: direction with the margin give it within a few steps; the guess is one small programme.
GUESS_AFTER = 12


def cone_facets(generators: np.ndarray) -> np.ndarray | Literal["everywhere", "flat"]:
    """Inward unit facet normals (f, n) of the cone spanned by the generators (g, n).

    The cone is ``{x : F x >= 0}``. Returns ``"everywhere"`` when the generators span the
    whole space positively (any wrench is balanced) and ``"flat"`` when they do not span it
    (e.g. every remaining support frictionless: equilibrium only for loads on a measure-zero
    set of directions). Three dimensions (planar): cross products of pairs, exact. Six
    (spatial): the facets of a section of the cone, from qhull (joggled input, ``QJ``: the
    pyramids' coplanar edges are degenerate for exact arithmetic; facets move by about 1e-11).
    """
    n = generators.shape[1]
    if n == 3:
        # A planar check asks for the same cone again (a fifth of its calls: the scene's
        # friction, mu = 0, a case's cone in several checks); facets are a pure function of
        # the generators' bits, so the last few answers are kept (read-only).
        key = generators.tobytes() + bytes([len(generators)])
        known = _RECENT_PLANAR.get(key)
        if known is None:
            known = _cone_facets(generators)
            if isinstance(known, np.ndarray):
                known.setflags(write=False)
            if len(_RECENT_PLANAR) >= RECENT_PLANAR:
                del _RECENT_PLANAR[next(iter(_RECENT_PLANAR))]
            _RECENT_PLANAR[key] = known
        return known
    return _cone_facets(generators)


#: Planar cones' facets recently computed (:func:`cone_facets`), oldest first.
_RECENT_PLANAR: dict[bytes, np.ndarray | Literal["everywhere", "flat"]] = {}
RECENT_PLANAR = 64


def _cone_facets(generators: np.ndarray) -> np.ndarray | Literal["everywhere", "flat"]:
    n = generators.shape[1]
    if n == 3:
        rows = generators.tolist()
        if not _rank_three_by_minor(rows) and _flat(generators):
            return "flat"
        return _planar_facets(rows)
    if _flat(generators):
        return "flat"
    normals = _hull_facets(generators)
    # (generators, facets): the least and largest side of each facet reduce along the long
    # axis (numpy's reductions along short rows cost a call per row).
    side = generators @ normals.T
    tol = HULL_FACET_TOL if n > 3 else FACET_TOL
    # The least and the largest side against the tolerance: every generator on one side
    # (a NaN fails both, as the element-wise tests would).
    upper = side.min(axis=0) >= -tol
    lower = side.max(axis=0) <= tol
    facets = np.vstack([normals[upper], -normals[lower & ~upper]])
    if not len(facets):
        return "everywhere"
    return unique_rounded_rows(facets, HULL_FACET_DECIMALS if n > 3 else FACET_DECIMALS)


def _flat(generators: np.ndarray) -> bool:
    """``np.linalg.matrix_rank(generators, tol=FACET_TOL) < n``, without its wrapper's cost (a
    planar jamming check asks for a few thousand cones): the same singular values."""
    n = generators.shape[1]
    return bool(np.count_nonzero(np.linalg.svd(generators, compute_uv=False) > FACET_TOL) < n)


def _rank_three_by_minor(rows: Sequence[Sequence[float]]) -> bool:
    """Whether the first three of three-dimensional rows certainly have rank 3 by
    :func:`_flat`'s test, without an SVD: removing rows lowers no singular value, and three
    rows' ``|det| = s1 s2 s3 <= s3 (s1^2 + s2^2) / 2 <= s3 |S|_F^2 / 2``, so ``2 |det| /
    |S|_F^2`` bounds the least singular value from below; asked to exceed FACET_TOL by
    RANK_MINOR_MARGIN, far beyond either computation's rounding. False: undecided (the SVD
    decides)."""
    if len(rows) < 3 or not math.isfinite(sum(v * v for row in rows for v in row)):
        return False  # a non-finite generator: the SVD's answer, as before
    (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = rows[0], rows[1], rows[2]
    det = a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0) + a2 * (b0 * c1 - b1 * c0)
    frobenius = sum(v * v for row in rows[:3] for v in row)
    return 2.0 * abs(det) > RANK_MINOR_MARGIN * FACET_TOL * frobenius


def _planar_facets(generators: list[list[float]]) -> np.ndarray | Literal["everywhere"]:
    """Facets of a three-dimensional cone spanned by its generators (g, 3), of rank 3, in plain
    float arithmetic: a planar jamming check asks for a few thousand such cones of at most
    six generators, where numpy's per-call overhead was most of the time. Cross products of
    pairs (i < j) normalised (squares summed left to right, as ``np.linalg.norm``), those
    with every generator on one side (within FACET_TOL), rounded as ``np.round`` (``rint(x
    10^d) / 10^d``, the zero's sign kept), sorted and deduplicated as ``unique_rows``."""
    normals = []
    count = len(generators)
    for i in range(count):
        a0, a1, a2 = generators[i]
        for j in range(i + 1, count):
            b0, b1, b2 = generators[j]
            c = (a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0)
            size = math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
            if size > FACET_TOL:
                normals.append((c[0] / size, c[1] / size, c[2] / size))
    upper, lower = [], []
    for f0, f1, f2 in normals:
        # The sides are finite (unit normals, finite generators: _flat's SVD or the minor
        # passed them), so min and max decide as the element-wise tests would.
        side = [f0 * g0 + f1 * g1 + f2 * g2 for g0, g1, g2 in generators]
        if min(side) >= -FACET_TOL:
            upper.append((f0, f1, f2))
        elif max(side) <= FACET_TOL:
            lower.append((-f0, -f1, -f2))
    facets = upper + lower
    if not facets:
        return "everywhere"
    scale = 10.0**FACET_DECIMALS  # unit facets: |f scale| is far inside RINT_SHIFT's bound
    rounded: list[tuple[float, ...]] = [
        round3_like_numpy(f0, f1, f2, scale) for f0, f1, f2 in facets
    ]
    return sorted_unique_tuples(rounded)


def planar_cone_holds(
    generators: Sequence[Sequence[float]],
    against: Sequence[float],
    limit: float,
    margin: float,
) -> bool | None:
    """``np.all(cone_facets(G) @ against >= limit)`` (True also for ``"everywhere"``, False
    for ``"flat"``) of a three-dimensional cone's unit generators ``G`` (finite, rows in
    ``sorted_unique_tuples``' order, as ``statics._planar_generator_rows`` makes them), in
    plain float arithmetic without building the facets' array: the same rank test
    (:func:`_rank_three_by_minor`) and the same rounded facets (:func:`_planar_facets`'
    operations), each facet's product compared as it comes (the first clearly below
    ``limit`` decides False). numpy's product may differ from the plain one by a few
    roundings (it fuses multiply-adds): a product within ``margin`` of ``limit`` (the
    caller's bound on that difference), or a rank the SVD must decide, gives None:
    undecided, the caller asks :func:`cone_facets`."""
    count = len(generators)
    if count < 3:
        return None
    # _rank_three_by_minor of unit (finite) generators, its sums written out: the squares
    # are non-negative, so adding them to sum()'s start 0 first changes no bit.
    (p0, p1, p2), (q0, q1, q2), (s0, s1, s2) = generators[0], generators[1], generators[2]
    det = p0 * (q1 * s2 - q2 * s1) - p1 * (q0 * s2 - q2 * s0) + p2 * (q0 * s1 - q1 * s0)
    frobenius = (
        p0 * p0 + p1 * p1 + p2 * p2 + q0 * q0 + q1 * q1 + q2 * q2 + s0 * s0 + s1 * s1 + s2 * s2
    )
    if not 2.0 * abs(det) > RANK_MINOR_MARGIN * FACET_TOL * frobenius:
        return None
    a0, a1, a2 = against
    scale = 10.0**FACET_DECIMALS  # unit facets: |f scale| is far inside RINT_SHIFT's bound
    close = False
    for i in range(count):
        g0, g1, g2 = generators[i]
        for j in range(i + 1, count):
            h0, h1, h2 = generators[j]
            c0, c1, c2 = g1 * h2 - g2 * h1, g2 * h0 - g0 * h2, g0 * h1 - g1 * h0
            size = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
            if not size > FACET_TOL:
                continue
            f0, f1, f2 = c0 / size, c1 / size, c2 / size
            side = [f0 * x0 + f1 * x1 + f2 * x2 for x0, x1, x2 in generators]
            if min(side) >= -FACET_TOL:
                r0, r1, r2 = round3_like_numpy(f0, f1, f2, scale)
            elif max(side) <= FACET_TOL:
                r0, r1, r2 = round3_like_numpy(-f0, -f1, -f2, scale)
            else:
                continue
            value = r0 * a0 + r1 * a1 + r2 * a2
            if value < limit - margin:
                return False
            if value < limit + margin:
                close = True
    return None if close else True


def pointing(vectors: np.ndarray, *guesses: Callable[[], np.ndarray | None]) -> np.ndarray | None:
    """A direction ``h`` with ``vectors @ h > 0`` (the cone they span is pointed), or None.

    Perceptron steps from the mean of the unit vectors first (enough for most cones), then
    each ``guess()`` in turn when given (a caller's cheaper ways to one, the first kept that
    passes the linear programme's own acceptance: every ``v . h`` above LP_POSITIVE at
    ``|h_i| <= 1``), else that linear programme, maximising the smallest ``v . h`` over
    ``|h_i| <= 1``.
    """
    unit = vectors / row_lengths(vectors)
    h = unit.mean(axis=0)
    # Perceptron steps towards the violated vectors: converges when the cone is pointed with
    # some margin, at the cost of a few matrix-vector products. A direction barely inside
    # makes a badly scaled section, so a small margin goes on to the linear programme.
    for _ in range(GUESS_AFTER if guesses else PERCEPTRON_STEPS):
        side = unit @ h
        # |h| as np.linalg.norm computes it (sqrt of h . h), without its wrapper's cost.
        bad = side <= WELL_INSIDE * math.sqrt(float(h.dot(h)))
        if not bad.any():
            return h
        h = h + unit[bad].mean(axis=0)
    for guess in guesses:
        found = guess()
        # The programme's own acceptance below: every margin above LP_POSITIVE at |h_i| <= 1.
        if found is not None and np.all(unit @ found > LP_POSITIVE * np.abs(found).max()):
            return found
    n = vectors.shape[1]
    # maximise t subject to unit @ h >= t, |h_i| <= 1, t <= 1 (an LP, solved by clarabel:
    # a tenth of scipy's per-call overhead, and already imported for the conic problems).
    rows = np.vstack(
        [
            np.column_stack([-unit, np.ones(len(unit))]),
            np.hstack([np.eye(n), np.zeros((n, 1))]),
            np.hstack([-np.eye(n), np.zeros((n, 1))]),
            np.append(np.zeros(n), 1.0),
        ]
    )
    rhs = np.concatenate([np.zeros(len(unit)), np.ones(2 * n), [1.0]])
    x = _solve_lp(np.append(np.zeros(n), -1.0), rows, rhs)
    # A margin below LP_POSITIVE is within the solver's tolerances: not pointed (flat).
    return x[:n] if x is not None and x[n] > LP_POSITIVE else None


def _solve_lp(cost: np.ndarray, rows: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    """Minimise ``cost . x`` subject to ``rows @ x <= rhs`` with clarabel; None unless solved."""
    import clarabel

    from kcheck.mechanics.csc import Csc

    settings = clarabel.DefaultSettings()
    settings.verbose = False
    n = len(cost)
    solver = clarabel.DefaultSolver(
        Csc.empty(n),
        cost,
        Csc.of(rows),
        rhs,
        [clarabel.NonnegativeConeT(len(rhs))],
        settings,
    )
    solution = solver.solve()
    return np.asarray(solution.x) if str(solution.status) == "Solved" else None


def inside_image(generators: np.ndarray, image: np.ndarray) -> np.ndarray | None:
    """An ``x`` with ``image @ x`` inside the cone the generators (g, n) span, as deep as a
    linear programme finds it: ``image @ x = sum lambda_i g_i`` with ``sum lambda = 1`` and
    the least ``lambda_i`` largest; None when it is not positive (above LP_POSITIVE).

    Then ``f . image @ x > 0`` for every facet ``f`` of that cone that some generator lies
    strictly inside of: a pointing direction for the rows ``F @ image`` (``image`` (n, m)),
    from a programme with g + m + 1 variables and g + n + 1 rows, whatever the facets' count.
    """
    import clarabel

    from kcheck.mechanics.csc import Csc

    g, n = generators.shape
    m = image.shape[1]
    # Variables (lambda (g), x (m), t); rows: G^T lambda - image x = 0, sum lambda = 1 (zero
    # cone), then t - lambda_i <= 0 (non-negative cone).
    rows = np.zeros((n + 1 + g, g + m + 1))
    rows[:n, :g] = generators.T
    rows[:n, g : g + m] = -image
    rows[n, :g] = 1.0
    rows[n + 1 :, :g] = -np.eye(g)
    rows[n + 1 :, -1] = 1.0
    rhs = np.zeros(n + 1 + g)
    rhs[n] = 1.0
    cost = np.zeros(g + m + 1)
    cost[-1] = -1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solver = clarabel.DefaultSolver(
        Csc.empty(g + m + 1),
        cost,
        Csc.of(rows),
        rhs,
        [clarabel.ZeroConeT(n + 1), clarabel.NonnegativeConeT(g)],
        settings,
    )
    solution = solver.solve()
    if str(solution.status) != "Solved":
        return None
    x = np.asarray(solution.x)
    return x[g : g + m] if x[-1] > LP_POSITIVE else None


def balanced_image(generators: np.ndarray, image: np.ndarray) -> np.ndarray | None:
    """An ``x`` with ``image @ x = sum lambda_i g_i``, every ``lambda_i`` positive, from least
    squares (no programme): ``lambda`` the nearest to all ones whose combination lies in the
    range of ``image`` (n, m); None where some ``lambda_i`` is not positive or the range is
    not of full rank. A cheaper, less central :func:`inside_image`."""
    n, m = image.shape
    q, r = np.linalg.qr(image, mode="complete")
    if not np.all(np.abs(np.diag(r[:m])) > IMAGE_RANK_RTOL * np.abs(r).max()):
        return None
    across = q[:, m:].T @ generators.T  # (n - m, g): what leaves the range
    gram = across @ across.T
    try:
        lam = 1.0 - across.T @ np.linalg.solve(gram, across.sum(axis=1))
    except np.linalg.LinAlgError:
        return None
    if not lam.min() > 0:
        return None
    return np.linalg.solve(r[:m], q[:, :m].T @ (generators.T @ lam))


def _section(vectors: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points where the rays cross ``h . x = 1``, in an orthonormal basis ``Q`` of ``h``'s
    complement: returns ``(Y, Q)`` with ``x = Q y + h / |h|^2``."""
    q = np.linalg.svd(np.eye(len(h)) - np.outer(h, h) / (h @ h))[0][:, : len(h) - 1]
    return (vectors / (vectors @ h)[:, None]) @ q, q


def _hull_facets(generators: np.ndarray) -> np.ndarray:
    """Facet normals of the cone spanned by the generators (four or more dimensions).

    A pointed cone: the facets of a section (qhull). A cone containing a line (two supports
    squeezing the body between them inside their friction cones): its facets are those of
    its projection onto the complement of that lineality space.
    """
    h = pointing(generators)
    if h is not None:
        return _section_facets(generators, h)
    lineality = _lineality(generators)
    n = generators.shape[1]
    if lineality.shape[1] == n:
        return np.zeros((0, n))
    basis = np.linalg.svd(np.eye(n) - lineality @ lineality.T)[0][:, : n - lineality.shape[1]]
    reduced = generators @ basis
    reduced = reduced[np.linalg.norm(reduced, axis=1) > FACET_TOL]
    k = basis.shape[1]
    if k == 1:
        return np.sign(reduced[:1, 0])[:, None] * basis.T
    if k == 2:
        angles = np.arctan2(reduced[:, 1], reduced[:, 0])
        rays = reduced[[int(np.argmin(angles)), int(np.argmax(angles))]]
        facets = np.column_stack([-rays[:, 1], rays[:, 0]])
    elif k == 3:
        i, j = np.triu_indices(len(reduced), 1)
        facets = np.cross(reduced[i], reduced[j])
        facets = facets[np.linalg.norm(facets, axis=1) > FACET_TOL]
    else:
        h = pointing(reduced)
        if h is None:  # numerically borderline: no trustworthy facets
            return np.zeros((0, n))
        facets = _section_facets(reduced, h)
    normals = facets @ basis.T
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def _section_facets(generators: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Facet normals of a pointed cone (``generators @ h > 0``) from qhull on a section."""
    from scipy.spatial import ConvexHull

    y, q = _section(generators, h)
    eq = ConvexHull(y, qhull_options="QJ").equations
    # e . y + o <= 0 inside, with y = Q^T x on h . x = 1: (Q e + o h) . x <= 0.
    normals = -(eq[:, :-1] @ q.T) - eq[:, -1:] * h[None, :]
    return normals / row_lengths(normals)


def _lineality(generators: np.ndarray) -> np.ndarray:
    """Orthonormal basis (n, l) of the largest subspace inside the cone: the span of the
    generators that take part in a positive dependency ``sum lambda_i g_i = 0`` (an LP)."""
    g, n = generators.shape
    # Variables lambda (g), t (g): maximise sum t with 0 <= t <= lambda, t <= 1,
    # G^T lambda = 0 (as two inequalities), lambda <= 1e6 (bounded).
    eye, zero = np.eye(g), np.zeros((g, g))
    rows = np.vstack(
        [
            np.hstack([-eye, eye]),
            np.hstack([zero, eye]),
            np.hstack([zero, -eye]),
            np.hstack([-eye, zero]),
            np.hstack([eye, zero]),
            np.hstack([generators.T, np.zeros((n, g))]),
            np.hstack([-generators.T, np.zeros((n, g))]),
        ]
    )
    rhs = np.concatenate([np.zeros(g), np.ones(g), np.zeros(2 * g), np.full(g, 1e6)])
    rhs = np.concatenate([rhs, np.full(2 * n, LP_EQUALITY_SLACK)])
    x = _solve_lp(np.concatenate([np.zeros(g), -np.ones(g)]), rows, rhs)
    inside = x[g:] > LP_POSITIVE if x is not None else np.zeros(g, bool)
    if not np.any(inside):
        return np.zeros((n, 0))
    u, s, _ = np.linalg.svd(generators[inside].T, full_matrices=False)
    return u[:, s > FACET_TOL * s[0]]


def essential_rows(rows: np.ndarray, *inside: Callable[[], np.ndarray | None]) -> np.ndarray | None:
    """Indices of the rows that are extreme rays of the cone they span: the others are
    non-negative combinations of them, so ``rows @ x >= 0`` keeps its solutions without them.
    None when that cone is not pointed (the solution set has an empty interior).

    ``inside``: the caller's ways to an ``x`` with ``rows @ x > 0``, cheapest first, tried
    where perceptron steps find none (:func:`pointing`); the rows kept do not depend on it."""
    if len(rows) <= rows.shape[1]:
        return np.arange(len(rows))
    _, s, vt = np.linalg.svd(rows, full_matrices=False)
    rank = int(np.count_nonzero(s > FACET_TOL * s[0]))
    reduced = rows @ vt[:rank].T

    def reduce(found: Callable[[], np.ndarray | None]) -> Callable[[], np.ndarray | None]:
        def guess() -> np.ndarray | None:
            x = found()
            return None if x is None else vt[:rank] @ x

        return guess

    h = pointing(reduced, *(reduce(found) for found in inside))
    if h is None:
        return None
    if rank <= 2:
        y = _section(reduced, h)[0][:, 0] if rank == 2 else np.zeros(len(rows))
        return np.unique([int(np.argmin(y)), int(np.argmax(y))])
    from scipy.spatial import ConvexHull, QhullError

    points = _section(reduced, h)[0]
    # A hull's vertices, sorted: the distinct indices of its simplices (what scipy's
    # ``vertices`` is, without np.unique's cost).
    try:  # exact arithmetic first: joggling is relative to the spread of the points
        return unique(ConvexHull(points).simplices)
    except QhullError:
        return unique(ConvexHull(points, qhull_options="QJ").simplices)
