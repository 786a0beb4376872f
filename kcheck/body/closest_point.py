"""The closest point of a triangle to a point, for many (triangle, point) pairs at once: the
method of Ericson, *Real-Time Collision Detection* (2005), §5.1.5 (ClosestPtPointTriangle),
vectorised as trimesh's ``triangles.closest_point`` does it (trimesh 4–5, MIT licence), step
for step, so that the answers are the same to the last bit without importing trimesh."""

from __future__ import annotations

import numpy as np

__all__ = ["closest_point"]

#: trimesh's ``tol.zero``: 100 times float64's decimal resolution, 1e-15 (the same float).
_ZERO = 1e-13


def closest_point(triangles: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The point of each triangle (n, 3, 3) closest to its point (n, 3), (n, 3)."""
    triangles = np.asarray(triangles, dtype=np.float64)
    points = np.asarray(points, dtype=np.float64)
    result = np.zeros_like(points)
    remain = np.ones(len(points), dtype=bool)
    ones = np.ones(3)
    a, b, c = triangles[:, 0, :], triangles[:, 1, :], triangles[:, 2, :]
    ab, ac, ap = b - a, c - a, points - a
    # np.dot against ones, not a sum, as trimesh adds (the same rounding).
    d1, d2 = np.dot(ab * ap, ones), np.dot(ac * ap, ones)
    is_a = (d1 < _ZERO) & (d2 < _ZERO)
    result[is_a] = a[is_a]
    remain[is_a] = False
    # A and B coincide: the triangle is the segment AC (or a point).
    collapsed = np.all(ab == 0.0, axis=1)
    if collapsed.any():
        segment = ac[collapsed]
        length2 = np.sum(segment**2, axis=1)
        factor = np.zeros(len(segment))
        np.divide(np.sum(ap[collapsed] * segment, axis=1), length2, out=factor, where=length2 > 0)
        result[collapsed] = a[collapsed] + np.clip(factor, 0, 1)[:, None] * segment
        remain[collapsed] = False
    bp = points - b
    d3, d4 = np.dot(ab * bp, ones), np.dot(ac * bp, ones)
    is_b = (d3 > -_ZERO) & (d4 <= d3) & remain
    result[is_b] = b[is_b]
    remain[is_b] = False
    vc = d1 * d4 - d3 * d2
    is_ab = (vc < _ZERO) & (d1 > -_ZERO) & (d3 < _ZERO) & remain
    if is_ab.any():
        v = (d1[is_ab] / (d1[is_ab] - d3[is_ab])).reshape((-1, 1))
        result[is_ab] = a[is_ab] + v * ab[is_ab]
        remain[is_ab] = False
    cp = points - c
    d5, d6 = np.dot(ab * cp, ones), np.dot(ac * cp, ones)
    is_c = (d6 > -_ZERO) & (d5 <= d6) & remain
    result[is_c] = c[is_c]
    remain[is_c] = False
    vb = d5 * d2 - d1 * d6
    is_ac = (vb < _ZERO) & (d2 > -_ZERO) & (d6 < _ZERO) & remain
    if is_ac.any():
        w = (d2[is_ac] / (d2[is_ac] - d6[is_ac])).reshape((-1, 1))
        result[is_ac] = a[is_ac] + w * ac[is_ac]
        remain[is_ac] = False
    va = d3 * d6 - d5 * d4
    is_bc = (va < _ZERO) & ((d4 - d3) > -_ZERO) & ((d5 - d6) > -_ZERO) & remain
    if is_bc.any():
        d43 = d4[is_bc] - d3[is_bc]
        w = (d43 / (d43 + (d5[is_bc] - d6[is_bc]))).reshape((-1, 1))
        result[is_bc] = b[is_bc] + w * (c[is_bc] - b[is_bc])
        remain[is_bc] = False
    if remain.any():
        denom = 1.0 / (va[remain] + vb[remain] + vc[remain])
        v = (vb[remain] * denom).reshape((-1, 1))
        w = (vc[remain] * denom).reshape((-1, 1))
        result[remain] = a[remain] + ab[remain] * v + ac[remain] * w
    return result
