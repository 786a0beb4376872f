"""Hertz contact of two elastic bodies with curved surfaces: the elliptical contact in general.

Johnson, *Contact Mechanics* (Cambridge 1985), §4.1 (geometry), §4.2 (Hertz theory) and
chapter 3 (the elliptical pressure distribution on a half-space). Near the contact point the gap
between the unloaded surfaces is ``h = A x^2 + B y^2`` (``0 < A <= B``, the principal
curvature sums, convex curvature positive). Under a normal force ``P`` the contact is an ellipse
with semi-axes ``a >= b`` (``a`` along ``x``, the direction of the smaller sum), pressure
``p0 sqrt(1 - x^2/a^2 - y^2/b^2)``, and with ``e^2 = 1 - (b/a)^2``:

    A = p0 b / (E* e^2 a^2) [K(e) - E(e)]
    B = p0 b / (E* e^2 a^2) [(a/b)^2 E(e) - K(e)]
    delta = p0 b K(e) / E*,    P = 2/3 pi a b p0

(restated in docs/checks.md), ``K``, ``E`` the complete elliptic
integrals of modulus ``e`` and ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``. Their ratio fixes
``b/a`` from ``B/A`` alone; then ``a``, ``p0`` and ``delta`` follow in closed form. Since
``b/a`` does not depend on the load, ``a ~ P^(1/3)`` and ``delta ~ P^(2/3)``, so the tangent
stiffness is exactly ``dP/d delta = 3 P / (2 delta)``.

The elliptic integrals come from the arithmetic-geometric mean (DLMF 19.8.1 and 19.8.6), written
in the complementary modulus ``k' = b/a`` and without cancellation near the circle, so every
quantity is exact to rounding from the circle (``b = a``) to very slender ellipses. Everything
is numpy, vectorised over contacts, SI units.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from kcheck.numerics.thresholds import AGM_ULP_FRACTION, CURVATURE_RTOL, EPS, PARALLEL_SIN
from kcheck.records import dataclass

__all__ = [
    "HertzContact",
    "contact_modulus",
    "curvature_tensor",
    "curvature_sums",
    "curvature_sums_crossed",
    "elliptic_integrals",
    "ellipse_ratio",
    "hertz",
    "contact_shear_modulus",
    "tangential_stiffness",
]

# Iterations of the AGM: quadratic convergence; 1e-300 < k' needs fewer than 12.
_AGM_STEPS = 40


@dataclass(frozen=True)
class HertzContact:
    """Contacts under normal forces (arrays of one shape, SI units).

    ``a``, ``b``: the contact ellipse's semi-axes (m), ``a >= b``; ``max_pressure`` ``p0``
    (Pa); ``mean_pressure`` ``P / (pi a b)`` (Pa); ``approach`` ``delta`` (m), how far the
    two bodies' distant points come together; ``stiffness`` the tangent ``dP/d delta`` (N/m).
    """

    force: np.ndarray
    a: np.ndarray
    b: np.ndarray
    max_pressure: np.ndarray
    approach: np.ndarray
    stiffness: np.ndarray

    @property
    def mean_pressure(self) -> np.ndarray:
        """Mean contact pressure ``P / (pi a b)`` in Pa (two thirds of ``p0``)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return self.force / (np.pi * self.a * self.b)


def contact_modulus(
    youngs1: np.ndarray | Sequence[float] | float,
    poisson1: np.ndarray | Sequence[float] | float,
    youngs2: np.ndarray | Sequence[float] | float,
    poisson2: np.ndarray | Sequence[float] | float,
) -> np.ndarray:
    """Contact modulus ``E* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`` in Pa (Johnson §4.2)."""
    e1, n1, e2, n2 = (np.asarray(x, dtype=float) for x in (youngs1, poisson1, youngs2, poisson2))
    return 1.0 / ((1.0 - n1**2) / e1 + (1.0 - n2**2) / e2)


