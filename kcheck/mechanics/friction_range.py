"""Friction ranges: where a retracted case closes for **every** coefficient in a range, exactly.

Along a range every support's coefficient moves together, ``mu_j(t) = low_j + t (high_j -
low_j)`` for ``t`` in [0, 1] (:class:`FrictionPath`; one common coefficient when the scene gives
one range). Friction enters the equations linearly, so the forward and backward system
matrices are pencils in ``t``: ``K(t) = K0 + F(low) + t F(high - low)`` (backward: minus the
friction part). By Cramer's rule every forward unknown is ``N_k(t, d) / det K(t)`` with the
numerator a polynomial in ``t`` of degree below the matrix size and affine in the force
direction ``d``; ``det K(t) / det K0`` is the effective mass (Painlevé when not positive).
These polynomials are interpolated exactly (Chebyshev series on the Lobatto points of ``t``,
``x = 2 t - 1``) from determinants, so:

* a case closes at ``d`` for every ``t`` iff both effective masses and every numerator
  ``N_k(., d)`` are positive on [0, 1]: real roots of low-degree polynomials
  (:func:`kcheck.numerics.chebyshev.positive`) — exact, no sampling;
* in a sweep plane, the angles that close for every ``t`` (:func:`range_arcs`) are bounded by
  the arc ends at ``t = 0`` and ``t = 1`` and by **envelope** points where an arc end turns
  back (``dN/dt = 0`` with ``N = 0``: a polynomial in ``t`` whose roots give them); between
  consecutive candidate angles the answer is constant and one exact decision per piece
  settles it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from kcheck.mechanics.arcs import FULL, TAU, ArcSet, union
from kcheck.mechanics.dynamics import (
    ILL_CONDITIONED,
    Case,
    Problem,
    _equilibrate,
    friction_matrices,
)
from kcheck.numerics import chebyshev as cheb
from kcheck.numerics.thresholds import (
    DET_ROUNDING,
    ENVELOPE_IMAG_TOL,
    ENVELOPE_INSIDE_SLACK,
    ENVELOPE_TOL,
    EPS,
    SAMPLE_STEP_FLOOR,
)
from kcheck.records import dataclass

__all__ = [
    "FrictionPath",
    "RangeCase",
    "range_cases",
    "range_arcs",
    "condition_series",
    "determinant_error",
]


@dataclass(frozen=True)
class FrictionPath:
    """Coefficients along a range: support ``j`` has ``low_j + t (high_j - low_j)``, ``t`` in
    [0, 1]. ``reference`` is the support whose coefficient is reported (the largest upper end):
    its value stands for the whole path in messages."""

    low: np.ndarray  # (k,)
    high: np.ndarray  # (k,)

    @property
    def fixed(self) -> bool:
        """Whether the path is a single point (no range)."""
        return bool(np.array_equal(self.low, self.high))

    @property
    def reference(self) -> int:
        """Index of the support whose coefficient names a point of the path."""
        return int(np.argmax(self.high))

    def at(self, t: float | np.ndarray) -> np.ndarray:
        """Coefficients (..., k) at ``t``."""
        t = np.asarray(t, float)[..., None]
        return self.low + t * (self.high - self.low)

    def mu(self, t: float | np.ndarray) -> np.ndarray:
        """The reference support's coefficient at ``t``."""
        return self.at(t)[..., self.reference]

    def uniform(self) -> bool:
        """Whether every support with friction moves alike (one common coefficient)."""
        rough = self.high > 0
        if not np.any(rough):
            return True
        return bool(np.ptp(self.low[rough]) == 0 and np.ptp(self.high[rough]) == 0)


