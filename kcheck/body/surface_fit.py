"""Least-squares fits of the simple surfaces a coupling's contacts are made of: plane, sphere,
cylinder, cone, torus, over the vertices of one smooth patch of a mesh (lengths in the mesh's
unit).

Each fit returns a :class:`Primitive` with its RMS residual (the root mean square distance of
the points from the fitted surface). Spheres, cylinders, cones and tori start from a linear
estimate (a cone's tangent planes all pass through its apex; a torus's points moved along
their normals by the tube radius lie on a circle) and are refined geometrically with scipy's
``least_squares`` (imported lazily).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from kcheck.numerics.thresholds import SMOOTH_PATCH_DEG, SURFACE_FIT_RTOL
from kcheck.records import dataclass

#: Least squares run on at most this many of a patch's vertices (every k-th): a tessellated
#: ball of 40,000 vertices fits to rounding on a few thousand, in a fraction of the time.
MAX_FIT_POINTS = 2000

__all__ = [
    "Primitive",
    "fit_plane",
    "fit_sphere",
    "fit_cylinder",
    "fit_cone",
    "fit_torus",
    "fit_surface",
    "residuals",
]


@dataclass(frozen=True)
class Primitive:
    """A fitted surface: ``kind`` plane (``point``, unit ``axis`` = normal), sphere (``point``
    = centre, ``radius``), cylinder (``point`` on the axis, unit ``axis``, ``radius``), cone
    (``point`` its apex, unit ``axis`` from the apex into the patch, ``half_angle`` between
    generator and axis in rad) or torus (``point`` its centre, unit ``axis``, ``radius`` the
    tube circle's, ``tube`` the tube's); ``rms`` the fit's residual, ``size`` the patch's
    extent, ``outward`` +1 when the patch's face normals point away from the centre, axis or
    tube circle (a ball, a pin, a canoe ball), -1 towards it (a bore, a socket, a
    countersink); for a plane its normal is the faces' outward one."""

    kind: str
    point: np.ndarray
    axis: np.ndarray
    radius: float
    rms: float
    size: float
    outward: float = 1.0
    half_angle: float = 0.0
    tube: float = 0.0


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


