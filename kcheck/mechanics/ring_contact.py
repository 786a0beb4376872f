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
points' forces (:func:`ring_peak_load`).

Tangential (Mindlin, no-slip) compliance of the line contact (:func:`line_tangential_stiffness`).
Below slip a tangential line load ``q`` (N/m) sticks the whole strip, with the traction
``q / (pi sqrt(b^2 - x^2))`` (Johnson 1985, §7.1, the two-dimensional Cattaneo–Mindlin
problem), under which the strip moves rigidly. Like the normal approach, its displacement is
defined only against a datum at a depth ``d`` in each body; from Flamant's line-load solution
(Johnson §2.2, plane strain: ``sigma_r = -2 F cos(phi) / (pi r)``, with its displacements)
integrated over that traction, for ``d >> b``, each body gives

    in the meridian plane (across the line):  u = q / (pi G) ((1 - nu) ln(2d / b) + 1/2)
    along the line (antiplane shear):         u = q / (pi G) ln(2d / b)

(``G`` the shear modulus; the surface term ``ln(b/2)`` is the strip's, the ``1/2`` the
datum's offset in Flamant's solution). With the same datum as the normal approach (``d = R``
in both bodies) the stiffness per unit length of the two bodies in series is
``k'_m = pi / sum_i((1 - nu_i) ln(2R/b) + 1/2) / G_i`` across the line and ``k'_c = pi /
sum_i ln(2R/b) / G_i`` along it; a datum between ``R/2`` and ``2R`` changes each compliance
by ``ln 2`` of its logarithm's factor (:func:`line_tangential_uncertainty`). The load does not
enter but through ``b``: the no-slip stiffness is linear in ``q``. On a ring the meridional
direction is across the line and the circumferential one along it; the ball in the cone gains
axially ``2 pi r_c k'_m sin^2 h`` and radially ``pi r_c (k'_m cos^2 h + k'_c)``
(:func:`cone_tangential_stiffness`). Everything is numpy, vectorised, SI units.
"""

from __future__ import annotations

import numpy as np

from kcheck.records import dataclass

__all__ = [
    "LineContact",
    "line_contact",
    "line_uncertainty",
    "ring_peak_load",
    "cone_stiffness",
    "line_tangential_stiffness",
    "line_tangential_uncertainty",
    "cone_tangential_stiffness",
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


def _shear(youngs: np.ndarray, poisson: np.ndarray) -> np.ndarray:
    return youngs / (2.0 * (1.0 + poisson))


def line_tangential_stiffness(
    half_width: np.ndarray | float,
    radius: np.ndarray | float,
    youngs1: np.ndarray | float,
    poisson1: np.ndarray | float,
    youngs2: np.ndarray | float,
    poisson2: np.ndarray | float,
) -> tuple[np.ndarray, np.ndarray]:
    """No-slip tangential stiffness per unit length (Pa) of line contacts of half-width ``b``
    (m) of a cylinder of ``radius`` ``R`` (m) between two materials (E in Pa, nu): across the
    line ``pi / sum_i ((1 - nu_i) ln(2R/b) + 1/2) / G_i`` and along it ``pi / sum_i ln(2R/b) /
    G_i`` (module docstring: a datum ``R`` deep in both bodies); zero where ``b`` is 0."""
    b, r, e1, n1, e2, n2 = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (half_width, radius, youngs1, poisson1, youngs2,
                                               poisson2))
    )  # fmt: skip
    live = b > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        log = np.where(live, np.log(2.0 * r / np.where(live, b, 1.0)), 0.0)
    g1, g2 = _shear(e1, n1), _shear(e2, n2)
    across = ((1.0 - n1) * log + 0.5) / g1 + ((1.0 - n2) * log + 0.5) / g2
    along = log / g1 + log / g2
    with np.errstate(divide="ignore", invalid="ignore"):
        return (
            np.where(live, np.pi / across, 0.0),
            np.where(live & (along > 0), np.pi / along, 0.0),
        )


def line_tangential_uncertainty(
    half_width: np.ndarray | float, radius: np.ndarray | float, poisson: np.ndarray | float
) -> np.ndarray:
    """Relative uncertainty of the across-the-line tangential compliance from the datum's
    depth (``R/2`` to ``2R``), for like materials: ``(1 - nu) ln 2 / ((1 - nu) ln(2R/b) +
    1/2)`` (along the line it is ``ln 2 / ln(2R/b)``, larger)."""
    b, r, nu = (np.asarray(x, dtype=float) for x in (half_width, radius, poisson))
    with np.errstate(divide="ignore"):
        log = np.log(2.0 * r / b)
    return (1.0 - nu) * np.log(2.0) / ((1.0 - nu) * log + 0.5)


def cone_tangential_stiffness(
    across: np.ndarray | float,
    along: np.ndarray | float,
    ring_radius: np.ndarray | float,
    normal_angle: np.ndarray | float,
) -> tuple[np.ndarray, np.ndarray]:
    """Axial and radial stiffness (N/m) a ball in a cone gains from the ring's tangential
    stiffness per unit length across the line ``k'_m`` (meridional) and along it ``k'_c``
    (circumferential), Pa: ``2 pi r_c k'_m sin^2 h`` and ``pi r_c (k'_m cos^2 h + k'_c)``."""
    km, kc, r, h = (np.asarray(x, dtype=float) for x in (across, along, ring_radius, normal_angle))
    return 2.0 * np.pi * r * km * np.sin(h) ** 2, np.pi * r * (km * np.cos(h) ** 2 + kc)