@dataclass(frozen=True)
class RangeCase:
    """One retracted case along a friction path, as Chebyshev series in ``x = 2 t - 1``.

    ``effective`` (2, m): forward and backward ``det K(t) / det K0``; ``numerators``
    (n, 1 + dim, m): each forward unknown's Cramer numerator over ``det K0``, for the fixed
    wrench and per component of the force direction. ``trusted``: well conditioned at every
    interpolation point (else no answer, as for one coefficient).
    """

    index: int
    effective: np.ndarray
    numerators: np.ndarray
    trusted: bool
    #: Absolute error bounds of the series' values on [-1, 1] (same units): ``(2,)`` for the
    #: effective masses, ``(n, 1 + dim)`` for the numerators (:func:`determinant_error`).
    effective_error: np.ndarray | None = None
    numerator_error: np.ndarray | None = None

    def condition_errors(self, directions: np.ndarray | None) -> np.ndarray:
        """Error bounds (q, n) of :meth:`conditions`' values at unit directions (q, dim)
        (``None``: the fixed wrench, q = 1); zeros when no bounds were computed."""
        n = self.numerators.shape[0]
        if self.numerator_error is None:
            q = 1 if directions is None else len(np.atleast_2d(directions))
            return np.zeros((q, n))
        fixed = self.numerator_error[:, 0]
        if directions is None:
            return fixed[None]
        d = np.abs(np.atleast_2d(directions))
        return fixed[None] + d @ self.numerator_error[:, 1:].T

    @property
    def painleve_free(self) -> bool:
        """Whether the effective mass stays positive for every coefficient of the path, under
        forward and backward friction (else the case is Painlevé-type somewhere: ambiguous)."""
        return bool(np.all(cheb.positive(self.effective)))

    def painleve_at(self, x: np.ndarray) -> np.ndarray:
        """Whether the case is Painlevé-type at points ``x`` (m,) of the path."""
        return np.any(cheb.values(self.effective, x) <= 0, axis=0)

    def conditions(self, directions: np.ndarray | None) -> np.ndarray:
        """Series (q, n, m) of every forward unknown (its numerator) at unit directions
        (q, dim); ``None``: under the fixed wrench alone (q = 1)."""
        fixed = self.numerators[:, 0]
        if directions is None:
            return fixed[None]
        d = np.atleast_2d(directions)
        return fixed[None] + np.einsum("qi,kim->qkm", d, self.numerators[:, 1:])

    def closes(self, directions: np.ndarray | None) -> np.ndarray:
        """Whether the case closes at each direction (q, dim) for every coefficient of the
        path: (q,). Exact (real roots of the numerators and effective masses)."""
        q = 1 if directions is None else len(np.atleast_2d(directions))
        if not self.trusted or not self.painleve_free:
            return np.zeros(q, bool)
        return np.all(cheb.positive(self.conditions(directions)), axis=1)

    def closing_at(self, directions: np.ndarray | None, x: np.ndarray) -> np.ndarray:
        """Whether the case closes at each direction (q, dim) at the points ``x`` (m,) of the
        path: (q, m)."""
        unknowns = cheb.values(self.conditions(directions), x)  # (q, n, m)
        ok = np.all(unknowns > 0, axis=1)
        return ok & ~self.painleve_at(x)[None] & self.trusted


def _determinants(stack: np.ndarray, log_base: np.ndarray) -> np.ndarray:
    """``det(stack) / exp(log_base)`` with signs, overflow-safe (stack (..., n, n))."""
    with np.errstate(all="ignore"):
        sign, logdet = np.linalg.slogdet(stack)
        return sign * np.exp(logdet - log_base)


def determinant_error(stack: np.ndarray, log_base: np.ndarray) -> np.ndarray:
    """An absolute bound of the rounding error of ``det(stack) / exp(log_base)`` (stack
    (..., n, n)), whatever the conditioning: LU with partial pivoting computes the exact
    determinant of ``K + E`` with ``|E_ij| <= γ |K|`` row by row, and ``|d det / d K_ij|`` (a
    cofactor) is at most the product of the other rows' norms (Hadamard), so the error is at
    most ``n γ`` times the product of every row's norm; ``γ = DET_ROUNDING n eps``
    (:data:`kcheck.numerics.thresholds.DET_ROUNDING`)."""
    n = stack.shape[-1]
    with np.errstate(all="ignore"):
        rows = np.sum(np.log(np.sqrt(np.sum(stack * stack, axis=-1))), axis=-1)
        return DET_ROUNDING * n * n * EPS * np.exp(rows - log_base)


