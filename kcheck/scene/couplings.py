"""Coupling shorthands: a ball and the surfaces it rests on, expanded into point supports.

Each function returns the contacts of one coupling as :class:`Contact` values: the contact
point, the unit normal ``n`` from the mating surface towards the ball centre, and the mating
surface's shape. The contact point is the ball centre minus ``r n``. Lengths may be in any one
unit (the scene's, so that ``kcheck expand`` writes exactly what the loader computes); angles
are in degrees. :func:`supports` turns contacts into :class:`~kcheck.scene.Support` values in
SI units, flipping every normal when the ball sits on the base (the groove is then on the
body, and the supports push the body along ``-n``).

Curvatures (for contact mechanics) follow :class:`~kcheck.scene.Surface`: radii positive for
convex surfaces, negative for concave ones, ``inf`` where flat; a cylinder's first radius is
along its axis (``inf``), the second across it (its radius); a conical seat's first radius is
along the generator (``inf``), the second along the circumference: by Meusnier's theorem the
normal curvature of the contact circle (radius ``rho`` about the cone's axis, principal normal
towards the axis) is ``sin(h) / rho`` for a cone whose normal makes the angle ``h`` with its
axis, concave seen from the ball, so the radius is ``-rho / sin(h)`` (``-r`` for a seated
ball of radius ``r``: ball and cone conform around the circle, which is why the contact is a
line).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import numpy as np

from kcheck.numerics.thresholds import EPS, PARALLEL_COS
from kcheck.records import dataclass
from kcheck.scene.types import ContactGeometry, Support, Surface

__all__ = [
    "Contact",
    "CouplingError",
    "GAP_RTOL",
    "FLAT",
    "unit",
    "ball_vee",
    "ball_cylinders",
    "ball_spheres",
    "ball_trihedral",
    "ball_cone",
    "ball_flat",
    "supports",
]

#: A ball must touch the cylinder or sphere it rests on: the distance between their centres
#: (or the ball centre and the cylinder axis) may differ from the sum of radii by this much,
#: relative to that sum.
GAP_RTOL = 0.01
#: A flat surface's radii.
FLAT = (math.inf, math.inf)


class CouplingError(ValueError):
    """Inconsistent coupling geometry; ``where`` is the field path inside the coupling."""

    def __init__(self, message: str, where: tuple[str | int, ...] = ()) -> None:
        super().__init__(message)
        self.where = where


@dataclass(frozen=True)
class Contact:
    """One contact of a ball: point, unit normal from the mating surface towards the ball
    centre, and the mating surface's shape (radii in the input's length unit)."""

    point: np.ndarray
    normal: np.ndarray
    mate: Surface


def unit(vector: Sequence[float] | np.ndarray) -> np.ndarray:
    """The unit vector along ``vector``; a vector already of unit length to rounding (within
    4 ulp) is returned unchanged, so normalising twice changes nothing."""
    v = np.asarray(vector, dtype=float)
    norm = float(np.sqrt(v @ v))
    if abs(norm - 1.0) <= 4 * EPS:
        return v
    return v / norm


def _perpendicular(
    v: np.ndarray, to: np.ndarray, what: str, where: tuple[str, ...], against: str = "`up`"
) -> np.ndarray:
    """Unit component of ``v`` perpendicular to the unit vector ``to`` (named ``against``);
    a CouplingError at ``where`` (the field of ``v`` inside the coupling) if they are
    parallel."""
    if abs(unit(v) @ to) > PARALLEL_COS:
        raise CouplingError(f"{what} is parallel to {against}; it must not be", where)
    return unit(v - (v @ to) * to)


def _default_reference(up: np.ndarray) -> np.ndarray:
    """A direction perpendicular to ``up``: the coordinate axis least aligned with it,
    projected (deterministic, so a scene always expands the same way)."""
    axis = np.eye(3)[int(np.argmin(np.abs(up)))]
    return unit(axis - (axis @ up) * up)


def _ring(
    center: np.ndarray,
    radius: float,
    up: np.ndarray,
    half_angle_deg: float,
    reference: np.ndarray,
    count: int = 3,
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Normals tilted ``half_angle`` from ``up``, their contacts at 0, 120, 240 deg about it
    from ``reference``: (point, normal, unit radial direction of the point) per contact."""
    h = math.radians(half_angle_deg)
    e2 = np.cross(up, reference)
    out = []
    for k in range(count):
        theta = 2 * math.pi * k / count
        radial = math.cos(theta) * reference + math.sin(theta) * e2
        normal = unit(math.cos(h) * up - math.sin(h) * radial)
        out.append((center - radius * normal, normal, radial))
    return out


