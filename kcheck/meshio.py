"""Reading mesh files for mass properties: any format trimesh reads, STEP through the optional
``step`` extra (cascadio, OpenCASCADE, which converts the file's declared unit to metres),
scaled to metres, with vertices closer than a millionth of the mesh's size merged (STEP
tessellations and some STL exports repeat them per face), and the open edges of a mesh that
is not watertight located. trimesh is imported only inside these functions.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from kcheck.errors import FieldPath, MeshError

if TYPE_CHECKING:
    import trimesh

__all__ = ["MERGE_RTOL", "STEP_INSTALL", "load_mesh", "not_watertight", "step_length_unit"]

#: Vertices closer than this fraction of the mesh's largest extent are one vertex.
MERGE_RTOL = 1e-6
STEP_INSTALL = "pip install 'kcheck[step]'"

_STEP_UNITS = (
    (re.compile(r"SI_UNIT\s*\(\s*\.MILLI\.\s*,\s*\.METRE\.\s*\)", re.I), "mm"),
    (re.compile(r"SI_UNIT\s*\(\s*\.CENTI\.\s*,\s*\.METRE\.\s*\)", re.I), "cm"),
    (re.compile(r"SI_UNIT\s*\(\s*\.MICRO\.\s*,\s*\.METRE\.\s*\)", re.I), "um"),
    (re.compile(r"CONVERSION_BASED_UNIT\s*\(\s*'INCH'", re.I), "in"),
    (re.compile(r"CONVERSION_BASED_UNIT\s*\(\s*'(?:FOOT|FEET)'", re.I), "ft"),
    (re.compile(r"SI_UNIT\s*\(\s*\$\s*,\s*\.METRE\.\s*\)", re.I), "m"),
)


def step_length_unit(path: Path) -> str | None:
    """The length unit a STEP file declares (``mm``, ``in``, ...), from its text, or None.

    Only for reporting: OpenCASCADE applies the unit itself when it converts to metres. The
    unit is the LENGTH_UNIT among the representation context's assigned units.
    """
    try:
        with open(path, "rb") as handle:
            text = handle.read(8 << 20).decode("latin-1")
    except OSError:
        return None
    context = re.search(r"GLOBAL_UNIT_ASSIGNED_CONTEXT\s*\(\s*\(([^)]*)\)", text, re.I)
    candidates = []
    if context:
        for ref in re.findall(r"#\d+", context.group(1)):
            entity = re.search(rf"{ref}\s*=\s*([^;]*);", text)
            if entity and re.search(r"LENGTH_UNIT", entity.group(1), re.I):
                candidates.append(entity.group(1))
    candidates.append(text)  # no context found: the first unit named anywhere
    for candidate in candidates:
        found = [(m.start(), unit) for rx, unit in _STEP_UNITS if (m := rx.search(candidate))]
        if found:
            return min(found)[1]
    return None


def _merge_close(mesh: trimesh.Trimesh, tolerance: float) -> tuple[trimesh.Trimesh, int]:
    """The mesh with vertices closer than ``tolerance`` (m) joined, and how many were."""
    import trimesh
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(mesh.vertices).query_pairs(tolerance, output_type="ndarray")
    if len(pairs) == 0:
        return mesh, 0
    n = len(mesh.vertices)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    count, labels = connected_components(graph, directed=False)
    first = np.full(count, n)
    np.minimum.at(first, labels, np.arange(n))
    faces = labels[mesh.faces]
    keep = (
        (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    )
    merged = trimesh.Trimesh(mesh.vertices[first], faces[keep], process=False)
    return merged, n - count


def _read(path: Path, field: FieldPath | str) -> trimesh.Trimesh:
    import trimesh

    if path.suffix.lower() in (".step", ".stp") and importlib.util.find_spec("cascadio") is None:
        raise MeshError(
            path,
            f"STEP files need the optional `step` extra (OpenCASCADE via cascadio): {STEP_INSTALL}",
            field=field,
        )
    try:
        mesh = trimesh.load_mesh(str(path), process=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise MeshError(
            path, f"cannot read the mesh ({type(exc).__name__}: {exc})", field=field
        ) from exc
    if isinstance(mesh, trimesh.Scene):
        mesh = mesh.to_mesh()
    if not isinstance(mesh, trimesh.Trimesh) or mesh.is_empty or len(mesh.faces) == 0:
        raise MeshError(path, "the mesh is empty (no triangles)", field=field)
    return mesh


def load_mesh(path: Path, scale: float, field: FieldPath | str) -> trimesh.Trimesh:
    """Load a mesh file as one Trimesh scaled to metres (``scale`` metres per file unit), with
    vertices closer than ``MERGE_RTOL`` of its size merged; MeshError if it is unusable."""
    mesh = _read(path, field).copy()
    mesh.apply_scale(scale)
    if not np.all(np.isfinite(mesh.vertices)):
        raise MeshError(path, "the mesh has non-finite vertex coordinates", field=field)
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    if extent > 0:
        mesh, merged = _merge_close(mesh, MERGE_RTOL * extent)
        if merged:
            mesh.metadata["kcheck_merged"] = merged
    return mesh


def _holes(mesh: trimesh.Trimesh) -> list[tuple[np.ndarray, float, int]]:
    """Open boundaries: (centre in m, size in m, number of edges), largest first."""
    import trimesh
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    single = trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)
    edges = mesh.edges_sorted[single]
    if len(edges) == 0:
        return []
    n = len(mesh.vertices)
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    out = []
    for label in np.unique(labels[edges[:, 0]]):
        loop = edges[labels[edges[:, 0]] == label]
        points = mesh.vertices[np.unique(loop)]
        size = float(np.linalg.norm(np.ptp(points, axis=0)))
        out.append((points.mean(axis=0), size, len(loop)))
    return sorted(out, key=lambda h: -h[1])


def not_watertight(
    mesh: trimesh.Trimesh, path: Path, field: FieldPath | str, scale: float, units: str
) -> MeshError:
    """The located error for an open mesh: how many open edges, where the largest hole is."""
    _, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    holes = _holes(mesh)
    open_edges = sum(h[2] for h in holes)
    crowded = int(np.count_nonzero(counts > 2))
    parts = []
    if holes:
        centre, size, _ = holes[0]
        c = ", ".join(f"{v:.4g}" for v in np.round(centre / scale, 12) + 0.0)
        parts.append(
            f"{open_edges} open edge(s) in {len(holes)} hole(s); the largest is centred at "
            f"({c}) {units} in the file's coordinates, {size / scale:.4g} {units} across"
        )
    if crowded:
        parts.append(f"{crowded} edge(s) shared by more than two faces")
    return MeshError(
        path,
        "the mesh is not watertight (" + "; ".join(parts) + "), so it encloses no volume and "
        "has no meaningful centre of mass; close it in CAD and export again, or set "
        "`repair: true` to let kcheck merge vertices, fix the winding and fill small holes",
        field=field,
    )
