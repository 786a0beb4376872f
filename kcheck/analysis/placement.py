"""Supports against the body's mesh: each contact point on the body's surface, each normal
pointing into the body there.

A support is a contact between the body and the base: its point lies on the body's surface
and its normal points from the base into the body. With a mesh, both can be checked:

* ``support-off-surface`` (an error): the point is farther than :data:`SURFACE_RTOL` of the
  body's size (its bounding-box diagonal) from the surface, outside or inside the body.
* ``support-normal-outward`` (an error): a short step along the normal leaves the body and a
  step against it enters (the normal points out of the body); the message gives the
  surface's inward normal there.
* ``support-unchecked`` (a warning): the mesh cannot tell: it is not closed (no inside, and
  perhaps no face where the support is), or a step either way lands on the same side (an edge,
  a corner, a thin wall) and the normal points away from the nearest face's inward side.

Where most supports are off the body and reading the mesh in another unit would put every one
on its surface (spread over the body, not shrunk into a corner of it), the errors name that
unit. Where every support is on the surface but crowded into a corner of the body (less than
:data:`CORNER_SPAN` of it along every axis), and the mesh read in another unit would carry
them all as well and be spanned by them, a ``mesh-units-suspect`` warning names the unit (a
block whose mesh is in cm read as mm, with a corner at the origin).

Planar scenes are checked in the plane of motion: the body's section at the supports' height
(or at the mesh's mid-height when the supports lie outside it: in a planar scene the height of
the supports is not a position on the body). Coupling shorthands' contacts are checked like
explicit supports: the contact lies on the body's ball (``ball_on: body``) or on the seat in
the body (``ball_on: base``: a groove, pins, a vee block), which must be part of the body's
mesh for the check to pass; a simplified mesh may leave them out, so a contact off the
surface by up to the ball's diameter (plus the tolerance) is a ``support-unchecked`` warning
instead of an error.
"""

from __future__ import annotations

import numpy as np

from kcheck.body.surface import (
    Surface,
    closest_on_segments,
    closest_point,
    face_normals,
    inside,
    section_segments,
)
from kcheck.fmt import format_length, format_vector
from kcheck.records import dataclass
from kcheck.result import Finding
from kcheck.scene import Scene
from kcheck.scene.units import LENGTH_TO_M

__all__ = ["SURFACE_RTOL", "PROBE_RTOL", "Placement", "support_placement"]

#: A support farther than this fraction of the body's size (its bounding-box diagonal) from
#: the mesh's surface is off the body: 1 % is 2.6 mm on a 200 × 150 × 85 mm block, well
#: above a CAD export's faceting of a fillet or a point picked by eye on a drawing, well below
#: any unit slip (a factor of 2.54 at least).
SURFACE_RTOL = 1e-2
#: The step along a support's normal (a fraction of the body's size, at least twice the
#: support's distance to the surface) that must land inside the body, and against it
#: outside: small enough for walls a thousandth of the body's size.
PROBE_RTOL = 1e-3
#: Supports spanning less than this fraction of the body along every axis crowd into a
#: corner of it; with a mesh unit that would make them span it, a units slip is likelier.
CORNER_SPAN = 0.2


@dataclass(frozen=True)
class Placement:
    """What the mesh says about the supports: errors (input errors of the scene: a support
    off the body or a normal pointing out) and warnings (where the mesh cannot tell)."""

    errors: tuple[Finding, ...] = ()
    warnings: tuple[Finding, ...] = ()


def _section_height(scene: Scene, surface: Surface) -> float:
    z = float(scene.supports[0].position[2])
    low, high = surface.bounds[:, 2]
    margin = PROBE_RTOL * float(np.linalg.norm(np.ptp(surface.bounds, axis=0)))
    return z if low + margin < z < high - margin else float((low + high) / 2)


def _distances(scene: Scene, surface: Surface, points: np.ndarray) -> tuple[np.ndarray, ...]:
    """Closest surface points, distances (m) and inward unit normals there."""
    if scene.kind == "planar":
        z = _section_height(scene, surface)
        segments = section_segments(surface.triangles, z)
        if len(segments) == 0:
            n = len(points)
            return np.full((n, 3), np.nan), np.full(n, np.inf), np.zeros((n, 3))
        q2, d = closest_on_segments(segments, points[:, :2])
        # the perpendicular of the closest segment, turned inward below
        a, b = segments[:, 0], segments[:, 1]
        q = np.column_stack([q2, np.full(len(q2), z)])
        along = np.zeros((len(points), 3))
        for i, p in enumerate(q2):
            k = int(np.argmin(_segment_distance(a, b, p)))
            along[i, :2] = b[k] - a[k]
        perp = np.column_stack([-along[:, 1], along[:, 0], np.zeros(len(points))])
        length = np.linalg.norm(perp, axis=1, keepdims=True)
        perp = perp / np.where(length > 0, length, 1.0)
        size = float(np.linalg.norm(np.ptp(surface.bounds, axis=0)))
        step = PROBE_RTOL * size
        inward = np.where(inside(surface.triangles, q + step * perp)[:, None], perp, -perp)
        return q, d, inward
    q, d, face = closest_point(surface.triangles, points, surface.vertices)
    return q, d, -face_normals(surface.triangles[face])


