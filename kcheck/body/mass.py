"""Mass properties of the body from its mesh(es), in SI units, gated for meaningful input.

trimesh is imported here and in :mod:`kcheck.body.meshio` (which reads the files) only, and only
when a check needs mass properties. Meshes are scaled explicitly from the scene's (or the
part's) ``units`` (never guessed from file names), the density is always set (trimesh
defaults to 1), and a mesh that cannot have a meaningful centre of mass (open, inconsistent
winding, inverted, empty, zero volume) is an error, not a number. Parts are placed by their
transforms and point masses added by the parallel-axis theorem.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.errors import FieldPath, MeshError
from kcheck.numerics.thresholds import DEGENERATE_FACE_RTOL, NO_VOLUME_RTOL
from kcheck.result import Finding, MassProperties
from kcheck.scene import Body, Part
from kcheck.scene.limits import LIMITS

if TYPE_CHECKING:
    import trimesh

    from kcheck.body.mesh_edges import Closure
    from kcheck.body.meshio import MERGE_RTOL, load_mesh, step_length_unit

__all__ = [
    "MERGE_RTOL",
    "body_limits_problem",
    "body_mass_properties",
    "combine",
    "inertia_problem",
    "load_mesh",
    "mesh_closure",
    "mesh_mass_properties",
    "part_mass_properties",
    "point_mass",
    "principal_axes",
    "read_mesh",
    "shared_meshes",
    "step_length_unit",
    "transformed",
]


#: The mesh reader's names this module gives too. The reader (:mod:`kcheck.body.meshio`) is
#: imported when a mesh is read, not with this module: a body with explicit mass properties
#: never needs it (its import is 3-5 ms of every start, issue 24).
_FROM_MESHIO = frozenset({"MERGE_RTOL", "load_mesh", "step_length_unit"})


def __getattr__(name: str) -> Any:
    if name in _FROM_MESHIO:
        from kcheck.body import meshio

        return getattr(meshio, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def principal_axes(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending, kg m^2) and axes (columns) of an inertia tensor."""
    moments, axes = np.linalg.eigh(inertia)
    return moments, axes


def point_mass(mass: float, point: np.ndarray) -> MassProperties:
    """A point mass (kg at m): no inertia about itself, no volume."""
    return MassProperties(float(mass), np.asarray(point, dtype=float), np.zeros((3, 3)), "mesh")


def combine(parts: Sequence[MassProperties]) -> MassProperties:
    """Combine bodies rigidly joined: masses add, inertias move by the parallel-axis theorem.

    The volume is the sum of the known volumes (point masses have none); the bounds are the
    union of the known bounds.
    """
    mass = sum(p.mass for p in parts)
    com = np.asarray(sum(p.mass * p.center_of_mass for p in parts) / mass)
    inertia = np.zeros((3, 3))
    for p in parts:
        r = p.center_of_mass - com
        inertia += p.inertia + p.mass * (np.dot(r, r) * np.eye(3) - np.outer(r, r))
    volumes = [p.volume for p in parts if p.volume is not None]
    boxes = [p.bounds for p in parts if p.bounds is not None]
    bounds = None
    if boxes:
        bounds = np.array([np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], 0)])
    return MassProperties(
        float(mass),
        com,
        inertia,
        parts[0].source,
        float(sum(volumes)) if volumes else None,
        tuple(n for p in parts for n in p.notes),
        bounds,
        tuple(w for p in parts for w in p.warnings),
        tuple(b for p in parts for b in p.part_bounds),
    )


def transformed(
    props: MassProperties, rotation: np.ndarray, translation: np.ndarray
) -> MassProperties:
    """Mass properties of a body moved by ``x -> R x + t`` (inertia ``R I Rᵀ``)."""
    com = rotation @ props.center_of_mass + translation
    inertia = rotation @ props.inertia @ rotation.T
    bounds = None
    if props.bounds is not None:
        corners = np.array(
            [
                [props.bounds[i, 0], props.bounds[j, 1], props.bounds[k, 2]]
                for i in (0, 1)
                for j in (0, 1)
                for k in (0, 1)
            ]
        )
        moved = corners @ rotation.T + translation
        bounds = np.array([moved.min(axis=0), moved.max(axis=0)])
    return dataclasses.replace(
        props,
        center_of_mass=com,
        inertia=inertia,
        bounds=bounds,
        part_bounds=() if bounds is None else (bounds,),
    )


