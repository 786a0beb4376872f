"""Twist kinematics of point-supported rigid bodies, one implementation for 2D and 3D.

A small rigid motion is a twist ``xi = (w, v)``: angular velocity ``w`` (1 component in 2D,
3 in 3D) and the velocity ``v`` of the body point at the origin. Support ``j`` keeps contact
while ``n_j . u(p_j) = 0``, i.e. ``[p_j x n_j, n_j] . xi = 0`` (methods.md §2). The row is
also the wrench of a unit normal force, so the same function builds constraint rows and
contact wrenches.

Everything here works on nondimensional arrays (see :class:`Frame`): positions divided by a
characteristic length, so twists are unit vectors whose rotational and translational parts are
commensurate and singular values do not depend on mm versus m.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from kcheck.numerics.thresholds import RANK_RTOL as RANK_RTOL  # re-exported
from kcheck.records import dataclass

__all__ = [
    "Frame",
    "unit_rows",
    "row_norms",
    "norm3",
    "unit3",
    "FreeTwist",
    "moment",
    "wrenches",
    "point_velocity",
    "layout_singular_values",
    "free_twist",
    "free_twists",
    "free_twist_arrays",
    "cross3",
    "other_supports",
    "maxwell_cos",
    "maxwell_angle",
]

_FLOAT = np.dtype(np.float64)


def row_norms(vectors: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of ``vectors`` (..., n) without overflow or underflow.

    Each row is divided by its largest magnitude before squaring, so a component of 1e300 or
    1e-300 gives its norm instead of ``inf`` or 0.
    """
    v = np.asarray(vectors, dtype=float)
    if v.ndim == 1 and 0 < len(v) <= 3:
        # One finite vector of 1-3 parts (most calls of a planar scene): norm3, a numpy float.
        values = v.tolist()
        if all(map(math.isfinite, values)):
            return np.float64(norm3(values))
    big = np.abs(v).max(axis=-1, keepdims=True)
    safe = np.where(big > 0, big, 1.0)
    return np.sqrt(np.sum((v / safe) ** 2, axis=-1)) * big[..., 0]


def unit_rows(vectors: np.ndarray) -> np.ndarray:
    """Rows scaled to unit length (overflow-safe, see :func:`row_norms`); zero rows stay zero."""
    v = np.asarray(vectors, dtype=float)
    big = np.abs(v).max(axis=-1, keepdims=True)
    scaled = v / np.where(big > 0, big, 1.0)
    norm = np.sqrt(np.sum(scaled * scaled, axis=-1, keepdims=True))
    return scaled / np.where(norm > 0, norm, 1.0)


def norm3(values: Sequence[float]) -> float:
    """:func:`row_norms` of one finite vector of 1-3 parts in plain float arithmetic, the same
    bits (numpy adds a row's squares left to right; adding the first to 0.0 changes no bit);
    for one vector numpy's per-call overhead is most of the time."""
    big = max(map(abs, values))
    safe = big if big > 0 else 1.0
    total = 0.0
    for x in values:
        x /= safe
        total += x * x
    return math.sqrt(total) * big


def unit3(values: list[float]) -> list[float]:
    """:func:`unit_rows` of one 3-vector in plain float arithmetic, the same bits."""
    big = max(abs(x) for x in values)
    safe = big if big > 0 else 1.0
    scaled = [x / safe for x in values]
    a, b, c = scaled
    norm = math.sqrt(a * a + b * b + c * c)
    safe = norm if norm > 0 else 1.0
    return [x / safe for x in scaled]


@dataclass(frozen=True)
class Frame:
    """Nondimensionalisation: ``x~ = (x - origin) / length``; forces divided by ``force``."""

    origin: np.ndarray
    length: float
    force: float
    dim: int

    def point(self, x: np.ndarray) -> np.ndarray:
        """Nondimensional in-plane/space coordinates (..., dim) of points (..., 3) in m."""
        return ((np.asarray(x) - self.origin) / self.length)[..., : self.dim]

    def vector(self, x: np.ndarray) -> np.ndarray:
        """Components (..., dim) of free vectors (..., 3), unscaled."""
        return np.asarray(x)[..., : self.dim]

    @classmethod
    def for_points(cls, points: np.ndarray, dim: int, force: float) -> Frame:
        """Frame centred on the support centroid, length = largest distance from it."""
        points = np.asarray(points, dtype=float)
        # Numpy's order is a C-ordered array's (it adds a column-major one's rows otherwise).
        if points.ndim == 2 and 0 < len(points) <= FEW_POINTS and points.flags.c_contiguous:
            plain = _plain_frame(points.tolist())
            if plain is not None:
                return cls(np.array(plain[0]), plain[1], force, dim)
        big = float(np.abs(points).max()) if points.size else 0.0
        scale = big if big > 0 and np.isfinite(big) else 1.0
        origin = (points / scale).mean(axis=0) * scale
        length = float(row_norms(points - origin).max()) if len(points) else 0.0
        if not (length > 0 and np.isfinite(length)):
            length = 1.0
        return cls(origin, length, force, dim)


