"""Reading a scene file: YAML → field models → checked values in SI units.

Every error of a file is collected and raised together (:class:`~kcheck.errors.SceneErrors`),
each naming the file, the field, its line (and column) and what was expected. Loading never
touches a mesh beyond checking that its path is a readable file (mass properties are
:mod:`kcheck.mass`'s, computed only when a check needs them).
"""

from __future__ import annotations

import dataclasses
import errno
import os
import stat
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import ValidationError

from kcheck import couplings
from kcheck.scene.limits import INERTIA_SYMMETRY_RTOL, LIMITS, MIN_FORCE
from kcheck.scene.models import (
    BodyModel,
    LoadModel,
    PartModel,
    SceneModel,
    SweepModel,
    TransformModel,
)
from kcheck.scene.types import (
    PLANAR_TOL,
    Body,
    ExplicitMass,
    Load,
    Part,
    PointMass,
    Preload,
    Scene,
    Support,
    Sweep,
)
from kcheck.scene.validate import Problems, plain_value_problems, pydantic_problems
from kcheck.units import LENGTH_TO_M, MATERIALS, density_of
from kcheck.yamlio import DEFAULT_LIMITS, FieldPath, YamlLimits, read_yaml

__all__ = ["SCENE_GLOB", "load_scene", "rotation_matrix"]

SCENE_GLOB = "*.kcheck.yaml"
STEP_SUFFIXES = (".step", ".stp")


def load_scene(
    path: Path | str, *, allow_outside: bool = False, limits: YamlLimits = DEFAULT_LIMITS
) -> Scene:
    """Read and validate a scene file; raise SceneError (SceneErrors for several), each
    naming file, field, line and what was expected."""
    path = Path(path)
    document = read_yaml(path, limits=limits)
    problems = Problems(path, document.lines, document.columns)
    data = document.data
    if not isinstance(data, dict):
        raise problems.error((), f"expected a mapping of scene fields, got {type(data).__name__}")
    plain_value_problems(data, problems)
    model: SceneModel | None = None
    try:
        model = SceneModel.model_validate(data)
    except ValidationError as exc:
        pydantic_problems(exc, SceneModel, problems)
    problems.raise_if_any()
    assert model is not None
    scene = _Builder(path, model, problems, allow_outside, document).build()
    problems.raise_if_any()
    assert scene is not None
    return scene


