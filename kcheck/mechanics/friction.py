"""For which friction coefficients a retracted case closes: exact intervals of ``mu``.

Friction enters the equations of a case as ``K(mu) = K0 + mu F`` (forward sliding; backward
sliding is ``K(-mu)``), with ``mu`` the scene's largest coefficient and every support keeping
its share of it (equal coefficients: one common ``mu``; frictionless supports stay
frictionless; see :meth:`kcheck.mechanics.dynamics.Problem.friction_pattern`). Every quantity the
outcome depends on is a ratio of determinants polynomial in ``mu`` (Cramer's rule): ``lambda`` and
the normal forces under forward and backward friction, and the effective mass
``det K(+-mu) / det K(0)`` (Painlevé). So "closes" can only change where one of these
polynomials has a real root: the real eigenvalues of the pencils ``(A0, A1)`` with
``det(A0 + mu A1) = 0`` — ``K`` itself and ``K`` with one column replaced by the right-hand
side. Between consecutive roots the outcome is constant; one evaluation per piece decides it.

The roots come from numpy alone: for a shift ``s`` with ``B = A0 + s A1`` well conditioned,
``det(A0 + mu A1) = det B det(I + (mu - s) B^-1 A1)``, so ``mu = s - 1 / eig(B^-1 A1)``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from kcheck.fmt import format_number
from kcheck.mechanics.dynamics import ILL_CONDITIONED, Case, Problem, _equilibrate, solve_each
from kcheck.mechanics.outcomes import outcome
from kcheck.numerics.thresholds import (
    DET_ROUNDING,
    EPS,
    IMAG_RTOL,
    MU_END_RTOL,
    PENCIL_INFINITE_RTOL,
    PENCIL_SINGULAR,
    PENCIL_UNSHIFTED,
    SAME_FRICTION_RTOL,
    SAME_ROOT_RTOL,
)
from kcheck.records import dataclass

__all__ = [
    "FrictionIntervals",
    "friction_intervals",
    "limiting_friction",
    "friction_intervals_many",
    "friction_intervals_batch",
    "pencil_roots",
    "root_errors",
    "describe_friction",
]

# Shifts tried for the pencils; the best-conditioned one is used per pencil.
SHIFTS = np.array([0.0, 0.6180339887, -0.7548776662, 1.7320508076, -2.2360679775, 4.1231056256])


@dataclass(frozen=True)
class FrictionIntervals:
    """The friction coefficients for which a case closes (uniquely), and the scene's.

    ``intervals`` are closed intervals ``(lo, hi)`` of ``mu`` (``hi`` may be ``inf``), sorted;
    ``mu`` is the scene's (largest) coefficient and ``closes`` whether the case closes there;
    ``painleve`` the intervals where the case is Painlevé-type (ambiguous); ``uniform`` whether
    every support with friction has the same coefficient (else the others scale with ``mu``).
    """

    intervals: tuple[tuple[float, float], ...]
    mu: float
    closes: bool
    painleve: tuple[tuple[float, float], ...] = ()
    uniform: bool = True
    #: Per interval, a bound of each end's numerical error ``(lo_error, hi_error)`` (0 at 0
    #: and at infinity): :func:`root_errors`.
    errors: tuple[tuple[float, float], ...] = ()

    @property
    def unresolved(self) -> tuple[tuple[float, float], ...]:
        """The intervals no wider than their ends' error bounds: a sliver that rounding may
        have made or moved; neither closing nor failing can be said of it."""
        return tuple(
            (lo, hi)
            for (lo, hi), (elo, ehi) in zip(self.intervals, self.errors, strict=True)
            if np.isfinite(hi) and hi - lo <= elo + ehi
        )

    @property
    def containing(self) -> tuple[float, float] | None:
        """The interval that holds the scene's ``mu``, or None when it does not close there."""
        if not self.closes:
            return None
        return _around(self.intervals, self.mu)

    @property
    def limiting(self) -> float | None:
        """Upper end of the interval holding the scene's ``mu`` (``inf``: none stops it)."""
        around = self.containing
        return None if around is None else around[1]

    @property
    def painleve_from(self) -> float | None:
        """Where the Painlevé interval holding the scene's ``mu`` starts, or None."""
        around = _around(self.painleve, self.mu)
        return None if around is None else around[0]


def _around(intervals: tuple[tuple[float, float], ...], mu: float) -> tuple[float, float] | None:
    """The interval containing ``mu`` (with a relative tolerance at its ends), or None."""
    tol = MU_END_RTOL * max(1.0, abs(mu))
    for lo, hi in intervals:
        if lo - tol <= mu <= hi + tol:
            return lo, hi
    return None


