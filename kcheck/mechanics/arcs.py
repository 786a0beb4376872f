"""Exact sets of force angles: arcs on the circle and caps on the sphere of directions.

Within one friction assumption every unknown of the dynamics is affine in the force direction
``d``: ``x_k(d) = a_k + c_k . d`` (methods.md §4). On the sweep circle
``d = cos(alpha) e1 + sin(alpha) e2`` this is ``a + b cos(alpha) + c sin(alpha)``, positive on
one arc centred on ``atan2(c, b)`` with half-width ``arccos(-a / hypot(b, c))``. On the sphere
it is positive on a cap about ``c / |c|`` with the same angular radius.

An arc set is a tuple of disjoint arcs ``(start, end)`` in radians with ``0 <= start < 2 pi``
and ``start < end <= start + 2 pi``, sorted by start; the full circle is ``((0, 2 pi),)``.
"""

from __future__ import annotations

import math

import numpy as np

from kcheck.numerics.arrays import unique
from kcheck.numerics.thresholds import ARC_ZERO_RTOL, EPS

__all__ = [
    "TAU",
    "FULL",
    "ArcSet",
    "positive_arc",
    "affine_arcs",
    "intersect",
    "intersect_single",
    "complement",
    "union",
    "contains",
    "margin",
    "to_degrees",
    "boundary_angles",
    "cap_geometry",
    "cap_margin_matrix",
    "cap_margins",
]

TAU = 2.0 * np.pi
ArcSet = tuple[tuple[float, float], ...]
FULL: ArcSet = ((0.0, TAU),)


def positive_arc(a: float, b: float, c: float, *, zero_tol: float = 0.0) -> ArcSet:
    """Angles where ``a + b cos(alpha) + c sin(alpha) > 0`` (radians).

    ``zero_tol`` is the size below which ``hypot(b, c)`` counts as zero (then the sign of ``a``
    decides for every angle).
    """
    r = math.hypot(b, c)
    if r <= zero_tol:
        return FULL if a > 0 else ()
    ratio = -a / r
    if ratio <= -1.0:
        return FULL
    if ratio >= 1.0:
        return ()
    half = math.acos(ratio)
    start = (math.atan2(c, b) - half) % TAU
    return ((start, start + 2.0 * half),)


def affine_arcs(
    a: np.ndarray,
    c: np.ndarray,
    e1: np.ndarray,
    e2: np.ndarray,
    error: np.ndarray | None,
) -> tuple[ArcSet, float | None]:
    """Angles (from ``e1`` towards ``e2``) where every ``a_k + c_k . d`` is positive.

    ``a`` (k,), ``c`` (k, dim) and the absolute errors ``error`` (k,) of the coefficients.
    Returns the arc set and an estimate of the error of its ends in radians: at each end, the
    error of the condition that vanishes there over its rate of change across the end,
    ``sqrt(b^2 + c^2 - a^2)``; None when the set has no ends (empty or full circle) or when
    ``error`` is None (no estimate wanted).
    """
    a = np.asarray(a, dtype=float)
    b, s = c @ e1, c @ e2
    if len(a) == 1:
        return _one_arc(float(a[0]), float(b[0]), float(s[0]), float(np.abs(c).max()), error)
    if len(a) <= FEW_CONDITIONS:
        return _few_arcs(a, b, s, c, error)
    # Per condition: a direction term below rounding of that condition's own size is no term.
    # A tolerance shared by all would erase the direction term of a small unknown whenever
    # another one is huge (e.g. a heavy body's weight on one support).
    zero_tol = ARC_ZERO_RTOL * np.maximum(np.abs(a), np.abs(c).max(axis=1))
    # positive_arc for every condition at once: full, empty, or one arc.
    r = np.hypot(b, s)
    flat = r <= zero_tol
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(flat, np.where(a > 0, -np.inf, np.inf), -a / np.where(flat, 1.0, r))
    if np.any(ratio >= 1.0):
        arcs: ArcSet = ()
    else:
        bounded = ratio > -1.0
        half = np.arccos(np.clip(ratio[bounded], -1.0, 1.0))
        start = (np.arctan2(s[bounded], b[bounded]) - half) % TAU
        arcs = intersect_single(start, start + 2.0 * half)
    if error is None or not arcs or arcs == FULL:
        return arcs, None
    ends = boundary_angles(arcs)
    # Scaled per condition so that squares cannot overflow.
    size = np.maximum(np.maximum(np.abs(a), np.abs(b)), np.abs(s))
    size = np.where(size > 0, size, 1.0)
    an, bn, sn = a / size, b / size, s / size
    slope = np.sqrt(np.maximum(bn * bn + sn * sn - an * an, 0.0))
    values = np.abs(an + np.outer(np.cos(ends), bn) + np.outer(np.sin(ends), sn))  # (ends, k)
    # The end moves by the coefficients' error over the slope; arccos and atan2 add rounding
    # of the same kind (eps |a| / slope) and of the angle itself (eps of 2 pi).
    rounding = EPS * (np.abs(an) + np.hypot(bn, sn))
    with np.errstate(divide="ignore", invalid="ignore"):
        miss = np.where(slope > 0, values / slope, np.inf)  # angular distance to its zero
        per = np.where(slope > 0, (error / size + rounding) / slope, np.inf) + EPS * TAU
    active = np.argmin(miss, axis=1)
    return arcs, float(np.max(per[active]))