def body_volumes(mesh: trimesh.Trimesh, pairs: np.ndarray | None = None) -> np.ndarray:
    """Signed volume (m³) of each edge-connected body of a closed mesh, from the divergence
    theorem per face; without building a mesh per body as ``mesh.split`` does. ``pairs``:
    the faces sharing an edge (k, 2) if known (for a closed mesh, its ``face_adjacency``)."""
    import trimesh

    if pairs is None:
        pairs = mesh.face_adjacency
    labels = trimesh.graph.connected_component_labels(pairs, node_count=len(mesh.faces))
    triangles = mesh.triangles
    per_face = np.einsum("ij,ij->i", triangles[:, 0], np.cross(triangles[:, 1], triangles[:, 2]))
    return np.bincount(labels, weights=per_face) / 6.0


def mesh_mass_properties(
    mesh: trimesh.Trimesh,
    density: float,
    path: Path,
    field: FieldPath | str,
    *,
    repair: bool = False,
    scale: float = 1.0,
    units: str = "m",
) -> MassProperties:
    """Mass properties (SI) of a closed mesh already in metres, after gating it.

    With ``repair``, an open or inconsistently wound mesh is re-wound and its small holes are
    filled; if that closes it, the result carries a warning. ``scale`` and ``units`` (metres
    per file unit, its name) only word the messages in the file's units.
    """
    import trimesh

    # Set before anything is cached: trimesh drops a mesh's whole cache when its density
    # changes (the triangles, their cross products, the adjacency, the mass properties).
    mesh.density = density
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    areas = mesh.area_faces
    degenerate = int(np.count_nonzero(areas <= (DEGENERATE_FACE_RTOL * extent) ** 2))
    if extent == 0 or degenerate == len(areas):
        raise MeshError(
            path, "the mesh is degenerate (zero extent or zero-area faces only)", field=field
        )
    notes: list[str] = []
    warnings: list[Finding] = []
    merged = int(mesh.metadata.get("kcheck_merged", 0))
    if merged:
        notes.append(f"{path.name}: {merged} duplicate vertices merged")
    closure = mesh_closure(mesh)
    if repair and not (closure.watertight and closure.consistent):
        # Orienting a flat (volume-less) mesh divides by its volume inside trimesh; the
        # volume is checked below and refused with a message, so the division's warning is not.
        with np.errstate(divide="ignore", invalid="ignore"):
            trimesh.repair.fix_winding(mesh)
            filled = trimesh.repair.fill_holes(mesh)
            trimesh.repair.fix_normals(mesh, multibody=True)
        closure = mesh_closure(mesh)
        if closure.watertight and closure.consistent:
            where = field if isinstance(field, tuple) else None
            warnings.append(
                Finding(
                    f"mesh {path.name} was repaired (winding fixed"
                    f"{', holes filled' if filled else ''}) because `repair: true`; its mass "
                    "properties are those of the repaired mesh",
                    code="mesh-repaired",
                    field=where,
                )
            )
    if not closure.watertight:
        from kcheck.body.meshio import not_watertight

        raise not_watertight(mesh, path, field, scale, units)
    if not closure.consistent:
        raise MeshError(
            path,
            "the mesh's face winding is inconsistent (set `repair: true` to re-wind it)",
            field=field,
        )
    with np.errstate(all="ignore"):  # trimesh divides by the volume before we can check it
        volume = float(mesh.volume)
    if not np.isfinite(volume) or abs(volume) <= (NO_VOLUME_RTOL * extent) ** 3:
        raise MeshError(
            path, f"the mesh encloses (almost) no volume: {volume:.3e} m^3", field=field
        )
    if volume < 0:
        raise MeshError(
            path,
            f"the mesh is inverted (negative volume {volume:.6g} m^3: faces wound inwards)",
            field=field,
        )
    if degenerate:
        notes.append(f"{path.name}: {degenerate} zero-area face(s) ignored")
    volumes = body_volumes(mesh, closure.edges.pairs)
    if len(volumes) > 1:
        inverted = int(np.count_nonzero(volumes < 0))
        text = f"{path.name}: {len(volumes)} disconnected closed bodies combined"
        if inverted:
            text += f" ({inverted} wound inwards, counted as cavities)"
        notes.append(text)
    props = mesh.mass_properties  # computed once: with the volume above
    com = np.asarray(props.center_mass, dtype=float)
    inertia = np.asarray(props.inertia, dtype=float)
    if not (np.all(np.isfinite(com)) and np.all(np.isfinite(inertia))):
        raise MeshError(path, "the mesh gives non-finite mass properties", field=field)
    allowed = LIMITS["mass"]  # the range an explicit mass must lie in
    if not allowed.contains(float(props.mass)):
        raise MeshError(
            path,
            f"the mesh gives a mass of {float(props.mass):.3g} kg, outside {allowed.text()} "
            f"(volume {volume:.3g} m^3, density {density:g} kg/m^3: are the units right?)",
            field=field,
        )
    problem = inertia_problem(inertia)  # the range explicit principal moments must lie in
    if problem is not None:
        raise MeshError(path, f"the mesh gives {problem} (are the units right?)", field=field)
    return MassProperties(
        float(props.mass),
        com,
        inertia,
        "mesh",
        volume,
        tuple(notes),
        np.asarray(mesh.bounds, dtype=float),
        tuple(warnings),
        (np.asarray(mesh.bounds, dtype=float),),
    )


