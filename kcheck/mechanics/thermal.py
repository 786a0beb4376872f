"""Thermal pose shift of a seated coupling under a uniform temperature change, and its thermal
centre.

The body, the base and the balls each expand by ``alpha dT`` (their materials' coefficients)
about the seat's origin ``o``. A ball of radius ``r``, centre ``c``, fixed to one side, touches
a seat surface of the other side at ``p`` with support normal ``N`` (pushing the body). The gap
along ``N`` stays closed when the body moves by the small twist ``xi``:

    ball on the body: w . xi = -dT (alpha_body N.(c - o) - alpha_ball r - alpha_base N.(p - o))
    ball on the base: w . xi = -dT (alpha_body N.(p - o) - alpha_base N.(c - o) - alpha_ball r)

(``w . xi = N . (v + omega x (p - o))``, the body's motion along ``N`` at the contact; the seat
surface expands with its side, the ball's radius with the ball's material; each term vanishes
when everything expands alike). This is a statically determinate coupling's exact small-motion
answer (one solve with the contact-wrench matrix). The **pose shift** of a body point ``x`` is
its displacement relative to the base point it sits over,

    u(x) = v + omega x (x - o) + (alpha_body - alpha_base) dT (x - o),

which does not depend on where either part is taken to expand from; the **thermal centre** is
the point where ``u = 0`` (none when the body and the base expand alike: then the pose shift
is a rigid motion). A symmetric three-vee's thermal centre is its centre.
"""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.seat import Seat, point_translation, twist_from_approach
from kcheck.numerics.thresholds import THERMAL_CENTRE_DET, ZERO_GUARD
from kcheck.records import dataclass

__all__ = ["ThermalShift", "thermal_approach", "thermal_shift"]


@dataclass(frozen=True)
class ThermalShift:
    """The body's small twist (rotation rad, then translation of the seat's origin, m), the
    pose shift ``u`` (m, 3) of the point asked for, and the thermal centre (m, or None)."""

    twist: np.ndarray
    shift: np.ndarray
    centre: np.ndarray | None


def thermal_approach(
    positions: np.ndarray,
    normals: np.ndarray,
    centers: np.ndarray,
    radii: np.ndarray,
    ball_on_body: np.ndarray,
    origin: np.ndarray,
    alpha_body: float,
    alpha_base: float,
    alpha_ball: np.ndarray,
    temperature_change: float,
) -> np.ndarray:
    """The change of each contact's approach (m, (k,)) that the expansion alone would make,
    before the body moves (module docstring): ``dT`` times the bracket."""
    n = np.asarray(normals, float)
    p = np.asarray(positions, float) - origin
    c = np.asarray(centers, float) - origin
    np_, nc = np.einsum("ij,ij->i", n, p), np.einsum("ij,ij->i", n, c)
    r = np.asarray(radii, float) * np.asarray(alpha_ball, float)
    on_body = alpha_body * nc - r - alpha_base * np_
    on_base = alpha_body * np_ - alpha_base * nc - r
    return temperature_change * np.where(np.asarray(ball_on_body, bool), on_body, on_base)


def thermal_shift(
    seat: Seat,
    approach: np.ndarray,
    expansion_difference: float,
    point: np.ndarray,
) -> ThermalShift | None:
    """The body's twist that keeps every contact closed against the thermal ``approach``
    changes, the pose shift of ``point`` (m) and the thermal centre; ``expansion_difference``
    is ``(alpha_body - alpha_base) dT``. None when the layout is singular."""
    sol = twist_from_approach(seat, approach)
    if sol.value is None:
        return None
    twist = sol.value
    origin = seat.frame.origin
    beta = float(expansion_difference)

    def shift(x: np.ndarray) -> np.ndarray:
        u = point_translation(seat, twist, x)
        grow = beta * (np.asarray(x, float) - origin)
        if seat.dim == 2:
            grow[2] = 0.0
        return u + grow

    at_origin = shift(origin)[: seat.dim]
    # u(x) = u(o) + M (x - o), M = beta I + [omega]x (planar: omega about z)
    nw = seat.rotations
    w = twist[:nw]
    if seat.dim == 3:
        m = beta * np.eye(3) + np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    else:
        m = np.array([[beta, -w[0]], [w[0], beta]])
    # No centre when the parts expand alike: the shift is then a rigid motion.
    scale = max(float(np.abs(m).max()), ZERO_GUARD)
    centre = None
    if abs(np.linalg.det(m / scale)) > THERMAL_CENTRE_DET:
        offset = np.linalg.solve(m, -at_origin)
        centre = origin.copy()
        centre[: seat.dim] += offset
    return ThermalShift(twist, shift(np.asarray(point, float)), centre)
