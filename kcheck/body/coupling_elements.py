"""From fitted contact regions to a coupling's elements: which regions are point contacts (a
ball on a plane, a pin or a ball; crossed pins), where each touches and its normal, and which
contacts cannot be used (a line or an area touches: over-constraint; a near miss).

Each ball's point contacts are recognised as a coupling shorthand of
:mod:`kcheck.scene.couplings` (ball-flat, ball-vee, ball-trihedral, ball-cylinders,
ball-sphere) when the shorthand's own expansion gives the same contacts; otherwise they stay
explicit supports. Lengths in metres; normals point from the base into the body, as a scene's
support normals do.
"""

from __future__ import annotations

import math
from dataclasses import field, replace
from typing import Any

import numpy as np

from kcheck.body.contact_regions import Region
from kcheck.body.surface_fit import Primitive
from kcheck.numerics.thresholds import EXTRUSION_DEG
from kcheck.records import dataclass

__all__ = [
    "PointContact",
    "LineContact",
    "Element",
    "Unusable",
    "Recognition",
    "Planar",
    "recognise",
    "planar",
    "onto_z",
    "extrusion_faces",
]

#: Shorthand expansions must reproduce the fitted contacts to this (relative to the ball;
#: normals to 10 times it). Not tighter: an STL's float32 coordinates tilt each fitted plane
#: by up to ~1e-7 rad, so an exact trihedral seat (three normals from two angles and an axis)
#: exported as STL misses its own expansion at 1e-9 and would lose its curvatures (hertz).
_MATCH_RTOL = 1e-6
#: Two axes within this angle (degrees) are parallel: a pin on a pin along them is a line.
_PARALLEL_DEG = 1.0


@dataclass(frozen=True)
class PointContact:
    """A point contact: where (m), its unit normal from the base into the body, the gap of
    the fitted surfaces there (m, negative where they overlap), the distance from the fitted
    contact to the nearest touching point of the meshes (m), and what touches."""

    point: np.ndarray
    normal: np.ndarray
    gap: float
    to_mesh: float
    ball: Primitive | None
    ball_on: str
    key: tuple[str, int]
    mate: Primitive
    region: Region
    canoe: Primitive | None = None


@dataclass
class Element:
    """One coupling element: its ``kind`` (a shorthand type, ``cylinder-crossed`` or
    ``supports``), the ball (if any) and which part carries it, its point contacts, and the
    shorthand's fields in metres (None for explicit supports)."""

    kind: str
    name: str
    ball: Primitive | None
    ball_on: str
    contacts: list[PointContact]
    fields: dict[str, Any] | None = None


@dataclass(frozen=True)
class LineContact:
    """A line contact (a cylinder lying on a plane or on a parallel cylinder): its direction
    ``axis`` (unit), the middle of the touching line's extent along it (``point``, m), the
    extent's half-length (m), the unit normal from the base into the body (perpendicular to
    the axis), the fitted surfaces' gap (m) and the cylinder(s) and plane fitted there."""

    point: np.ndarray
    axis: np.ndarray
    half_length: float
    normal: np.ndarray
    gap: float
    body_fit: Primitive
    base_fit: Primitive


@dataclass(frozen=True)
class Unusable:
    """A contact region that is not a point contact: ``what`` touches, ``why`` it cannot be
    used, and how many constraints it imposes (0 for a near miss); for a line contact, the
    line (a point contact of a planar coupling when the parts are extrusions along it)."""

    what: str
    why: str
    constraints: int
    region: Region
    line: LineContact | None = None


@dataclass
class Recognition:
    """The elements recognised and the regions that could not be used."""

    elements: list[Element] = field(default_factory=list)
    unusable: list[Unusable] = field(default_factory=list)

    @property
    def contact_count(self) -> int:
        return sum(len(e.contacts) for e in self.elements)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _name(p: Primitive | None) -> str:
    if p is None:
        return "an unrecognised surface"
    if p.kind == "plane":
        return "a plane"
    concave = p.outward < 0
    if p.kind == "sphere":
        return "a spherical socket" if concave else "a ball"
    if p.kind == "cone":
        return "a conical seat" if concave else "a cone"
    if p.kind == "torus":
        return "a toroidal groove" if concave else "a canoe ball (torus)"
    return "a bore" if concave else "a cylinder"


def _foot(point: np.ndarray, cylinder: Primitive) -> np.ndarray:
    return cylinder.point + ((point - cylinder.point) @ cylinder.axis) * cylinder.axis