def _segment_distance(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> np.ndarray:
    ab = b - a
    length_sq = np.einsum("ij,ij->i", ab, ab)
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(length_sq > 0, length_sq, 1.0), 0, 1)
    return np.asarray(np.linalg.norm(a + t[:, None] * ab - p, axis=1))


def _evaluated(scene: Scene, surface: Surface) -> np.ndarray:
    """The support points where they are checked (a planar scene's at the section height)."""
    points = np.array([s.position for s in scene.supports], dtype=float)
    if scene.kind == "planar":
        points[:, 2] = _section_height(scene, surface)
    return points


def _fits(scene: Scene, surface: Surface, moved: np.ndarray, tol: float) -> bool:
    """Whether supports moved to ``moved`` all lie on the surface, spread over the body
    (shrunk towards an origin, any layout ends up near a surface)."""
    if scene.kind == "planar":
        moved = moved.copy()
        moved[:, 2] = _section_height(scene, surface)
    _, d, _ = _distances(scene, surface, moved)
    return bool(np.all(d <= tol)) and _span(scene, moved, surface.bounds) >= CORNER_SPAN


def _unit_slip(scene: Scene, surface: Surface, points: np.ndarray, tol: float) -> str | None:
    """The unit mix-ups that put every support on the surface, worded as a hint: the scene's
    coordinates in another unit (when every mesh has a unit of its own), or a lone mesh in
    another unit; None if none does."""
    if scene.body is None or not scene.body.parts:
        return None
    parts = scene.body.parts
    fits = []
    for unit, metres in LENGTH_TO_M.items():
        if unit != scene.units and _fits(scene, surface, points * metres / scene.scale, tol):
            # meshes without a unit of their own follow the scene's: they keep theirs
            keep = (
                f" and `units: {scene.units}` on the meshes"
                if any(p.units == scene.units for p in parts)
                else ""
            )
            fits.append(f"the scene's coordinates in {unit} (`units: {unit}`{keep})")
            break
    if len(parts) == 1:
        part = parts[0]
        t = np.asarray(part.translation, dtype=float)
        for unit, metres in LENGTH_TO_M.items():
            c = metres / part.scale  # the mesh would be c times as large
            if unit != part.units and _fits(scene, surface, (points - t) / c + t, tol):
                fits.append(f"the mesh read in {unit} (`units: {unit}` on it)")
                break
    if not fits:
        return None
    return (
        f"the numbers fit a unit mix-up: with {' or with '.join(fits)}, every support lies on "
        "the body's surface"
    )


def _coverage(scene: Scene, bounds: np.ndarray) -> float:
    """The largest fraction of the body's extent the supports span along an axis (x, y in a
    planar scene)."""
    return _span(scene, np.array([s.position for s in scene.supports], dtype=float), bounds)


def _span(scene: Scene, points: np.ndarray, bounds: np.ndarray) -> float:
    """The largest fraction of the body's extent the points span along an axis."""
    axes = 2 if scene.kind == "planar" else 3
    extent = np.ptp(bounds, axis=0)[:axes]
    span = np.ptp(points, axis=0)[:axes]
    return float(np.max(span / np.where(extent > 0, extent, np.inf)))


def _cornered(scene: Scene, surface: Surface) -> Finding | None:
    """A warning when the supports crowd into a small corner of the body and the mesh read in
    another unit would also carry every support, spanning the body: a mesh in cm read as mm
    whose origin is a corner of the body leaves every support on its surface."""
    if scene.body is None or len(scene.body.parts) != 1:
        return None
    covered = _coverage(scene, surface.bounds)
    if covered >= CORNER_SPAN:
        return None
    part = scene.body.parts[0]
    t = np.asarray(part.translation, dtype=float)
    for unit, metres in LENGTH_TO_M.items():
        c = metres / part.scale
        if unit == part.units or c > 1:
            continue
        scaled = Surface((surface.triangles - t) * c + t, surface.closed)
        spans = _coverage(scene, scaled.bounds)
        if spans < CORNER_SPAN or spans > 1 + SURFACE_RTOL:
            continue
        if _findings(scene, scaled).errors:
            continue
        return Finding(
            f"the supports span at most {covered:.0%} of the body along any axis; read in "
            f"{unit} instead of {part.units}, the mesh would carry every support as well, "
            f"and they would span {spans:.0%} of it",
            code="mesh-units-suspect",
            field=(*part.field, "mesh"),
            hint=f"is the mesh in {unit}? Give it `units: {unit}`",
        )
    return None


def support_placement(scene: Scene, surface: Surface) -> Placement:
    """Each support's distance to the body's surface and its normal against the surface's
    inward side there (module docstring)."""
    found = _findings(scene, surface)
    if found.errors or not surface.closed:
        return found
    cornered = _cornered(scene, surface)
    return found if cornered is None else Placement(found.errors, (*found.warnings, cornered))


