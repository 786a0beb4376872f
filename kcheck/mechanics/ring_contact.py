"""A ball seated in a cone: a line contact around a circle (the ring contact).

A ball of radius ``R`` in a cone whose contact normal makes the angle ``h`` with the cone's
axis (the ``ball-cone`` shorthand's ``half_angle``; ``h = 90° - alpha`` for a cone of
geometric half-angle ``alpha``) touches along a circle of radius ``r_c = R sin h`` (``R cos
alpha``). In every meridian section the contact is a 2D cylinder (radius ``R``) on a straight
flank: Hertz's line contact (Johnson, *Contact Mechanics*, 1985, §4.3) under the line load
``w`` (N/m):

    b = sqrt(4 w R / (pi E*)),    p0 = 2 w / (pi b) = sqrt(w E* / (pi R))

The approach of a line contact is not unique: it grows with the logarithm of the depth of the
point it is measured to. kcheck takes the logarithmic form of the approach of a cylinder's axis
to its contact line (Johnson 1985, the 2D contact of cylinders; Puttock & Thwaite, CSIRO 1969,
give forms of the same kind) for both bodies together through ``E*``, i.e. a datum about ``R``
deep in either body:

    delta = w / (pi E*) (2 ln(4 R / b) - 1),    k' = dw/d delta = pi E* / (2 (ln(4 R / b) - 1))

(``b ~ sqrt(w)``, so ``d ln b / d w = 1 / (2 w)``). Its uncertainty, a datum between ``R/2``
and ``2R`` deep, is ``2 ln 2 / (2 ln(4R/b) - 1)`` of ``delta`` (:func:`line_uncertainty`).

The ring is modelled, like the shorthand's supports, by three points 120° apart, each standing
for a third of the circle (arc ``L = 2 pi r_c / 3``): its line load ``w_k = N_k / L`` and its
stiffness ``L k'``. Three such points give the ring's own axial and radial stiffness exactly
(:func:`cone_stiffness`). The ring's peak line load is that of the first-harmonic distribution
``w0 + w1 cos(theta - theta0)`` through the three samples, whose resultant equals the three
points' forces (:func:`ring_peak_load`). Everything is numpy, vectorised, SI units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "LineContact",
    "line_contact",
    "line_uncertainty",
    "ring_peak_load",
    "cone_stiffness",
]


@dataclass(frozen=True)
class LineContact:
    """Line contacts under line loads ``w`` (N/m): half-width ``b`` (m), peak pressure ``p0``
    (Pa), approach ``delta`` (m, to a datum about ``R`` deep in both bodies) and tangent
    stiffness per unit length ``k'`` (N/m per m, Pa)."""

    load: np.ndarray
    half_width: np.ndarray
    max_pressure: np.ndarray
    approach: np.ndarray
    stiffness: np.ndarray


def line_contact(
    load: np.ndarray | float, radius: np.ndarray | float, modulus: np.ndarray | float
) -> LineContact:
    """Hertz line contacts of a cylinder of ``radius`` (m) on a flat under line loads ``load``
    (N/m, >= 0) with contact modulus ``modulus`` ``E*`` (Pa); zero load gives zeros."""
    w, r, e = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (load, radius, modulus)))
    if np.any(w < 0):
        raise ValueError("a contact cannot pull: negative line load")
    b = np.sqrt(4.0 * w * r / (np.pi * e))
    p0 = np.sqrt(w * e / (np.pi * r))
    live = w > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        log = np.where(live, np.log(4.0 * r / b), 0.0)
    delta = np.where(live, w / (np.pi * e) * (2.0 * log - 1.0), 0.0)
    # Zero load: the tangent stiffness vanishes like 1/ln(1/w).
    stiffness = np.where(live, np.pi * e / (2.0 * (log - 1.0)), 0.0)
    return LineContact(w, b, p0, delta, stiffness)


def line_uncertainty(half_width: np.ndarray | float, radius: np.ndarray | float) -> np.ndarray:
    """Relative uncertainty of the line contact's approach and stiffness from the datum's depth
    (between ``R/2`` and ``2R``): ``2 ln 2 / (2 ln(4R/b) - 1)``."""
    b, r = (np.asarray(x, dtype=float) for x in (half_width, radius))
    with np.errstate(divide="ignore"):
        return 2.0 * np.log(2.0) / (2.0 * np.log(4.0 * r / b) - 1.0)


def ring_peak_load(samples: np.ndarray) -> np.ndarray:
    """The peak line load (N/m) around each ring from its samples (..., 3) at 0, 120, 240 deg:
    ``w0 + |w1|`` of the first harmonic through them, ``w0`` their mean and ``|w1| = 2/3 |sum_k
    w_k exp(i theta_k)|`` (either sense of rotation gives the same)."""
    w = np.asarray(samples, dtype=float)
    theta = 2.0 * np.pi * np.arange(3) / 3.0
    first = (2.0 / 3.0) * np.abs(np.sum(w * np.exp(1j * theta), axis=-1))
    return np.mean(w, axis=-1) + first


def cone_stiffness(
    line_stiffness: np.ndarray | float,
    ring_radius: np.ndarray | float,
    normal_angle: np.ndarray | float,
) -> tuple[np.ndarray, np.ndarray]:
    """Axial and radial stiffness (N/m) of a ball in a cone from the ring's normal stiffness
    per unit length ``k'`` (Pa), the ring radius ``r_c`` (m) and the angle ``h`` (rad) between
    the contact normal and the axis: ``2 pi r_c k' cos^2 h`` and ``pi r_c k' sin^2 h`` (the
    normal stiffness projected on the axis and on one radial direction around the circle)."""
    k, r, h = (np.asarray(x, dtype=float) for x in (line_stiffness, ring_radius, normal_angle))
    return 2.0 * np.pi * r * k * np.cos(h) ** 2, np.pi * r * k * np.sin(h) ** 2