def range_cases(
    problem: Problem,
    cases: Sequence[Case],
    path: FrictionPath,
    nodes: int | None = None,
    rhs: tuple[np.ndarray, np.ndarray] | None = None,
) -> list[RangeCase | None]:
    """The polynomial form of each determined case along a friction path (None for the
    others), all in one batch of numpy calls.

    ``problem`` gives the geometry, mass and load (``rhs``: another external wrench
    ``b0 + B d`` to sweep, e.g. the weight's direction); its own friction is not used.
    """
    live = [i for i, c in enumerate(cases) if c.determined and c.k0 is not None]
    out: list[RangeCase | None] = [None] * len(cases)
    if not live:
        return out
    chosen = [cases[i] for i in live]
    k0 = np.stack([c.k0 for c in chosen])  # type: ignore[misc]
    f_low = friction_matrices(problem, chosen, path.low)
    f_span = friction_matrices(problem, chosen, path.high - path.low)
    n = k0.shape[-1]
    x = cheb.lobatto(n + 2 if nodes is None else nodes)
    t = 0.5 * (x + 1.0)
    b0, big_b = problem.load_basis() if rhs is None else rhs
    columns_rhs = np.column_stack([b0, big_b])  # (n, 1 + dim)
    # One scaling for every matrix of a case keeps the determinant ratios exact.
    rows, cols = _equilibrate(k0 + f_low + 0.5 * f_span)
    scale = rows[:, None, :, None] * cols[:, None, None, :]
    sense = np.array([1.0, -1.0])[:, None, None, None, None]
    friction = f_low[None, :, None] + t[None, None, :, None, None] * f_span[None, :, None]
    systems = (k0[None, :, None] + sense * friction) * scale[None]  # (2, c, m, n, n)
    with np.errstate(all="ignore"):
        sign0, log0 = np.linalg.slogdet(k0 * scale[:, 0])  # (c,)
    effective = sign0[None, :, None] * _determinants(systems, log0[None, :, None])  # (2, c, m)
    # Cramer: column k of the forward system replaced by each right-hand side column.
    forward = systems[0]  # (c, m, n, n)
    scaled_rhs = columns_rhs[None, :, :] * rows[:, :, None]  # (c, n, 1 + dim)
    shape = forward.shape[:2] + (columns_rhs.shape[1], n, n, n)
    replaced = np.broadcast_to(forward[:, :, None, None], shape).copy()  # (c, m, 1 + dim, k, n, n)
    columns = np.moveaxis(scaled_rhs, 2, 1)  # (c, 1 + dim, n)
    for k in range(n):
        replaced[:, :, :, k, :, k] = (columns * cols[:, None, k, None])[:, None]
    numer = sign0[:, None, None, None] * _determinants(replaced, log0[:, None, None, None])
    quality = _hadamard_ok(systems)  # (c,)
    eff_series = cheb.interpolate(x, np.moveaxis(effective, 2, 0))  # (2, c, m)
    num_series = cheb.interpolate(x, np.moveaxis(numer, 1, 0))  # (c, 1 + dim, n, m)
    # Values' errors at the nodes carry over to the series on [-1, 1] times the Lebesgue
    # constant of the nodes (Chebyshev–Lobatto: below 2/π ln m + 1).
    lebesgue = 2.0 / np.pi * np.log(len(x)) + 1.0
    eff_error = lebesgue * determinant_error(systems, log0[None, :, None]).max(axis=2)  # (2, c)
    num_error = lebesgue * determinant_error(replaced, log0[:, None, None, None]).max(axis=1)
    for j, i in enumerate(live):
        out[i] = RangeCase(
            index=i,
            effective=eff_series[:, j],
            numerators=np.moveaxis(num_series[j], 1, 0),
            trusted=bool(quality[j]),
            effective_error=eff_error[:, j],
            numerator_error=num_error[j].T,  # (n, 1 + dim)
        )
    return out


