"""Least-squares fits of the simple surfaces a coupling's contacts are made of: plane, sphere,
cylinder, over the vertices of one smooth patch of a mesh (lengths in the mesh's unit).

Each fit returns a :class:`Primitive` with its RMS residual (the root mean square distance of
the points from the fitted surface). Spheres and cylinders start from an algebraic (linear)
fit and are refined geometrically with scipy's ``least_squares`` (imported lazily).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kcheck.numerics.thresholds import SMOOTH_PATCH_DEG, SURFACE_FIT_RTOL

#: Least squares run on at most this many of a patch's vertices (every k-th): a tessellated
#: ball of 40,000 vertices fits to rounding on a few thousand, in a fraction of the time.
MAX_FIT_POINTS = 2000

__all__ = ["Primitive", "fit_plane", "fit_sphere", "fit_cylinder", "fit_surface"]


@dataclass(frozen=True)
class Primitive:
    """A fitted surface: ``kind`` plane (``point``, unit ``axis`` = normal), sphere (``point``
    = centre, ``radius``) or cylinder (``point`` on the axis, unit ``axis``, ``radius``); ``rms``
    the fit's residual, ``size`` the patch's extent, ``outward`` +1 when the patch's face
    normals point away from the centre or axis (a ball, a pin), -1 towards it (a bore, a
    socket); for a plane its normal is the faces' outward one."""

    kind: str
    point: np.ndarray
    axis: np.ndarray
    radius: float
    rms: float
    size: float
    outward: float = 1.0


def fit_plane(points: np.ndarray, centres: np.ndarray, normals: np.ndarray) -> Primitive:
    """The least-squares plane through ``points`` (n, 3); its normal oriented as the mean of
    the faces' ``normals`` (faces at ``centres``)."""
    centre = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - centre, full_matrices=False)
    n = vt[-1]
    if n @ normals.mean(axis=0) < 0:
        n = -n
    rms = float(np.sqrt(np.mean(((points - centre) @ n) ** 2)))
    return Primitive("plane", centre, n, np.inf, rms, _size(points))


def fit_sphere(points: np.ndarray, centres: np.ndarray, normals: np.ndarray) -> Primitive:
    """The least-squares sphere through ``points``: |x|² = 2 c·x + k linearly, then the
    geometric distances ||x − c|| − r refined."""
    from scipy.optimize import least_squares

    a = np.column_stack([2 * points, np.ones(len(points))])
    b = np.einsum("ij,ij->i", points, points)
    sol = np.linalg.lstsq(a, b, rcond=None)[0]
    c0 = sol[:3]
    r0 = float(np.sqrt(max(sol[3] + c0 @ c0, 0.0)))

    def residual(p: np.ndarray) -> np.ndarray:
        return np.linalg.norm(points - p[:3], axis=1) - p[3]

    fit = least_squares(residual, np.append(c0, r0), method="lm", xtol=1e-15, ftol=1e-15)
    c, r = fit.x[:3], abs(float(fit.x[3]))
    rms = float(np.sqrt(np.mean(residual(np.append(c, r)) ** 2)))
    outward = 1.0 if np.mean(np.einsum("ij,ij->i", centres - c, normals)) >= 0 else -1.0
    return Primitive("sphere", c, np.zeros(3), r, rms, _size(points), outward)