def _tilted(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors perpendicular to ``axis`` and to each other."""
    e1 = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 = e1 / np.linalg.norm(e1)
    return e1, np.cross(axis, e1)


def _cone_distance(points: np.ndarray, apex: np.ndarray, axis: np.ndarray, half: float):
    d = points - apex
    h = d @ axis
    rho = np.linalg.norm(d - np.outer(h, axis), axis=1)
    return rho * np.cos(half) - h * np.sin(half)


def fit_cone(points: np.ndarray, centres: np.ndarray, normals: np.ndarray) -> Primitive:
    """The least-squares cone through ``points``: the axis first from the face ``normals``
    (at one angle to it: on a circle of directions), the apex where the faces' planes meet,
    then apex, axis and half-angle refined on the distances from the surface."""
    from scipy.optimize import least_squares

    _, _, vt = np.linalg.svd(normals - normals.mean(axis=0), full_matrices=False)
    axis0 = vt[-1]
    apex0 = np.linalg.lstsq(normals, np.einsum("ij,ij->i", normals, centres), rcond=None)[0]
    if np.mean((points - apex0) @ axis0) < 0:
        axis0 = -axis0
    d = points - apex0
    h = d @ axis0
    half0 = float(np.arctan2(np.mean(np.linalg.norm(d - np.outer(h, axis0), axis=1)), h.mean()))
    e1, e2 = _tilted(axis0)

    def geometry(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        axis = axis0 + p[3] * e1 + p[4] * e2
        return apex0 + p[:3], axis / np.linalg.norm(axis)

    def residual(p: np.ndarray) -> np.ndarray:
        apex, axis = geometry(p)
        return _cone_distance(points, apex, axis, p[5])

    fit = least_squares(residual, np.array([0, 0, 0, 0, 0, half0]), method="lm", xtol=1e-15)
    apex, axis = geometry(fit.x)
    rms = float(np.sqrt(np.mean(residual(fit.x) ** 2)))
    d = centres - apex
    radial = d - np.outer(d @ axis, axis)
    outward = 1.0 if np.mean(np.einsum("ij,ij->i", radial, normals)) >= 0 else -1.0
    prim = Primitive("cone", apex, axis, np.inf, rms, _size(points), outward)
    return replace(prim, half_angle=float(fit.x[5]))


def _torus_distance(
    points: np.ndarray, centre: np.ndarray, axis: np.ndarray, radius: float, tube: float
) -> np.ndarray:
    d = points - centre
    h = d @ axis
    rho = np.linalg.norm(d - np.outer(h, axis), axis=1)
    return np.hypot(rho - radius, h) - tube


def _circle(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The least-squares circle through points ``q`` (n, 3): centre, plane normal, radius,
    RMS distance of the points from it (algebraic fit in their best plane)."""
    mean = q.mean(axis=0)
    _, _, vt = np.linalg.svd(q - mean, full_matrices=False)
    e1, e2, n = vt
    uv = np.column_stack([(q - mean) @ e1, (q - mean) @ e2])
    a = np.column_stack([2 * uv, np.ones(len(uv))])
    sol = np.linalg.lstsq(a, np.einsum("ij,ij->i", uv, uv), rcond=None)[0]
    centre = mean + sol[0] * e1 + sol[1] * e2
    radius = float(np.sqrt(max(sol[2] + sol[:2] @ sol[:2], 0.0)))
    d = q - centre
    off = d @ n
    rho = np.linalg.norm(d - np.outer(off, n), axis=1)
    return centre, n, radius, float(np.sqrt(np.mean((rho - radius) ** 2 + off**2)))


def fit_torus(points: np.ndarray, centres: np.ndarray, normals: np.ndarray) -> Primitive:
    """The least-squares torus through ``points``: the tube radius first as the distance
    along the face ``normals`` that puts the face centres best on one circle (the tube's
    centre circle), then centre, axis and both radii refined on the distances from the
    surface. A patch on the outside of the tube (a canoe ball) has ``outward`` +1."""
    from scipy.optimize import least_squares, minimize_scalar

    size = _size(points)
    if size == 0:
        return Primitive("torus", points.mean(axis=0), np.zeros(3), 0.0, np.inf, 0.0)

    def spread(t: float) -> float:
        return _circle(centres - t * normals)[3]

    # Tube radii from a hundredth to a hundred patch sizes, either side of the surface.
    trials = np.concatenate([-np.geomspace(1e-2, 1e2, 25), np.geomspace(1e-2, 1e2, 25)]) * size
    cost = [spread(t) for t in trials]
    k = int(np.argmin(cost))
    lo, hi = trials[max(k - 1, 0)], trials[min(k + 1, len(trials) - 1)]
    t0 = float(minimize_scalar(spread, bounds=(min(lo, hi), max(lo, hi)), method="bounded").x)
    c0, axis0, r0, _ = _circle(centres - t0 * normals)
    e1, e2 = _tilted(axis0)

    def geometry(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        axis = axis0 + p[3] * e1 + p[4] * e2
        return c0 + p[:3], axis / np.linalg.norm(axis)

    def residual(p: np.ndarray) -> np.ndarray:
        centre, axis = geometry(p)
        return _torus_distance(points, centre, axis, p[5], p[6])

    start = np.array([0, 0, 0, 0, 0, r0, abs(t0)])
    fit = least_squares(residual, start, method="lm", xtol=1e-15)
    centre, axis = geometry(fit.x)
    rms = float(np.sqrt(np.mean(residual(fit.x) ** 2)))
    # Outward: the face normals point away from the tube's centre circle.
    d = centres - centre
    h = d @ axis
    radial = d - np.outer(h, axis)
    ring = centre + fit.x[5] * radial / np.linalg.norm(radial, axis=1)[:, None]
    outward = 1.0 if np.mean(np.einsum("ij,ij->i", centres - ring, normals)) >= 0 else -1.0
    prim = Primitive("torus", centre, axis, abs(float(fit.x[5])), rms, size, outward)
    return replace(prim, tube=abs(float(fit.x[6])))


def fit_surface(
    points: np.ndarray, centres: np.ndarray, normals: np.ndarray, facet_deg: float | None = None
) -> tuple[Primitive | None, list[Primitive]]:
    """The simplest of plane, sphere, cylinder, cone and torus that fits ``points`` within
    :data:`SURFACE_FIT_RTOL` of the patch's size, with every face normal within
    ``facet_deg`` (the largest angle between neighbouring faces of the patch, + 0.5 deg;
    default :data:`SMOOTH_PATCH_DEG`) of the fitted surface's normal (None if none does), and
    every fit tried; ``centres`` and ``normals`` are the patch's faces' (to orient the fit).

    The normals decide when the vertices alone cannot: a band of faces between two circles
    (a countersink, a short pin) has all its vertices on a sphere too."""
    # The fits run on at most MAX_FIT_POINTS points (every k-th), the checks on all.
    step = max(1, len(points) // MAX_FIT_POINTS)
    sub = points[::step]
    every = max(1, len(centres) // MAX_FIT_POINTS)
    tolerance = SMOOTH_PATCH_DEG if facet_deg is None else facet_deg + 0.5
    tried = []
    fitters = ((fit_plane, 3), (fit_sphere, 5), (fit_cylinder, 6), (fit_cone, 7), (fit_torus, 8))
    for fitter, least in fitters:
        if len(sub) < least:
            break
        fit = fitter(sub, centres[::every], normals[::every])
        if step > 1:
            fit = _with_rms(fit, points)
        tried.append(fit)
        if fit.rms <= SURFACE_FIT_RTOL * fit.size and _normals_agree(
            fit, centres, normals, tolerance
        ):
            return fit, tried
    return None, tried


def residuals(fit: Primitive, points: np.ndarray) -> np.ndarray:
    """The signed distance of each of ``points`` (n, 3, m) from the fitted surface (m)."""
    d = points - fit.point
    if fit.kind == "plane":
        return np.asarray(d @ fit.axis)
    if fit.kind == "sphere":
        return np.asarray(np.linalg.norm(d, axis=1) - fit.radius)
    if fit.kind == "cone":
        return np.asarray(_cone_distance(points, fit.point, fit.axis, fit.half_angle))
    if fit.kind == "torus":
        return np.asarray(_torus_distance(points, fit.point, fit.axis, fit.radius, fit.tube))
    return np.asarray(np.linalg.norm(d - np.outer(d @ fit.axis, fit.axis), axis=1) - fit.radius)


def _with_rms(fit: Primitive, points: np.ndarray) -> Primitive:
    """The fit with its RMS residual and size over all ``points``."""
    r = residuals(fit, points)
    return replace(fit, rms=float(np.sqrt(np.mean(r**2))), size=_size(points))


def _normals_agree(
    fit: Primitive, centres: np.ndarray, normals: np.ndarray, tolerance_deg: float
) -> bool:
    """Whether every face normal is within ``tolerance_deg`` of the fitted surface's normal
    below the face's centre: a tessellated pin's vertices lie on its two end circles, which
    also lie on a sphere; its faces' normals tell the two apart."""
    if fit.kind == "plane":
        expected = np.broadcast_to(fit.axis, normals.shape)
    else:
        d = centres - fit.point
        if fit.kind in ("cylinder", "cone", "torus"):
            radial = d - np.outer(d @ fit.axis, fit.axis)
            radial = radial / np.linalg.norm(radial, axis=1)[:, None]
            if fit.kind == "cylinder":
                d = radial
            elif fit.kind == "cone":
                d = np.cos(fit.half_angle) * radial - np.sin(fit.half_angle) * fit.axis
            else:
                d = centres - (fit.point + fit.radius * radial)
        expected = fit.outward * d / np.linalg.norm(d, axis=1)[:, None]
    cos = np.einsum("ij,ij->i", expected, normals)
    return bool(np.all(cos >= np.cos(np.radians(tolerance_deg))))


def _size(points: np.ndarray) -> float:
    return float(np.linalg.norm(np.ptp(points, axis=0)))
