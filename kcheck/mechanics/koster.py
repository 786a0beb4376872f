"""Koster's construction for one retracted support, pure and nondimensional (the geometry of
:mod:`kcheck_checks.graphical_2d`; methods.md §5): the pole as a homogeneous point, the virtual
power of the swept force with the fixed forces acting with it, the friction-tilted twist, and
the funnel, friction and jamming arcs in closed form.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from kcheck.mechanics.arcs import ArcSet, affine_arcs, complement, intersect
from kcheck.mechanics.dynamics import friction_directions
from kcheck.mechanics.kinematics import (
    FreeTwist,
    cross3,
    free_twist,
    point_velocity,
    row_norms,
    wrenches,
)
from kcheck.numerics import chebyshev as cheb
from kcheck.numerics.thresholds import EPS, TILTED_UNDETERMINED
from kcheck.records import dataclass

__all__ = [
    "GraphicalCase",
    "homogeneous_pole",
    "virtual_power",
    "tilted_twist",
    "condition_arc",
    "construct_case",
    "friction_over_range",
]

# Roundings per unit of conditioning in a virtual-power coefficient (error estimates;
# calibrated against 50-digit references, tests/kcheck/test_errors.py).
ROUNDINGS = 1.5


@dataclass(frozen=True)
class GraphicalCase:
    """The construction for one retracted support (nondimensional twists, arcs in radians)."""

    retracted: int
    keep: np.ndarray
    free: FreeTwist
    tilted: np.ndarray | None  # friction twist xi'_r, None when it cannot be oriented
    sliding: np.ndarray  # (2,) bool per remaining support
    funnel: ArcSet
    friction: ArcSet
    jamming: ArcSet
    safe: ArcSet
    error_rad: float | None  # of the safe arcs' ends; None without ends


def homogeneous_pole(twist: np.ndarray) -> np.ndarray:
    """Homogeneous pole ``(-v_y, v_x, w)`` of a planar twist ``(w, v_x, v_y)``."""
    return np.array([-twist[2], twist[1], twist[0]])


def virtual_power(
    twist: np.ndarray,
    point: np.ndarray,
    arm: float,
    fixed: Sequence[tuple[np.ndarray, np.ndarray]] = (),
) -> tuple[float, np.ndarray]:
    """``xi . W(d) = a + c . d`` for a unit force ``d`` at ``point`` with torque ``arm * |F|``
    and the fixed forces ``(point, force / F)`` acting with it.

    Nondimensional: points and ``arm`` in layout lengths. ``c = u(point)``,
    ``a = w arm + sum f . u(p)``.
    """
    a = float(twist[0] * arm)
    for where, force in fixed:
        a += float(force @ point_velocity(twist, where))
    return a, point_velocity(twist, point)


def tilted_twist(
    points: np.ndarray, normals: np.ndarray, mu: np.ndarray, free: FreeTwist, keep: np.ndarray
) -> tuple[np.ndarray | None, np.ndarray, float]:
    """Free twist of the friction-tilted reaction lines ``n_j + mu_j t_j`` of the kept supports.

    ``t_j`` opposes forward sliding under ``free``; a contact that does not slide keeps its
    normal (friction undetermined, zero as in the thesis). The twist is the cross product of
    the two tilted constraint rows (orthogonal to both), signed like the frictionless one at
    ``mu = 0`` (which is ``xi`` itself): the friction pole's sense followed continuously from
    the pole's as friction grows. Returns it as a unit vector (None when the tilted rows are
    parallel), the sliding mask and the determinacy of the tilted rows (``|a x b| / |a||b|``).
    """
    t, sliding = friction_directions(free.twist, points[keep], +1)
    tilted_rows = wrenches(points[keep], normals[keep] + mu[keep, None] * t)
    plain_rows = wrenches(points[keep], normals[keep])
    tilted = cross3(tilted_rows[0], tilted_rows[1])
    plain = cross3(plain_rows[0], plain_rows[1])
    size = float(np.linalg.norm(tilted))
    determinacy = size / float(np.linalg.norm(tilted_rows[0]) * np.linalg.norm(tilted_rows[1]))
    if determinacy <= TILTED_UNDETERMINED:
        return None, sliding, determinacy
    sign = 1.0 if float(plain @ free.twist) > 0 else -1.0
    return sign * tilted / size, sliding, determinacy


def condition_arc(
    a: float, c: np.ndarray, e1: np.ndarray, e2: np.ndarray, coef_error: float
) -> tuple[ArcSet, float | None]:
    """Angles from ``e1`` towards ``e2`` where ``a + c . d > 0``, and the ends' error (rad;
    None without ends)."""
    return affine_arcs(np.array([a]), c[None, :], e1, e2, np.array([coef_error]))


def construct_case(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    retracted: int,
    q: np.ndarray,
    arm: float,
    e1: np.ndarray,
    e2: np.ndarray,
    fixed: Sequence[tuple[np.ndarray, np.ndarray]] = (),
) -> GraphicalCase:
    """Koster's construction for one retracted support (all inputs nondimensional; ``fixed``
    are the forces acting with the swept one, ``(point, force / F)``)."""
    keep = np.flatnonzero(np.arange(len(points)) != retracted)
    free = free_twist(points, normals, retracted)
    scale = 1.0 + float(row_norms(q)) + abs(arm)
    with np.errstate(over="ignore"):
        scale += sum(float(row_norms(f) * (1.0 + row_norms(p))) for p, f in fixed)
    # A null vector is perturbed by about eps over its singular-value gap.
    a, c = virtual_power(free.twist, q, arm, fixed)
    funnel, err_f = condition_arc(
        a, c, e1, e2, ROUNDINGS * EPS / max(free.determinacy, EPS) * scale
    )
    tilted, sliding, det_t = tilted_twist(points, normals, mu, free, keep)
    if tilted is None:
        friction: ArcSet = ()
        err_t = None
    else:
        at, ct = virtual_power(tilted, q, arm, fixed)
        friction, err_t = condition_arc(at, ct, e1, e2, ROUNDINGS * EPS / max(det_t, EPS) * scale)
    return GraphicalCase(
        retracted=retracted,
        keep=keep,
        free=free,
        tilted=tilted,
        sliding=sliding,
        funnel=funnel,
        friction=friction,
        jamming=intersect(funnel, complement(friction)),
        safe=intersect(funnel, friction),
        error_rad=max((e for e in (err_f, err_t) if e is not None), default=None),
    )


def friction_over_range(
    case: GraphicalCase,
    points: np.ndarray,
    normals: np.ndarray,
    low: np.ndarray,
    high: np.ndarray,
    q: np.ndarray,
    arm: float,
    e1: np.ndarray,
    e2: np.ndarray,
    fixed: Sequence[tuple[np.ndarray, np.ndarray]] = (),
) -> GraphicalCase:
    """The case with its friction condition held for **every** coefficient from ``low`` to
    ``high`` (k,), exactly.

    The tilted rows are affine in the coefficients, so their cross product (unnormalised,
    signed as at ``mu = 0``) and with it the virtual power ``a + c . d`` are quadratic along
    the range: :func:`kcheck.mechanics.friction_range.range_arcs` intersects the arcs over it (ends
    of the range and envelope points, one exact decision per piece).
    """
    from kcheck.mechanics.friction_range import RangeCase, range_arcs

    if case.tilted is None:
        return case
    keep, free = case.keep, case.free
    t_dir, _ = friction_directions(free.twist, points[keep], +1)
    plain_rows = wrenches(points[keep], normals[keep])
    sign = 1.0 if float(cross3(plain_rows[0], plain_rows[1]) @ free.twist) > 0 else -1.0
    x = cheb.lobatto(5)
    samples = []
    for t in 0.5 * (x + 1.0):
        mu = low + t * (high - low)
        rows = wrenches(points[keep], normals[keep] + mu[keep, None] * t_dir)
        a, c = virtual_power(sign * cross3(rows[0], rows[1]), q, arm, fixed)
        samples.append(np.concatenate([[a], c]))
    series = cheb.interpolate(x, np.array(samples))  # (1 + dim, 5)
    one = np.zeros(5)
    one[0] = 1.0  # mass-free: no effective mass to turn negative
    condition = RangeCase(case.retracted, np.stack([one, one]), series[None], True)
    friction, _ = range_arcs(condition, e1, e2)
    return dataclasses.replace(
        case,
        friction=friction,
        jamming=intersect(case.funnel, complement(friction)),
        safe=intersect(case.funnel, friction),
    )