#: Meshes read within :func:`shared_meshes`, by file and scale (None: outside it).
_SHARED: dict[tuple[str, float], trimesh.Trimesh] | None = None
#: The closures of the faces of meshes in :data:`_SHARED` (the faces, their closure).
_CLOSURES: list[tuple[np.ndarray, Closure]] = []
#: The closures kept (the latest): a part's mass properties and its supports' check ask in turn.
_KEEP_CLOSURES = 8


def mesh_closure(mesh: trimesh.Trimesh) -> Closure:
    """Whether the mesh is watertight and consistently wound, and its shared edges
    (:func:`kcheck.body.mesh_edges.closure_of`): within :func:`shared_meshes`, worked out once
    for equal faces (they depend on nothing else: mass properties, ``body_volumes`` and the
    supports' check of a part share them; a repaired mesh's changed faces get their own)."""
    from kcheck.body.mesh_edges import closure_of

    faces = np.asarray(mesh.faces)
    if mesh.is_empty:  # trimesh: an empty mesh is neither watertight nor consistently wound
        return closure_of(faces[:0], empty=True)
    if _SHARED is None:
        return closure_of(faces)
    for known, closure in _CLOSURES:
        if known.shape == faces.shape and np.array_equal(known, faces):
            return closure
    closure = closure_of(faces)
    _CLOSURES.insert(0, (faces.copy(), closure))
    del _CLOSURES[_KEEP_CLOSURES:]  # a scene of many parts: no growing scan
    return closure


@contextlib.contextmanager
def shared_meshes() -> Iterator[None]:
    """Within it each mesh file is read once: mass properties and the supports' check
    (:mod:`kcheck.body.surface`) share it. The meshes are let go on leaving."""
    global _SHARED
    outer = _SHARED
    if outer is None:
        _SHARED = {}
    try:
        yield
    finally:
        if outer is None:
            _SHARED = None
            _CLOSURES.clear()


def _load(part: Part, max_mesh_bytes: int | None, *, copy: bool = True) -> trimesh.Trimesh:
    """The part's mesh in metres (unplaced): read, or a copy of the one read already within
    :func:`shared_meshes` (a copy: repairs and placement change a mesh in place); without
    ``copy``, the one read itself, for a caller that changes neither its vertices nor faces."""
    from kcheck.body.meshio import load_mesh

    field = (*part.field, "mesh")
    if _SHARED is None:
        return load_mesh(part.mesh, part.scale, field, max_bytes=max_mesh_bytes)
    key = (str(part.mesh), part.scale)
    if key not in _SHARED:
        _SHARED[key] = load_mesh(part.mesh, part.scale, field, max_bytes=max_mesh_bytes)
    return _SHARED[key].copy() if copy else _SHARED[key]


def read_mesh(part: Part, max_mesh_bytes: int | None = None) -> trimesh.Trimesh:
    """The part's mesh in metres, unplaced, as read (within :func:`shared_meshes` the one
    mass properties use: not to be changed; :func:`placed_mesh` gives a copy to change)."""
    return _load(part, max_mesh_bytes, copy=False)


def part_mass_properties(part: Part, max_mesh_bytes: int | None = None) -> MassProperties:
    """Mass properties of one part in the scene's frame (its transform applied); its mesh
    file at most ``max_mesh_bytes`` (default :data:`kcheck.body.meshio.MAX_MESH_BYTES`)."""
    field = (*part.field, "mesh")
    # without `repair` the mesh's vertices and faces are left as they are: no copy (its
    # density and the cached arrays trimesh derives are set on the one mesh read)
    mesh = _load(part, max_mesh_bytes, copy=part.repair)
    props = mesh_mass_properties(
        mesh,
        part.density,
        part.mesh,
        field,
        repair=part.repair,
        scale=part.scale,
        units=part.units,
    )
    if part.is_step:
        from kcheck.body.meshio import step_length_unit

        declared = step_length_unit(part.mesh)
        note = f"{part.mesh.name}: STEP, declared unit {declared or 'unknown'}, read in metres"
        props = dataclasses.replace(props, notes=(*props.notes, note))
    if part.rotation is None and part.translation == (0.0, 0.0, 0.0):
        return props
    rotation = np.eye(3) if part.rotation is None else np.asarray(part.rotation, dtype=float)
    placed = transformed(props, rotation, np.asarray(part.translation, dtype=float))
    assert placed.bounds is not None
    largest = float(np.abs(placed.bounds).max())
    from kcheck.body.meshio import MAX_COORDINATE_M

    if not largest <= MAX_COORDINATE_M:  # the mesh's own coordinates were checked on reading
        raise MeshError(
            part.mesh,
            f"placed by its transform, the mesh reaches {largest:.7g} m from the origin, "
            f"beyond {MAX_COORDINATE_M:g} m (are `translate` and the units right?)",
            field=field,
        )
    return placed


