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

from dataclasses import dataclass

import numpy as np

__all__ = [
    "Frame",
    "FreeTwist",
    "moment",
    "wrenches",
    "point_velocity",
    "layout_singular_values",
    "free_twist",
    "maxwell_cos",
]

# Singular values below this fraction of the largest count as zero (rank decisions).
RANK_RTOL = 1e-10


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
        origin = points.mean(axis=0)
        length = float(np.linalg.norm(points - origin, axis=1).max())
        if not length > 0:
            length = 1.0
        return cls(origin, length, force, dim)


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


def moment(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Moment ``p x f`` about the origin: (..., 1) in 2D, (..., 3) in 3D."""
    if points.shape[-1] == 2:
        return _cross2(points, forces)[..., None]
    return np.cross(points, forces)


def wrenches(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Wrenches ``(p x f, f)`` of forces at points: (..., 3) in 2D, (..., 6) in 3D.

    With unit normals these are the constraint rows: ``wrenches(p, n) @ xi = n . u(p)``.
    """
    points, forces = np.broadcast_arrays(points, forces)
    return np.concatenate([moment(points, forces), forces], axis=-1)


def point_velocity(twist: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Velocity ``u(p) = v + w x p`` of body points (..., dim) under a twist (3 or 6,)."""
    dim = points.shape[-1]
    nw = 1 if dim == 2 else 3
    w, v = twist[..., :nw], twist[..., nw:]
    if dim == 2:
        return v + w * np.stack([-points[..., 1], points[..., 0]], axis=-1)
    return v + np.cross(w, points)


def layout_singular_values(points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Singular values (descending) of the full constraint matrix; rank = determinacy."""
    return np.linalg.svd(wrenches(points, normals), compute_uv=False)


def free_twist(points: np.ndarray, normals: np.ndarray, retracted: int) -> FreeTwist:
    """Free twist of the supports other than ``retracted``, oriented to close its gap.

    The null space of the remaining rows, from the SVD (methods.md §2). A pole at infinity
    (parallel normals) is a twist with ``w = 0`` and needs no special case.
    """
    keep = np.arange(len(points)) != retracted
    rows = wrenches(points[keep], normals[keep])
    _, s, vt = np.linalg.svd(rows)
    twist = vt[-1]
    determinacy = float(s[-1] / s[0]) if s[0] > 0 else 0.0
    gap_rate = float(normals[retracted] @ point_velocity(twist, points[retracted]))
    if gap_rate > 0:
        twist, gap_rate = -twist, -gap_rate
    return FreeTwist(twist, determinacy, -gap_rate)


def maxwell_cos(free: FreeTwist, point: np.ndarray, normal: np.ndarray) -> float:
    """Maxwell's measure: cos of the angle between the free motion of a contact and its normal."""
    u = point_velocity(free.twist, point)
    speed = float(np.linalg.norm(u))
    if speed == 0.0:
        return float("nan")
    return abs(float(normal @ u)) / speed