def _hadamard_ok(systems: np.ndarray) -> np.ndarray:
    """Per case, whether every matrix (2, c, m, n, n) is farther from singular than the
    analysis trusts: ``|det| / prod(row norms)`` above ``1 / ILL_CONDITIONED``, except where
    the determinant itself crosses zero (a Painlevé root, decided by the effective mass)."""
    with np.errstate(all="ignore"):
        sign, logdet = np.linalg.slogdet(systems)
        rows = np.sum(np.log(np.sqrt(np.sum(systems * systems, axis=-1))), axis=-1)
        ratio = np.where(sign != 0, np.exp(logdet - rows), 0.0)
    bad = ~(ratio > 1.0 / ILL_CONDITIONED)
    # A matrix near a root of its determinant is Painlevé, not ill-conditioned: its
    # neighbours along the path are fine. Only a matrix singular at every node is untrusted.
    return ~np.all(bad, axis=2).any(axis=0)


def condition_series(rc: RangeCase, e1: np.ndarray, e2: np.ndarray) -> np.ndarray:
    """Per forward unknown, ``[P, Q1, Q2]`` (n, 3, m): the numerator is
    ``P + Q1 cos(a) + Q2 sin(a)`` at angle ``a`` in the plane ``(e1, e2)``."""
    fixed = rc.numerators[:, 0]
    along = rc.numerators[:, 1:]
    q1 = np.einsum("i,kim->km", e1, along)
    q2 = np.einsum("i,kim->km", e2, along)
    return np.stack([fixed, q1, q2], axis=1)


def _envelope(series: np.ndarray) -> np.ndarray:
    """Candidate points ``x`` in [-1, 1] per condition (n, r) near which an arc end of
    ``P + Q1 cos a + Q2 sin a > 0`` turns back: ``N = 0`` and ``dN/dx = 0`` have a common
    angle, i.e. ``(P'Q2 - PQ2')^2 + (PQ1' - P'Q1)^2 = (Q1Q2' - Q2Q1')^2``.

    Both ends of a half circle (``P = 0``: no fixed wrench) turn back together, a double root;
    rounding may split it into a complex pair, so nearly real roots are kept too (a spare
    candidate only costs one decision)."""
    p, q1, q2 = series[:, 0], series[:, 1], series[:, 2]
    dp, dq1, dq2 = (cheb.derivative(s) for s in (p, q1, q2))
    u = cheb.product(dp, q2) - cheb.product(p, dq2)
    v = cheb.product(p, dq1) - cheb.product(dp, q1)
    w = cheb.product(q1, dq2) - cheb.product(q2, dq1)
    e = cheb.product(u, u) + cheb.product(v, v) - cheb.product(w, w)
    return cheb.real_roots(e, imag_tol=ENVELOPE_IMAG_TOL)