def _ball_contact(
    ball: Primitive, mate: Primitive, ball_on: str, region: Region, gap_tol: float
) -> PointContact | list[PointContact] | Unusable:
    """A ball against a plane, a convex cylinder or a convex sphere: one point contact; in a
    conical seat, the ``ball-cone`` shorthand's three."""
    c, r = ball.point, ball.radius
    what = f"{_name(ball)} (radius {r:.6g} m) on {_name(mate)}"
    if mate.kind == "plane":
        n = mate.axis if (c - mate.point) @ mate.axis >= 0 else -mate.axis
        gap = float((c - mate.point) @ n - r)
    elif mate.kind == "cone" and mate.outward < 0:
        return _ring(ball, mate, ball_on, region, gap_tol)
    elif mate.kind in ("cone", "torus"):
        return Unusable(what, f"a ball on {_name(mate)} is not a supported element", 0, region)
    elif mate.outward < 0:
        conform = abs(mate.radius - r) <= gap_tol
        if mate.kind == "sphere" and conform:
            return Unusable(what, "an area contact (a ball in its socket)", 3, region)
        return Unusable(
            what,
            "a ball inside a concave "
            + ("cylinder (bore)" if mate.kind == "cylinder" else "sphere")
            + (": a line contact" if conform and mate.kind == "cylinder" else "")
            + " is not a supported element",
            2 if conform else 1,
            region,
        )
    elif mate.kind == "cylinder":
        d = c - _foot(c, mate)
        n = _unit(d)
        gap = float(np.linalg.norm(d) - r - mate.radius)
    else:
        d = c - mate.point
        n = _unit(d)
        gap = float(np.linalg.norm(d) - r - mate.radius)
    point = c - r * n
    to_mesh = float(np.linalg.norm(region.points - point, axis=1).min())
    normal = n if ball_on == "body" else -n
    return PointContact(point, normal, gap, to_mesh, ball, ball_on, ("", 0), mate, region)


def _ring(
    ball: Primitive, cone: Primitive, ball_on: str, region: Region, gap_tol: float
) -> list[PointContact] | Unusable:
    """A ball in a conical seat: a circle of contact, written as the ``ball-cone`` shorthand
    models it (three points 120 deg apart); the ball's centre must be on the cone's axis."""
    from kcheck.scene import couplings

    c, r = ball.point, ball.radius
    what = f"{_name(ball)} (radius {r:.6g} m) in {_name(cone)}"
    off = c - _foot(c, cone)
    if np.linalg.norm(off) > gap_tol:
        return Unusable(
            what,
            f"the ball's centre is {np.linalg.norm(off):.3g} m off the cone's axis: it touches "
            "the seat at one point of its circle, not a kinematic seat",
            0,
            region,
        )
    # The seat opens along `up`, towards the ball; its normals lean in by 90 deg - half-angle.
    up = cone.axis if (c - cone.point) @ cone.axis >= 0 else -cone.axis
    half = 90.0 - math.degrees(cone.half_angle)
    gap = float(((c - cone.point) @ up) * math.sin(cone.half_angle) - r)
    out = []
    for contact in couplings.ball_cone(c, r, up, half):
        to_mesh = float(np.linalg.norm(region.points - contact.point, axis=1).min())
        normal = contact.normal if ball_on == "body" else -contact.normal
        out.append(
            PointContact(contact.point, normal, gap, to_mesh, ball, ball_on, ("", 0), cone, region)
        )
    return out


def _canoe(canoe: Primitive, plane: Primitive, on: str, region: Region) -> PointContact | Unusable:
    """A canoe ball (the outside of a torus's tube) on a flat: one point contact, where the
    torus's normal is opposite the flat's; its own ball is the tube's circle there."""
    what = f"{_name(canoe)} (radii {canoe.radius:.6g} m, tube {canoe.tube:.6g} m) on {_name(plane)}"
    n = plane.axis if (canoe.point - plane.point) @ plane.axis >= 0 else -plane.axis
    m = -n  # the canoe's outward normal at the contact
    across = m - (m @ canoe.axis) * canoe.axis
    if np.linalg.norm(across) < math.sin(math.radians(_PARALLEL_DEG)):
        return Unusable(what, "a line contact (the torus's circle on a flat)", 2, region)
    tube = canoe.point + canoe.radius * _unit(across)
    point = tube + canoe.tube * m
    gap = float((tube - plane.point) @ n - canoe.tube)
    to_mesh = float(np.linalg.norm(region.points - point, axis=1).min())
    ball = Primitive("sphere", tube, np.zeros(3), canoe.tube, canoe.rms, canoe.size, 1.0)
    normal = n if on == "body" else -n
    return PointContact(point, normal, gap, to_mesh, ball, on, ("", 0), plane, region, canoe)