#: Up to this many conditions :func:`affine_arcs` works in plain float arithmetic: a case's
#: own conditions (its unknowns, about six), where numpy's per-call overhead on arrays this
#: small was most of the time. The same formulas in the same order; ``math``'s hypot, acos,
#: atan2, cos and sin may differ from numpy's in the last bit, far inside the ends' error.
FEW_CONDITIONS = 12


def _few_arcs(
    a: np.ndarray, b: np.ndarray, s: np.ndarray, c: np.ndarray, error: np.ndarray | None
) -> tuple[ArcSet, float | None]:
    """:func:`affine_arcs` for a few conditions (``b = c . e1``, ``s = c . e2``) in plain
    float arithmetic."""
    al, bl, sl = a.tolist(), b.tolist(), s.tolist()
    singles = []
    for ak, bk, sk, ck in zip(al, bl, sl, c.tolist(), strict=True):
        # Per condition, as in affine_arcs: a direction term below rounding of its own size.
        zero_tol = ARC_ZERO_RTOL * max(abs(ak), max(abs(x) for x in ck))
        r = math.hypot(bk, sk)
        if r <= zero_tol:
            if ak > 0:
                continue  # holds everywhere
            return (), None
        ratio = -ak / r
        if ratio >= 1.0:
            return (), None
        if ratio > -1.0:
            half = math.acos(ratio)
            start = (math.atan2(sk, bk) - half) % TAU
            singles.append(((start, start + 2.0 * half),))
    arcs = intersect(*singles)
    if error is None or not arcs or arcs == FULL:
        return arcs, None
    ends = sorted(x % TAU for arc in arcs for x in arc)
    given = np.asarray(error, float)
    errors = (given if given.shape == a.shape else np.broadcast_to(given, a.shape)).tolist()
    terms = []  # per condition: (an, bn, sn, slope, error per unit of slope)
    for ak, bk, sk, ek in zip(al, bl, sl, errors, strict=True):
        size = max(abs(ak), abs(bk), abs(sk))
        size = size if size > 0 else 1.0
        an, bn, sn = ak / size, bk / size, sk / size
        slope = math.sqrt(max(bn * bn + sn * sn - an * an, 0.0))
        rounding = EPS * (abs(an) + math.hypot(bn, sn))
        per = (ek / size + rounding) / slope + EPS * TAU if slope > 0 else math.inf
        terms.append((an, bn, sn, slope, per))
    worst = -math.inf
    for end in ends:
        cos_e, sin_e = math.cos(end), math.sin(end)
        # The condition that vanishes at this end: the least angular distance to its zero
        # (the first on ties, as numpy's argmin).
        best, best_per = math.inf, math.inf
        first = True
        for an, bn, sn, slope, per in terms:
            miss = abs(an + cos_e * bn + sin_e * sn) / slope if slope > 0 else math.inf
            if first or miss < best:
                best, best_per, first = miss, per, False
        worst = max(worst, best_per)
    return arcs, float(worst)