def _hadamard(
    matrices: np.ndarray, slogdet: tuple[np.ndarray, np.ndarray] | None = None
) -> np.ndarray:
    """``|det A| / prod(row norms)`` in [0, 1] for a stack: 1 for orthogonal rows, 0 when
    singular — a cheap (LU instead of SVD) measure of how far from singular a matrix is.
    ``slogdet``: the stack's ``numpy.linalg.slogdet``, when already computed."""
    with np.errstate(all="ignore"):
        sign, logdet = np.linalg.slogdet(matrices) if slogdet is None else slogdet
        rows = 0.5 * np.sum(np.log(np.einsum("...ij,...ij->...i", matrices, matrices)), axis=-1)
        ratio = np.where(sign != 0, np.exp(logdet - rows), 0.0)
    return np.where(np.isfinite(ratio), ratio, 0.0)


def _eigvals_each(base: np.ndarray, a1: np.ndarray) -> np.ndarray:
    """Eigenvalues of ``base^-1 a1`` for a stack (p, n, n); NaN for a pencil LAPACK fails on
    (a batch fails as a whole; then each is solved alone, so one does not spoil a stack)."""
    try:
        return np.linalg.eigvals(np.linalg.solve(base, a1))
    except np.linalg.LinAlgError:
        out = np.full(base.shape[:-1], np.nan, complex)
        for i, (b, a) in enumerate(zip(base, a1, strict=True)):
            try:
                out[i] = np.linalg.eigvals(np.linalg.solve(b, a))
            except np.linalg.LinAlgError:
                pass
        return out


def pencil_roots(a0: np.ndarray, a1: np.ndarray) -> np.ndarray:
    """Real roots ``mu`` of ``det(A0 + mu A1)`` for a stack of pencils (p, n, n): (p, n), NaN
    where a pencil has fewer.

    Each pencil is equilibrated, shifted to the least singular ``B = A0 + s A1`` of a few
    shifts (by the Hadamard ratio; unshifted, ``s = 0``, when that ratio is at least
    PENCIL_UNSHIFTED), and its roots are ``s - 1 / eig(B^-1 A1)`` (zero
    eigenvalues are roots at infinity). A pencil singular for every ``mu`` (e.g. an unknown
    that is zero for every ``mu``) has no roots.
    """
    p, n = a0.shape[0], a0.shape[-1]
    out = np.full((p, n), np.nan)
    rows, cols = _equilibrate(np.abs(a0) + np.abs(a1))
    a0 = a0 * rows[..., :, None] * cols[..., None, :]
    a1 = a1 * rows[..., :, None] * cols[..., None, :]
    # Unshifted where that is well enough conditioned; the others try every shift.
    unshifted = _hadamard(a0)
    best = np.zeros(p, np.int64)
    best_quality = unshifted
    rest = np.flatnonzero(~(unshifted >= PENCIL_UNSHIFTED))
    if len(rest):
        shifted = a0[None, rest] + SHIFTS[:, None, None, None] * a1[None, rest]  # (s, r, n, n)
        quality = _hadamard(shifted)
        best[rest] = np.argmax(quality, axis=0)
        best_quality = unshifted.copy()
        best_quality[rest] = quality[best[rest], np.arange(len(rest))]
    usable = best_quality > 1.0 / PENCIL_SINGULAR
    if not np.any(usable):
        return out
    picked = np.flatnonzero(usable)
    base = a0[picked] + SHIFTS[best[picked], None, None] * a1[picked]
    shift = SHIFTS[best[picked]]
    with np.errstate(all="ignore"):
        values = _eigvals_each(base, a1[picked])
        size = np.abs(values).max(axis=1, keepdims=True)
        finite = np.abs(values) > PENCIL_INFINITE_RTOL * np.where(size > 0, size, 1.0)
        roots = shift[:, None] - 1.0 / np.where(finite, values, 1.0)
    real = (
        finite & np.isfinite(roots) & (np.abs(roots.imag) <= IMAG_RTOL * (1.0 + np.abs(roots.real)))
    )
    out[picked] = np.where(real, roots.real, np.nan)
    return out