def _end_angles(series: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Both arc ends (rad, (2, ...)) of conditions (..., 3, m) at points ``x`` (...): centre
    minus and plus the half-width; NaN where the arc is full or empty."""
    vander = np.polynomial.chebyshev.chebvander(x, series.shape[-1] - 1)
    p, q1, q2 = (np.sum(series[..., i, :] * vander, axis=-1) for i in range(3))
    norm = np.hypot(q1, q2)
    with np.errstate(all="ignore"):
        ratio = -p / norm
        half = np.where(np.abs(ratio) < 1.0, np.arccos(np.clip(ratio, -1.0, 1.0)), np.nan)
    centre = np.arctan2(q2, q1)
    return np.stack([centre - half, centre + half])


def _turning_ends(series: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Where each arc end near the candidates ``x`` (r,) of conditions (r, 3, m) turns back:
    the least and the largest angle of both ends within 1e-3 of each candidate (golden-section
    search on the closed form, all at once): angles (4 r,), NaN where none."""
    width = 1e-3
    ref = _end_angles(series, x)  # (2, r): both ends at the candidates
    branch = np.array([0, 0, 1, 1])[:, None]  # (4, 1): start, start, end, end
    sign = np.array([1.0, -1.0, 1.0, -1.0])[:, None]  # least, largest

    def f(z: np.ndarray) -> np.ndarray:
        angle = np.take_along_axis(_end_angles(series, z), branch[None], axis=0)[0]
        return sign * ((angle - ref[branch[:, 0]] + np.pi) % TAU - np.pi)

    a = np.broadcast_to(np.clip(x - width, -1.0, 1.0), (4, len(x))).copy()
    b = np.broadcast_to(np.clip(x + width, -1.0, 1.0), (4, len(x))).copy()
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(32):
        left = fc < fd  # the least lies in [a, d]; NaN compares False
        a, b = np.where(left, a, c), np.where(left, d, b)
        c, d = np.where(left, b - GOLDEN * (b - a), d), np.where(left, c, a + GOLDEN * (b - a))
        fc, fd = f(c), f(d)
    ends = np.take_along_axis(_end_angles(series, 0.5 * (a + b)), branch[None], axis=0)[0]
    return ends.ravel() % TAU


GOLDEN = 0.5 * (np.sqrt(5.0) - 1.0)


def range_arcs(rc: RangeCase, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, dict[float, float]]:
    """Angles (rad from ``e1`` towards ``e2``) where the case closes for every coefficient of
    the path, exactly, and for each arc end the path parameter ``t`` where it binds.

    Candidate ends: the arc ends at ``t = 0`` and ``t = 1`` and at the envelope points
    (:func:`_envelope`); one exact decision (:meth:`RangeCase.closes`) per piece between them.
    """
    if not rc.trusted or not rc.painleve_free:
        return (), {}
    series = condition_series(rc, e1, e2)
    tagged: dict[float, float] = {}
    ends = _end_angles(series[None], np.array([[-1.0], [1.0]]))  # (2, 2, n): branch, t, k
    for j, t in enumerate((0.0, 1.0)):
        for angle in ends[:, j].ravel():
            if np.isfinite(angle):
                tagged.setdefault(float(angle % TAU), t)
    envelope = _envelope(series)
    rows, cols = np.nonzero(np.isfinite(envelope))
    if len(rows):
        x = envelope[rows, cols]
        for angle, xc in zip(_turning_ends(series[rows], x), np.tile(x, 4), strict=True):
            if np.isfinite(angle):
                tagged.setdefault(float(angle), 0.5 * (float(xc) + 1.0))
    if not tagged:
        inside = bool(rc.closes(e1[None])[0])
        return (FULL if inside else ()), {}
    cuts = np.array(sorted(tagged))
    nxt = np.append(cuts[1:], cuts[0] + TAU)
    mids = 0.5 * (cuts + nxt)
    dirs = np.cos(mids)[:, None] * e1 + np.sin(mids)[:, None] * e2
    ok = rc.closes(dirs)
    if np.all(ok):
        return FULL, {}
    pieces = [((float(s), float(e)),) for s, e, good in zip(cuts, nxt, ok, strict=True) if good]
    arcs = union(*pieces) if pieces else ()
    return arcs, tagged


# --- the sphere of directions ----------------------------------------------------------------

# The most samples spent on one condition (for the angular error ENVELOPE_TOL); the grid on
# which envelope points are looked for inside the region.
MAX_SAMPLES = 64
ENVELOPE_GRID = 257


def _envelope_points(p: np.ndarray, q: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Envelope points (m, 2, 3) of one condition's circles ``P + Q . d = 0`` at the points
    ``x`` (m,) of the path: where the line ``P + Q . d = 0 = P' + Q' . d`` meets the sphere
    (NaN where it does not)."""
    a, b = cheb.values(p, x), cheb.values(cheb.derivative(p), x)  # (m,)
    n1 = cheb.values(q, x).T  # (m, 3)
    n2 = cheb.values(cheb.derivative(q), x).T
    g11, g12, g22 = (np.sum(u * v, axis=1) for u, v in ((n1, n1), (n1, n2), (n2, n2)))
    with np.errstate(all="ignore"):
        det = g11 * g22 - g12 * g12
        alpha = (-a * g22 + b * g12) / det
        beta = (-b * g11 + a * g12) / det
        base = alpha[:, None] * n1 + beta[:, None] * n2
        w = np.cross(n1, n2)
        rest = (1.0 - np.sum(base * base, axis=1)) / np.sum(w * w, axis=1)
        gamma = np.where(rest >= 0, np.sqrt(rest), np.nan)[:, None]
    return np.stack([base + gamma * w, base - gamma * w], axis=1)


def range_caps(rc: RangeCase) -> tuple[np.ndarray, np.ndarray, float]:
    """Caps ``a + c . d > 0`` (k,), (k, 3) whose intersection is the set of directions where the
    case closes for every coefficient of the path, and the angular error (rad) of its boundary.

    The set's boundary lies on the circles at the ends of the path or on the **envelope** of a
    condition's circles (where consecutive circles meet). So: the region ``R`` of the end caps
    is computed exactly; envelope points are looked for on a grid of ``t`` and kept where they
    lie in ``R`` (elsewhere they cannot bound the set). With none, ``R`` is the set (checked
    by one exact decision at its deepest point). Where some lie in ``R``, the condition also
    contributes caps at coefficients spaced ``h`` apart over that stretch: the intersection
    then contains the true set, whose boundary lies at most ``B h^2 / 8 / s`` inside it
    (``B`` bounds the condition's second derivative along the path, ``s = sqrt(|Q|^2 - P^2)``
    is its rate across the boundary) — the returned error. A Painlevé-type case gets one cap
    that holds nowhere.
    """
    from kcheck.mechanics.caps import region
    from kcheck.mechanics.deepest import deepest_point

    if not rc.trusted or not rc.painleve_free:
        return np.array([-1.0]), np.zeros((1, 3)), 0.0
    p, q = rc.numerators[:, 0], rc.numerators[:, 1:]  # (n, m), (n, 3, m)
    ends = np.array([-1.0, 1.0])
    a_end = cheb.values(p, ends).reshape(-1)
    c_end = np.moveaxis(cheb.values(q, ends), 1, 2).reshape(-1, 3)
    ends_region = region(a_end, c_end)
    if ends_region.empty:
        return a_end, c_end, 0.0
    keep = ends_region.caps.source[ends_region.bounding]
    a_all, c_all = [a_end[keep]], [c_end[keep]]
    grid = cheb.lobatto(ENVELOPE_GRID)
    error = 0.0
    added = False
    for k in range(len(p)):
        points = _envelope_points(p[k], q[k], grid).reshape(-1, 3)
        ok = np.all(np.isfinite(points), axis=1)
        inside = np.zeros(len(points), bool)
        if np.any(ok):
            inside[ok] = np.all(a_end + points[ok] @ c_end.T > -ENVELOPE_INSIDE_SLACK, axis=1)
        hit = np.flatnonzero(inside.reshape(-1, 2).any(axis=1))
        if not len(hit):
            continue
        lo, hi = grid[max(hit.min() - 1, 0)], grid[min(hit.max() + 1, len(grid) - 1)]
        samples, err = _samples(p[k], q[k], lo, hi)
        error = max(error, err)
        a_all.append(cheb.values(p[k], samples))
        c_all.append(cheb.values(q[k], samples).T)
        added = True
    if not added:
        # No envelope point in R: the set is R or empty (R holds no end circle inside).
        deepest, _ = deepest_point(ends_region)
        if deepest is not None and not bool(rc.closes(deepest[None])[0]):
            return np.array([-1.0]), np.zeros((1, 3)), 0.0
    return np.concatenate(a_all), np.vstack(c_all), float(error)


def _samples(p: np.ndarray, q: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, float]:
    """Points of the path in [lo, hi] at which one condition's caps stand in for its envelope,
    spaced for an angular error of about ``ENVELOPE_TOL``, and the error bound (rad)."""
    second = cheb.derivative(cheb.derivative(np.vstack([p[None], q])))
    bound = float(cheb.abs_bound(second[0]) + np.linalg.norm(cheb.abs_bound(second[1:])))
    probe = np.linspace(lo, hi, 17)
    a, c = cheb.values(p, probe), cheb.values(q, probe).T
    slope = float(np.sqrt(np.maximum(np.sum(c * c, axis=1) - a * a, 0.0)).min())
    if bound <= 0:
        return np.array([lo, hi]), 0.0
    want = np.sqrt(8.0 * ENVELOPE_TOL * slope / bound)
    count = int(min(MAX_SAMPLES, max(2, np.ceil((hi - lo) / max(want, SAMPLE_STEP_FLOOR)) + 1)))
    h = (hi - lo) / (count - 1)
    error = bound * h * h / 8.0 / slope if slope > 0 else float(np.pi)
    return np.linspace(lo, hi, count), float(min(error, np.pi))