def ball_vee(
    center: np.ndarray,
    radius: float,
    axis: np.ndarray,
    up: np.ndarray,
    half_angle_deg: float,
    flank_radius: float | None = None,
) -> list[Contact]:
    """A ball in a V-groove: two flanks whose normals make ``half_angle`` with ``up``; flat,
    or (``flank_radius``) concave across the groove with that radius and straight along it (a
    gothic arch: two arcs meeting at the bottom; a conformal groove as the radius nears the
    ball's). The contact normals are the same either way: at the contact the arc's normal
    passes through the ball centre.

    Contact 1's normal leans towards ``up × axis``, contact 2's away from it.
    """
    if flank_radius is not None and not flank_radius > radius:
        raise CouplingError(
            f"the groove's flank radius {flank_radius:.6g} must exceed the ball's radius "
            f"{radius:.6g} (a smaller one touches at two edges, not at a point)",
            ("groove", "radius"),
        )
    a = unit(axis)
    u = _perpendicular(
        up,
        a,
        "the groove's `up` (out of the groove, towards the ball)",
        ("groove", "up"),
        "the groove's `axis` (along it)",
    )
    side = np.cross(u, a)
    h = math.radians(half_angle_deg)
    normals = [unit(math.cos(h) * u + sign * math.sin(h) * side) for sign in (1.0, -1.0)]
    flank = Surface(FLAT) if flank_radius is None else Surface((math.inf, -flank_radius), a)
    return [Contact(center - radius * n, n, flank) for n in normals]


def _touching(distance: float, radius: float, other: float, what: str, where: tuple) -> None:
    expected = radius + other
    if abs(distance - expected) > GAP_RTOL * expected:
        raise CouplingError(
            f"the ball does not touch {what}: its centre is {distance:.6g} from it, expected "
            f"ball radius + its radius = {expected:.6g} (within {GAP_RTOL:.0%}); check the "
            "positions and radii",
            where,
        )


def ball_cylinders(
    center: np.ndarray,
    radius: float,
    cylinders: Sequence[tuple[np.ndarray, np.ndarray, float]],
) -> list[Contact]:
    """A ball on cylinders (dowel pins, rods), each given as (point on axis, axis, radius).

    The normal runs from the nearest point of the cylinder's axis to the ball centre; the
    cylinder's first radius (``inf``) is along its axis (``direction``), the second across.
    """
    out = []
    for i, (point, axis, cyl_radius) in enumerate(cylinders):
        a = unit(axis)
        offset = center - point
        foot = point + (offset @ a) * a
        d = center - foot
        distance = float(np.sqrt(d @ d))
        _touching(distance, radius, cyl_radius, f"cylinder {i + 1}", ("cylinders", i))
        n = unit(d)
        out.append(Contact(center - radius * n, n, Surface((math.inf, cyl_radius), a)))
    return out


