"""Assemblies built from trimesh primitives for `kcheck contacts` tests: balls resting on flats,
in vees and trihedral seats made of boxes, and on pins; the exact contacts are known in closed
form (contact = ball centre - r n, n the flat's normal; on a pin, along the line from its axis
to the ball centre)."""

from __future__ import annotations

import numpy as np
import trimesh

R = 6.0  # ball radius, mm


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def ball(center, radius=R):
    return trimesh.creation.icosphere(subdivisions=4, radius=radius).apply_translation(center)


def flat(center, normal, radius=R, side=None, thickness=4.0):
    """A box whose top face (normal ``normal``) touches the ball at ``center`` (radius)."""
    n = unit(normal)
    side = 1.6 * radius if side is None else side
    box = trimesh.creation.box(extents=[side, side, thickness])
    rot = trimesh.geometry.align_vectors([0, 0, 1], n)
    box.apply_transform(rot)
    contact = np.asarray(center, float) - radius * n
    return box.apply_translation(contact - thickness / 2 * n)


def vee_normals(axis, up, half_angle_deg):
    a, u = unit(axis), unit(up)
    side = np.cross(u, a)
    h = np.radians(half_angle_deg)
    return [unit(np.cos(h) * u + s * np.sin(h) * side) for s in (1.0, -1.0)]


def vee(center, axis, up=(0, 0, 1), half_angle=45.0, radius=R):
    return [flat(center, n, radius) for n in vee_normals(axis, up, half_angle)]


def trihedral_normals(up=(0, 0, 1), half_angle=54.7356103172):
    h = np.radians(half_angle)
    out = []
    for k in range(3):
        t = 2 * np.pi * k / 3
        radial = np.array([np.cos(t), np.sin(t), 0.0])
        out.append(unit(np.cos(h) * np.asarray(up, float) - np.sin(h) * radial))
    return out


def pin(point, axis, radius, length=20.0):
    cyl = trimesh.creation.cylinder(radius=radius, height=length, sections=256)
    cyl.apply_transform(trimesh.geometry.align_vectors([0, 0, 1], unit(axis)))
    return cyl.apply_translation(point)


def combine(parts):
    return trimesh.util.concatenate(parts)


THREE_VEE_CENTERS = [
    np.array([50 * np.cos(t), 50 * np.sin(t), 0.0]) for t in np.radians([90, 210, 330])
]


def three_vee(lift=0.0):
    """Three radial 90° vees on the base, three balls on a plate above (the body)."""
    base, body = [], []
    for c in THREE_VEE_CENTERS:
        base += vee(c, axis=unit([c[0], c[1], 0]))
        body.append(ball(c + [0, 0, lift]))
    plate = trimesh.creation.box(extents=[130, 130, 6]).apply_translation([0, 0, 9 + lift])
    return combine(base), combine([*body, plate])


def expected_three_vee():
    """(point, normal) of the six contacts of :func:`three_vee`, closed form."""
    out = []
    for c in THREE_VEE_CENTERS:
        for n in vee_normals(unit([c[0], c[1], 0]), [0, 0, 1], 45.0):
            out.append((c - R * n, n))
    return out
