"""The least friction that holds: the smallest common coefficient for which the remaining
supports can balance a wrench (:mod:`kcheck.mechanics.statics` decides single coefficients).

* Planar: exactly, as the least feasible root among the pair and triple determinants of the
  edge wrenches (:func:`friction_candidates`), found by bisection over those candidates.
* Spatial: where every contact pressed at the limit slides there, the limit itself by
  Newton's method, checked without a conic solve
  (:func:`kcheck.mechanics.sliding_limit.sliding_limit`); otherwise
  Dinkelbach-type steps on the largest friction ratio of balancing forces, each a conic
  programme (:func:`least_friction_exactly`).
* Otherwise (and as the check of both): bisection on the monotone feasibility
  (:func:`least_friction`).

Nondimensional, as :mod:`kcheck.mechanics.statics`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from kcheck.mechanics.csc import Csc
from kcheck.mechanics.kinematics import cross3, wrenches
from kcheck.mechanics.sliding_limit import largest_ratio, remember_limit, sliding_limit
from kcheck.mechanics.statics import (
    Statics,
    _contact_axes,
    _solve_conic,
    tangent_frames,
)
from kcheck.numerics.arrays import unique
from kcheck.numerics.thresholds import (
    CUBIC_IMAG_RTOL,
    DINKELBACH_STALL,
    FRICTIONLESS_MISS,
    MU_FLOOR,
    MU_RTOL,
    POLY_ZERO_RTOL,
    ZERO_GUARD,
)

__all__ = [
    "friction_candidates",
    "least_friction",
    "least_friction_exactly",
    "rough_supports",
]

#: Most Dinkelbach-type steps of :func:`least_friction_exactly` (it needs 3 to 8).
STEPS = 30
#: A plain step whose ``s`` is within this of its bound -1 hit it (the supports squeeze).
SATURATED = 1e-6
#: Rounds of steps, each checked at ``(1 - rtol)`` times its result, before bisection.
ROUNDS = 3


def least_friction_exactly(
    statics: Statics,
    keep: np.ndarray,
    wrench: np.ndarray,
    scale: np.ndarray,
    upper: float = 1.0,
    *,
    largest: float = 100.0,
    rtol: float = MU_RTOL,
    upper_fails: bool | Callable[[], bool] = False,
) -> float | None:
    """Spatial: the smallest common coefficient ``mu`` for which the supports ``keep``, with
    coefficients ``mu * scale`` and exact circular cones, balance ``wrench``; None when not
    even ``largest`` does. ``upper_fails``: the caller knows that ``upper`` does not (the
    search then starts by doubling it); a callable is asked only if the conic search runs.

    First :func:`~kcheck.mechanics.sliding_limit.sliding_limit` (no conic solve; it answers
    about 93 % of the jamming check's cases, and its limit is remembered for
    :func:`~kcheck.mechanics.sliding_limit.certified_holding`). Otherwise:
    the least coefficient is ``min over balancing forces of max_j |f_t,j| / (scale_j f_n,j)``,
    a generalised fractional programme. From a balance found at a feasible coefficient
    (doubling ``upper``), Dinkelbach-type steps (Crouzeix, Ferland & Schaible 1985), each a
    conic programme (:func:`_solve_conic`), lower the largest ratio of actual balancing
    forces; they converge quadratically and stop when a step gains less than
    ``DINKELBACH_STALL * rtol`` (relative). The result is then checked as bisection would
    have found it: it holds, and ``(1 - rtol)`` times it does not; where it does (the steps
    stalled), the balance found there starts them again, and after ROUNDS rounds bisection
    below it decides. About 6 conic solves instead of bisection's 17. Where the supports
    can squeeze the body, the steps go on in homogeneous form (:func:`_fractional_steps`):
    8 to 16 solves there instead of 17 to 38.
    """
    scale = np.asarray(scale, float)
    # The contacts' axes once (equilibrium_forces would rebuild them per coefficient).
    _, columns = _contact_axes(statics, keep)

    def feasible(mu: float) -> bool:
        return _solve_conic(columns, wrench, mu * scale[keep], None) is not None

    # A certified limit also shows that coefficient 0 does not hold: it goes first.
    sliding = sliding_limit(columns, wrench, scale[keep], rtol)
    if sliding is not None and sliding <= largest:
        remember_limit(statics, keep, wrench, scale[keep], sliding, (1.0 - rtol) * sliding)
        return sliding
    if not _frictionless_misses(columns, wrench) and feasible(0.0):
        return 0.0
    mu = max(upper, 1e-3)
    if upper_fails() if callable(upper_fails) else upper_fails:
        if mu >= largest:
            return None
        mu = min(2.0 * mu, largest)
    while (found := _solve_conic(columns, wrench, mu * scale[keep], None)) is None:
        if mu >= largest:
            return None
        mu = min(2.0 * mu, largest)
    local, kept = found[0], scale[keep]
    ratio = largest_ratio(local, kept)
    for _ in range(ROUNDS):
        local, ratio = _fractional_steps(columns, wrench, kept, local, ratio, rtol)
        # Whether (1 - rtol) times the result holds, as a step there: its least ``s`` is
        # positive exactly where no balance lies inside those cones. The plain feasibility
        # programme so near the boundary of its feasible coefficients is nearly infeasible
        # and took clarabel 11 to 200 iterations (44 % of these checks ended
        # AlmostPrimalInfeasible, NumericalError, InsufficientProgress or MaxIterations),
        # the step about 9.
        # (The shrink scaled to a largest entry of 1: after squeezing steps the forces can
        # be 1e11, and s so small that the solver's tolerance decides its sign.)
        shrink = np.maximum(local[:, 0] * kept, 0.0)
        shrink = shrink / max(float(shrink.max()), ZERO_GUARD)
        below = _solve_conic(columns, wrench, ratio * (1.0 - rtol) * kept, shrink)
        if below is None or below[1] > 0.0:
            return ratio
        # Not converged (a stall): the balance found below it starts the steps again.
        lower = largest_ratio(below[0], kept)
        if not lower < ratio:
            break
        local, ratio = below[0], lower
    return least_friction(feasible, ratio, largest=largest, rtol=rtol)


def _fractional_steps(
    columns: np.ndarray,
    wrench: np.ndarray,
    kept: np.ndarray,
    local: np.ndarray,
    ratio: float,
    rtol: float,
) -> tuple[np.ndarray, float]:
    """Dinkelbach-type steps from the balance ``local`` (k, 3) of largest ratio ``ratio``
    until a step gains less than ``DINKELBACH_STALL * rtol`` (relative) or none gains: the
    last balance and its ratio (``local`` up to a positive factor: the ratios do not depend
    on it).

    Where the remaining supports can squeeze the body (forces growing without limit inside
    the cones), the plain step's ``s`` is unbounded below and stops at its bound ``s >= -1``
    with an arbitrary point of it: the ratio then falls only linearly. From the first such
    step on, the steps are the homogeneous programme (:func:`_homogeneous_step`), whose
    forces are normalised, so that its ``s`` stays bounded."""
    homogeneous = False
    for _ in range(STEPS):
        shrink = np.maximum(local[:, 0] * kept, 0.0)
        step = None
        if not homogeneous:
            step = _solve_conic(columns, wrench, ratio * kept, shrink)
            homogeneous = step is not None and step[1] <= SATURATED - 1.0
        if homogeneous:
            step = _homogeneous_step(columns, wrench, ratio * kept, shrink)
        if step is None:
            break
        lower = largest_ratio(step[0], kept)
        if not lower < ratio:
            break
        gain = ratio - lower
        local, ratio = step[0], lower
        if gain <= DINKELBACH_STALL * rtol * ratio:
            break
    return local, ratio


def _homogeneous_step(
    columns: np.ndarray, wrench: np.ndarray, mu: np.ndarray, shrink: np.ndarray
) -> tuple[np.ndarray, float] | None:
    """The Dinkelbach-type step in homogeneous form: forces ``f`` (k, 3, the contacts' axes)
    and a factor ``w >= 0`` on the wrench, ``f`` balancing ``w * wrench``, the normal forces
    and ``w`` summing to 1, minimising ``s`` subject to ``|f_t| <= mu f_n + s shrink``.

    The ratios ``|f_t| / f_n`` of ``f`` are those of the balance ``f / w``, and a solution at
    ``w = 0`` is a squeeze that, added to a balance in a large enough multiple, lowers its
    ratios to its own (every contact ``shrink`` presses is pressed where ``s < 0``). The
    normalisation bounds ``s`` where the plain step's is unbounded. The forces (k, 3) and
    ``s``; None unless clarabel solves it."""
    import clarabel

    k, n = len(mu), len(wrench)
    size = 3 * k + 2  # f, w, s
    normal = 3 * np.arange(k)
    matrix = np.zeros((n + 1 + 3 * k + k + 1, size))
    matrix[:n, : 3 * k] = columns.T
    matrix[:n, 3 * k] = wrench
    matrix[n, normal] = 1.0
    matrix[n, 3 * k] = 1.0
    cones = n + 1
    matrix[cones + np.arange(3 * k), np.arange(3 * k)] = -1.0
    matrix[cones + normal, normal] = -mu
    matrix[cones + normal, -1] = -shrink
    matrix[cones + 3 * k + np.arange(k), normal] = -1.0  # f_n >= 0
    matrix[-1, 3 * k] = -1.0  # w >= 0
    rhs = np.zeros(len(matrix))
    rhs[n] = 1.0
    cost = np.zeros(size)
    cost[-1] = 1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solver = clarabel.DefaultSolver(
        Csc.empty(size),
        cost,
        Csc.of(matrix),
        rhs,
        [clarabel.ZeroConeT(n + 1)]
        + [clarabel.SecondOrderConeT(3)] * k
        + [clarabel.NonnegativeConeT(k + 1)],
        settings,
    )
    solution = solver.solve()
    if str(solution.status) not in ("Solved", "AlmostSolved"):
        return None
    x = np.asarray(solution.x)
    return x[: 3 * k].reshape(k, 3), float(x[-1])


def _frictionless_misses(columns: np.ndarray, wrench: np.ndarray) -> bool:
    """Whether no normal forces of any sign balance ``wrench`` (columns (3k, n) as
    :func:`kcheck.mechanics.statics._contact_axes`, every third a contact's normal wrench),
    by a residual far above the conic solver's tolerances: then no coefficient 0 holds, and
    the conic programme need not be solved (its answer is the same)."""
    normals = columns[0::3].T
    if normals.shape[1] >= normals.shape[0]:
        return False  # as many normals as equations: a least-squares fit may be exact
    x = np.linalg.lstsq(normals, -wrench, rcond=None)[0]
    miss = float(np.linalg.norm(normals @ x + wrench))
    return miss > FRICTIONLESS_MISS * float(np.linalg.norm(wrench))


def rough_supports(friction: np.ndarray) -> np.ndarray:
    """Which supports a common friction coefficient applies to: those with friction in the
    scene, or all of them when the scene is frictionless (as for the limiting friction)."""
    rough = friction > 0
    return rough if np.any(rough) else np.ones_like(rough)


def friction_candidates(
    statics: Statics, keep: np.ndarray, wrench: np.ndarray, scale: np.ndarray
) -> np.ndarray:
    """Planar: every common coefficient ``mu > 0`` at which the supports ``keep``, with the
    coefficients ``mu * scale``, can start to balance ``wrench`` (sorted).

    Each edge wrench is affine in ``mu``, ``g(mu) = a + mu b`` (``a`` the normal's wrench,
    ``b`` the tangent's). By Carathéodory ``x = -wrench`` is balanced iff it is a non-negative
    combination of at most three independent edges, whose coefficients are ratios of
    determinants (Cramer): ``det[x, g_v, g_w] / det[g_u, g_v, g_w]``. Their signs change only
    where a numerator (``x`` on the plane of two edges: a quadratic in ``mu``) or a
    denominator (three edges in one plane, the cone turning into a half-space or the whole
    space: a cubic) vanishes; the positive real roots of these polynomials are the
    candidates (exact up to rounding).
    """
    points, normals = statics.points[keep], statics.normals[keep]
    x = -np.asarray(wrench, float)
    if statics.dim == 2:
        coefficients = _planar_coefficients(points, normals, scale[keep], x)
        return unique(_positive_roots(coefficients))
    return unique(_positive_roots(_coefficients(points, normals, scale[keep], x)))


def _coefficients(
    points: np.ndarray, normals: np.ndarray, scale: np.ndarray, x: np.ndarray
) -> np.ndarray:
    """The polynomials of :func:`friction_candidates` (rows, highest power first): the
    pairs' quadratics (a leading 0) then the triples' cubics."""
    tangents = tangent_frames(normals)[:, 0]
    a = wrenches(points, normals)
    b = scale[:, None] * wrenches(points, tangents)
    # Both edges of each cone, n + mu t and n - mu t; an edge that does not move with mu
    # (a frictionless support) once.
    moving = np.any(b != 0, axis=1)
    a, b = np.concatenate([a, a[moving]]), np.concatenate([b, -b[moving]])
    i, j = np.triu_indices(len(a), 1)
    # det[x, a_i + mu b_i, a_j + mu b_j]: coefficients of mu^2, mu, 1 (a leading 0: cubics)
    ax, bx = cross3(a, x), cross3(b, x)  # det[x, p, q] = -(p x x) . q
    pairs = -np.column_stack(
        [
            np.zeros(len(i)),
            np.sum(bx[i] * b[j], axis=1),
            np.sum(ax[i] * b[j] + bx[i] * a[j], axis=1),
            np.sum(ax[i] * a[j], axis=1),
        ]
    )
    u, v, w = _triples(len(a))
    # det[g_u, g_v, g_w] = (g_u x g_v) . g_w: coefficients of mu^3 ... 1
    aa, ab, ba, bb = (cross3(p[u], q[v]) for p, q in ((a, a), (a, b), (b, a), (b, b)))
    triples = np.column_stack(
        [
            np.sum(bb * b[w], axis=1),
            np.sum(bb * a[w] + (ab + ba) * b[w], axis=1),
            np.sum((ab + ba) * a[w] + aa * b[w], axis=1),
            np.sum(aa * a[w], axis=1),
        ]
    )
    return np.vstack([pairs, triples])


def _planar_coefficients(
    points: np.ndarray, normals: np.ndarray, scale: np.ndarray, x: np.ndarray
) -> np.ndarray:
    """:func:`_coefficients` of a planar scene in plain float arithmetic (numpy's per-call
    overhead on 3-vectors was most of its time): the same operations in numpy's order
    (``cross3``'s formulas, each row's three products summed left to right from +0.0 as
    ``np.sum`` does: a sum of negative zeros is +0.0; the pairs' leading zero negated to
    -0.0), so the same bits."""
    a: list[tuple[float, float, float]] = []
    b: list[tuple[float, float, float]] = []
    for (px, py), (nx, ny), s in zip(
        points.tolist(), normals.tolist(), scale.tolist(), strict=True
    ):
        tx, ty = -ny, nx
        a.append((px * ny - py * nx, nx, ny))
        b.append((s * (px * ty - py * tx), s * tx, s * ty))
    moving = [k for k, v in enumerate(b) if v[0] != 0 or v[1] != 0 or v[2] != 0]
    a = a + [a[k] for k in moving]
    b = b + [(-b[k][0], -b[k][1], -b[k][2]) for k in moving]
    x0, x1, x2 = x.tolist()

    def cross(p: tuple[float, ...], q: tuple[float, ...]) -> tuple[float, float, float]:
        return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])

    def dot(p: tuple[float, ...], q: tuple[float, ...]) -> float:
        return 0.0 + p[0] * q[0] + p[1] * q[1] + p[2] * q[2]

    n = len(a)
    ax = [cross(v, (x0, x1, x2)) for v in a]
    bx = [cross(v, (x0, x1, x2)) for v in b]
    rows: list[tuple[float, float, float, float]] = []
    for i in range(n):
        for j in range(i + 1, n):
            mixed = [ax[i][c] * b[j][c] + bx[i][c] * a[j][c] for c in range(3)]
            rows.append(
                (
                    -0.0,
                    -dot(bx[i], b[j]),
                    -(0.0 + mixed[0] + mixed[1] + mixed[2]),
                    -dot(ax[i], a[j]),
                )
            )
    for u in range(n):
        for v in range(u + 1, n):
            aa, ab = cross(a[u], a[v]), cross(a[u], b[v])
            ba, bb = cross(b[u], a[v]), cross(b[u], b[v])
            both = [ab[c] + ba[c] for c in range(3)]
            for w in range(v + 1, n):
                aw, bw = a[w], b[w]
                second = [bb[c] * aw[c] + both[c] * bw[c] for c in range(3)]
                first = [both[c] * aw[c] + aa[c] * bw[c] for c in range(3)]
                rows.append(
                    (
                        dot(bb, bw),
                        0.0 + second[0] + second[1] + second[2],
                        0.0 + first[0] + first[1] + first[2],
                        dot(aa, aw),
                    )
                )
    return np.array(rows, dtype=float).reshape(-1, 4)


def _triples(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Indices (u < v < w) of every triple of ``n`` items."""
    u, v, w = (
        np.array(
            [(u, v, w) for u in range(n) for v in range(u + 1, n) for w in range(v + 1, n)], int
        )
        .reshape(-1, 3)
        .T
    )
    return u, v, w


def _positive_roots(coefficients: np.ndarray) -> np.ndarray:
    """Positive real roots of polynomials of degree up to three (rows, highest power first),
    all at once; none of a polynomial that does not depend on ``mu`` (relative to its size).
    The companion matrices' eigenvalues, then Newton steps on each polynomial (the
    eigenvalues are accurate relative to the largest root, not each one)."""
    size = np.abs(coefficients).sum(axis=1, keepdims=True)
    c = np.where(np.abs(coefficients) > POLY_ZERO_RTOL * size, coefficients, 0.0)
    found = []
    # Each polynomial by its degree: its leading coefficient non-zero, those before it zero.
    nonzero = c != 0
    first, second = nonzero[:, 0], nonzero[:, 1]
    lower = ~first & ~second
    degrees = {3: first, 2: ~first & second, 1: lower & nonzero[:, 2]}
    for degree in (3, 2, 1):
        lead = 3 - degree
        rows = c[degrees[degree]]
        if not len(rows):
            continue
        monic = rows[:, lead + 1 :] / rows[:, lead : lead + 1]  # (r, degree)
        companion = np.zeros((len(rows), degree, degree))
        companion[:, 0, :] = -monic
        companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
        roots = np.linalg.eigvals(companion)  # (r, degree)
        real = np.abs(roots.imag) <= CUBIC_IMAG_RTOL * np.maximum(np.abs(roots), 1.0)
        owner = np.repeat(np.arange(len(rows)), degree)[real.ravel()]  # each root's row
        found += _newton_steps(roots.real[real].tolist(), rows[owner].tolist())
    return np.array(found, dtype=float)


def _newton_steps(roots: list[float], polys: list[list[float]]) -> list[float]:
    """Three Newton steps on each root of its cubic (highest power first, a step of 0 where
    the slope is 0), the positive results: elementwise numpy's formulas in plain float
    arithmetic (the same operations in the same order, so the same bits; a case has some
    twenty roots, where numpy's per-call overhead on a dozen arrays was most of the time)."""
    out = []
    for x, (p0, p1, p2, p3) in zip(roots, polys, strict=True):
        for _ in range(3):
            value = ((p0 * x + p1) * x + p2) * x + p3
            slope = (3.0 * p0 * x + 2.0 * p1) * x + p2
            x = x - (value / slope if slope != 0 else 0.0)
        if x > 0:
            out.append(x)
    return out


def least_friction(
    feasible: Callable[[float], bool],
    upper: float = 1.0,
    *,
    largest: float = 100.0,
    rtol: float = MU_RTOL,
    candidates: np.ndarray | None = None,
) -> float | None:
    """Smallest common coefficient ``mu`` with ``feasible(mu)``.

    Feasibility is monotone in ``mu`` (every friction cone grows with it). With
    ``candidates`` (sorted values among which feasibility can change,
    :func:`friction_candidates`) the least feasible candidate, found by bisection over them:
    the exact value. Otherwise, and should the candidates miss the change (degenerate
    geometry), by bisection: ``upper`` is a first guess, doubled up to ``largest``; the
    result is within ``rtol`` (relative) above the true value. None when not even
    ``largest`` holds the body (the load would need a pulling support).
    """
    if feasible(0.0):
        return 0.0
    if candidates is not None:
        found = _least_candidate(feasible, candidates, largest, rtol)
        if found is not None:
            return found
    hi = max(upper, 1e-3)
    while not feasible(hi):
        if hi >= largest:
            return None
        hi = min(2.0 * hi, largest)
    lo = 0.0
    # The absolute floor ends a bisection towards an infimum of 0 that 0 itself does not
    # attain (a degenerate balance): relative steps alone would halve into denormals and
    # then loop forever at 5e-324 (fuzz finding extreme-4245-885: a jamming check ran past
    # its 120 s budget).
    while hi - lo > max(rtol * hi, MU_FLOOR):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
    return hi


def _least_candidate(
    feasible: Callable[[float], bool], candidates: np.ndarray, largest: float, rtol: float
) -> float | None:
    """The least feasible coefficient, given that feasibility is constant between
    consecutive candidates: bisection over the candidates interleaved with a point inside
    each interval after one. None if nothing up to ``largest`` is feasible. When the least is
    an infimum (feasible just above a candidate, not at it: the cone turning into a
    half-space or the whole space there), a value within ``rtol`` above it, as bisection
    gives."""
    ends = [float(c) for c in candidates if 0 < c < largest]
    if not ends:
        return None
    upper = [*ends[1:], largest]
    sequence: list[tuple[float, bool]] = []
    for c, above in zip(ends, upper, strict=True):
        sequence += [(c, True), (0.5 * (c + above), False)]
    lo, hi = 0, len(sequence)
    while lo < hi:
        mid = (lo + hi) // 2
        if feasible(sequence[mid][0]):
            hi = mid
        else:
            lo = mid + 1
    if lo == len(sequence):
        return None
    value, attained = sequence[lo]
    if attained:
        return value
    # Not attained at the candidate below (or that candidate is rounded below the change):
    # bisection from it, as without candidates, mostly one step.
    low = sequence[lo - 1][0]
    probe = low * (1.0 + rtol)
    if probe < value and feasible(probe):
        return probe
    while value - low > rtol * value:
        middle = 0.5 * (low + value)
        low, value = (low, middle) if feasible(middle) else (middle, value)
    return value