def curvature_tensor(
    radii: np.ndarray, direction: np.ndarray | None, normal: np.ndarray
) -> np.ndarray:
    """Curvature tensors (..., 3, 3) of surfaces in the tangent planes of their contacts.

    ``radii`` (..., 2): principal radii (m), positive convex, negative concave, ``inf`` flat;
    ``direction`` (..., 3): the direction of the first radius (projected into the tangent
    plane), or None when both radii are equal; ``normal`` (..., 3): unit contact normals. The
    tensor is ``sum_j (1/R_j) t_j t_j^T`` with ``t_1`` along ``direction``, ``t_2 = n x t_1``.
    """
    radii = np.asarray(radii, dtype=float)
    n = np.asarray(normal, dtype=float)
    kappa = 1.0 / radii
    tangent = np.eye(3) - n[..., :, None] * n[..., None, :]
    if direction is None:
        if not np.allclose(kappa[..., 0], kappa[..., 1], rtol=CURVATURE_RTOL, atol=0.0):
            raise ValueError("a surface with two different radii needs a direction")
        return kappa[..., 0, None, None] * tangent
    t1 = np.einsum("...ij,...j->...i", tangent, np.asarray(direction, dtype=float))
    norm = np.linalg.norm(t1, axis=-1, keepdims=True)
    if np.any(norm < PARALLEL_SIN):
        raise ValueError("a surface direction is parallel to its contact normal")
    t1 = t1 / norm
    t2 = np.cross(n, t1)
    return (
        kappa[..., 0, None, None] * t1[..., :, None] * t1[..., None, :]
        + kappa[..., 1, None, None] * t2[..., :, None] * t2[..., None, :]
    )


def curvature_sums(
    tensor: np.ndarray, normal: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Curvature sums ``A <= B`` (1/m) and the unit direction (..., 3) of ``A``.

    ``tensor`` (..., 3, 3) is the sum of both bodies' curvature tensors (each convex-positive
    about its own outward normal); the gap is ``h = 1/2 x^T tensor x`` in the tangent plane, so
    ``A`` and ``B`` are half its eigenvalues there. The contact ellipse's major axis ``a`` lies
    along the direction of ``A``.
    """
    n = np.asarray(normal, dtype=float)
    # An orthonormal tangent basis (u, v) per contact: u from the axis least aligned with n.
    helper = np.eye(3)[np.argmin(np.abs(n), axis=-1)]
    u = np.cross(n, helper)
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    v = np.cross(n, u)
    basis = np.stack([u, v], axis=-2)  # (..., 2, 3)
    reduced = 0.5 * np.einsum("...ai,...ij,...bj->...ab", basis, tensor, basis)
    values, vectors = np.linalg.eigh(reduced)
    direction = np.einsum("...a,...ai->...i", vectors[..., :, 0], basis)
    return values[..., 0], values[..., 1], direction


def curvature_sums_crossed(
    body1: tuple[float, float], body2: tuple[float, float], angle: float
) -> tuple[float, float]:
    """Johnson's closed form for ``A <= B`` (1/m) from principal radii and the angle (rad)
    between the planes of the first radii (Johnson §4.1, geometry of smooth non-conforming
    surfaces):

        A + B = 1/2 (1/R1' + 1/R1'' + 1/R2' + 1/R2'')
        B - A = 1/2 sqrt((k1' - k1'')^2 + (k2' - k2'')^2 + 2 (k1' - k1'')(k2' - k2'') cos 2 psi)
    """
    k1a, k1b = (1.0 / r for r in body1)
    k2a, k2b = (1.0 / r for r in body2)
    total = 0.5 * (k1a + k1b + k2a + k2b)
    d1, d2 = k1a - k1b, k2a - k2b
    diff = 0.5 * np.sqrt(max(d1 * d1 + d2 * d2 + 2.0 * d1 * d2 * np.cos(2.0 * angle), 0.0))
    return float(0.5 * (total - diff)), float(0.5 * (total + diff))


def _agm_series(kp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``K`` and ``sigma = S / e^2`` for complementary moduli ``kp = b/a`` in (0, 1].

    AGM of ``(1, kp)`` with ``c_0 = e = sqrt(1 - kp^2)`` and ``c_(n+1) = c_n^2 / (4 a_(n+1))``
    (no subtraction); ``K = pi / (2 AGM)`` and ``E = K (1 - S)``, ``S = sum 2^(n-1) c_n^2``
    (DLMF 19.8.6). ``sigma = S / e^2`` is computed from ``gamma_n = c_n / e`` so the circle
    (``e = 0``, ``sigma = 1/2``) needs no limit.
    """
    a = np.ones_like(kp)
    b = kp.copy()
    e = np.sqrt((1.0 - kp) * (1.0 + kp))
    gamma = np.ones_like(kp)
    sigma = 0.5 * gamma**2
    weight = 0.5
    for _ in range(_AGM_STEPS):
        a_next = 0.5 * (a + b)
        b = np.sqrt(a * b)
        gamma = e * gamma**2 / (4.0 * a_next)
        a = a_next
        weight *= 2.0
        term = weight * gamma**2
        sigma = sigma + term
        if np.all(term <= EPS * sigma * AGM_ULP_FRACTION):
            break
    return np.pi / (2.0 * a), sigma


