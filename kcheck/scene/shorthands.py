"""Coupling shorthands of a scene file: each `couplings:` entry checked and expanded through
:mod:`kcheck.scene.couplings` (in the scene's units, then scaled to SI)."""

from __future__ import annotations

from typing import Any

import numpy as np

from kcheck.scene import couplings
from kcheck.scene.types import Support, Surface
from kcheck.scene.validate import Problems
from kcheck.scene.yamlio import FieldPath

__all__ = ["expand_coupling", "contact_count"]


def contact_count(c: Any) -> int:
    """How many supports a coupling entry makes."""
    if c.type == "ball-cylinders":
        return len(c.cylinders)
    if c.type == "ball-sphere":
        return len(c.spheres)
    return {"ball-vee": 2, "ball-flat": 1}.get(c.type, 3)


def expand_coupling(
    c: Any, where: FieldPath, p: Problems, scale: float, friction: float
) -> tuple[Support, ...] | None:
    """The supports (SI) of one `couplings:` entry, or None after recording its errors;
    ``scale`` is metres per scene unit, ``friction`` the entry's (largest) coefficient."""
    ok = p.coordinates((*where, "ball", "center"), c.ball.center, scale) is not None
    ok &= p.in_range((*where, "ball", "radius"), c.ball.radius, "radius", scale)
    center = np.asarray(c.ball.center, dtype=float)
    radius = float(c.ball.radius)

    def direction(field: FieldPath, vector: list[float] | None, what: str) -> Any:
        nonlocal ok
        if vector is None:
            return None
        v = p.direction((*where, *field), vector, what)
        ok &= v is not None
        return v

    contacts: list[couplings.Contact] = []
    try:
        if c.type == "ball-vee":
            axis = direction(("groove", "axis"), c.groove.axis, "the groove's axis")
            up = direction(("groove", "up"), c.groove.up, "the groove's `up`")
            if ok:
                contacts = couplings.ball_vee(
                    center, radius, axis, up, c.groove.half_angle, c.groove.radius
                )
        elif c.type == "ball-cylinders":
            cylinders = []
            for j, cyl in enumerate(c.cylinders):
                cw: FieldPath = ("cylinders", j)
                ok &= p.coordinates((*where, *cw, "point"), cyl.point, scale) is not None
                axis = direction((*cw, "axis"), cyl.axis, "the cylinder's axis")
                ok &= p.in_range((*where, *cw, "radius"), cyl.radius, "radius", scale)
                cylinders.append((np.asarray(cyl.point, dtype=float), axis, cyl.radius))
            if ok:
                contacts = couplings.ball_cylinders(center, radius, cylinders)
        elif c.type == "ball-sphere":
            spheres = []
            for j, sph in enumerate(c.spheres):
                sw: FieldPath = ("spheres", j)
                ok &= p.coordinates((*where, *sw, "center"), sph.center, scale) is not None
                ok &= p.in_range((*where, *sw, "radius"), sph.radius, "radius", scale)
                spheres.append((np.asarray(sph.center, dtype=float), sph.radius))
            if ok:
                contacts = couplings.ball_spheres(center, radius, spheres)
        elif c.type in ("ball-trihedral", "ball-cone"):
            up = direction(("up",), c.up, "`up`")
            ref = direction(("reference",), c.reference, "`reference`")
            if ok and c.type == "ball-trihedral":
                contacts = couplings.ball_trihedral(center, radius, up, c.half_angle, ref)
            elif ok:
                contacts = couplings.ball_cone(center, radius, up, c.half_angle, ref)
        elif c.type == "ball-flat":
            normal = direction(("normal",), c.normal, "the flat's normal")
            if ok:
                contacts = couplings.ball_flat(center, radius, normal)
    except couplings.CouplingError as exc:
        p.add((*where, *exc.where), str(exc))
        return None
    surface = _ball_surface(c, where, p, scale)
    if not ok or surface is False:
        return None
    return couplings.supports(
        c.name, c.type, center, radius, contacts, c.ball_on, friction, scale, surface
    )


def _ball_surface(c: Any, where: FieldPath, p: Problems, scale: float) -> Any:
    """A canoe ball's contact surface (scene units), None for a plain ball, False after
    recording an error."""
    radii = c.ball.surface_radii
    bw: FieldPath = (*where, "ball")
    if radii is None:
        if c.ball.surface_direction is not None:
            p.add((*bw, "surface_direction"), "applies only with `surface_radii`")
            return False
        return None
    ok = all(
        [p.in_range((*bw, "surface_radii", j), r, "radius", scale) for j, r in enumerate(radii)]
    )
    direction = None
    if c.ball.surface_direction is not None:
        direction = p.direction((*bw, "surface_direction"), c.ball.surface_direction, "it")
        ok &= direction is not None
    elif radii[0] != radii[1]:
        p.add(
            (*bw, "surface_direction"),
            "expected the direction of the first surface radius: the two radii differ",
        )
        ok = False
    return Surface((float(radii[0]), float(radii[1])), direction) if ok else False