def _one_arc(
    a: float, b: float, s: float, size_c: float, error: np.ndarray | None
) -> tuple[ArcSet, float | None]:
    """:func:`affine_arcs` for a single condition, in scalar arithmetic (no array overhead)."""
    arcs = positive_arc(a, b, s, zero_tol=ARC_ZERO_RTOL * max(abs(a), size_c))
    if error is None or not arcs or arcs == FULL:
        return arcs, None
    size = max(abs(a), abs(b), abs(s)) or 1.0
    an, bn, sn = a / size, b / size, s / size
    slope = math.sqrt(max(bn * bn + sn * sn - an * an, 0.0))
    if slope == 0.0:
        return arcs, float("inf")
    rounding = EPS * (abs(an) + math.hypot(bn, sn))
    return arcs, (float(error[0]) / size + rounding) / slope + EPS * TAU


def _intervals(arcs: ArcSet) -> list[tuple[float, float]]:
    """Split arcs into intervals inside [0, 2 pi]."""
    out: list[tuple[float, float]] = []
    for s, e in arcs:
        if e <= TAU:
            out.append((s, e))
        else:
            out.append((s, TAU))
            out.append((0.0, e - TAU))
    return sorted(out)


def _from_intervals(intervals: list[tuple[float, float]]) -> ArcSet:
    """Merge sorted intervals in [0, 2 pi] into an arc set, joining across angle 0."""
    merged: list[list[float]] = []
    for s, e in sorted(intervals):
        if e <= s:
            continue
        if merged and s <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], e)
        else:
            merged.append([s, e])
    if not merged:
        return ()
    if merged[0][0] <= 0.0 and merged[-1][1] >= TAU:
        if len(merged) == 1:
            return FULL
        first = merged.pop(0)
        merged[-1][1] = TAU + first[1]
    return tuple((float(s), float(e)) for s, e in merged)


def intersect(*sets: ArcSet) -> ArcSet:
    """Intersection of arc sets."""
    current = [(0.0, TAU)]
    for arcs in sets:
        other = _intervals(arcs)
        nxt = []
        for s1, e1 in current:
            for s2, e2 in other:
                s, e = max(s1, s2), min(e1, e2)
                if e > s:
                    nxt.append((s, e))
        current = nxt
    return _from_intervals(current)


def intersect_single(start: np.ndarray, end: np.ndarray) -> ArcSet:
    """Intersection of single arcs ``(start_k, end_k)`` (``0 <= start < 2 pi``,
    ``start < end <= start + 2 pi``), the same as :func:`intersect` of them, at once.

    The ends (split at 2 pi, as :func:`intersect` splits them) cut [0, 2 pi] into elementary
    intervals, each wholly inside or outside every arc; the inside ones, those covered by as
    many pieces as there are arcs (an arc's two pieces meet at most in a point), are merged.
    Coverage is counted by sorting the pieces' ends, not by an (intervals, arcs) table. The
    result's ends are the same floats."""
    if len(start) <= 1:
        return intersect(*(((float(x), float(y)),) for x, y in zip(start, end, strict=True)))
    wraps = end > TAU
    cuts = unique(np.concatenate([[0.0, TAU], start, np.where(wraps, TAU, end), end[wraps] - TAU]))
    lo, hi = cuts[:-1], cuts[1:]
    # Pieces: [start, min(end, 2 pi)], and [0, end - 2 pi] where an arc wraps, cut at its
    # start (end - 2 pi may round past it: the pieces would overlap). A piece covers
    # [lo, hi] iff it starts at or before lo and ends at or after hi, i.e. after lo (its ends
    # are cuts).
    opens = np.sort(np.concatenate([start, np.zeros(np.count_nonzero(wraps))]))
    closes = np.sort(
        np.concatenate([np.minimum(end, TAU), np.minimum(end[wraps] - TAU, start[wraps])])
    )
    covered = np.searchsorted(opens, lo, "right") - np.searchsorted(closes, lo, "right")
    inside = covered == len(start)
    return _from_intervals(list(zip(lo[inside].tolist(), hi[inside].tolist(), strict=True)))


def complement(arcs: ArcSet) -> ArcSet:
    """The angles not in an arc set (boundaries belong to both)."""
    if arcs == FULL:
        return ()
    if not arcs:
        return FULL
    gaps = [(arcs[i][1], arcs[i + 1][0]) for i in range(len(arcs) - 1)]
    gaps.append((arcs[-1][1], arcs[0][0] + TAU))
    out = []
    for s, e in gaps:
        if e > s:
            out.append(_shifted(s, e))
    return tuple(sorted(out))