#: Up to this many points :meth:`Frame.for_points` works in Python floats (a scene's supports).
FEW_POINTS = 12


def _plain_frame(rows: list[list[float]]) -> tuple[list[float], float] | None:
    """:meth:`Frame.for_points`' origin and length of a few finite points, in Python floats:
    numpy's operations in its order (the mean adds the rows in turn, then divides by their
    count; :func:`row_norms` of each offset); None for a non-finite or empty coordinate
    (numpy decides those)."""
    flat = [x for row in rows for x in row]
    if not flat or not all(map(math.isfinite, flat)):
        return None
    big = max(map(abs, flat))
    scale = big if big > 0 else 1.0
    count = len(rows)
    sums = [x / scale for x in rows[0]]
    for row in rows[1:]:
        sums = [s + x / scale for s, x in zip(sums, row, strict=True)]
    origin = [s / count * scale for s in sums]
    length = 0.0
    for row in rows:
        length = max(length, norm3([x - o for x, o in zip(row, origin, strict=True)]))
    if not (length > 0 and math.isfinite(length)):
        length = 1.0
    return origin, length


@dataclass(frozen=True)
class FreeTwist:
    """The motion left free when one support is removed.

    ``twist`` is a unit vector oriented to close the gap; ``determinacy`` is the smallest
    singular value of the remaining rows over the largest (0: more than one free motion);
    ``closing`` is ``-n_r . u(p_r)`` (0: removing the support frees nothing that closes it).
    """

    twist: np.ndarray
    determinacy: float
    closing: float


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product of 3-vectors (..., 3), broadcasting; ``np.cross`` without its overhead."""
    if a.shape == (3,) == b.shape and a.dtype == _FLOAT == b.dtype:
        # Two float 3-vectors (most calls of a planar scene): the same products and
        # differences in Python floats (IEEE doubles, as numpy's), no array arithmetic.
        x0, x1, x2 = a.tolist()
        y0, y1, y2 = b.tolist()
        return np.array([x1 * y2 - x2 * y1, x2 * y0 - x0 * y2, x0 * y1 - x1 * y0])
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape), np.result_type(a, b, float))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def moment(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Moment ``p x f`` about the origin: (..., 1) in 2D, (..., 3) in 3D."""
    if points.shape[-1] == 2:
        return _cross2(points, forces)[..., None]
    return cross3(points, forces)


