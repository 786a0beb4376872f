"""Exact geometry of an intersection of spherical caps: area, distance, deepest point.

Every closing condition of a spatial case is affine in the unit direction ``d``:
``a_k + c_k . d > 0`` holds on the cap of directions within the angular radius
``r_k = arccos(-a_k / |c_k|)`` of the axis ``u_k = c_k / |c_k|``. The safe region ``S`` is the
intersection of all caps. Here, in closed form:

* its **area** by Stokes' theorem (the integral form of Gauss–Bonnet): with a pole ``N`` whose
  antipode lies outside ``S``, the area form is ``d alpha`` with
  ``alpha = (1 - cos theta) d phi`` (``theta`` from ``N``), so the area is the integral of
  ``alpha`` along the boundary arcs of ``S`` — the parts of each cap's circle inside every
  other cap. Along a circle of radius ``r`` that integral is
  ``-cos r (t2 - t1) + (N . u + cos r) int dt / (B0 + rho cos(t - t0))``, elementary. Caps
  larger than a hemisphere, several pieces and holes need no special case; nor do corners
  (the corner angles of Gauss–Bonnet are carried by ``alpha``, which is smooth there);
* the **distance** of a direction to ``S``: inside, to its boundary (the nearest circle);
  outside, to the nearest point of ``S``, which is the foot of the perpendicular on a circle
  or a vertex where two circles meet;
* the deepest point (most robust direction) is in :mod:`kcheck.mechanics.deepest`.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import combinations

import numpy as np

from kcheck.mechanics.arcs import cap_geometry
from kcheck.mechanics.kinematics import cross3
from kcheck.numerics.thresholds import ATAN_SERIES, AXIS_FOOT, ON_BOUNDARY, SAME_CAP
from kcheck.records import dataclass

__all__ = [
    "FOUR_PI",
    "CapSet",
    "Region",
    "cap_set",
    "region",
    "regions",
    "angle_between",
    "signed_distance",
    "margin_in",
]

FOUR_PI = 4.0 * np.pi


@dataclass(frozen=True)
class CapSet:
    """The caps ``u_k . d > cos r_k`` that bound a region (duplicates and caps holding
    everywhere removed). ``source`` maps each cap to its condition; ``empty`` is True when
    some condition holds nowhere."""

    axes: np.ndarray  # (k, 3) unit
    cos_radius: np.ndarray  # (k,)
    radius: np.ndarray  # (k,) rad, in (0, pi)
    source: np.ndarray  # (k,) index of the condition
    empty: bool


def cap_set(a: np.ndarray, c: np.ndarray) -> CapSet:
    """The caps of conditions ``a_k + c_k . d > 0`` (``a`` (k,), ``c`` (k, 3))."""
    a = np.asarray(a, float)
    c = np.asarray(c, float).reshape(-1, 3)
    ratio, axes, radius = cap_geometry(a, c)
    empty = bool(np.any(ratio >= 1.0))
    live = np.flatnonzero((ratio > -1.0) & (ratio < 1.0))
    # The same cap twice (within SAME_CAP), every pair at once; the first of each is kept,
    # in order (a cap matching only a dropped one stays), as a loop over the caps would.
    r, u = ratio[live], axes[live]
    same = (np.abs(r[:, None] - r[None, :]) <= SAME_CAP) & (
        np.abs(u[:, None, :] - u[None, :, :]).max(axis=2, initial=0.0) <= SAME_CAP
    )
    same = np.tril(same, -1)
    if not same.any():
        idx = live
    else:
        kept: list[int] = []
        for n in range(len(live)):
            if not same[n, kept].any():
                kept.append(n)
        idx = live[kept]
    return CapSet(axes[idx], ratio[idx], radius[idx], idx, empty)


def angle_between(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angle (rad) between unit vectors, accurate near 0 and pi (atan2 of |u x v| and u . v);
    broadcasts over leading axes."""
    cross = cross3(u, v)
    return np.arctan2(np.sqrt(np.sum(cross * cross, axis=-1)), np.sum(u * v, axis=-1))