def _crossed(body: Primitive, base: Primitive, region: Region) -> PointContact | Unusable:
    """A convex cylinder on another: a point contact where their axes cross, a line where
    they are parallel."""
    what = f"a cylinder (radius {body.radius:.6g} m) on a cylinder (radius {base.radius:.6g} m)"
    cross = np.cross(body.axis, base.axis)
    if np.linalg.norm(cross) < math.sin(math.radians(_PARALLEL_DEG)):
        d = body.point - base.point
        across = d - (d @ base.axis) * base.axis
        n = _unit(across)  # from the base's axis towards the body's
        gap = float(np.linalg.norm(across) - body.radius - base.radius)
        line = _line(base.point + base.radius * n, base.axis, n, gap, body, base, region)
        return Unusable(what, "a line contact (parallel axes)", 2, region, line)
    # The closest points of the two axes.
    w = body.point - base.point
    a, b, c = body.axis @ body.axis, body.axis @ base.axis, base.axis @ base.axis
    d, e = body.axis @ w, base.axis @ w
    den = a * c - b * b
    s, t = (b * e - c * d) / den, (a * e - b * d) / den
    p_body, p_base = body.point + s * body.axis, base.point + t * base.axis
    n = _unit(p_body - p_base)
    gap = float(np.linalg.norm(p_body - p_base) - body.radius - base.radius)
    point = p_base + base.radius * n
    to_mesh = float(np.linalg.norm(region.points - point, axis=1).min())
    return PointContact(point, n, gap, to_mesh, None, "body", ("", 0), base, region)


def _contact(region: Region, gap_tol: float) -> PointContact | list[PointContact] | Unusable | None:
    """What a region is; None for surfaces that come near only at an edge (their fitted
    surfaces meet beyond the meshes' faces, as a ball passing a groove's end face does)."""
    found = _touch(region, gap_tol)
    if region.least_distance <= gap_tol:
        return found
    first = found[0] if isinstance(found, list) else found
    if isinstance(first, PointContact) and first.gap > gap_tol:
        return Unusable(
            _what(region),
            f"a gap with no contact: the surfaces come within {first.gap:.3g} m, more than "
            f"the gap tolerance {gap_tol:.3g} m",
            0,
            region,
        )
    return None


def _what(region: Region) -> str:
    return f"{_name(region.body_fit)} on the body against {_name(region.base_fit)} on the base"


def _touch(region: Region, gap_tol: float) -> PointContact | list[PointContact] | Unusable | None:
    body, base = region.body_fit, region.base_fit
    what = f"{_name(body)} on the body against {_name(base)} on the base"
    if body is None or base is None:
        side = "body" if body is None else "base"
        fits = ", ".join(f"{f.kind} RMS {f.rms:.3g} m" for f in region.tried[side])
        return Unusable(
            what,
            f"the {side}'s surface there is not a plane, sphere or cylinder ({fits})",
            0,
            region,
        )
    for ball, mate, ball_on in ((body, base, "body"), (base, body, "base")):
        if ball.kind == "sphere" and ball.outward > 0:
            if mate.kind == "sphere" and mate.outward > 0 and ball_on == "base":
                continue  # ball on ball: the body's is the ball
            found = _ball_contact(ball, mate, ball_on, region, gap_tol)
            return _keyed(found, ball_on, region)
    for canoe, mate, on in ((body, base, "body"), (base, body, "base")):
        if canoe.kind == "torus" and canoe.outward > 0 and mate.kind == "plane":
            return _keyed(_canoe(canoe, mate, on, region), on, region)
    if body.kind == "plane" and base.kind == "plane":
        if body.axis @ base.axis < -math.cos(math.radians(_PARALLEL_DEG)):
            return Unusable(what, "an area contact (flat on flat)", 3, region)
        return None  # a face's edge on another face: part of an area contact found beside
    if {body.kind, base.kind} == {"plane", "cylinder"}:
        cyl, plane = (body, base) if body.kind == "cylinder" else (base, body)
        if abs(cyl.axis @ plane.axis) < math.sin(math.radians(_PARALLEL_DEG)):
            line = None
            if cyl.outward > 0:
                # s: the plane's normal towards the cylinder; the line is the cylinder's
                # generator nearest the plane, the normal the plane's towards the body.
                s = plane.axis if (cyl.point - plane.point) @ plane.axis >= 0 else -plane.axis
                gap = float((cyl.point - plane.point) @ s - cyl.radius)
                axis = _unit(cyl.axis - (cyl.axis @ s) * s)
                n = s if plane is base else -s
                line = _line(cyl.point - cyl.radius * s, axis, n, gap, body, base, region)
            why = "a line contact (a cylinder lying on a plane)"
            return Unusable(what, why, 2, region, line)
    if body.kind == "cylinder" and base.kind == "cylinder":
        if body.outward > 0 and base.outward > 0:
            found = _crossed(body, base, region)
            if isinstance(found, PointContact):
                found = PointContact(**{**found.__dict__, "key": ("body", region.body_patch)})
            return found
        return Unusable(what, "a pin in a bore (a line or area contact)", 2, region)
    return Unusable(what, "not a recognised pair of surfaces", 0, region)