def _shifted(s: float, e: float) -> tuple[float, float]:
    """A gap ``(s, e)`` moved by whole turns so that it starts in [0, 2 pi): ``floor(s / 2 pi)``
    turns, in plain float arithmetic (a positive quotient below 2^52: ``math.floor``'s integer
    times 2 pi is the same float as ``np.floor``'s; zero, negative or huge quotients, whose
    signed zeros or size the integer would not keep, go to numpy)."""
    turns = s / TAU
    if 0.0 < turns < 2.0**52:
        shift = math.floor(turns) * TAU
        return (float(s - shift), float(e - shift))
    shift = np.floor(turns) * TAU
    return (float(s - shift), float(e - shift))


def union(*sets: ArcSet) -> ArcSet:
    """Union of arc sets."""
    return complement(intersect(*(complement(s) for s in sets)))


def contains(arcs: ArcSet, angle: float) -> bool:
    """Whether an angle (radians) lies inside an arc set."""
    angle = angle % TAU
    return any(s <= angle <= e or s <= angle + TAU <= e for s, e in arcs)


def margin(arcs: ArcSet, angle: float) -> float:
    """Signed angular distance (radians) from an angle to the nearest arc end.

    Positive inside the set, negative outside; ``pi`` for the full circle, ``-pi`` for none.
    """
    if arcs == FULL:
        return np.pi
    if not arcs:
        return -np.pi
    ends = np.array([x for arc in arcs for x in arc])
    diff = (angle - ends + np.pi) % TAU - np.pi
    distance = float(np.abs(diff).min())
    return distance if contains(arcs, angle) else -distance


def to_degrees(arcs: ArcSet) -> list[list[float]]:
    """Arc set in degrees, as JSON lists ``[start, end]``."""
    return [[float(np.degrees(s)), float(np.degrees(e))] for s, e in arcs]


def boundary_angles(arcs: ArcSet) -> np.ndarray:
    """All arc ends in [0, 2 pi), sorted (empty for the full circle)."""
    if arcs == FULL:
        return np.zeros(0)
    return np.sort(np.array([x % TAU for arc in arcs for x in arc]))


def cap_geometry(a: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geometry of the caps ``a_k + c_k . d > 0``: ``(ratio, axes, radius)``.

    ``ratio`` (k,) is ``-a_k / |c_k|``, the cosine of the angular radius (``-inf`` for a
    condition that holds everywhere with ``c_k = 0``, ``+inf`` for one that holds nowhere);
    ``axes`` (k, 3) the unit cap axes (zero where ``c_k = 0``); ``radius`` (k,) the angular
    radius in rad, ``arccos`` of the ratio clipped to [-1, 1].
    """
    r = np.linalg.norm(c, axis=1)
    safe = np.where(r > 0, r, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(r > 0, -a / safe, np.where(a > 0, -np.inf, np.inf))
    axes = np.where(r[:, None] > 0, c / safe[:, None], 0.0)
    return ratio, axes, np.arccos(np.clip(ratio, -1.0, 1.0))


def cap_margin_matrix(a: np.ndarray, c: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Signed angular margin (rad) of each direction (m, 3) inside each cap: (m, k).

    Positive inside the cap; ``pi`` for a condition that holds everywhere (no boundary),
    ``-pi`` for one that holds nowhere.
    """
    ratio, axes, radius = cap_geometry(a, c)
    out = radius[None, :] - np.arccos(np.clip(directions @ axes.T, -1.0, 1.0))
    out[:, ratio <= -1.0] = np.pi
    out[:, ratio >= 1.0] = -np.pi
    return out


def cap_margins(a: np.ndarray, c: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Angular margin (rad) of unit directions inside every cap ``a_k + c_k . d > 0``.

    ``a`` (k,), ``c`` (k, 3), ``directions`` (m, 3) -> (m,) the smallest, over ``k``, of the
    angular distance to the cap's boundary circle, positive inside all caps. Since the
    boundary of an intersection lies on the caps' circles, this is the distance to the
    boundary of the safe region for directions inside it. A condition with ``c_k = 0`` is a
    full sphere (margin ``pi``) or empty (``-pi``) by the sign of ``a_k``.
    """
    if len(a) == 0:
        return np.full(len(directions), np.pi)
    return cap_margin_matrix(a, c, directions).min(axis=1)