def elliptic_integrals(kp: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
    """Complete elliptic integrals ``K(e)`` and ``E(e)`` for the complementary modulus
    ``kp = sqrt(1 - e^2)`` in (0, 1] (scipy's ``ellipk(m)``, ``ellipe(m)`` at ``m = 1 - kp^2``)."""
    kp = np.asarray(kp, dtype=float)
    big_k, sigma = _agm_series(np.atleast_1d(kp))
    e2 = (1.0 - kp) * (1.0 + kp)
    return big_k.reshape(kp.shape), (big_k * (1.0 - sigma * np.atleast_1d(e2))).reshape(kp.shape)


def _log_ratio(kp: np.ndarray) -> np.ndarray:
    """``ln(B/A)`` of an ellipse with axis ratio ``kp = b/a``: ``B/A = (1 - sigma) / (kp^2 sigma)``.

    From ``B/A = (E/kp^2 - K) / (K - E)`` with ``K - E = K S`` and ``E/kp^2 - K = K (e^2 - S)
    / kp^2``; ``1 - sigma = 1/2 - sum_(n>=1) 2^(n-1) gamma_n^2`` stays accurate near the circle.
    """
    _, sigma = _agm_series(kp)
    return np.log1p(-sigma) - np.log(sigma) - 2.0 * np.log(kp)


def ellipse_ratio(ratio: np.ndarray | float) -> np.ndarray:
    """Axis ratio ``b/a`` in (0, 1] of the contact ellipse for curvature sums ``B/A >= 1``.

    Solves the elliptic-integral equation (module docstring) for ``kp = b/a`` by a safeguarded
    secant (Illinois) iteration on ``ln kp`` from the Brewe–Hamrock estimate
    ``kp ~ (B/A)^(-2/pi)``, to rounding.
    """
    rho = np.atleast_1d(np.asarray(ratio, dtype=float))
    if np.any(~(rho >= 1.0)) or np.any(~np.isfinite(rho)):
        raise ValueError(f"expected curvature-sum ratios B/A >= 1, got {rho}")
    target = np.log(rho)
    out = np.ones_like(rho)
    todo = target > 0
    if not np.any(todo):
        return out.reshape(np.shape(ratio))
    goal = target[todo]
    # ln(B/A) decreases with t = ln kp; f(t) = ln(B/A)(t) - goal, f(0) = -goal < 0.
    hi = np.zeros_like(goal)
    f_hi = -goal
    lo = np.minimum(-2.0 / np.pi * goal - 0.5, -1e-3)
    f_lo = _log_ratio(np.exp(lo)) - goal
    for _ in range(200):
        low = f_lo <= 0
        if not np.any(low):
            break
        lo = np.where(low, 2.0 * lo - 1.0, lo)
        f_lo = np.where(low, _log_ratio(np.exp(lo)) - goal, f_lo)
    side = np.zeros_like(goal)
    t = hi
    for _ in range(200):
        t_old = t
        t = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        f = _log_ratio(np.exp(t)) - goal
        pos = f > 0
        # Illinois: halve the stale end's value when the same end is kept twice.
        f_hi = np.where(pos & (side > 0), 0.5 * f_hi, f_hi)
        f_lo = np.where(~pos & (side < 0), 0.5 * f_lo, f_lo)
        lo, f_lo = np.where(pos, t, lo), np.where(pos, f, f_lo)
        hi, f_hi = np.where(pos, hi, t), np.where(pos, f_hi, f)
        side = np.where(pos, 1.0, -1.0)
        if np.all((np.abs(t - t_old) <= 4 * EPS * (1.0 + np.abs(t))) | (f == 0)):
            break
    out[todo] = np.exp(t)
    return out.reshape(np.shape(ratio))


def hertz(
    force: np.ndarray | float,
    sum_a: np.ndarray | float,
    sum_b: np.ndarray | float,
    modulus: np.ndarray | float,
) -> HertzContact:
    """Hertz contacts under normal forces ``force`` (N, >= 0) with curvature sums
    ``0 < sum_a <= sum_b`` (1/m) and contact modulus ``modulus`` ``E*`` (Pa).

    A zero force gives a point contact: zero size, pressure, approach and stiffness.
    """
    p, big_a, big_b, e_star = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (force, sum_a, sum_b, modulus))
    )
    if np.any(~(big_a > 0)):
        raise ValueError(
            "the surfaces do not touch at a point (a curvature sum <= 0: conformal or concave)"
        )
    if np.any(big_b < big_a * (1 - CURVATURE_RTOL)):
        raise ValueError("expected sum_a <= sum_b")
    if np.any(p < 0):
        raise ValueError("a contact cannot pull: negative normal force")
    kp = ellipse_ratio(np.maximum(big_b / big_a, 1.0))
    big_k, sigma = _agm_series(np.atleast_1d(kp).ravel())
    big_k, sigma = big_k.reshape(kp.shape), sigma.reshape(kp.shape)
    a = np.cbrt(3.0 * p * big_k * sigma / (2.0 * np.pi * e_star * big_a))
    b = kp * a
    with np.errstate(invalid="ignore", divide="ignore"):
        p0 = np.where(p > 0, 3.0 * p / (2.0 * np.pi * a * b), 0.0)
        delta = p0 * b * big_k / e_star
        stiffness = np.where(p > 0, 1.5 * p / delta, 0.0)
    return HertzContact(p, a, b, p0, delta, stiffness)