def _line(
    start: np.ndarray,
    axis: np.ndarray,
    normal: np.ndarray,
    gap: float,
    body: Primitive,
    base: Primitive,
    region: Region,
) -> LineContact:
    """The line through ``start`` along ``axis``, from where both patches begin to where the
    first ends (their vertices' extents along it; the near points' without the vertices)."""
    sides = [region.vertices[k] for k in ("body", "base") if k in region.vertices]
    if len(sides) == 2:
        ts = [(v - start) @ axis for v in sides]
        lo, hi = max(float(t.min()) for t in ts), min(float(t.max()) for t in ts)
    else:
        t = (region.points - start) @ axis
        lo, hi = float(t.min()), float(t.max())
    point = start + (lo + hi) / 2 * axis
    return LineContact(point, axis, (hi - lo) / 2, normal, gap, body, base)


def _keyed(
    found: PointContact | list[PointContact] | Unusable, on: str, region: Region
) -> PointContact | list[PointContact] | Unusable:
    """The contacts keyed by the ball's patch (its contacts make one element)."""
    key = (on, region.body_patch if on == "body" else region.base_patch)
    if isinstance(found, PointContact):
        return PointContact(**{**found.__dict__, "key": key})
    if isinstance(found, list):
        return [PointContact(**{**c.__dict__, "key": key}) for c in found]
    return found


def _same(contacts: list[PointContact], expanded: list[Any], scale: float) -> bool:
    """Whether a shorthand's expansion (its contacts' points and normals from the mate
    towards the ball) gives exactly ``contacts``, in any order."""
    if len(expanded) != len(contacts):
        return False
    left = list(expanded)
    for c in contacts:
        n = c.normal if c.ball_on == "body" else -c.normal
        hit = [
            k
            for k, e in enumerate(left)
            if np.linalg.norm(e.point - c.point) <= _MATCH_RTOL * scale
            and np.linalg.norm(e.normal - n) <= _MATCH_RTOL * 10
        ]
        if not hit:
            return False
        left.pop(hit[0])
    return True