def _pencils(k0: np.ndarray, big_f: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per case (..., n, n), ``K`` and, per unknown, ``K`` with that column replaced by the
    right-hand side (n,): (..., n + 1, n, n) each."""
    n = k0.shape[-1]
    a0 = np.repeat(k0[..., None, :, :], n + 1, axis=-3)
    a1 = np.repeat(big_f[..., None, :, :], n + 1, axis=-3)
    idx = np.arange(n)
    a0[..., idx + 1, :, idx] = rhs
    a1[..., idx + 1, :, idx] = 0.0
    return a0, a1


def _breakpoints(roots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row of roots (c, m): the sorted distinct positive ``|root|`` values (roots of
    either sign matter: ``K(-mu)`` is the backward system), padded with ``inf`` (c, m), and
    how many there are (c,)."""
    size = np.abs(roots)
    size = np.sort(np.where(np.isfinite(size) & (size > 0), size, np.inf), axis=1)
    with np.errstate(invalid="ignore"):
        same = np.diff(size, axis=1) <= SAME_ROOT_RTOL * size[:, 1:]
    size[:, 1:][same] = np.inf
    size = np.sort(size, axis=1)
    return size, np.sum(np.isfinite(size), axis=1)


def _samples(points: np.ndarray, counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One ``mu`` inside each piece between 0, the breakpoints (c, m; ``counts`` of them per
    row) and infinity, all rows' in one array, and the row of each."""
    c, m = points.shape
    edges = np.concatenate([np.zeros((c, 1)), points], axis=1)
    with np.errstate(invalid="ignore"):
        inner = 0.5 * (edges[:, :-1] + edges[:, 1:])
    rows = np.arange(c)
    last = np.concatenate([inner, np.zeros((c, 1))], axis=1)
    last[rows, counts] = 2.0 * edges[rows, counts] + 1.0
    used = np.arange(m + 1)[None, :] <= counts[:, None]
    return last[used], np.broadcast_to(rows[:, None], used.shape)[used]


def root_errors(a0: np.ndarray, a1: np.ndarray, roots: np.ndarray) -> np.ndarray:
    """Error bounds (p, r) of real roots ``mu`` (p, r) of pencils ``det(A0 + mu A1)`` (p, n, n):
    the determinant over the product of its rows' norms errs by at most ``DET_ROUNDING n² eps``
    (LU's backward error, Hadamard's bound on cofactors), so a root errs by that over the
    slope of the normalised determinant there (a central difference across the root); NaN
    roots stay NaN, and a root where the slope vanishes (a double root) gets its own size."""
    n = a0.shape[-1]
    bound = DET_ROUNDING * n * n * EPS
    out = np.full(roots.shape, np.nan)
    pencil, which = np.nonzero(np.isfinite(roots))
    if not len(pencil):
        return out
    mu = roots[pencil, which]
    step = 1e-6 * np.maximum(1.0, np.abs(mu))
    # Both sides of every finite root in one batch (the NaN ones need none).
    at = np.concatenate([mu + step, mu - step])
    both = np.concatenate([pencil, pencil])
    m = a0[both] + at[:, None, None] * a1[both]
    with np.errstate(all="ignore"):
        sign, logdet = np.linalg.slogdet(m)
        rows = np.sum(np.log(np.sqrt(np.sum(m * m, axis=-1))), axis=-1)
        value = sign * np.exp(logdet - rows)
        slope = np.abs(value[: len(mu)] - value[len(mu) :]) / (2.0 * step)
        size = np.maximum(1.0, np.abs(mu))
        error = np.where(slope > 0, bound / slope, size)
    out[pencil, which] = np.minimum(error, size)
    return out


def _end_errors(
    intervals: tuple[tuple[float, float], ...], roots: np.ndarray, errors: np.ndarray
) -> tuple[tuple[float, float], ...]:
    """Each interval end's error: the largest error of the roots (either sign) at that
    breakpoint; 0 at 0 and at infinity."""
    size, err = np.abs(roots[np.isfinite(roots)]), errors[np.isfinite(roots)]

    def at(value: float) -> float:
        if value <= 0 or not np.isfinite(value):
            return 0.0
        near = np.abs(size - value) <= SAME_ROOT_RTOL * value
        return float(err[near].max()) if np.any(near) else 0.0

    return tuple((at(lo), at(hi)) for lo, hi in intervals)


def _pieces(points: np.ndarray, flags: np.ndarray) -> tuple[tuple[float, float], ...]:
    """Closed intervals from the pieces ``[0, p1], [p1, p2], ..., [pm, inf)`` whose flag holds,
    adjacent ones merged."""
    edges = [0.0, *points.tolist(), np.inf]
    out: list[list[float]] = []
    for i, flag in enumerate(flags.tolist()):
        if not flag:
            continue
        if out and out[-1][1] == edges[i]:
            out[-1][1] = edges[i + 1]
        else:
            out.append([edges[i], edges[i + 1]])
    return tuple((lo, hi) for lo, hi in out)


def _evaluate(
    k0: np.ndarray,
    big_f: np.ndarray,
    sign0: np.ndarray,
    rhs: np.ndarray,
    mus: np.ndarray,
    solved: int,
) -> tuple[np.ndarray, np.ndarray]:
    """At each sample ``mu`` (m,) of a case (``k0``, ``big_f`` (m, n, n) stacked per sample,
    ``sign0`` (m,) the sign of ``det k0``, ``rhs`` (m, n)): whether the case closes uniquely
    (only the first ``solved`` samples are solved for; the others' is False), and whether it
    is Painlevé-type."""
    m = len(mus)
    signed = np.concatenate([mus, -mus])
    stack = np.concatenate([k0, k0]) + signed[:, None, None] * np.concatenate([big_f, big_f])
    rows, cols = _equilibrate(stack)
    scaled = stack * rows[..., :, None] * cols[..., None, :]
    closes = np.zeros(m, bool)
    with np.errstate(all="ignore"):
        determinant = np.linalg.slogdet(scaled)
        quality = _hadamard(scaled, determinant)
        effective = determinant[0] * np.concatenate([sign0, sign0]) > 0
        painleve = ~(effective[:m] & effective[m:])
        if solved == 0:
            return closes, painleve
        forward = (
            solve_each(scaled[:solved], (rhs[:solved] * rows[:solved])[..., None])[0][..., 0]
            * cols[:solved]
        )
    trusted = (quality[:solved] > 1.0 / ILL_CONDITIONED) & (
        quality[m : m + solved] > 1.0 / ILL_CONDITIONED
    )
    closes[:solved] = (
        trusted & ~painleve[:solved] & (forward[:, 0] > 0) & np.all(forward[:, 1:] > 0, axis=1)
    )
    return closes, painleve


def friction_intervals_many(
    problem: Problem, cases: Sequence[Case], direction: np.ndarray | None
) -> list[FrictionIntervals]:
    """:func:`friction_intervals` for several cases of one problem, in one batch of numpy
    calls (:func:`friction_intervals_batch` of one problem)."""
    return friction_intervals_batch([problem], [cases], [direction])[0]


def friction_intervals_batch(
    problems: Sequence[Problem],
    cases: Sequence[Sequence[Case]],
    directions: Sequence[np.ndarray | None],
) -> list[list[FrictionIntervals]]:
    """:func:`friction_intervals_many` of several problems (e.g. the scenes of a worker's
    chunk; per problem its cases and force direction): every case of every problem with
    systems of one size is stacked and solved in one batch of numpy calls. Each matrix is
    factorised on its own, so every case gets the values it gets alone."""
    out: list[list[FrictionIntervals]] = []
    live: dict[int, list[tuple[int, int]]] = {}  # by system size: (problem, case index)
    for p, (problem, chosen) in enumerate(zip(problems, cases, strict=True)):
        _, mu = problem.friction_pattern()
        rough = problem.friction[problem.friction > 0]
        uniform = bool(len(rough) == 0 or np.ptp(rough) <= SAME_FRICTION_RTOL * rough.max())
        out.append([FrictionIntervals((), mu, False, (), uniform) for _ in chosen])
        for i, one in enumerate(chosen):
            if one.determined and one.k0 is not None and one.k_friction is not None:
                live.setdefault(one.k0.shape[-1], []).append((p, i))
    used = {p for members in live.values() for p, _ in members}
    wrench = {p: problems[p].wrench(directions[p]) for p in used}
    for members in live.values():
        found = _intervals_stacked(
            [cases[p][i] for p, i in members],
            np.stack([wrench[p] for p, _ in members]),
            [directions[p] for p, _ in members],
            [out[p][i] for p, i in members],
        )
        for (p, i), intervals in zip(members, found, strict=True):
            out[p][i] = intervals
    return out


def _intervals_stacked(
    live: Sequence[Case],
    rhs: np.ndarray,
    directions: Sequence[np.ndarray | None],
    empty: Sequence[FrictionIntervals],
) -> list[FrictionIntervals]:
    """The friction intervals of determined cases with systems of one size, each with its
    right-hand side (c, n), force direction and problem's coefficient (``empty``: the
    intervals of a case that closes for no ``mu``)."""
    k0 = np.stack([c.k0 for c in live])  # type: ignore[misc]
    big_f = np.stack([c.k_friction for c in live])  # type: ignore[misc]
    c, n = k0.shape[0], k0.shape[-1]
    a0, a1 = _pencils(k0, big_f, rhs)
    all_a0, all_a1 = a0.reshape(-1, n, n), a1.reshape(-1, n, n)
    roots = pencil_roots(all_a0, all_a1).reshape(c, n + 1, n)
    # Samples of every case, for closing (all roots) and for Painlevé (det K roots only).
    points, counts = _breakpoints(roots.reshape(c, -1))
    det_points, det_counts = _breakpoints(roots[:, 0])
    first, first_owner = _samples(points, counts)
    second, second_owner = _samples(det_points, det_counts)
    owner = np.concatenate([first_owner, second_owner])
    with np.errstate(all="ignore"):
        sign0 = np.linalg.slogdet(k0)[0]
    closes, painleve = _evaluate(
        k0[owner],
        big_f[owner],
        sign0[owner],
        rhs[owner],
        np.concatenate([first, second]),
        len(first),
    )
    bounds = np.concatenate([[0], np.cumsum(counts + 1)])
    det_bounds = len(first) + np.concatenate([[0], np.cumsum(det_counts + 1)])
    pieces = [_pieces(points[i, : counts[i]], closes[bounds[i] : bounds[i + 1]]) for i in range(c)]
    # Error bounds only of the roots at an interval's end (the only ones _end_errors reads).
    at_end = np.zeros(roots.shape, bool)
    size = np.abs(roots)
    for i, intervals in enumerate(pieces):
        for end in {x for interval in intervals for x in interval if 0 < x < np.inf}:
            at_end[i] |= np.abs(size[i] - end) <= SAME_ROOT_RTOL * end
    errors = root_errors(all_a0, all_a1, np.where(at_end, roots, np.nan).reshape(-1, n)).reshape(
        c, n + 1, n
    )
    return [
        FrictionIntervals(
            pieces[i],
            empty[i].mu,
            outcome(case, directions[i])[0] == "closes",
            _pieces(det_points[i, : det_counts[i]], painleve[det_bounds[i] : det_bounds[i + 1]]),
            empty[i].uniform,
            _end_errors(pieces[i], roots[i], errors[i]),
        )
        for i, case in enumerate(live)
    ]


def friction_intervals(
    problem: Problem, case: Case, direction: np.ndarray | None
) -> FrictionIntervals:
    """The intervals of ``mu`` for which a case closes at a force direction (or under the
    fixed wrench alone, ``direction`` None), exact to the roots' rounding.

    The scene's ``mu`` is placed by the case's own outcome, so ``closes`` agrees with
    :func:`kcheck.mechanics.outcomes.outcome` there.
    """
    return friction_intervals_many(problem, [case], direction)[0]


def _distinct(value: float, scene_mu: float) -> str:
    """``value`` to 3 significant digits, more (up to 6) while it would read as the scene's
    coefficient: "jams at μ = 0.15; it closes for μ ≤ 0.1498", not "μ ≤ 0.15"."""
    for digits in range(3, 7):
        text = format_number(value, digits)
        if value == scene_mu or text != format_number(scene_mu, digits):
            return text
    return text


def describe_friction(intervals: FrictionIntervals) -> str:
    """Where the case closes, in a designer's words: "closes for μ ≤ 0.122", "needs μ ≥ 0.08",
    "closes for 0.05 ≤ μ ≤ 0.3 or μ ≥ 0.9", "closes for every μ", "closes for no μ"."""

    def _mu(value: float) -> str:
        return _distinct(value, intervals.mu)

    if intervals.closes and intervals.containing is not None:
        lo, hi = intervals.containing
        if lo > 0 and np.isfinite(hi):
            return f"needs μ ≥ {_mu(lo)} and closes up to μ = {_mu(hi)}"
        if lo > 0:
            return f"needs μ ≥ {_mu(lo)}"
        if np.isfinite(hi):
            return f"closes for μ ≤ {_mu(hi)}"
        return "closes for every μ"
    if not intervals.intervals:
        return "closes for no μ"
    parts = []
    for lo, hi in intervals.intervals:
        if lo <= 0 and not np.isfinite(hi):
            parts.append("every μ")
        elif lo <= 0:
            parts.append(f"μ ≤ {_mu(hi)}")
        elif not np.isfinite(hi):
            parts.append(f"μ ≥ {_mu(lo)}")
        else:
            parts.append(f"{_mu(lo)} ≤ μ ≤ {_mu(hi)}")
    return "closes for " + " or ".join(parts)


def limiting_friction(problem: Problem, case: Case, direction: np.ndarray | None) -> float | None:
    """Upper end of the interval of friction coefficients, containing the scene's, for which
    the case closes at ``direction`` (:func:`friction_intervals`).

    ``inf`` when no larger coefficient stops it; None when the case does not close at the
    scene's friction.
    """
    return friction_intervals(problem, case, direction).limiting
