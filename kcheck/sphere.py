"""Safe force directions on the unit sphere: the intersection of spherical caps.

Within the forward friction assumption every unknown of a retracted case is affine in the unit
force direction ``d`` (methods.md §4): ``x_k(d) = a_k + c_k . d``, positive on a spherical cap
about ``c_k / |c_k|`` of angular radius ``arccos(-a_k / |c_k|)``. The directions that are safe
for every retracted case form the intersection of all caps. The angular margin of a direction
(its distance to the nearest cap boundary, :func:`kcheck.arcs.cap_margins`) is exact; the area
of the intersection is a quadrature over a Fibonacci sphere.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kcheck.arcs import cap_geometry, cap_margins

__all__ = [
    "GOLDEN_ANGLE",
    "fibonacci_sphere",
    "grid_spacing",
    "SafeFraction",
    "safe_fraction",
    "cap_fraction",
    "most_robust_direction",
    "to_lon_lat",
    "from_lon_lat",
]

GOLDEN_ANGLE = float(np.pi * (3.0 - np.sqrt(5.0)))


def fibonacci_sphere(n: int) -> np.ndarray:
    """``n`` nearly uniform unit vectors (n, 3), each the centre of a cell of area 4 pi / n."""
    if n < 1:
        raise ValueError(f"need at least one point, got {n}")
    k = np.arange(n, dtype=float)
    z = 1.0 - (2.0 * k + 1.0) / n  # cell centres of equal-area bands
    rho = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = GOLDEN_ANGLE * k
    return np.column_stack([rho * np.cos(phi), rho * np.sin(phi), z])


def grid_spacing(n: int) -> float:
    """Typical distance (rad) between neighbouring points of an ``n``-point Fibonacci sphere."""
    return float(np.sqrt(4.0 * np.pi / n))


@dataclass(frozen=True)
class SafeFraction:
    """Fraction of the sphere inside every cap, with an error estimate (both in [0, 1])."""

    fraction: float
    error: float
    points: int


def safe_fraction(
    a: np.ndarray, c: np.ndarray, n: int = 20000, *, margins: np.ndarray | None = None
) -> SafeFraction:
    """Fraction of all directions inside every cap ``a_k + c_k . d > 0``.

    Each of ``n`` Fibonacci points is classified exactly; only the cells cut by a boundary are
    uncertain. The error estimate is half the fraction of points within one grid spacing of a
    boundary: a band one spacing wide about the boundary, the area of the cut cells.
    ``margins`` (n,): the margins of the ``n`` Fibonacci points when already computed.
    """
    if margins is None:
        margins = cap_margins(a, c, fibonacci_sphere(n))
    h = grid_spacing(n)
    inside = np.count_nonzero(margins > 0)
    near = np.count_nonzero(np.abs(margins) < h)
    return SafeFraction(inside / n, 0.5 * near / n, n)


def cap_fraction(a: float, c: np.ndarray) -> float:
    """Exact fraction of the sphere where ``a + c . d > 0`` (one cap): ``(1 - cos r) / 2``."""
    r = float(np.linalg.norm(c))
    if r == 0.0:
        return 1.0 if a > 0 else 0.0
    cos_radius = float(np.clip(-a / r, -1.0, 1.0))
    return 0.5 * (1.0 - cos_radius)


def _refine(a: np.ndarray, c: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Maximise the smallest cap margin from ``start`` (SLSQP on the epigraph form).

    maximise t subject to ``d . u_k >= cos(r_k - t)`` and ``|d| = 1``: smooth, unlike the
    margin itself (a minimum of arccos terms).
    """
    from scipy.optimize import minimize

    ratio, axes, radius = cap_geometry(a, c)
    live = (ratio > -1.0) & (ratio < 1.0)
    if not np.any(live):
        return start
    axes, radius = axes[live], radius[live]
    t0 = float(cap_margins(a, c, start[None])[0])
    x0 = np.append(start, t0)

    def constraints(x: np.ndarray) -> np.ndarray:
        # Cap the angle at pi so cos stays monotone where the optimiser wanders.
        return axes @ x[:3] - np.cos(np.clip(radius - x[3], 0.0, np.pi))

    result = minimize(
        lambda x: -x[3],
        x0,
        jac=lambda x: np.array([0.0, 0.0, 0.0, -1.0]),
        method="SLSQP",
        # The margin cannot exceed the smallest radius; beyond it cos(r - t) is not monotone.
        bounds=[(-1.5, 1.5)] * 3 + [(t0, float(radius.min()))],
        constraints=[
            {"type": "ineq", "fun": constraints},
            {"type": "eq", "fun": lambda x: x[:3] @ x[:3] - 1.0},
        ],
        options={"ftol": 1e-12, "maxiter": 200},
    )
    d = result.x[:3]
    norm = float(np.linalg.norm(d))
    return start if not np.all(np.isfinite(d)) or norm == 0 else d / norm


def most_robust_direction(
    a: np.ndarray, c: np.ndarray, n: int = 20000, *, margins: np.ndarray | None = None
) -> tuple[np.ndarray, float]:
    """Direction deepest inside every cap and its margin (rad): grid argmax, then refined.

    The refined point replaces the grid's best only if its exact margin is larger, so the
    result is never worse than the grid's (within one grid spacing of the optimum).
    ``margins`` (n,): the margins of the ``n`` Fibonacci points when already computed.
    """
    points = fibonacci_sphere(n)
    if margins is None:
        margins = cap_margins(a, c, points)
    best = points[int(np.argmax(margins))]
    best_margin = float(margins.max())
    if best_margin > 0:
        refined = _refine(a, c, best)
        refined_margin = float(cap_margins(a, c, refined[None])[0])
        if refined_margin > best_margin:
            best, best_margin = refined, refined_margin
    return best, best_margin


def to_lon_lat(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth from +x in (-pi, pi] and elevation from the xy-plane (rad) of unit vectors."""
    d = np.asarray(directions, float)
    return np.arctan2(d[..., 1], d[..., 0]), np.arcsin(np.clip(d[..., 2], -1.0, 1.0))


def from_lon_lat(lon: np.ndarray, lat: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 3) from azimuth and elevation (rad)."""
    lon, lat = np.broadcast_arrays(np.asarray(lon, float), np.asarray(lat, float))
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], -1)
