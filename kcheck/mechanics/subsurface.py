"""Stress below a Hertz contact: the largest shear and von Mises stresses and their depths.

Under a frictionless elliptical Hertz contact (semi-axes ``a >= b``, peak pressure ``p0``) the
largest shear and von Mises stresses lie on the axis through the contact's centre, below the
surface (Johnson, *Contact Mechanics*, 1985, §3.7 and §4.2; for a circle: ``tau_max = 0.31 p0``
at ``z = 0.48 a``, von Mises ``0.62 p0``, nu = 0.3). On that axis the stresses ``sigma_x``,
``sigma_y``, ``sigma_z`` are principal (the ellipse's symmetry). They are found by superposing
Boussinesq's point-load solution (Johnson eq. 3.22) over the elliptical pressure ``p0 sqrt(1 -
x^2/a^2 - y^2/b^2)`` in polar coordinates about the axis: along each ray the pressure is a
circle's, so the radial integrals are closed forms (:func:`_ray_integrals`), and the average
over the ray's angle (smooth and periodic; the nodes graded towards the long axis, where a
slender ellipse's rays turn fast) is taken by the trapezoidal rule, which converges spectrally.
For a circle this is Johnson's eq. 3.46. The depth of each maximum is refined by
parabolic interpolation on ever finer stencils. A 2D line contact (the ring of a ball in a
cone) has its axis stresses in closed form (Johnson §4.3; :func:`line_subsurface_stress`).
Everything is numpy, vectorised over contacts, SI units.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from kcheck.records import dataclass

__all__ = [
    "SubsurfaceStress",
    "axis_stresses",
    "line_axis_stresses",
    "line_subsurface_stress",
    "subsurface_stress",
]

_PHI = 256  # trapezoid nodes (stresses to 1e-9 p0 down to b/a = 1/100)
#: A contact with b/a above 1 - this is a circle (Johnson's eq. 3.46 directly); the ray average
#: equals it to rounding there, so the switch is seamless.
CIRCLE_RTOL = 1e-6
_REFINEMENTS = 4  # parabolic steps, each on a stencil 8 times finer than the last


@dataclass(frozen=True)
class SubsurfaceStress:
    """The largest shear stress (Tresca, ``(sigma_1 - sigma_3)/2``) and von Mises stress below
    each contact (Pa) and their depths below the surface (m)."""

    max_shear: np.ndarray
    max_shear_depth: np.ndarray
    von_mises: np.ndarray
    von_mises_depth: np.ndarray


def _ray_integrals(zeta: np.ndarray) -> tuple[np.ndarray, ...]:
    """The integrals of Boussinesq's kernels along a ray of the pressure ``sqrt(1 - s^2)``
    (``s = r / R``, ``zeta = z / R``), in closed form (checked against quadrature in the tests):

        I_a = int s sqrt(1 - s^2) / (q (q + zeta)) ds = ln(sqrt(1 + zeta^2) / zeta) + t - 1
        I_b = int zeta s sqrt(1 - s^2) / q^3 ds      = 1 - t
        I_c = int 3 zeta s^3 sqrt(1 - s^2) / q^5 ds  = 3 (1 - t) - 1 / (1 + zeta^2)
        I_z = int 3 zeta^3 s sqrt(1 - s^2) / q^5 ds  = 1 / (1 + zeta^2)

    over ``s`` from 0 to 1, ``q = sqrt(s^2 + zeta^2)``, ``t = zeta atan(1 / zeta)``."""
    t = zeta * np.arctan(1.0 / zeta)
    inv = 1.0 / (1.0 + zeta * zeta)
    i_a = 0.5 * np.log1p(1.0 / (zeta * zeta)) + t - 1.0
    return i_a, 1.0 - t, 3.0 * (1.0 - t) - inv, inv


def axis_stresses(
    depth: np.ndarray | float,
    a: np.ndarray | float,
    b: np.ndarray | float,
    max_pressure: np.ndarray | float,
    poisson: np.ndarray | float,
) -> np.ndarray:
    """Principal stresses ``(sigma_x, sigma_y, sigma_z)`` (Pa, compression negative), shape
    (..., 3), at ``depth`` (m, > 0) below the centre of an elliptical Hertz contact with
    semi-axes ``a`` along x and ``b`` along y (m) and peak pressure ``max_pressure`` (Pa).

    Along each ray at angle ``phi`` from the axis the pressure is a circle's of radius
    ``R(phi)``, so the radial integrals are closed forms (:func:`_ray_integrals`); what is left
    is the average over ``phi`` of ``k I_a cos 2 phi - I_c cos^2 phi + k I_b sin^2 phi``
    (``sigma_x``; ``sigma_y`` with ``sin`` and ``cos`` swapped; ``k = 1 - 2 nu``) and of
    ``-I_z`` (``sigma_z``), smooth and periodic: the trapezoidal rule converges spectrally."""
    z, big_a, big_b, p0, nu = (
        np.asarray(v, dtype=float)[..., None]
        for v in np.broadcast_arrays(depth, a, b, max_pressure, poisson)
    )
    # The ray angle phi through tan phi = lam tan u, lam = sqrt(b/a): the nodes crowd where a
    # slender ellipse's rays turn fast (near its long axis), d phi = w du.
    u = (np.arange(_PHI) + 0.5) * (2.0 * np.pi / _PHI)
    lam = np.sqrt(big_b / big_a)
    phi = np.arctan2(lam * np.sin(u), np.cos(u))
    weight = lam / (np.cos(u) ** 2 + lam**2 * np.sin(u) ** 2)  # d phi / d u, mean 1
    c2, s2 = np.cos(phi) ** 2, np.sin(phi) ** 2
    radius = 1.0 / np.sqrt(c2 / big_a**2 + s2 / big_b**2)  # the ellipse along each ray
    i_a, i_b, i_c, i_z = _ray_integrals(z / radius)
    k = 1.0 - 2.0 * nu
    sx = np.mean(weight * (k * i_a * (c2 - s2) - i_c * c2 + k * i_b * s2), axis=-1)
    sy = np.mean(weight * (k * i_a * (s2 - c2) - i_c * s2 + k * i_b * c2), axis=-1)
    sz = -np.mean(weight * i_z, axis=-1)
    return np.stack([sx, sy, sz], axis=-1) * p0


def _circle_axis(depth: np.ndarray, a: np.ndarray, p0: np.ndarray, nu: np.ndarray) -> np.ndarray:
    """Johnson's closed form (eq. 3.46) on the axis of a circular contact: ``sigma_z = -p0 /
    (1 + zeta^2)``, ``sigma_r = sigma_theta = -p0 [(1 + nu)(1 - zeta atan(1/zeta)) - 1 / (2 (1
    + zeta^2))]``, ``zeta = z / a``; shape (..., 3)."""
    zeta = depth / a
    sz = -p0 / (1.0 + zeta**2)
    sr = -p0 * ((1.0 + nu) * (1.0 - zeta * np.arctan(1.0 / zeta)) - 0.5 / (1.0 + zeta**2))
    return np.stack([sr, sr, sz], axis=-1)


def _stresses(
    z: np.ndarray, a: np.ndarray, b: np.ndarray, p0: np.ndarray, nu: np.ndarray
) -> np.ndarray:
    """Axis stresses: the closed form for circles, the quadrature for ellipses."""
    circle = b >= a * (1.0 - CIRCLE_RTOL)
    if np.all(circle):
        return _circle_axis(z, a, p0, nu)
    out = axis_stresses(z, a, b, p0, nu)
    if np.any(circle):
        out = np.where(circle[..., None], _circle_axis(z, a, p0, nu), out)
    return out


def _shear(stress: np.ndarray) -> np.ndarray:
    return 0.5 * (stress.max(axis=-1) - stress.min(axis=-1))


def _von_mises(stress: np.ndarray) -> np.ndarray:
    d = stress - np.roll(stress, 1, axis=-1)
    return np.sqrt(0.5 * np.sum(d * d, axis=-1))


def _maximum(
    measure: Callable[[np.ndarray], np.ndarray],
    a: np.ndarray,
    b: np.ndarray,
    p0: np.ndarray,
    nu: np.ndarray,
    stresses: Callable[..., np.ndarray] = _stresses,
) -> tuple[np.ndarray, np.ndarray]:
    """Largest ``measure`` along the axis and its depth: a grid in ``z / b``, then parabolic
    steps around the best node."""
    grid = np.linspace(0.2, 1.2, 11)  # the maxima lie at 0.48 b (circle) to 0.79 b (line)
    values = measure(stresses(grid * b[..., None], a[..., None], b[..., None],
                              p0[..., None], nu[..., None]))  # fmt: skip
    best = np.clip(np.argmax(values, axis=-1), 1, grid.size - 2)
    depth = grid[best] * b
    step = (grid[1] - grid[0]) * b
    for _ in range(_REFINEMENTS):
        # the vertex of the parabola through three points around the best depth so far
        z = depth[..., None] + step[..., None] * np.array([-1.0, 0.0, 1.0])
        f = measure(stresses(z, a[..., None], b[..., None], p0[..., None], nu[..., None]))
        curve = f[..., 0] - 2.0 * f[..., 1] + f[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            shift = np.where(curve < 0, 0.5 * (f[..., 0] - f[..., 2]) / curve, 0.0)
        depth = depth + step * np.clip(shift, -1.0, 1.0)
        step = step / 8.0
    return measure(stresses(depth, a, b, p0, nu)), depth


def subsurface_stress(
    a: np.ndarray | float,
    b: np.ndarray | float,
    max_pressure: np.ndarray | float,
    poisson: np.ndarray | float,
) -> SubsurfaceStress:
    """Largest shear and von Mises stresses (Pa) below frictionless Hertz contacts and their
    depths (m); semi-axes ``a >= b`` (m), peak pressure (Pa), Poisson's ratio of the body the
    stresses are in. A contact of zero size gives zeros."""
    big_a, big_b, p0, nu = (
        np.atleast_1d(np.asarray(v, dtype=float))
        for v in np.broadcast_arrays(a, b, max_pressure, poisson)
    )
    # the two families apart: the quadrature only where it is needed
    circle = big_b >= big_a * (1.0 - CIRCLE_RTOL)
    shape = np.shape(np.broadcast_arrays(a, b, max_pressure, poisson)[0])
    live = (big_b > 0) & (p0 > 0)
    out = [np.zeros_like(big_a) for _ in range(4)]
    for group in (live & circle, live & ~circle):
        if not np.any(group):
            continue
        args = (big_a[group], big_b[group], p0[group], nu[group])
        shear, shear_depth = _maximum(_shear, *args)
        mises, mises_depth = _maximum(_von_mises, *args)
        for o, v in zip(out, (shear, shear_depth, mises, mises_depth), strict=True):
            o[group] = v
    return SubsurfaceStress(*(o.reshape(shape) for o in out))


def line_axis_stresses(
    depth: np.ndarray | float,
    half_width: np.ndarray | float,
    max_pressure: np.ndarray | float,
    poisson: np.ndarray | float,
) -> np.ndarray:
    """Principal stresses ``(sigma_x, sigma_y, sigma_z)`` (Pa, compression negative), shape
    (..., 3), at ``depth`` (m) below the centre of a 2D Hertz line contact of half-width ``b``
    (m, across the line along x; the line along y, plane strain) and peak pressure ``p0``:
    Johnson §4.3, ``sigma_x = -(p0/b) ((b^2 + 2 z^2) / sqrt(b^2 + z^2) - 2 z)``, ``sigma_z =
    -p0 b / sqrt(b^2 + z^2)``, ``sigma_y = nu (sigma_x + sigma_z)``."""
    z, b, p0, nu = (np.asarray(v, dtype=float) for v in (depth, half_width, max_pressure, poisson))
    root = np.sqrt(b * b + z * z)
    sx = -(p0 / b) * ((b * b + 2.0 * z * z) / root - 2.0 * z)
    sz = -p0 * b / root
    return np.stack(np.broadcast_arrays(sx, nu * (sx + sz), sz), axis=-1)


def _line(
    z: np.ndarray, a: np.ndarray, b: np.ndarray, p0: np.ndarray, nu: np.ndarray
) -> np.ndarray:
    return line_axis_stresses(z, b, p0, nu)


def line_subsurface_stress(
    half_width: np.ndarray | float, max_pressure: np.ndarray | float, poisson: np.ndarray | float
) -> SubsurfaceStress:
    """Largest shear and von Mises stresses (Pa) below frictionless 2D Hertz line contacts and
    their depths (m): half-width ``b`` (m), peak pressure (Pa), Poisson's ratio (for nu = 0.3:
    ``0.30 p0`` at ``0.78 b`` and ``0.56 p0`` at ``0.70 b``). Zero width gives zeros."""
    b, p0, nu = (
        np.atleast_1d(np.asarray(v, dtype=float))
        for v in np.broadcast_arrays(half_width, max_pressure, poisson)
    )
    shape = np.shape(np.broadcast_arrays(half_width, max_pressure, poisson)[0])
    live = (b > 0) & (p0 > 0)
    out = [np.zeros_like(b) for _ in range(4)]
    if np.any(live):
        args = (b[live], b[live], p0[live], nu[live])
        shear, shear_depth = _maximum(_shear, *args, stresses=_line)
        mises, mises_depth = _maximum(_von_mises, *args, stresses=_line)
        for o, v in zip(out, (shear, shear_depth, mises, mises_depth), strict=True):
            o[live] = v
    return SubsurfaceStress(*(o.reshape(shape) for o in out))