def rotation_matrix(axis: np.ndarray, angle_deg: float) -> np.ndarray:
    """Proper rotation by ``angle_deg`` about the unit ``axis`` (Rodrigues)."""
    a = np.radians(angle_deg)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * (k @ k)


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
        if not p.errors:
            kind = self.kind(supports, fields)
        planar = kind == "planar"
        sweep = self.sweep(m.sweep, planar)
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
        )

    # --- supports -------------------------------------------------------------------------

    def supports(self) -> tuple[tuple[Support, ...], list[FieldPath]]:
        """Explicit supports, then every coupling's contacts; the field of each."""
        m, p = self.m, self.p
        out: list[Support] = []
        fields: list[FieldPath] = []
        names: dict[str, FieldPath] = {}

        for i, s in enumerate(m.supports):
            where: FieldPath = ("supports", i)
            self.unique_name(names, s.name, where)
            position = p.coordinates((*where, "position"), s.position, self.scale)
            normal = p.direction((*where, "normal"), s.normal, "the normal")
            if position is None or normal is None:
                continue
            mu = m.friction if s.friction is None else s.friction
            out.append(Support(s.name, position, normal, float(mu), None, where))
            fields.append(where)
        for i, c in enumerate(m.couplings):
            where = ("couplings", i)
            made = self.coupling(c, where)
            for k in range(1, _contact_count(c) + 1):
                self.unique_name(names, f"{c.name}.{k}", where)
            for s in made or ():
                out.append(dataclasses.replace(s, field=where))
                fields.append(where)
            if made and c.type == "ball-cone":
                self.notes.append(
                    f"coupling `{c.name}` (ball-cone) is a line contact around a circle, "
                    "modelled as 3 points 120° apart"
                )
        return tuple(out), fields

    def unique_name(self, names: dict[str, FieldPath], name: str, where: FieldPath) -> None:
        """Record a support's name; an error if another support has it."""
        if name in names:
            self.p.add(
                (*where, "name"), f"support name `{name}` used twice (also {_show(names[name])})"
            )
        else:
            names[name] = where

    def coupling(self, c: Any, where: FieldPath) -> tuple[Support, ...] | None:
        """The supports of one coupling entry, or None after recording its errors."""
        p, scale = self.p, self.scale
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
                    contacts = couplings.ball_vee(center, radius, axis, up, c.groove.half_angle)
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
        if not ok:
            return None
        mu = self.m.friction if c.friction is None else c.friction
        return couplings.supports(
            c.name, c.type, center, radius, contacts, c.ball_on, float(mu), scale
        )

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
        if np.ptp(z) > PLANAR_TOL * max(length, 1e-300):
            self.p.add(
                where,
                "a 3-support (planar) scene needs every support at the same z, "
                f"got z = {z.tolist()} m",
            )
            ok = False
        return "planar" if ok else None

    # --- forces and frames ----------------------------------------------------------------

    def sweep(self, model: SweepModel, planar: bool) -> Sweep | None:
        p = self.p
        normal = p.direction(("sweep", "normal"), model.normal, "the sweep plane normal")
        zero = p.direction(("sweep", "zero"), model.zero, "the sweep zero direction")
        if normal is None or zero is None:
            return None
        e1 = zero - (zero @ normal) * normal
        if np.linalg.norm(e1) < 1e-9:
            p.add(("sweep", "zero"), "expected a direction not parallel to the sweep normal")
            return None
        e1 = e1 / np.linalg.norm(e1)
        if planar and abs(abs(normal[2]) - 1) > PLANAR_TOL:
            p.add(("sweep", "normal"), "a planar scene sweeps in the xy-plane: use [0, 0, 1]")
            return None
        return Sweep(normal, e1, np.cross(normal, e1))

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

    # --- body -----------------------------------------------------------------------------

    def body(self, model: BodyModel, planar: bool) -> Body | None:
        p = self.p
        where: FieldPath = ("body",)
        explicit = self.explicit(model, planar)
        has_explicit = model.mass is not None or model.inertia is not None
        parts: list[Part] = []
        if model.mesh is not None and model.parts is not None:
            p.add(where, "give either `mesh` or `parts`, not both")
        elif model.mesh is not None:
            rho = self.density(where, model.material, model.density, has_explicit)
            mesh = self.mesh_path((*where, "mesh"), model.mesh)
            if mesh is not None and rho is not None:
                parts.append(self.part(mesh, rho, where, None, None, model.repair))
        elif model.parts is not None:
            if model.material is not None or model.density is not None:
                p.add(where, "with `parts`, give `material`/`density` per part")
            for i, pm in enumerate(model.parts):
                pw: FieldPath = (*where, "parts", i)
                rho = self.density(pw, pm.material, pm.density, has_explicit)
                mesh = self.mesh_path((*pw, "mesh"), pm.mesh)
                if mesh is not None and rho is not None:
                    parts.append(self.part(mesh, rho, pw, pm, pm.transform, pm.repair))
        elif not has_explicit and model.center_of_mass is None:
            p.add(where, "expected `mesh`, `parts`, or explicit mass properties")
        if model.repair and model.mesh is None:
            p.add((*where, "repair"), "`repair` applies to `mesh`; with `parts`, set it per part")
        point_masses = []
        names: set[str] = set()
        for i, pm in enumerate(model.point_masses):
            pw = (*where, "point_masses", i)
            if pm.name in names:
                p.add((*pw, "name"), f"point mass name `{pm.name}` used twice")
            names.add(pm.name)
            point = p.coordinates((*pw, "point"), pm.point, self.scale)
            if p.in_range((*pw, "mass"), pm.mass, "mass") and point is not None:
                point_masses.append(PointMass(pm.name, float(pm.mass), point))
        return Body(tuple(parts), explicit, tuple(point_masses))

    def density(
        self, where: FieldPath, material: str | None, density: float | None, optional: bool
    ) -> float | None:
        """kg/m^3 from exactly one of `material` and `density`; 0.0 when explicit mass
        properties make it unnecessary and neither is given."""
        p = self.p
        if material is not None and density is not None:
            p.add(where, "give either `material` or `density`, not both")
            return None
        if density is not None:
            return density
        if material is None:
            if optional:
                return 0.0
            p.add(
                where,
                "expected `material` or `density` for the mesh (trimesh would assume 1 kg/m^3)",
            )
            return None
        value = density_of(material)
        if value is None:
            known = ", ".join(sorted(MATERIALS))
            p.add((*where, "material"), f"unknown material `{material}`; known: {known}")
        return value

    def part(
        self,
        mesh: Path,
        density: float,
        where: FieldPath,
        model: PartModel | None,
        transform: TransformModel | None,
        repair: bool,
    ) -> Part:
        units = self.m.units if model is None or model.units is None else model.units
        scale = LENGTH_TO_M[units]
        if mesh.suffix.lower() in STEP_SUFFIXES:
            if model is not None and model.units is not None:
                self.p.add(
                    (*where, "units"),
                    "a STEP file declares its own length unit (it is read in metres); "
                    "remove `units`",
                )
            units, scale = "m", 1.0
        rotation = None
        translation = (0.0, 0.0, 0.0)
        if transform is not None:
            tw: FieldPath = (*where, "transform")
            if transform.translate is not None:
                t = self.p.coordinates((*tw, "translate"), transform.translate, self.scale)
                if t is not None:
                    translation = (float(t[0]), float(t[1]), float(t[2]))
            if transform.rotate is not None:
                r = self.rotation((*tw, "rotate"), transform.rotate)
                if r is not None:
                    rotation = tuple(tuple(float(x) for x in row) for row in r)
        return Part(mesh, density, where, scale, units, rotation, translation, repair)  # type: ignore[arg-type]

    def rotation(self, where: FieldPath, value: Any) -> np.ndarray | None:
        """A proper rotation from axis-angle or a 3x3 matrix (checked, then orthonormalised)."""
        if not isinstance(value, list):
            axis = self.p.direction((*where, "axis"), value.axis, "the rotation axis")
            return None if axis is None else rotation_matrix(axis, value.angle)
        r = np.asarray(value, dtype=float)
        if not np.all(np.abs(r) <= 1.0 + 1e-6):
            self.p.add(where, f"not a rotation matrix: entries must lie in [-1, 1], got {value}")
            return None
        error = float(np.abs(r.T @ r - np.eye(3)).max())
        if error > 1e-6:
            self.p.add(
                where,
                f"not a rotation matrix: RᵀR differs from the identity by {error:.3g} "
                "(allowed 1e-6); its columns must be orthonormal",
            )
            return None
        if np.linalg.det(r) < 0:
            self.p.add(
                where,
                "not a rotation: the matrix mirrors (determinant -1); a mirrored part "
                "is a different part — mirror it in CAD",
            )
            return None
        u, _, vt = np.linalg.svd(r)  # the nearest exact rotation
        return u @ vt

    def mesh_path(self, where: FieldPath, name: str) -> Path | None:
        """The mesh file, resolved; confined to the scene's folder unless allowed."""
        p = self.p
        folder = self.path.parent.resolve()
        candidate = folder / name
        try:
            resolved = candidate.resolve()
        except (OSError, RuntimeError, ValueError):
            resolved = candidate
        if not self.allow_outside and not resolved.is_relative_to(folder):
            p.add(
                where,
                f"mesh path `{name}` leaves the scene's folder {folder}; "
                "pass --allow-outside-paths to permit it",
            )
            return None
        try:
            info = os.stat(candidate)
        except OSError as exc:
            p.add(where, f"mesh file `{name}` {_os_reason(candidate, exc)}")
            return None
        if stat.S_ISDIR(info.st_mode):
            p.add(where, f"mesh path `{name}` is a folder, not a mesh file")
            return None
        if not stat.S_ISREG(info.st_mode):
            p.add(where, f"mesh path `{name}` is not a regular file")
            return None
        if not os.access(candidate, os.R_OK):
            p.add(where, f"mesh file `{name}` cannot be read (permission denied)")
            return None
        return resolved

    def explicit(self, model: BodyModel, planar: bool) -> ExplicitMass | None:
        p = self.p
        where: FieldPath = ("body",)
        given = {
            "mass": model.mass,
            "center_of_mass": model.center_of_mass,
            "inertia": model.inertia,
        }
        if all(v is None for v in given.values()):
            return None
        missing = [k for k, v in given.items() if v is None]
        if missing:
            p.add(
                (*where, missing[0]),
                "explicit mass properties need `mass`, `center_of_mass` and `inertia` together",
            )
            return None
        mass_ok = p.in_range((*where, "mass"), float(model.mass), "mass")  # type: ignore[arg-type]
        inertia = self.inertia((*where, "inertia"), model.inertia, planar)
        com = p.coordinates((*where, "center_of_mass"), model.center_of_mass, self.scale)  # type: ignore[arg-type]
        if inertia is None or com is None or not mass_ok:
            return None
        return ExplicitMass(float(model.mass), com, inertia)  # type: ignore[arg-type]

    def inertia(self, where: FieldPath, value: Any, planar: bool) -> np.ndarray | None:
        p = self.p
        r = LIMITS["inertia"]
        if isinstance(value, (int, float)):
            if not planar:
                p.add(where, "a spatial scene needs the full 3x3 inertia tensor")
                return None
            if not p.in_range(where, float(value), "inertia"):
                return None
            # Only I_zz matters for motion in the xy-plane; the rest is never read.
            return np.diag([np.nan, np.nan, float(value)])
        tensor = np.asarray(value, dtype=float)
        largest = float(np.abs(tensor).max())
        if largest > r.high:
            p.add(where, f"out of range: expected entries |I| ≤ {r.high:g} kg m^2, got {value}")
            return None
        asym = float(np.abs(tensor - tensor.T).max())
        if asym > INERTIA_SYMMETRY_RTOL * largest:
            i, j = np.unravel_index(int(np.argmax(np.abs(tensor - tensor.T))), (3, 3))
            p.add(
                where,
                f"expected a symmetric inertia tensor (to {INERTIA_SYMMETRY_RTOL:g} of its "
                f"largest entry): [{i}][{j}] = {tensor[i, j]:g} but [{j}][{i}] = {tensor[j, i]:g}",
            )
            return None
        tensor = (tensor + tensor.T) / 2
        eig = np.linalg.eigvalsh(tensor)
        if eig.min() <= 0:
            p.add(where, f"expected a positive definite inertia tensor, eigenvalues {eig}")
            return None
        if eig.min() < r.low:
            p.add(where, f"out of range: expected {r.text()}, got {eig.min():g}")
            return None
        a, b, c = np.sort(eig)
        if a + b < c * (1 - 1e-6):
            p.add(
                where,
                f"principal moments {eig} violate the triangle inequality (not a rigid body)",
            )
            return None
        return tensor


def _contact_count(c: Any) -> int:
    """How many supports a coupling entry makes."""
    if c.type == "ball-cylinders":
        return len(c.cylinders)
    if c.type == "ball-sphere":
        return len(c.spheres)
    return {"ball-vee": 2, "ball-flat": 1}.get(c.type, 3)


def _show(where: FieldPath) -> str:
    from kcheck.errors import format_path

    return format_path(where)


def _os_reason(path: Path, exc: OSError) -> str:
    """Why a path cannot be opened, in words."""
    if exc.errno == errno.ELOOP:
        return "is a loop of symbolic links"
    if exc.errno == errno.ENAMETOOLONG:
        return "has a path too long for the operating system"
    if exc.errno == errno.ENOENT and os.path.islink(path):
        return f"is a dangling symbolic link (to {os.readlink(path)})"
    if exc.errno == errno.ENOENT:
        return f"not found (looked for {path})"
    if exc.errno == errno.EACCES:
        return "cannot be reached (permission denied)"
    if exc.errno == errno.ENOTDIR:
        return "cannot be reached: a folder on its path is a file"
    return f"cannot be read ({exc.strerror or exc})"