def _frames(axes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors ``e1, e2`` (k, 3) with ``(e1, e2, u)`` right-handed for each axis ``u``."""
    helper = np.where(np.abs(axes[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = cross3(helper, axes)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    return e1, cross3(axes, e1)


@dataclass(frozen=True)
class Region:
    """An intersection of caps, exactly: its area (sr), boundary length (rad), which caps bound
    it, and a few of its boundary points (for distances)."""

    caps: CapSet
    area: float
    perimeter: float
    bounding: np.ndarray  # (k,) bool: the cap's circle carries part of the boundary
    empty: bool
    full: bool
    lengths: np.ndarray | None = None  # (k,) length (rad) of each cap's part of the boundary

    @property
    def fraction(self) -> float:
        """Share of the whole sphere."""
        return self.area / FOUR_PI


def region(a: np.ndarray, c: np.ndarray) -> Region:
    """The intersection of the caps ``a_k + c_k . d > 0``, exactly (area to rounding)."""
    return regions([(a, c)])[0]


def regions(conditions: Sequence[tuple[np.ndarray, np.ndarray]]) -> list[Region]:
    """:func:`region` of several sets of conditions ``(a, c)`` (e.g. every case of every
    variant of a study's chunk): the sets with the same number of caps are stacked and solved
    in one batch of numpy calls (and, past the cuts, those with the same number of pieces per
    circle). Every operation is elementwise, a product of same-shaped matrices or a reduction
    of one set's own array, so each region is the one it gets alone, bit for bit."""
    sets = [cap_set(a, c) for a, c in conditions]
    out: list[Region | None] = [None] * len(sets)
    groups: dict[int, list[int]] = {}
    for i, caps in enumerate(sets):
        k = len(caps.radius)
        if caps.empty:
            out[i] = Region(caps, 0.0, 0.0, np.zeros(k, bool), True, False)
        elif k == 0:
            out[i] = Region(caps, FOUR_PI, 0.0, np.zeros(k, bool), False, True)
        else:
            groups.setdefault(k, []).append(i)
    for members in groups.values():
        for i, reg in zip(members, _regions_stacked([sets[i] for i in members]), strict=True):
            out[i] = reg
    return [r for r in out if r is not None]


def _regions_stacked(sets: list[CapSet]) -> list[Region]:
    """The regions of cap sets with the same number ``k`` (> 0) of caps, stacked."""
    k = len(sets[0].radius)
    none = np.zeros(k, bool)
    axes = np.stack([s.axes for s in sets])  # (g, k, 3)
    cos_r = np.stack([s.cos_radius for s in sets])  # (g, k)
    radius = np.stack([s.radius for s in sets])
    gram = axes @ np.swapaxes(axes, 1, 2)  # (g, k, k)
    # Two caps that do not overlap: axes at least r_i + r_j apart (never when r_i + r_j > pi).
    total = radius[:, :, None] + radius[:, None, :]
    apart = gram <= np.cos(np.minimum(total, np.pi)) + SAME_CAP
    apart &= ~np.eye(k, dtype=bool)
    disjoint = np.any(apart & (total <= np.pi + SAME_CAP), axis=(1, 2))
    out: list[Region | None] = [
        Region(s, 0.0, 0.0, none, True, False) if d else None
        for s, d in zip(sets, disjoint, strict=True)
    ]
    live = np.flatnonzero(~disjoint)
    if not len(live):
        return [r for r in out if r is not None]
    axes, cos_r, radius, gram = axes[live], cos_r[live], radius[live], gram[live]
    e1, e2 = (f.reshape(len(live), k, 3) for f in _frames(axes.reshape(-1, 3)))
    # Where circle k crosses circle j: u_j . x(t) = cos r_j, i.e. A + B cos t + C sin t = 0.
    sin_r = np.sin(radius)
    axes_t = np.swapaxes(axes, 1, 2)
    big_a = cos_r[:, :, None] * gram - cos_r[:, None, :]
    big_b = sin_r[:, :, None] * (e1 @ axes_t)
    big_c = sin_r[:, :, None] * (e2 @ axes_t)
    size = np.hypot(big_b, big_c)
    with np.errstate(all="ignore"):
        ratio = -big_a / size
    crosses = (np.abs(ratio) < 1.0) & ~np.eye(k, dtype=bool)
    half = np.arccos(np.clip(ratio, -1.0, 1.0))
    centre = np.arctan2(big_c, big_b)
    cuts = np.concatenate(
        [np.where(crosses, centre - half, np.nan), np.where(crosses, centre + half, np.nan)], axis=2
    )
    cuts = np.sort(np.where(np.isnan(cuts), np.inf, np.mod(cuts, 2.0 * np.pi)), axis=2)
    count = np.isfinite(cuts).sum(axis=2)  # (g, k)
    pieces_each = np.maximum(count.max(axis=1), 1)
    cap_area = np.min(2.0 * np.pi * (1.0 - cos_r), axis=1)
    for m in np.unique(pieces_each):
        rows = np.flatnonzero(pieces_each == m)
        m = int(m)
        sub_cos, sub_sin, sub_axes = cos_r[rows], sin_r[rows], axes[rows]
        sub_e1, sub_e2, sub_count, sub_cuts = e1[rows], e2[rows], count[rows], cuts[rows]
        # Pieces between consecutive cuts (the last wraps round); a circle without cuts is
        # one piece.
        idx = np.arange(m)[None, None, :]
        padded = np.concatenate([sub_cuts, np.full((len(rows), k, 1), np.inf)], axis=2)
        start, end = padded[:, :, :m], padded[:, :, 1 : m + 1]
        end = np.where(idx + 1 == sub_count[:, :, None], sub_cuts[:, :, :1] + 2.0 * np.pi, end)
        uncut = (sub_count == 0)[:, :, None] & (idx == 0)
        start, end = np.where(uncut, 0.0, start), np.where(uncut, 2.0 * np.pi, end)
        valid = idx < np.maximum(sub_count, 1)[:, :, None]
        start, end = np.where(valid, start, 0.0), np.where(valid, end, 0.0)
        t = 0.5 * (start + end)
        mid = (
            sub_cos[:, :, None, None] * sub_axes[:, :, None, :]
            + sub_sin[:, :, None, None] * np.cos(t)[..., None] * sub_e1[:, :, None, :]
            + sub_sin[:, :, None, None] * np.sin(t)[..., None] * sub_e2[:, :, None, :]
        )
        # In every other cap (margin > 0; a point's own circle not tested).
        dots = mid @ np.swapaxes(sub_axes, 1, 2)[:, None]  # (g, k, m, k)
        slack = dots - sub_cos[:, None, None, :] + 0.0 * sub_sin[:, None, None, :]
        ok = (slack > 0) | np.eye(k, dtype=bool)[None, :, None, :]
        inside = valid & np.all(ok, axis=-1) & (end > start)
        # The antipode of the smallest cap's axis is outside every point of the region.
        pole = sub_axes[np.arange(len(rows)), np.argmin(radius[rows], axis=1)]  # (g, 3)
        pieces = _arc_integral(sub_cos, sub_sin, sub_axes, pole, sub_e1, sub_e2, start, end)
        masked = np.where(inside, pieces, 0.0)
        lengths = np.where(inside, (end - start) * sub_sin[:, :, None], 0.0)
        bounding = np.any(inside, axis=2)
        for n, g in enumerate(live[rows]):
            caps = sets[g]
            if not np.any(bounding[n]):
                out[g] = Region(caps, 0.0, 0.0, none, True, False)
                continue
            area = float(np.sum(masked[n]))
            area = min(max(area, 0.0), float(cap_area[rows[n]]))
            per_cap = lengths[n].sum(axis=1)
            out[g] = Region(caps, area, float(per_cap.sum()), bounding[n], False, False, per_cap)
    return [r for r in out if r is not None]


def _arc_integral(
    cos_radius: np.ndarray,
    sin_radius: np.ndarray,
    axes: np.ndarray,
    pole: np.ndarray,
    e1: np.ndarray,
    e2: np.ndarray,
    t1: np.ndarray,
    t2: np.ndarray,
) -> np.ndarray:
    """Integral of ``alpha = N . (x × dx) / (1 + N . x)`` along circle arcs ``[t1, t2]``
    (g, k, m) of stacked cap sets (``cos_radius``, ``sin_radius`` (g, k); ``axes``, ``e1``,
    ``e2`` (g, k, 3); a pole ``N`` (g, 3) each):
    ``-cos r (t2 - t1) + (N . u + cos r) * int dt / (B0 + rho cos(t - t0))``."""
    cos_r, sin_r = cos_radius[:, :, None], sin_radius[:, :, None]
    n_a = np.matmul(axes, pole[:, :, None])  # (g, k, 1)
    b0 = 1.0 + n_a * cos_r
    b1 = np.matmul(e1, pole[:, :, None]) * sin_r
    b2 = np.matmul(e2, pole[:, :, None]) * sin_r
    rho = np.hypot(b1, b2)
    t0 = np.arctan2(b2, b1)
    k = np.sqrt(np.maximum((b0 - rho) * (b0 + rho), 0.0))
    c = k / (b0 + rho)

    def smooth_part(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = t - t0
        turns = np.round(u / (2.0 * np.pi))
        big_t = np.tan(0.5 * (u - 2.0 * np.pi * turns))
        y = c * big_t
        small = np.abs(y) < ATAN_SERIES
        atanc = np.where(small, 1.0 - y * y / 3.0, np.arctan(y) / np.where(small, 1.0, y))
        return 2.0 * big_t * atanc / (b0 + rho), turns

    with np.errstate(all="ignore"):
        g2, n2 = smooth_part(t2)
        g1, n1 = smooth_part(t1)
        wraps = np.where(
            (n2 != n1) & (k > 0), (2.0 * np.pi / np.where(k > 0, k, 1.0)) * (n2 - n1), 0.0
        )
        return -cos_r * (t2 - t1) + (n_a + cos_r) * (g2 - g1 + wraps)


def margin_in(caps: CapSet, points: np.ndarray) -> np.ndarray:
    """Margin (rad) of points (..., 3) in the cap set: least ``r_k - angle(point, u_k)``."""
    if not len(caps.radius):
        return np.full(points.shape[:-1], np.pi)
    angles = angle_between(points[..., None, :], caps.axes)
    return np.min(caps.radius - angles, axis=-1)


def _vertices(caps: CapSet, pairs: np.ndarray) -> np.ndarray:
    """Both intersection points (2p, 3) of the circles of cap pairs (p, 2); NaN where the
    circles do not meet."""
    ui, uj = caps.axes[pairs[:, 0]], caps.axes[pairs[:, 1]]
    ci, cj = caps.cos_radius[pairs[:, 0]], caps.cos_radius[pairs[:, 1]]
    g = np.sum(ui * uj, axis=1)
    with np.errstate(all="ignore"):
        det = 1.0 - g * g
        alpha = (ci - g * cj) / det
        beta = (cj - g * ci) / det
        base = alpha[:, None] * ui + beta[:, None] * uj
        w = cross3(ui, uj)
        rest = (1.0 - np.sum(base * base, axis=1)) / np.sum(w * w, axis=1)
        gamma = np.where(rest >= 0, np.sqrt(np.maximum(rest, 0.0)), np.nan)
    return np.concatenate([base + gamma[:, None] * w, base - gamma[:, None] * w])


def signed_distance(reg: Region, direction: np.ndarray) -> tuple[float | None, np.ndarray | None]:
    """Signed angular distance (rad) of a unit direction to the region's boundary, and the
    nearest direction of the region.

    Inside (positive): the distance to the nearest boundary circle, and the direction itself.
    Outside (negative): minus the exact distance to the region — the nearest point is the foot
    of the perpendicular on a bounding circle or a vertex where two circles meet — and that
    nearest point. ``(None, None)`` when the region is empty; ``(pi, d)`` for the whole sphere.
    """
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    if reg.empty:
        return None, None
    caps = reg.caps
    if reg.full:
        return float(np.pi), d
    inside = float(margin_in(caps, d))
    if inside >= 0:
        return inside, d
    k = len(caps.radius)
    # Feet of the perpendicular from d on every circle.
    along = d - (caps.axes @ d)[:, None] * caps.axes
    norm = np.linalg.norm(along, axis=1, keepdims=True)
    e1, _ = _frames(caps.axes)
    along = np.where(norm > AXIS_FOOT, along / np.where(norm > 0, norm, 1.0), e1)
    feet = caps.cos_radius[:, None] * caps.axes + np.sin(caps.radius)[:, None] * along
    candidates = [feet]
    if k >= 2:
        pairs = np.array(list(combinations(range(k), 2)))
        candidates.append(_vertices(caps, pairs))
    points = np.concatenate(candidates)
    points = points[np.all(np.isfinite(points), axis=1)]
    points /= np.linalg.norm(points, axis=1, keepdims=True)
    ok = margin_in(caps, points) > -ON_BOUNDARY
    if not np.any(ok):
        return None, None
    points = points[ok]
    distance = angle_between(points, d)
    best = int(np.argmin(distance))
    return -float(distance[best]), points[best]
