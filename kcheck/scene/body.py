"""The scene's body: mesh parts (paths confined and checked, units, transforms), point masses
and explicit mass properties, each field checked and every error collected."""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.errors import describe_os_error
from kcheck.numerics.thresholds import PRINCIPAL_TRIANGLE_RTOL, ROTATION_TOL
from kcheck.scene.limits import INERTIA_SYMMETRY_RTOL, LIMITS
from kcheck.scene.materials import canonical, density_of, known_names
from kcheck.scene.types import Body, ExplicitMass, Part, PointMass
from kcheck.scene.units import LENGTH_TO_M
from kcheck.scene.validate import Problems
from kcheck.scene.yamlio import FieldPath

if TYPE_CHECKING:  # records of kcheck.scene.accept read like them; pydantic only for errors
    from kcheck.scene.models import BodyModel, PartModel, TransformModel

__all__ = ["BodyReader", "STEP_SUFFIXES", "rotation_matrix"]

STEP_SUFFIXES = (".step", ".stp")


def rotation_matrix(axis: np.ndarray, angle_deg: float) -> np.ndarray:
    """Proper rotation by ``angle_deg`` about the unit ``axis`` (Rodrigues)."""
    a = np.radians(angle_deg)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * (k @ k)


class BodyReader:
    """Reads the ``body`` field of one scene file into a :class:`~kcheck.scene.Body`."""

    def __init__(self, path: Path, problems: Problems, units: str, allow_outside: bool) -> None:
        self.path = path
        self.p = problems
        self.units = units
        self.scale = LENGTH_TO_M[units]
        self.allow_outside = allow_outside

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
        else:
            if not has_explicit and model.center_of_mass is None:
                p.add(where, "expected `mesh`, `parts`, or explicit mass properties")
            if model.material is not None or model.density is not None:
                # Unused without a mesh, but held to the same rules as with one: a material
                # must be in the table, and `material` and `density` are never both given.
                self.density(where, model.material, model.density, True)
        if model.repair and model.mesh is None:
            p.add((*where, "repair"), "`repair` applies to `mesh`; with `parts`, set it per part")
        point_masses = []
        names: set[str] = set()
        for i, point_mass in enumerate(model.point_masses):
            pw = (*where, "point_masses", i)
            if point_mass.name in names:
                p.add((*pw, "name"), f"point mass name `{point_mass.name}` used twice")
            names.add(point_mass.name)
            point = p.coordinates((*pw, "point"), point_mass.point, self.scale)
            if p.in_range((*pw, "mass"), point_mass.mass, "mass") and point is not None:
                point_masses.append(PointMass(point_mass.name, float(point_mass.mass), point))
        given = [model.material] + [pm.material for pm in model.parts or ()]
        named = (canonical(m) for m in given if m is not None)
        materials = tuple(dict.fromkeys(m for m in named if m is not None))
        return Body(tuple(parts), explicit, tuple(point_masses), materials)

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
            p.add((*where, "material"), f"unknown material `{material}`; known: {known_names()}")
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
        units = self.units if model is None or model.units is None else model.units
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
        if not np.all(np.abs(r) <= 1.0 + ROTATION_TOL):
            self.p.add(where, f"not a rotation matrix: entries must lie in [-1, 1], got {value}")
            return None
        error = float(np.abs(r.T @ r - np.eye(3)).max())
        if error > ROTATION_TOL:
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
        if a + b < c * (1 - PRINCIPAL_TRIANGLE_RTOL):
            p.add(
                where,
                f"principal moments {eig} violate the triangle inequality (not a rigid body)",
            )
            return None
        return tensor


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
    return f"cannot be read ({describe_os_error(exc)})"
