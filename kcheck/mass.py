"""Mass properties of the body from its mesh(es), in SI units, gated for meaningful input.

trimesh is imported here and only here, and only when a check needs mass properties.
Meshes are scaled explicitly from the scene's ``units`` (never guessed from file names), the
density is always set (trimesh defaults to 1), and a mesh that cannot have a meaningful centre
of mass (open, inconsistent winding, inverted, empty, zero volume) is an error, not a number.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from kcheck.errors import FieldPath, MeshError
from kcheck.scene import Body, Part

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "MassProperties",
    "body_mass_properties",
    "combine",
    "load_mesh",
    "mesh_mass_properties",
    "principal_axes",
]


@dataclass(frozen=True)
class MassProperties:
    """Mass (kg), centre of mass (m), inertia tensor about the centre of mass (kg m^2)."""

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    source: Literal["mesh", "explicit"]
    volume: float | None = None
    notes: tuple[str, ...] = ()

    def to_json(self) -> dict[str, object]:
        """The documented JSON form (SI units)."""
        out: dict[str, object] = {
            "mass": self.mass,
            "center_of_mass": self.center_of_mass.tolist(),
            "inertia": np.where(np.isfinite(self.inertia), self.inertia, None).tolist(),
            "source": self.source,
        }
        if self.volume is not None:
            out["volume"] = self.volume
        if self.notes:
            out["notes"] = list(self.notes)
        return out


def principal_axes(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending, kg m^2) and axes (columns) of an inertia tensor."""
    moments, axes = np.linalg.eigh(inertia)
    return moments, axes


def combine(parts: Sequence[MassProperties]) -> MassProperties:
    """Combine bodies rigidly joined: masses add, inertias move by the parallel-axis theorem."""
    mass = sum(p.mass for p in parts)
    com = sum(p.mass * p.center_of_mass for p in parts) / mass
    inertia = np.zeros((3, 3))
    for p in parts:
        r = p.center_of_mass - com
        inertia += p.inertia + p.mass * (np.dot(r, r) * np.eye(3) - np.outer(r, r))
    volume = None
    if all(p.volume is not None for p in parts):
        volume = float(sum(p.volume for p in parts))  # type: ignore[misc]
    notes = tuple(n for p in parts for n in p.notes)
    return MassProperties(float(mass), com, inertia, parts[0].source, volume, notes)


def load_mesh(path: Path, scale: float, field: FieldPath | str) -> trimesh.Trimesh:
    """Load a mesh file as one Trimesh scaled to metres; MeshError if it is unusable."""
    import trimesh

    try:
        # force="mesh" bakes scene graphs (glTF, 3MF, ...) into one mesh with transforms applied.
        mesh = trimesh.load_mesh(str(path), process=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise MeshError(
            path, f"cannot read the mesh ({type(exc).__name__}: {exc})", field=field
        ) from exc
    if isinstance(mesh, trimesh.Scene):
        mesh = mesh.to_mesh()
    if not isinstance(mesh, trimesh.Trimesh) or mesh.is_empty or len(mesh.faces) == 0:
        raise MeshError(path, "the mesh is empty (no triangles)", field=field)
    mesh = mesh.copy()
    mesh.apply_scale(scale)
    return mesh


def mesh_mass_properties(
    mesh: trimesh.Trimesh, density: float, path: Path, field: FieldPath | str
) -> MassProperties:
    """Mass properties (SI) of a closed mesh already in metres, after gating it."""
    if not np.all(np.isfinite(mesh.vertices)):
        raise MeshError(path, "the mesh has non-finite vertex coordinates", field=field)
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    areas = mesh.area_faces
    degenerate = int(np.count_nonzero(areas <= (1e-12 * extent) ** 2))
    if extent == 0 or degenerate == len(areas):
        raise MeshError(
            path, "the mesh is degenerate (zero extent or zero-area faces only)", field=field
        )
    if not mesh.is_watertight:
        raise MeshError(
            path,
            "the mesh is not watertight (some edges do not join exactly two faces), so it "
            "encloses no volume and has no meaningful centre of mass; close it in CAD "
            "and export again",
            field=field,
        )
    if not mesh.is_winding_consistent:
        raise MeshError(path, "the mesh's face winding is inconsistent", field=field)
    with np.errstate(all="ignore"):  # trimesh divides by the volume before we can check it
        volume = float(mesh.volume)
    if not np.isfinite(volume) or abs(volume) <= (1e-9 * extent) ** 3:
        raise MeshError(
            path, f"the mesh encloses (almost) no volume: {volume:.3e} m^3", field=field
        )
    if volume < 0:
        raise MeshError(
            path,
            f"the mesh is inverted (negative volume {volume:.6g} m^3: faces wound inwards)",
            field=field,
        )
    notes: list[str] = []
    if degenerate:
        notes.append(f"{path.name}: {degenerate} zero-area face(s) ignored")
    bodies = mesh.split(only_watertight=False)
    if len(bodies) > 1:
        inverted = sum(1 for b in bodies if b.volume < 0)
        text = f"{path.name}: {len(bodies)} disconnected closed bodies combined"
        if inverted:
            text += f" ({inverted} wound inwards, counted as cavities)"
        notes.append(text)
    mesh.density = density
    props = mesh.mass_properties
    com = np.asarray(props.center_mass, dtype=float)
    inertia = np.asarray(props.inertia, dtype=float)
    if not (np.all(np.isfinite(com)) and np.all(np.isfinite(inertia))):
        raise MeshError(path, "the mesh gives non-finite mass properties", field=field)
    return MassProperties(float(props.mass), com, inertia, "mesh", volume, tuple(notes))


def body_mass_properties(body: Body, scale: float) -> MassProperties:
    """Mass properties of a scene's body: explicit values win over the mesh parts."""
    if body.explicit is not None:
        e = body.explicit
        notes = (
            ("explicit mass properties from the scene file win over the mesh",)
            if body.parts
            else ()
        )
        return MassProperties(e.mass, e.center_of_mass, e.inertia, "explicit", None, notes)
    return combine([_part_props(p, scale) for p in body.parts])


def _part_props(part: Part, scale: float) -> MassProperties:
    field = (*part.field, "mesh")
    mesh = load_mesh(part.mesh, scale, field)
    return mesh_mass_properties(mesh, part.density, part.mesh, field)