def _shorthand(contacts: list[PointContact]) -> tuple[str, dict[str, Any] | None]:
    """The shorthand type and fields (m) that expand to a ball's contacts, or ``supports``."""
    from kcheck.scene import couplings

    ball = contacts[0].ball
    assert ball is not None
    c, r = ball.point, ball.radius
    canoe = contacts[0].canoe
    if canoe is not None:
        # A canoe ball's contacts make a shorthand when their tube circles' points coincide
        # (a flat, a vee or a trihedral seat square to the canoe) and so do its radii there.
        surface = _canoe_surface(contacts, canoe, r)
        if surface is None:
            return "supports", None
        # One ball for all: the tube circle's points agree to the fit's accuracy.
        common = replace(ball, point=np.mean([x.ball.point for x in contacts if x.ball], axis=0))
        kind, fields = _shorthand(
            [
                replace(
                    x,
                    canoe=None,
                    ball=common,
                    point=common.point - r * (x.normal if x.ball_on == "body" else -x.normal),
                )
                for x in contacts
            ]
        )
        if fields is not None:
            fields["ball"] = {**fields["ball"], **surface}
        return kind, fields
    kinds = {x.mate.kind for x in contacts}
    mates = [x.mate for x in contacts]
    toward = [x.normal if x.ball_on == "body" else -x.normal for x in contacts]
    base: dict[str, Any] = {"ball": {"center": c, "radius": r}}
    try:
        if kinds == {"plane"} and len(contacts) == 1:
            fields = {**base, "normal": toward[0]}
            if _same(contacts, couplings.ball_flat(c, r, toward[0]), r):
                return "ball-flat", fields
        elif kinds == {"plane"} and len(contacts) == 2:
            axis = _unit(np.cross(toward[0], toward[1]))
            up = _unit(toward[0] + toward[1])
            half = math.degrees(math.acos(min(1.0, float(toward[0] @ up))))
            fields = {**base, "groove": {"axis": axis, "up": up, "half_angle": half}}
            if _same(contacts, couplings.ball_vee(c, r, axis, up, half), r):
                return "ball-vee", fields
        elif kinds == {"plane"} and len(contacts) == 3:
            up = _unit(np.sum(toward, axis=0))
            half = math.degrees(math.acos(min(1.0, float(toward[0] @ up))))
            radial = toward[0] - (toward[0] @ up) * up
            reference = -_unit(radial)
            fields = {**base, "up": up, "half_angle": half, "reference": reference}
            if _same(contacts, couplings.ball_trihedral(c, r, up, half, reference), r):
                return "ball-trihedral", fields
        elif kinds == {"cylinder"} and len(contacts) <= 3:
            cyl = [(m.point, m.axis, m.radius) for m in mates]
            fields = {**base, "cylinders": cyl}
            if _same(contacts, couplings.ball_cylinders(c, r, cyl), r):
                return "ball-cylinders", fields
        elif kinds == {"cone"} and len(contacts) == 3:
            cone = mates[0]
            up = cone.axis if (c - cone.point) @ cone.axis >= 0 else -cone.axis
            half = 90.0 - math.degrees(cone.half_angle)
            fields = {**base, "up": up, "half_angle": half}
            if _same(contacts, couplings.ball_cone(c, r, up, half), r):
                return "ball-cone", fields
        elif kinds == {"sphere"} and len(contacts) <= 3:
            sph = [(m.point, m.radius) for m in mates]
            fields = {**base, "spheres": sph}
            if _same(contacts, couplings.ball_spheres(c, r, sph), r):
                return "ball-sphere", fields
    except couplings.CouplingError:
        pass
    return "supports", None


def _canoe_surface(
    contacts: list[PointContact], canoe: Primitive, r: float
) -> dict[str, Any] | None:
    """A canoe ball's ``surface_radii`` (m) and ``surface_direction`` where it touches: along
    the tube circle (R + a cos v) / cos v, across it the tube's a (v the contact normal's
    angle from the torus's plane); None when the contacts do not share one ball and one
    surface."""
    first = contacts[0]
    assert first.ball is not None
    # The tube circle's points must agree to the fit's accuracy (float32 exports: 1e-7).
    tolerance = 10 * canoe.rms + _MATCH_RTOL * r
    radii, direction = [], None
    for x in contacts:
        assert x.ball is not None
        if np.linalg.norm(x.ball.point - first.ball.point) > tolerance:
            return None
        m = -(x.normal if x.ball_on == "body" else -x.normal)  # the canoe's outward normal
        across = _unit(m - (m @ canoe.axis) * canoe.axis)
        cos_v = float(m @ across)
        radii.append((canoe.radius + canoe.tube * cos_v) / cos_v)
        direction = np.cross(canoe.axis, across) if direction is None else direction
    if max(radii) - min(radii) > tolerance * max(radii) / r:
        return None
    return {"surface_radii": [radii[0], canoe.tube], "surface_direction": direction}


def recognise(regions: list[Region], gap_tol: float) -> Recognition:
    """The coupling elements of the contact regions (``gap_tol`` in m)."""
    out = Recognition()
    groups: dict[tuple[str, int], list[PointContact]] = {}
    for region in regions:
        found = _contact(region, gap_tol)
        if isinstance(found, Unusable):
            out.unusable.append(found)
        elif isinstance(found, list):
            groups.setdefault(found[0].key, []).extend(found)
        elif found is not None:
            groups.setdefault(found.key, []).append(found)
    ordered = sorted(groups.values(), key=lambda g: tuple(np.round(g[0].point, 9)))
    for k, contacts in enumerate(ordered, start=1):
        contacts.sort(key=lambda x: tuple(np.round(x.point, 9)))
        first = contacts[0]
        if first.ball is None:
            out.elements.append(Element("cylinder-crossed", f"p{k}", None, "body", contacts, None))
            continue
        kind, fields = _shorthand(contacts)
        out.elements.append(Element(kind, f"b{k}", first.ball, first.ball_on, contacts, fields))
    return out


