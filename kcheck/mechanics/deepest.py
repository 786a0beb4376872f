"""The deepest point of an intersection of spherical caps (:mod:`kcheck.mechanics.caps`): the most
robust direction, the centre of the largest cap inside the safe region ``S``, equidistant from
one, two or three boundary circles (closed forms for each); for many caps by an active set.
"""

from __future__ import annotations

from functools import lru_cache
from itertools import combinations

import numpy as np

from kcheck.mechanics.caps import ON_BOUNDARY, CapSet, Region, angle_between, margin_in, region
from kcheck.mechanics.kinematics import cross3
from kcheck.mechanics.sphere import fibonacci_sphere
from kcheck.numerics.thresholds import ARCCOS_ANGLE_SLACK, ON_UNIT_SPHERE, QUADRATIC_LEAD

__all__ = ["deepest_point", "most_robust_direction"]

# The deepest point is found among all caps directly up to this many, else by an active set
# started from the caps nearest the best of GRID directions and grown ACTIVE_STEP at a time.
ACTIVE_START = 12
ACTIVE_STEP = 4
GRID = 400


def _candidates_pairs(caps: CapSet, pairs: np.ndarray) -> np.ndarray:
    """Points equidistant (in margin) from two circles on the great circle through their
    axes: ``angle(x, u_i) = (gamma + r_i - r_j) / 2``."""
    ui, uj = caps.axes[pairs[:, 0]], caps.axes[pairs[:, 1]]
    gamma = angle_between(ui, uj)
    theta = 0.5 * (gamma + caps.radius[pairs[:, 0]] - caps.radius[pairs[:, 1]])
    w = uj - np.sum(ui * uj, axis=1, keepdims=True) * ui
    norm = np.linalg.norm(w, axis=1, keepdims=True)
    with np.errstate(all="ignore"):
        w = w / norm
    return np.cos(theta)[:, None] * ui + np.sin(theta)[:, None] * w


def _candidates_triples(caps: CapSet, triples: np.ndarray) -> np.ndarray:
    """Points at equal margin ``t`` from three circles: ``x . u = cos(r - t)`` for the three,
    ``|x| = 1``. With ``x = P cos t + Q sin t`` (``P = U^-1 cos r``, ``Q = U^-1 sin r``) the
    unit length is a quadratic in ``tan t``; each root gives ``x`` and ``-x``."""
    u = caps.axes[triples]  # (p, 3, 3): rows are the axes
    cos_r, sin_r = caps.cos_radius[triples], np.sin(caps.radius[triples])
    # Inverse by cross products: U^-1 = [u1 x u2, u2 x u0, u0 x u1] / det (as columns).
    cof = np.stack(
        [cross3(u[:, 1], u[:, 2]), cross3(u[:, 2], u[:, 0]), cross3(u[:, 0], u[:, 1])],
        axis=1,
    )
    det = np.sum(u[:, 0] * cof[:, 0], axis=1)
    with np.errstate(all="ignore"):
        p = np.einsum("pk,pkj->pj", cos_r, cof) / det[:, None]
        q = np.einsum("pk,pkj->pj", sin_r, cof) / det[:, None]
        qa, qb, qc = np.sum(q * q, 1) - 1.0, 2.0 * np.sum(p * q, 1), np.sum(p * p, 1) - 1.0
        disc = np.sqrt(np.where(qb * qb - 4 * qa * qc >= 0, qb * qb - 4 * qa * qc, np.nan))
        out = []
        for sign in (1.0, -1.0):
            tau = np.where(
                np.abs(qa) > QUADRATIC_LEAD,
                (-qb + sign * disc) / (2 * qa),
                -qc / np.where(qb != 0, qb, np.nan),
            )
            t = np.arctan(tau)
            x = p * np.cos(t)[:, None] + q * np.sin(t)[:, None]
            out.extend([x, -x])
    points = np.concatenate(out)
    return points[
        np.all(np.isfinite(points), axis=1)
        & (np.abs(np.linalg.norm(points, axis=1) - 1) < ON_UNIT_SPHERE)
    ]


