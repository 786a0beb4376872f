"""Directions on the unit sphere: the Fibonacci lattice, and the safe share counted on it.

Within the forward friction assumption every unknown of a retracted case is affine in the unit
force direction ``d`` (methods.md §4): ``x_k(d) = a_k + c_k . d``, positive on a spherical cap.
The safe directions are the intersection of the caps. :mod:`kcheck.mechanics.caps` computes its
area, distances and deepest point exactly; this module counts the same region on a Fibonacci
lattice, in chunks so memory stays bounded at any number of directions. The count is reported beside
the exact share when a check is asked for lattice points (``lattice_points``), seeds the deepest
point's active set (:mod:`kcheck.mechanics.deepest`), and is the tests' independent check of
the closed forms.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from kcheck.mechanics.arcs import cap_margins
from kcheck.records import dataclass

__all__ = [
    "GOLDEN_ANGLE",
    "CHUNK",
    "fibonacci_sphere",
    "fibonacci_chunks",
    "grid_spacing",
    "SafeFraction",
    "safe_fraction",
    "lattice_best",
    "cap_fraction",
    "to_lon_lat",
    "from_lon_lat",
]

GOLDEN_ANGLE = float(np.pi * (3.0 - np.sqrt(5.0)))
# Directions evaluated at once: 2^16 x 48 caps x 8 bytes is about 25 MiB per temporary.
CHUNK = 1 << 16


def fibonacci_sphere(n: int, start: int = 0, stop: int | None = None) -> np.ndarray:
    """Points ``start .. stop - 1`` (default all) of the ``n``-point Fibonacci sphere (m, 3):
    nearly uniform unit vectors, each the centre of a cell of area 4 pi / n."""
    if n < 1:
        raise ValueError(f"need at least one point, got {n}")
    k = np.arange(start, n if stop is None else min(stop, n), dtype=float)
    z = 1.0 - (2.0 * k + 1.0) / n  # cell centres of equal-area bands
    rho = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = GOLDEN_ANGLE * k
    return np.column_stack([rho * np.cos(phi), rho * np.sin(phi), z])


def fibonacci_chunks(n: int, chunk: int = CHUNK) -> Iterator[np.ndarray]:
    """The ``n``-point Fibonacci sphere in consecutive chunks of at most ``chunk`` points."""
    for start in range(0, n, chunk):
        yield fibonacci_sphere(n, start, start + chunk)


def grid_spacing(n: int) -> float:
    """Typical distance (rad) between neighbouring points of an ``n``-point Fibonacci sphere."""
    return float(np.sqrt(4.0 * np.pi / n))


@dataclass(frozen=True)
class SafeFraction:
    """Fraction of the sphere inside every cap, with an error estimate (both in [0, 1]);
    ``points`` is the lattice size, 0 for the exact area."""

    fraction: float
    error: float
    points: int


def safe_fraction(a: np.ndarray, c: np.ndarray, n: int = 20000) -> SafeFraction:
    """Fraction of ``n`` Fibonacci directions inside every cap ``a_k + c_k . d > 0``.

    Each point is classified exactly; only the cells cut by a boundary are uncertain. The error
    estimate is half the fraction of points within one grid spacing of a boundary (a band one
    spacing wide about the boundary; conservative, see docs/performance.md).
    """
    h = grid_spacing(n)
    inside = near = 0
    for points in fibonacci_chunks(n):
        margins = cap_margins(a, c, points)
        inside += int(np.count_nonzero(margins > 0))
        near += int(np.count_nonzero(np.abs(margins) < h))
    return SafeFraction(inside / n, 0.5 * near / n, n)


def lattice_best(a: np.ndarray, c: np.ndarray, n: int) -> tuple[np.ndarray, float]:
    """The lattice direction with the largest margin, and that margin (rad), in chunks."""
    best, best_margin = np.zeros(3), -np.inf
    for points in fibonacci_chunks(n):
        margins = cap_margins(a, c, points)
        i = int(np.argmax(margins))
        if margins[i] > best_margin:
            best, best_margin = points[i], float(margins[i])
    return best, best_margin


def cap_fraction(a: float, c: np.ndarray) -> float:
    """Exact fraction of the sphere where ``a + c . d > 0`` (one cap): ``(1 - cos r) / 2``."""
    r = float(np.linalg.norm(c))
    if r == 0.0:
        return 1.0 if a > 0 else 0.0
    cos_radius = float(np.clip(-a / r, -1.0, 1.0))
    return 0.5 * (1.0 - cos_radius)


def to_lon_lat(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth from +x in (-pi, pi] and elevation from the xy-plane (rad) of unit vectors."""
    d = np.asarray(directions, float)
    return np.arctan2(d[..., 1], d[..., 0]), np.arcsin(np.clip(d[..., 2], -1.0, 1.0))


def from_lon_lat(lon: np.ndarray, lat: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 3) from azimuth and elevation (rad)."""
    lon, lat = np.broadcast_arrays(np.asarray(lon, float), np.asarray(lat, float))
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], -1)