def fit_cylinder(points: np.ndarray, centres: np.ndarray, normals: np.ndarray) -> Primitive:
    """The least-squares cylinder through ``points``: the axis first from the face
    ``normals`` (perpendicular to it), a circle fitted in the cross-section, then axis,
    point and radius refined on the geometric distances."""
    from scipy.optimize import least_squares

    _, _, vt = np.linalg.svd(normals, full_matrices=False)
    axis0 = vt[-1]
    e1 = vt[0]
    e2 = np.cross(axis0, e1)
    centre = points.mean(axis=0)
    uv = np.column_stack([(points - centre) @ e1, (points - centre) @ e2])
    a = np.column_stack([2 * uv, np.ones(len(uv))])
    b = np.einsum("ij,ij->i", uv, uv)
    sol = np.linalg.lstsq(a, b, rcond=None)[0]
    p0 = centre + sol[0] * e1 + sol[1] * e2
    r0 = float(np.sqrt(max(sol[2] + sol[:2] @ sol[:2], 0.0)))

    def geometry(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # The axis tilted by (p[0], p[1]) towards e1, e2; the point moved by (p[2], p[3]).
        axis = axis0 + p[0] * e1 + p[1] * e2
        axis = axis / np.linalg.norm(axis)
        return p0 + p[2] * e1 + p[3] * e2, axis

    def residual(p: np.ndarray) -> np.ndarray:
        point, axis = geometry(p)
        d = points - point
        radial = d - np.outer(d @ axis, axis)
        return np.linalg.norm(radial, axis=1) - p[4]

    fit = least_squares(residual, np.array([0, 0, 0, 0, r0]), method="lm", xtol=1e-15, ftol=1e-15)
    point, axis = geometry(fit.x)
    rms = float(np.sqrt(np.mean(residual(fit.x) ** 2)))
    d = centres - point
    radial = d - np.outer(d @ axis, axis)
    outward = 1.0 if np.mean(np.einsum("ij,ij->i", radial, normals)) >= 0 else -1.0
    # The point on the axis nearest the patch's centre, so that it is a meaningful place.
    point = point + ((centre - point) @ axis) * axis
    return Primitive("cylinder", point, axis, abs(float(fit.x[4])), rms, _size(points), outward)


def fit_surface(
    points: np.ndarray, centres: np.ndarray, normals: np.ndarray
) -> tuple[Primitive | None, list[Primitive]]:
    """The simplest of plane, sphere and cylinder that fits ``points`` within
    :data:`SURFACE_FIT_RTOL` of the patch's size (None if none does), and every fit tried;
    ``centres`` and ``normals`` are the patch's faces' (to orient the fit)."""
    # The fits run on at most MAX_FIT_POINTS points (every k-th), the checks on all.
    step = max(1, len(points) // MAX_FIT_POINTS)
    sub = points[::step]
    tried = []
    for fitter, least in ((fit_plane, 3), (fit_sphere, 5), (fit_cylinder, 6)):
        if len(sub) < least:
            break
        fit = fitter(sub, centres, normals)
        if step > 1:
            fit = _with_rms(fit, points)
        tried.append(fit)
        if fit.rms <= SURFACE_FIT_RTOL * fit.size and _normals_agree(fit, centres, normals):
            return fit, tried
    return None, tried


def _with_rms(fit: Primitive, points: np.ndarray) -> Primitive:
    """The fit with its RMS residual and size over all ``points``."""
    from dataclasses import replace

    d = points - fit.point
    if fit.kind == "plane":
        r = d @ fit.axis
    elif fit.kind == "sphere":
        r = np.linalg.norm(d, axis=1) - fit.radius
    else:
        r = np.linalg.norm(d - np.outer(d @ fit.axis, fit.axis), axis=1) - fit.radius
    return replace(fit, rms=float(np.sqrt(np.mean(r**2))), size=_size(points))


def _normals_agree(fit: Primitive, centres: np.ndarray, normals: np.ndarray) -> bool:
    """Whether every face normal is within :data:`SMOOTH_PATCH_DEG` of the fitted surface's
    normal below the face's centre: a tessellated pin's vertices lie on its two end circles,
    which also lie on a sphere; its faces' normals tell the two apart."""
    if fit.kind == "plane":
        expected = np.broadcast_to(fit.axis, normals.shape)
    else:
        d = centres - fit.point
        if fit.kind == "cylinder":
            d = d - np.outer(d @ fit.axis, fit.axis)
        expected = fit.outward * d / np.linalg.norm(d, axis=1)[:, None]
    cos = np.einsum("ij,ij->i", expected, normals)
    return bool(np.all(cos >= np.cos(np.radians(SMOOTH_PATCH_DEG))))


def _size(points: np.ndarray) -> float:
    return float(np.linalg.norm(np.ptp(points, axis=0)))