def deepest_point(reg: Region) -> tuple[np.ndarray | None, float | None]:
    """The direction whose margin (least distance to every cap boundary, negative outside)
    is largest, and that margin (rad); (None, None) without caps to measure against.

    At the optimum one, two or three circles are nearest (the gradients of their margins
    balance), so the answer is among the caps' axes, the equidistant points of pairs on the
    great circle through their axes, and the equidistant points of triples. With many caps
    (an empty region, several friction coefficients) the triples are too many to list, so an
    active set grows instead: the deepest point of a few caps is the answer for all when no
    other cap comes nearer to it (the margin over a subset bounds the margin over all from
    above); otherwise the caps that come nearer join the set.
    """
    caps = reg.caps
    k = len(caps.radius)
    if reg.full or k == 0:
        return None, None
    if k <= ACTIVE_START:
        return _deepest_among(caps, np.arange(k))
    grid = fibonacci_sphere(GRID)
    best, _ = _best(caps, grid)
    active = np.argsort(_margins_each(caps, grid[best]))[:ACTIVE_START]
    while True:
        point, margin = _deepest_among(caps, active)
        each = _margins_each(caps, point)
        nearer = np.setdiff1d(np.flatnonzero(each < margin - ON_BOUNDARY), active)
        if len(nearer) == 0:
            return point, float(min(margin, each.min()))
        worst = nearer[np.argsort(each[nearer])[:ACTIVE_STEP]]
        active = np.union1d(active, worst)


@lru_cache(maxsize=64)
def _subsets(n: int, size: int) -> np.ndarray:
    """Every ``size``-subset of ``range(n)``, in the order of :func:`itertools.combinations`
    (read-only: shared between calls)."""
    out = np.array(list(combinations(range(n), size)))
    out.setflags(write=False)
    return out


def _margins_each(caps: CapSet, points: np.ndarray) -> np.ndarray:
    """Margin (rad) of points (..., 3) in each cap (..., k): ``r_k - angle(point, u_k)``."""
    return caps.radius - angle_between(np.asarray(points)[..., None, :], caps.axes)


def _deepest_among(caps: CapSet, active: np.ndarray) -> tuple[np.ndarray, float]:
    """The deepest point of the caps ``active`` and its margin among them (rad), from every
    single, pair and triple of them."""
    sub = CapSet(
        caps.axes[active],
        caps.cos_radius[active],
        caps.radius[active],
        caps.source[active],
        caps.empty,
    )
    n = len(active)
    points = [sub.axes]
    if n >= 2:
        points.append(_candidates_pairs(sub, _subsets(n, 2)))
    if n >= 3:
        points.append(_candidates_triples(sub, _subsets(n, 3)))
    cand = np.concatenate(points)
    cand = cand[np.all(np.isfinite(cand), axis=1)]
    cand /= np.linalg.norm(cand, axis=1, keepdims=True)
    best, margin = _best(sub, cand)
    return cand[best], margin


def _best(caps: CapSet, points: np.ndarray) -> tuple[int, float]:
    """The first of points (n, 3) with the largest margin in the caps, and that margin (rad):
    ``argmax`` of :func:`~kcheck.mechanics.caps.margin_in`, the same bits. The accurate
    margins (``atan2``) are computed only for the points whose margin by ``arccos`` of the
    dot products comes within twice its rounding (:data:`ARCCOS_ANGLE_SLACK`) of the
    largest: no other can be (or tie with) the largest."""
    with np.errstate(invalid="ignore"):
        rough = np.min(caps.radius - np.arccos(np.clip(points @ caps.axes.T, -1.0, 1.0)), axis=-1)
    top = np.max(rough) if len(rough) else np.nan
    near = (
        np.flatnonzero(rough >= top - 2 * ARCCOS_ANGLE_SLACK)
        if np.isfinite(top) and np.all(np.isfinite(rough))
        else np.arange(len(points))
    )
    exact = margin_in(caps, points[near])
    j = int(np.argmax(exact))
    return int(near[j]), float(exact[j])


def most_robust_direction(a: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, float]:
    """Direction deepest inside every cap and its margin (rad), exactly
    (:func:`deepest_point`); without any bounding cap, ``+z`` and
    ``pi``."""
    direction, margin = deepest_point(region(a, c))
    if direction is None or margin is None:
        return np.array([0.0, 0.0, 1.0]), float(np.pi)
    return direction, margin