def inertia_problem(inertia: np.ndarray) -> str | None:
    """What is wrong with an inertia tensor's principal moments (kg m², their finite part: a
    planar scene's lone I_zz has NaN elsewhere), against ``LIMITS["inertia"]``; None if
    nothing."""
    allowed = LIMITS["inertia"]
    if np.all(np.isfinite(inertia)):
        moments = np.linalg.eigvalsh((inertia + inertia.T) / 2)
    else:
        moments = np.array([inertia[2, 2]])  # a planar scene's I_zz alone
    bad = [float(m) for m in moments if not allowed.contains(float(m))]
    if not bad:
        return None
    return f"a principal moment of inertia of {bad[0]:.3g} kg m^2, outside {allowed.text()}"


def body_limits_problem(props: MassProperties) -> str | None:
    """What is wrong with a whole body's mass properties (meshes or explicit values, point
    masses added) against the mass and principal-moment limits (``LIMITS``), which each of
    its pieces already met; None if nothing. The runner reports it at ``body``."""
    whole = "the body as a whole (its meshes or explicit values, and its point masses)"
    allowed = LIMITS["mass"]
    if not allowed.contains(props.mass):
        return f"{whole} has a mass of {props.mass:.3g} kg, outside {allowed.text()}"
    problem = inertia_problem(props.inertia)
    return None if problem is None else f"{whole} has {problem}"


def place(points: np.ndarray, part: Part) -> np.ndarray:
    """Points (..., 3) in the part file's frame, in metres, placed in the scene: ``R x + t``
    (the part's ``transform``)."""
    if part.rotation is not None:
        points = points @ np.asarray(part.rotation, dtype=float).T
    return points + np.asarray(part.translation, dtype=float)


def placed_mesh(part: Part, max_mesh_bytes: int | None = None) -> trimesh.Trimesh:
    """The part's mesh in the scene's frame, in metres: its units and transform applied."""
    mesh = _load(part, max_mesh_bytes)
    if part.rotation is not None or any(part.translation):
        mesh.vertices = place(np.asarray(mesh.vertices), part)
    return mesh


def body_mass_properties(
    body: Body, scale: float | None = None, max_mesh_bytes: int | None = None
) -> MassProperties:
    """Mass properties of a scene's body: explicit values win over the mesh parts; point
    masses are added to either. (``scale`` is not used: each part carries its own.) Mesh
    files are at most ``max_mesh_bytes`` (default :data:`kcheck.body.meshio.MAX_MESH_BYTES`)."""
    points = [point_mass(p.mass, p.point) for p in body.point_masses]
    added = _point_masses_note(body)
    if body.explicit is not None:
        e = body.explicit
        notes = (
            ("explicit mass properties from the scene file win over the mesh",)
            if body.parts
            else ()
        )
        explicit = MassProperties(e.mass, e.center_of_mass, e.inertia, "explicit", None, notes)
        if not points:
            return explicit
        combined = combine([explicit, *points])
        return dataclasses.replace(combined, notes=(*notes, added))
    from kcheck.body.meshio import release_memory

    props = combine([*(part_mass_properties(p, max_mesh_bytes) for p in body.parts), *points])
    release_memory(collect=sum(_file_size(p.mesh) for p in body.parts) >= COLLECT_BYTES)
    if points:
        props = dataclasses.replace(props, notes=(*props.notes, added))
    return props


def _point_masses_note(body: Body) -> str:
    """ "point mass added: magnet (0.012 kg)" — what was added to the meshes, by name."""
    if not body.point_masses:
        return ""
    named = ", ".join(f"{p.name} ({p.mass:.4g} kg)" for p in body.point_masses)
    return f"{POINT_MASS_NOTE}{'es' if len(body.point_masses) > 1 else ''} added: {named}"


#: How the note of added point masses starts (a report says "mesh + point masses").
POINT_MASS_NOTE = "point mass"
#: Mesh files this large in all (bytes) are worth a garbage collection after reading
#: (about 60 MB of cycles after a 16 MB STL; the collection costs tens of ms a scene).
COLLECT_BYTES = 4 * 2**20


def _file_size(path: Path) -> int:
    try:
        return path.stat().st_size
    except OSError:
        return 0