def _findings(scene: Scene, surface: Surface) -> Placement:
    """The errors and warnings of :func:`support_placement` (without the corner rule)."""
    size = float(np.linalg.norm(np.ptp(surface.bounds, axis=0)))
    tol = SURFACE_RTOL * size
    points = _evaluated(scene, surface)
    normals = np.array([s.normal for s in scene.supports], dtype=float)
    _, distance, inward = _distances(scene, surface, points)
    step = np.maximum(2 * distance, PROBE_RTOL * size)
    step = np.where(np.isfinite(step), step, PROBE_RTOL * size)
    n = len(points)
    if surface.closed:
        probes = np.concatenate(
            [points, points + step[:, None] * normals, points - step[:, None] * normals]
        )
        within = inside(surface.triangles, probes)
    else:
        within = np.zeros(3 * n, dtype=bool)
    inner, enters_all, leaves_all = within[:n], within[n : 2 * n], within[2 * n :]

    def length(value: float) -> str:
        return format_length(value, scene.scale, scene.units)

    errors: list[Finding] = []
    warnings: list[Finding] = []
    off: list[int] = []
    for i, s in enumerate(scene.supports):
        field = (*s.field, "position") if s.geometry is None else s.field
        # a coupling's contact lies on a ball or a seat (pins, vee blocks) that a simplified
        # mesh may leave out: off it by up to the ball's diameter
        reach = 0.0 if s.geometry is None else 2 * s.geometry.ball_radius
        if distance[i] > tol:
            side = "inside" if inner[i] else "outside"
            where = (
                "the body's section in the plane of motion"
                if scene.kind == "planar"
                else ("the body's surface")
            )
            text = (
                f"support `{s.name}` is {length(float(distance[i]))} from {where} ({side} "
                f"the body), more than the tolerance of {length(tol)} "
                f"({SURFACE_RTOL:.0%} of the body's size)"
                if np.isfinite(distance[i])
                else f"support `{s.name}`'s height misses the body: no section of the mesh there"
            )
            finding = Finding(
                text,
                code="support-off-surface",
                field=field,
                hint="a support is a contact point on the body: is it in the scene's units "
                f"({scene.units}), and is the mesh in its own?",
            )
            if not surface.closed:
                warnings.append(
                    Finding(
                        f"{text}; the body's mesh is not closed, so it may lack the face the "
                        "support touches",
                        code="support-unchecked",
                        field=field,
                    )
                )
            elif distance[i] <= reach + tol:
                side_of = "ball" if s.geometry.ball_on == "body" else "seat"  # type: ignore[union-attr]
                warnings.append(
                    Finding(
                        f"{text}; within a ball's diameter of it, so the {side_of} it touches "
                        "may just be missing from the mesh: the contact could not be checked",
                        code="support-unchecked",
                        field=field,
                        hint=f"model the coupling's {side_of}s in the body's mesh to check it",
                    )
                )
            else:
                errors.append(finding)
                off.append(i)
            continue
        if not surface.closed:
            warnings.append(
                Finding(
                    f"support `{s.name}`'s normal could not be checked: the body's mesh is not "
                    "closed, so it has no inside",
                    code="support-unchecked",
                    field=field,
                )
            )
            continue
        enters, leaves = bool(enters_all[i]), bool(leaves_all[i])
        if enters and not leaves:
            continue
        if enters == leaves and float(normals[i] @ inward[i]) >= 0:
            continue  # an edge or a corner (or a thin wall): the nearest face agrees
        normal_field = (*s.field, "normal") if s.geometry is None else s.field
        corrected = format_vector(inward[i], 3)
        if leaves and not enters:
            errors.append(
                Finding(
                    f"support `{s.name}`'s normal {format_vector(s.normal, 3)} points out of "
                    "the body (a normal points from the support into the body); the "
                    f"surface's inward normal there is {corrected}",
                    code="support-normal-outward",
                    field=normal_field,
                    hint=None
                    if s.geometry is None
                    else "put the ball on the other side (`ball_on`) or turn the seat's `up`",
                )
            )
        else:
            warnings.append(
                Finding(
                    f"support `{s.name}`'s normal could not be checked against the mesh: a step "
                    f"of {length(float(step[i]))} along it lands "
                    f"{'inside' if enters else 'outside'} the body either way (a thin wall or "
                    f"an edge); the surface's inward normal nearest to it is {corrected}",
                    code="support-unchecked",
                    field=normal_field,
                )
            )
    if 2 * len(off) > len(scene.supports):  # a unit slip moves most supports off the body
        slip = _unit_slip(scene, surface, _evaluated(scene, surface), tol)
        if slip is not None:
            errors = [
                Finding(f.message, f.code, f.field, slip) if f.code == "support-off-surface" else f
                for f in errors
            ]
    return Placement(tuple(errors), tuple(warnings))