@dataclass(frozen=True)
class Planar:
    """A planar coupling: line contacts all along one ``axis`` (unit, its largest component
    positive) of two extrusions along it; each line is a point contact of the cross-section."""

    axis: np.ndarray
    lines: list[tuple[LineContact, Unusable]]
    slides: list[Unusable] = field(default_factory=list)
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))


def onto_z(flat: Planar) -> Planar:
    """The planar coupling turned so that its axis is +z: its lines' points, axes and normals
    turned by the least rotation that does it (about ``axis`` × z), which ``rotation`` holds
    (scene = rotation · assembly)."""
    z = np.array([0.0, 0.0, 1.0])
    k = np.cross(flat.axis, z)
    s, c = float(np.linalg.norm(k)), float(flat.axis @ z)
    if s == 0.0:
        return flat
    k = k / s
    skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    r = np.eye(3) + s * skew + (1 - c) * skew @ skew  # Rodrigues
    lines = [
        (replace(x, point=r @ x.point, axis=r @ x.axis, normal=r @ x.normal), u)
        for x, u in flat.lines
    ]
    return Planar(z, lines, flat.slides, r @ flat.rotation)


def extrusion_faces(normals: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Indices of the faces (unit ``normals``, (n, 3)) neither parallel nor perpendicular to
    ``axis`` within :data:`~kcheck.numerics.thresholds.EXTRUSION_DEG`: none for an extrusion
    along it (its walls perpendicular, its end faces parallel)."""
    c = np.abs(normals @ axis)
    tol = math.radians(EXTRUSION_DEG)
    return np.flatnonzero((c > math.sin(tol)) & (c < math.cos(tol)))


def planar(found: Recognition, meshes: dict[str, np.ndarray]) -> Planar | str | None:
    """Whether the contacts found make a planar coupling: every region that constrains is a
    line contact (no point contacts) or a flat on a flat square to the lines (the plane the
    body slides on: ``slides``), the lines are parallel within :data:`_PARALLEL_DEG` and
    every part (``meshes``: name to unit face normals) is an extrusion along them, with 3
    lines. None when they are not all such (not a planar question); a sentence saying why not
    when they are lines but not a planar kinematic coupling."""
    over = [u for u in found.unusable if u.constraints]
    if found.elements or not any(u.line is not None for u in over):
        return None
    lines = [(u.line, u) for u in over if u.line is not None]
    slides = [u for u in over if u.line is None]
    if not all(_flat_on_flat(u) for u in slides):
        return None
    first = lines[0][0].axis
    axes = np.array([x.axis if x.axis @ first >= 0 else -x.axis for x, _ in lines])
    spread = max(math.degrees(math.acos(min(1.0, abs(float(a @ first))))) for a in axes)
    if spread > _PARALLEL_DEG:
        return (
            f"the {len(lines)} line contacts are not parallel (up to {spread:.3g} deg apart): "
            "not a planar coupling either (one needs every line along the extrusion's axis)"
        )
    axis = _unit(axes.mean(axis=0))
    axis = axis if axis[int(np.argmax(np.abs(axis)))] > 0 else -axis
    square = math.cos(math.radians(EXTRUSION_DEG))
    if any(abs(float(u.region.base_fit.axis @ axis)) < square for u in slides if u.region.base_fit):
        return None  # a flat on a flat that is not the plane of motion: over-constraint
    for name, normals in meshes.items():
        bad = extrusion_faces(normals, axis)
        if len(bad):
            n = ", ".join(f"{v:.4g}" for v in normals[bad[0]])
            a = ", ".join(f"{v:.4g}" for v in axis)
            return (
                f"the line contacts are parallel, along ({a}), but the {name} is not an "
                f"extrusion along them: {len(bad)} of its {len(normals)} faces are neither "
                f"parallel nor perpendicular to them (one has normal ({n})), so it is not a "
                "planar coupling either"
            )
    if len(lines) != 3:
        return (
            f"{len(lines)} line contacts of two extrusions (a planar coupling); a planar "
            "kinematic coupling has exactly 3"
        )
    lines.sort(key=lambda x: tuple(np.round(x[0].point, 9)))
    return Planar(axis, lines, slides)


def _flat_on_flat(u: Unusable) -> bool:
    """Whether an unusable region is an area contact of two fitted planes."""
    fits = (u.region.body_fit, u.region.base_fit)
    return all(f is not None and f.kind == "plane" for f in fits) and u.constraints == 3
