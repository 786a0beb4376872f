"""Reading a scene file: YAML → field models → checked values in SI units.

Every error of a file is collected and raised together (:class:`~kcheck.errors.SceneErrors`),
each naming the file, the field, its line (and column) and what was expected. Loading never
touches a mesh beyond checking that its path is a readable file (mass properties are
:mod:`kcheck.body.mass`'s, computed only when a check needs them).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from kcheck.numerics.thresholds import PARALLEL_COS, PARALLEL_SIN, ZERO_GUARD
from kcheck.scene.accept import accept
from kcheck.scene.body import BodyReader, rotation_matrix
from kcheck.scene.coefficients import resolve_friction
from kcheck.scene.limits import LIMITS, MIN_FORCE
from kcheck.scene.materials import canonical, known_names
from kcheck.scene.shorthands import contact_count, expand_coupling
from kcheck.scene.types import (
    PLANAR_TOL,
    Body,
    ContactGeometry,
    Friction,
    Load,
    Preload,
    Scene,
    Support,
    Surface,
    Sweep,
    Tolerances,
)
from kcheck.scene.units import LENGTH_TO_M
from kcheck.scene.validate import Problems, consequence_of, plain_value_problems, salvage
from kcheck.scene.yamlio import (
    DEFAULT_LIMITS,
    FieldPath,
    YamlDocument,
    YamlLimits,
    format_path,
    read_yaml,
)

if TYPE_CHECKING:  # records of kcheck.scene.accept read like them; pydantic only for errors
    from kcheck.scene.models import BodyModel, ContactModel, LoadModel, SceneModel, SweepModel

__all__ = ["SCENE_GLOB", "load_scene", "scene_from_document", "rotation_matrix"]

SCENE_GLOB = "*.kcheck.yaml"


def load_scene(
    path: Path | str, *, allow_outside: bool = False, limits: YamlLimits = DEFAULT_LIMITS
) -> Scene:
    """Read and validate a scene file; raise SceneError (SceneErrors for several), each
    naming file, field, line and what was expected."""
    path = Path(path)
    return scene_from_document(path, read_yaml(path, limits=limits), allow_outside=allow_outside)


def scene_from_document(
    path: Path, document: YamlDocument, *, allow_outside: bool = False
) -> Scene:
    """Validate the plain data of a scene file read before (or changed since: a study's
    variant, :mod:`kcheck.scene.variants`); errors are located in ``path`` by the document's
    lines."""
    problems = Problems(path, document.lines, document.columns)
    data = document.data
    if not isinstance(data, dict):
        raise problems.error((), f"expected a mapping of scene fields, got {type(data).__name__}")
    plain_value_problems(data, problems)
    # Values are checked on what is left of a file with wrong fields too (every mistake in
    # one run); an error that only follows from leaving a field out is not one of them.
    # Not when `units` is wrong: every length is read in it.
    # A valid file is read without pydantic (issue 24: start-up); any doubt, pydantic decides.
    model: Any = None if problems.errors else accept(data)
    dropped: set[FieldPath] = set()
    if model is None:
        model, dropped = salvage(data, problems)
    if model is None or ("units",) in dropped:
        problems.raise_if_any()
    said = len(problems.errors)
    scene = _Builder(path, model, problems, allow_outside, document).build()
    problems.errors[said:] = [
        e for e in problems.errors[said:] if not consequence_of(e.where, dropped)
    ]
    problems.raise_if_any()
    assert scene is not None
    return scene


def _with_friction(support: Support, mu: Friction) -> Support:
    """The support with its coefficients: ``friction`` the largest, the ranges kept when
    they are more than one number."""
    spec = None if mu.plain else mu
    return dataclasses.replace(support, friction=mu.largest, friction_spec=spec)


class _Builder:
    """Turns a validated model into a Scene, collecting every semantic error."""

    def __init__(
        self,
        path: Path,
        model: SceneModel,
        problems: Problems,
        allow_outside: bool,
        document: Any,
    ) -> None:
        self.path = path
        self.m = model
        self.p = problems
        self.allow_outside = allow_outside
        self.document = document
        self.scale = LENGTH_TO_M[model.units]
        self.notes: list[str] = []

    def build(self) -> Scene | None:
        m, p = self.m, self.p
        supports, fields = self.supports()
        kind: Literal["planar", "spatial"] | None = None
        if not (p.has(("supports",)) or p.has(("couplings",))):
            kind = self.kind(supports, fields)
        if kind is not None:
            self.layout(supports)
        planar = kind == "planar"
        sweep = self.sweep(m.sweep, planar, given="sweep" in m.model_fields_set)
        gravity = np.zeros(3)
        if m.gravity is not None:
            g = p.magnitude(("gravity",), m.gravity, "gravity")
            if g is not None:
                gravity = g
                if planar and gravity[2] != 0:
                    self.notes.append(
                        "gravity's z component is carried by the plane of motion and is ignored"
                    )
        load = None
        if m.load is not None and sweep is not None:
            load = self.load(m.load, sweep, planar)
        preloads = self.preloads(planar)
        tolerances = self.tolerances()
        # Without a known kind (the supports are wrong), don't judge a lone I_zz either way.
        body = None if m.body is None else self.body(m.body, planar or kind is None)
        if p.errors or kind is None or sweep is None:
            return None
        return Scene(
            path=self.path,
            name=m.name or self.path.name.removesuffix(".kcheck.yaml"),
            units=m.units,
            scale=self.scale,
            kind=kind,
            supports=supports,
            gravity=gravity,
            load=load,
            sweep=sweep,
            body=body,
            check_options={k: dict(v or {}) for k, v in m.checks.items()},
            lines=self.document.lines,
            notes=tuple(self.notes),
            preloads=preloads,
            columns=self.document.columns,
            tolerances=tolerances,
        )

    # --- supports -------------------------------------------------------------------------

    def supports(self) -> tuple[tuple[Support, ...], list[FieldPath]]:
        """Explicit supports, then every coupling's contacts; the field of each."""
        m, p = self.m, self.p
        out: list[Support] = []
        fields: list[FieldPath] = []
        names: dict[str, FieldPath] = {}
        scene_mu = resolve_friction(m.friction, ("friction",), p)

        for i, s in enumerate(m.supports):
            where: FieldPath = ("supports", i)
            self.unique_name(names, s.name, where)
            position = p.coordinates((*where, "position"), s.position, self.scale)
            normal = p.direction((*where, "normal"), s.normal, "the normal")
            if position is None or normal is None:
                continue
            mu = scene_mu
            if s.friction is not None:
                mu = resolve_friction(s.friction, (*where, "friction"), p)
            support = Support(s.name, position, normal, 0.0, None, where)
            if s.contact is not None:
                contact = self.contact(s.name, s.contact, (*where, "contact"), position, normal)
                support = dataclasses.replace(support, contact=contact)
            out.append(_with_friction(support, mu))
            fields.append(where)
        for i, c in enumerate(m.couplings):
            where = ("couplings", i)
            mu = scene_mu
            if c.friction is not None:
                mu = resolve_friction(c.friction, (*where, "friction"), p)
            made = expand_coupling(c, where, self.p, self.scale, mu.largest)
            for k in range(1, contact_count(c) + 1):
                self.unique_name(names, f"{c.name}.{k}", where)
            ball = self.material((*where, "ball_material"), c.ball_material)
            seat = self.material((*where, "seat_material"), c.seat_material)
            for made_support in made or ():
                g = made_support.geometry
                assert g is not None
                g = dataclasses.replace(g, ball_material=ball, seat_material=seat)
                support = dataclasses.replace(made_support, field=where, geometry=g)
                out.append(_with_friction(support, mu))
                fields.append(where)
            if made and c.type == "ball-cone":
                self.notes.append(
                    f"coupling `{c.name}` (ball-cone) is a line contact around a circle, "
                    "modelled as 3 points 120° apart"
                )
        return tuple(out), fields

    def material(self, where: FieldPath, name: str | None) -> str | None:
        """The table's name of a material given at ``where`` (None if not given); an error if
        the table does not know it."""
        if name is None:
            return None
        found = canonical(name)
        if found is None:
            self.p.add(where, f"unknown material `{name}`; known: {known_names()}")
        return found

    def contact(
        self, name: str, c: ContactModel, where: FieldPath, position: np.ndarray, normal: np.ndarray
    ) -> ContactGeometry | None:
        """An explicit support's contact shape (SI), or None after recording its errors."""
        p = self.p
        ok = p.in_range((*where, "ball_radius"), c.ball_radius, "radius", self.scale)
        radii = [math.inf if r is None else float(r) * self.scale for r in c.seat_radii or ()]
        radii = radii or [math.inf, math.inf]
        for j, r in enumerate(radii):
            if r != math.inf and not p.in_range((*where, "seat_radii", j), abs(r), "radius"):
                ok = False
        direction = None
        if c.seat_direction is not None:
            direction = p.direction((*where, "seat_direction"), c.seat_direction, "the direction")
            ok &= direction is not None
            if direction is not None and abs(direction @ normal) > PARALLEL_COS:
                p.add((*where, "seat_direction"), "is along the support's normal; it must not be")
                ok = False
        elif radii[0] != radii[1]:
            p.add(
                (*where, "seat_direction"),
                "expected the direction of the seat's first radius: its two radii differ",
            )
            ok = False
        ball_radii = [float(r) * self.scale for r in c.ball_radii or (c.ball_radius,) * 2]
        for j, r in enumerate(c.ball_radii or ()):
            ok &= p.in_range((*where, "ball_radii", j), r, "radius", self.scale)
        ball_direction = None
        if c.ball_direction is not None:
            ball_direction = p.direction((*where, "ball_direction"), c.ball_direction, "it")
            ok &= ball_direction is not None
        elif ball_radii[0] != ball_radii[1]:
            p.add(
                (*where, "ball_direction"),
                "expected the direction of the ball's first radius: its two radii differ",
            )
            ok = False
        ball_material = self.material((*where, "ball_material"), c.ball_material)
        seat_material = self.material((*where, "seat_material"), c.seat_material)
        if not ok:
            return None
        r = float(c.ball_radius) * self.scale
        ball = Surface((ball_radii[0], ball_radii[1]), ball_direction)
        seat = Surface((radii[0], radii[1]), direction)
        # The normal points into the body: a ball on the base sits below the contact point.
        sign = -1.0 if c.ball_on == "base" else 1.0
        body, base = (ball, seat) if c.ball_on == "body" else (seat, ball)
        return ContactGeometry(
            coupling=name,
            kind="explicit",
            index=1,
            ball_center=position + sign * r * normal,
            ball_radius=r,
            ball_on=c.ball_on,
            body=body,
            base=base,
            ball_material=ball_material,
            seat_material=seat_material,
        )

    def unique_name(self, names: dict[str, FieldPath], name: str, where: FieldPath) -> None:
        """Record a support's name; an error if another support has it."""
        if name in names:
            self.p.add(
                (*where, "name"),
                f"support name `{name}` used twice (also {format_path(names[name])})",
            )
        else:
            names[name] = where

    def kind(self, supports: tuple[Support, ...], fields: list[FieldPath]) -> Any:
        """``planar`` (3 supports in the xy-plane) or ``spatial`` (6); else an error."""
        n = len(supports)
        if n == 6:
            return "spatial"
        where: FieldPath = (
            ("supports",) if self.m.supports or not self.m.couplings else ("couplings",)
        )
        if n != 3:
            detail = ""
            if self.m.couplings:
                detail = (
                    f" ({len(self.m.supports)} in `supports`, {n - len(self.m.supports)} "
                    "from `couplings`)"
                )
            self.p.add(where, f"expected 3 supports (planar) or 6 (spatial), got {n}{detail}")
            return None
        positions = np.array([s.position for s in supports])
        length = float(np.ptp(positions, axis=0).max())
        ok = True
        for s, f in zip(supports, fields, strict=True):
            if abs(s.normal[2]) > PLANAR_TOL:
                at = (*f, "normal") if f[0] == "supports" else f
                self.p.add(
                    at,
                    "a 3-support (planar) scene needs normals in the xy-plane (z = 0), "
                    f"got {np.round(s.normal, 12).tolist()}",
                )
                ok = False
        z = positions[:, 2]
        if np.ptp(z) > PLANAR_TOL * max(length, ZERO_GUARD):
            self.p.add(
                where,
                "a 3-support (planar) scene needs every support at the same z, "
                f"got z = {z.tolist()} m",
            )
            ok = False
        return "planar" if ok else None

    def layout(self, supports: tuple[Support, ...]) -> None:
        """The supports' size (their largest distance from their centroid) within
        ``LIMITS["layout"]``: the algebra divides lengths by it."""
        positions = np.array([s.position for s in supports])
        offsets = positions - positions.mean(axis=0)
        big = float(np.abs(offsets).max())  # scaled first: the squares of 1e-300 underflow
        size = big * float(np.linalg.norm(offsets / big, axis=1).max()) if big > 0 else 0.0
        r = LIMITS["layout"]
        if r.contains(size):
            return
        where: FieldPath = ("supports",) if self.m.supports else ("couplings",)
        self.p.add(
            where,
            f"the supports lie within {size / self.scale:.3g} {self.m.units} ({size:.3g} m) of "
            f"their centroid, less than the smallest layout kcheck checks, {r.low:g} m "
            "(are the units right?)"
            if size < r.low
            else f"the supports lie {size:.3g} m from their centroid: {r.text()}",
        )

    # --- forces and frames ----------------------------------------------------------------

    def sweep(self, model: SweepModel, planar: bool, given: bool) -> Sweep | None:
        p = self.p
        normal = p.direction(("sweep", "normal"), model.normal, "the sweep plane normal")
        zero = p.direction(("sweep", "zero"), model.zero, "the sweep zero direction")
        if normal is None or zero is None:
            return None
        e1 = zero - (zero @ normal) * normal
        if np.linalg.norm(e1) < PARALLEL_SIN:
            p.add(("sweep", "zero"), "expected a direction not parallel to the sweep normal")
            return None
        e1 = e1 / np.linalg.norm(e1)
        if planar and abs(abs(normal[2]) - 1) > PLANAR_TOL:
            p.add(("sweep", "normal"), "a planar scene sweeps in the xy-plane: use [0, 0, 1]")
            return None
        # np.cross of two 3-vectors written out (its multiplies and subtractions, the same
        # floats; its call was most of this method's time).
        n0, n1, n2 = normal.tolist()
        z0, z1, z2 = e1.tolist()
        e2 = np.array([n1 * z2 - n2 * z1, n2 * z0 - n0 * z2, n0 * z1 - n1 * z0])
        return Sweep(normal, e1, e2, given)

    def load(self, model: LoadModel, sweep: Sweep, planar: bool) -> Load | None:
        p = self.p
        where: FieldPath = ("load",)
        if model.direction is not None and model.angle is not None:
            p.add(where, "give either `direction` or `angle`, not both")
            return None
        direction = None
        if model.direction is not None:
            direction = p.direction((*where, "direction"), model.direction, "the load direction")
        elif model.angle is not None:
            direction = sweep.direction(model.angle)
        if planar and direction is not None and abs(direction[2]) > PLANAR_TOL:
            p.add((*where, "direction"), "a planar scene needs a load direction with z = 0")
        torque = np.zeros(3)
        if model.torque is not None:
            t = p.magnitude((*where, "torque"), model.torque, "torque")
            if t is not None:
                torque = t
                if planar and np.any(torque[:2] != 0):
                    self.notes.append("torque x/y components act out of the plane and are ignored")
        point = None
        if model.point is not None:
            point = p.coordinates((*where, "point"), model.point, self.scale)
        if 0 < model.magnitude < MIN_FORCE:
            p.add(
                (*where, "magnitude"),
                f"out of range: a load is 0 (none) or at least {MIN_FORCE:g} N, "
                f"got {model.magnitude:g}",
            )
        return Load(float(model.magnitude), point, direction, torque)

    def preloads(self, planar: bool) -> tuple[Preload, ...]:
        p = self.p
        out = []
        names: dict[str, int] = {}
        for i, pre in enumerate(self.m.preloads):
            where: FieldPath = ("preloads", i)
            if pre.name in names:
                p.add((*where, "name"), f"preload name `{pre.name}` used twice")
            names[pre.name] = i
            point = p.coordinates((*where, "point"), pre.point, self.scale)
            force = p.magnitude((*where, "force"), pre.force, "force")
            if force is not None and 0 < np.linalg.norm(force) < MIN_FORCE:
                p.add(
                    (*where, "force"),
                    f"out of range: a preload is at least {MIN_FORCE:g} N, got {pre.force}",
                )
                continue
            if point is None or force is None:
                continue
            if planar and force[2] != 0:
                self.notes.append(
                    f"preload `{pre.name}`: its z component is carried by the plane of motion "
                    "and is ignored"
                )
            out.append(Preload(pre.name, point, force))
        return tuple(out)

    def tolerances(self) -> Tolerances | None:
        """The `tolerances:` entry in SI (positions in m, angles in degrees)."""
        t = self.m.tolerances
        if t is None:
            return None
        self.p.in_range(("tolerances", "position"), t.position, "tolerance_length", self.scale)
        return Tolerances(t.position * self.scale, t.normal, t.load_direction)

    # --- body -----------------------------------------------------------------------------

    def body(self, model: BodyModel, planar: bool) -> Body | None:
        """The body (:mod:`kcheck.scene.body`)."""
        return BodyReader(self.path, self.p, self.m.units, self.allow_outside).body(model, planar)