def contact_shear_modulus(
    youngs1: np.ndarray | Sequence[float] | float,
    poisson1: np.ndarray | Sequence[float] | float,
    youngs2: np.ndarray | Sequence[float] | float,
    poisson2: np.ndarray | Sequence[float] | float,
) -> np.ndarray:
    """``G* = 1 / ((2 - nu1)/G1 + (2 - nu2)/G2)`` in Pa, ``G = E / (2 (1 + nu))`` (Johnson
    §7.2, the tangential loading of a Hertz contact)."""
    e1, n1, e2, n2 = (np.asarray(x, dtype=float) for x in (youngs1, poisson1, youngs2, poisson2))
    g1, g2 = e1 / (2.0 * (1.0 + n1)), e2 / (2.0 * (1.0 + n2))
    return 1.0 / ((2.0 - n1) / g1 + (2.0 - n2) / g2)


def tangential_stiffness(contact: HertzContact, shear_modulus: np.ndarray | float) -> np.ndarray:
    """Mindlin's tangential stiffness without slip, ``k_t = 8 G* a`` (N/m; Johnson §7.2, a
    circular contact of radius ``a``); an elliptical contact takes the circle of equal area,
    ``a = sqrt(a b)`` (an approximation: the exact compliance of an ellipse differs by
    direction). It holds while friction keeps the contact from slipping (small tangential
    loads against ``mu N``)."""
    return 8.0 * np.asarray(shear_modulus, float) * np.sqrt(contact.a * contact.b)