def ball_spheres(
    center: np.ndarray, radius: float, spheres: Sequence[tuple[np.ndarray, float]]
) -> list[Contact]:
    """A ball resting on spheres (balls, screw heads), each given as (centre, radius)."""
    out = []
    for i, (sphere_center, sphere_radius) in enumerate(spheres):
        d = center - sphere_center
        distance = float(np.sqrt(d @ d))
        _touching(distance, radius, sphere_radius, f"sphere {i + 1}", ("spheres", i))
        n = unit(d)
        out.append(Contact(center - radius * n, n, Surface((sphere_radius, sphere_radius))))
    return out


def ball_trihedral(
    center: np.ndarray, radius: float, up: np.ndarray, half_angle_deg: float, reference: np.ndarray
) -> list[Contact]:
    """A ball in a trihedral socket: three flat flanks whose normals make ``half_angle`` with
    ``up``, the first flank in the direction ``reference`` from the ball (seen along ``up``),
    the others 120 and 240 deg counter-clockwise about ``up``."""
    u = unit(up)
    ref = _perpendicular(reference, u, "`reference`", ("reference",))
    ring = _ring(center, radius, u, half_angle_deg, ref)
    return [Contact(p, n, Surface(FLAT)) for p, n, _ in ring]


def ball_cone(
    center: np.ndarray,
    radius: float,
    up: np.ndarray,
    half_angle_deg: float,
    reference: np.ndarray | None = None,
) -> list[Contact]:
    """A ball in a conical seat (axis through the ball centre along ``up``; the cone's normal
    makes ``half_angle`` with ``up``): a line contact around a circle, modelled as three
    points 120 deg apart, the first towards ``reference`` (default: a fixed perpendicular).

    The seat is flat along its generator and concave around the circle, radius
    ``-rho / sin(half_angle)`` with ``rho`` the circle's radius (Meusnier).
    """
    u = unit(up)
    if reference is None:
        ref = _default_reference(u)
    else:
        ref = _perpendicular(reference, u, "`reference`", ("reference",))
    h = math.radians(half_angle_deg)
    out = []
    for point, normal, radial in _ring(center, radius, u, half_angle_deg, ref):
        rho = float((point - center) @ radial)  # distance from the cone's axis
        tangent = np.cross(u, radial)  # along the circle
        generator = unit(np.cross(tangent, normal))
        out.append(Contact(point, normal, Surface((math.inf, -rho / math.sin(h)), generator)))
    return out


def ball_flat(center: np.ndarray, radius: float, normal: np.ndarray) -> list[Contact]:
    """A ball on a flat whose normal points towards the ball centre."""
    n = unit(normal)
    return [Contact(center - radius * n, n, Surface(FLAT))]


def _si(surface: Surface, scale: float) -> Surface:
    return Surface((surface.radii[0] * scale, surface.radii[1] * scale), surface.direction)


def supports(
    name: str,
    kind: str,
    center: np.ndarray,
    radius: float,
    contacts: Sequence[Contact],
    ball_on: Literal["body", "base"],
    friction: float,
    scale: float,
    ball_surface: Surface | None = None,
) -> tuple[Support, ...]:
    """Supports ``<name>.1``, ``<name>.2``, ... in SI units (``scale`` metres per length unit
    of the contacts). With the ball on the body the supports push along ``n``; with the ball
    on the base, along ``-n``. ``ball_surface``: a canoe ball's contact surface (in the
    contacts' unit; default a sphere of ``radius``)."""
    ball = _si(ball_surface or Surface((radius, radius)), scale)
    out = []
    for k, c in enumerate(contacts, start=1):
        mate = _si(c.mate, scale)
        body, base = (ball, mate) if ball_on == "body" else (mate, ball)
        geometry = ContactGeometry(
            coupling=name,
            kind=kind,
            index=k,
            ball_center=center * scale,
            ball_radius=radius * scale,
            ball_on=ball_on,
            body=body,
            base=base,
            line_contact=kind == "ball-cone",
        )
        normal = c.normal if ball_on == "body" else -c.normal
        out.append(Support(f"{name}.{k}", c.point * scale, normal, friction, geometry))
    return tuple(out)