def wrenches(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Wrenches ``(p x f, f)`` of forces at points: (..., 3) in 2D, (..., 6) in 3D.

    With unit normals these are the constraint rows: ``wrenches(p, n) @ xi = n . u(p)``.
    """
    m = moment(points, forces)
    if forces.shape[:-1] != m.shape[:-1]:  # only then broadcast (its call is most of the cost)
        forces = np.broadcast_to(forces, m.shape[:-1] + forces.shape[-1:])
    return np.concatenate([m, forces], axis=-1)


def point_velocity(twist: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Velocity ``u(p) = v + w x p`` of body points (..., dim) under a twist (3 or 6,)."""
    dim = points.shape[-1]
    nw = 1 if dim == 2 else 3
    w, v = twist[..., :nw], twist[..., nw:]
    if dim == 2:
        # np.stack([-y, x], axis=-1) filled in place (thousands of calls a planar scene)
        perp = np.empty(points.shape, points.dtype)
        np.negative(points[..., 1], out=perp[..., 0])
        perp[..., 1] = points[..., 0]
        return v + w * perp
    return v + cross3(w, points)


def layout_singular_values(points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Singular values (descending) of the full constraint matrix; rank = determinacy.

    All zeros when the SVD does not converge (only on non-finite input): "not determined".
    """
    rows = wrenches(points, normals)
    try:
        return np.linalg.svd(rows, compute_uv=False)
    except np.linalg.LinAlgError:
        return np.zeros(min(rows.shape))


@functools.cache
def other_supports(k: int) -> np.ndarray:
    """Row ``r``: the indices of ``k`` supports other than ``r`` (k, k - 1), read-only."""
    out = np.array([np.flatnonzero(np.arange(k) != r) for r in range(k)], dtype=int)
    out = out.reshape(k, max(k - 1, 0))
    out.setflags(write=False)
    return out


def free_twist_arrays(
    points: np.ndarray, normals: np.ndarray, retracted: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`free_twists` as arrays, for layouts with any leading axes (e.g. samples):
    points and normals (..., k, dim) give twists (..., c, n), determinacy (..., c) and closing
    rate (..., c) for the ``c`` retracted supports (default every one)."""
    k = points.shape[-2]
    which = np.arange(k) if retracted is None else np.asarray(retracted, dtype=int)
    rows = wrenches(points, normals)  # (..., k, n)
    keep = other_supports(k)[which]
    try:
        _, s, vt = np.linalg.svd(rows[..., keep, :])
    except np.linalg.LinAlgError:  # only on non-finite input: no free motion to speak of
        shape = rows.shape[:-2] + (len(which),)
        return np.zeros(shape + rows.shape[-1:]), np.zeros(shape), np.zeros(shape)
    twist = vt[..., -1, :]
    gap_rate = np.sum(rows[..., which, :] * twist, axis=-1)  # n_r . u(p_r)
    sign = np.where(gap_rate > 0, -1.0, 1.0)
    top = s[..., 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        determinacy = np.where(top > 0, s[..., -1] / np.where(top > 0, top, 1.0), 0.0)
    return sign[..., None] * twist, determinacy, -sign * gap_rate


def free_twists(
    points: np.ndarray, normals: np.ndarray, retracted: np.ndarray | None = None
) -> list[FreeTwist]:
    """Free twists of the supports other than each ``retracted`` one (default: every support),
    oriented to close its gap, all from one batched SVD.

    The null space of the remaining rows (methods.md §2). A pole at infinity (parallel normals)
    is a twist with ``w = 0`` and needs no special case.
    """
    twist, determinacy, closing = free_twist_arrays(points, normals, retracted)
    return [
        FreeTwist(t, float(d), float(c))
        for t, d, c in zip(twist, determinacy, closing, strict=True)
    ]


def free_twist(points: np.ndarray, normals: np.ndarray, retracted: int) -> FreeTwist:
    """Free twist of the supports other than ``retracted``, oriented to close its gap
    (:func:`free_twists` for one support).

    The last few answers are kept (the twist read-only): the planar checks (maxwell, the
    friction-pole construction, jamming) each ask for every case's twist of the same
    supports; the answer is a pure function of the arguments' bits."""
    key: tuple[Any, ...] = (points.tobytes(), normals.tobytes(), int(retracted))
    key += (points.shape, normals.shape, points.dtype.str, normals.dtype.str)
    known = _RECENT_TWISTS.get(key)
    if known is None:
        known = free_twists(points, normals, np.array([retracted]))[0]
        known.twist.setflags(write=False)
        if len(_RECENT_TWISTS) >= RECENT_TWISTS:
            del _RECENT_TWISTS[next(iter(_RECENT_TWISTS))]
        _RECENT_TWISTS[key] = known
    return known


#: Free twists recently computed (:func:`free_twist`), oldest first.
_RECENT_TWISTS: dict[tuple[Any, ...], FreeTwist] = {}
RECENT_TWISTS = 32


def maxwell_cos(free: FreeTwist, point: np.ndarray, normal: np.ndarray) -> float:
    """Maxwell's measure: cos of the angle between the free motion of a contact and its normal."""
    u = point_velocity(free.twist, point)
    speed = float(np.linalg.norm(u))
    if speed == 0.0:
        return float("nan")
    return abs(float(normal @ u)) / speed


def maxwell_angle(free: FreeTwist, point: np.ndarray, normal: np.ndarray) -> float:
    """The angle (rad, in [0, pi/2]) between the free motion of a contact and its normal line,
    from the normal and tangential speeds (accurate near 0, unlike ``arccos`` of the cosine)."""
    u = point_velocity(free.twist, point)
    along = abs(float(normal @ u))
    across = float(np.linalg.norm(u - (normal @ u) * normal))
    if along == 0.0 and across == 0.0:
        return float("nan")
    return float(np.arctan2(across, along))
