"""Where two meshes in assembly position touch: the vertices of each within a gap of the other's
surface, grouped into contact regions by the smooth surface patches they lie on, and each
patch fitted with a plane, sphere or cylinder (:mod:`kcheck.body.surface_fit`).

Lengths are in metres (meshes from :func:`kcheck.body.meshio.load_mesh`). trimesh and scipy
are imported inside the functions. The distance of a point from a mesh is exact (point to
triangle); the triangles near a point are found through a KD-tree of points sampled on each
triangle no farther apart than the triangles' median edge, so no spatial index beyond scipy's
is needed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from kcheck.body.surface_fit import Primitive, fit_surface
from kcheck.numerics.thresholds import SMOOTH_PATCH_DEG

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "Near",
    "Region",
    "ClosedBody",
    "surface_distances",
    "smooth_patches",
    "closed_bodies",
    "contact_regions",
    "patch_fit",
]

#: Most sample points per mesh for the triangle search (memory: 24 bytes each, plus the tree).
MAX_SAMPLES = 4_000_000


@dataclass(frozen=True)
class Near:
    """Vertices of one mesh near the other's surface: vertex ``index``, signed distance
    (negative inside the other mesh), the closest point and its triangle on the other."""

    index: np.ndarray
    signed: np.ndarray
    closest: np.ndarray
    triangle: np.ndarray


@dataclass
class Region:
    """One contact region: the smooth patch on the body and on the base that touch there,
    the near points found (midpoints of vertex and closest point, m) and the smallest
    signed distance between the surfaces there (m)."""

    body_patch: int
    base_patch: int
    points: np.ndarray
    least_distance: float
    body_fit: Primitive | None = None
    base_fit: Primitive | None = None
    tried: dict[str, list[Primitive]] = field(default_factory=dict)


@dataclass(frozen=True)
class ClosedBody:
    """One edge-connected closed body of a mesh: its volume (m³) and bounds (2×3, m)."""

    volume: float
    bounds: np.ndarray


def _samples(mesh: trimesh.Trimesh, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Points on every triangle no farther than ``spacing`` from any point of it (a
    barycentric grid, one centroid for a small triangle), and their triangle ids."""
    tri = mesh.triangles
    edges = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
    n = np.maximum(1, np.ceil(edges / spacing)).astype(int)
    points = [tri.mean(axis=1)]
    ids = [np.arange(len(tri))]
    for k in np.unique(n[n > 1]):
        which = np.flatnonzero(n == k)
        i, j = np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="ij")
        keep = i + j <= k
        bary = np.column_stack([i[keep], j[keep], k - i[keep] - j[keep]]) / k
        pts = np.einsum("bk,tkd->tbd", bary, tri[which])
        points.append(pts.reshape(-1, 3))
        ids.append(np.repeat(which, len(bary)))
    return np.concatenate(points), np.concatenate(ids)


def surface_distances(points: np.ndarray, mesh: trimesh.Trimesh, radius: float) -> Near:
    """Exact distances from ``points`` (n, 3) to ``mesh``'s surface, for the points within
    ``radius`` of it; the sign from the closest triangle's outward normal."""
    import trimesh
    from scipy.spatial import cKDTree

    lo, hi = mesh.bounds[0] - radius, mesh.bounds[1] + radius
    inside = np.flatnonzero(np.all((points >= lo) & (points <= hi), axis=1))
    empty = Near(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)), np.zeros(0, int))
    if len(inside) == 0:
        return empty
    tri = mesh.triangles
    edges = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2)
    spacing = float(np.median(edges))
    area = float(mesh.area)
    spacing = max(spacing, np.sqrt(2 * area / MAX_SAMPLES))  # bounds the sample count
    samples, ids = _samples(mesh, spacing)
    # Every point of a triangle lies within `spacing` of one of its samples.
    pairs = (
        cKDTree(points[inside])
        .sparse_distance_matrix(cKDTree(samples), radius + spacing, output_type="ndarray")
        .astype([("i", int), ("j", int), ("v", float)])
    )
    if len(pairs) == 0:
        return empty
    candidates = np.unique(np.column_stack([pairs["i"], ids[pairs["j"]]]), axis=0)
    q = points[inside][candidates[:, 0]]
    closest = trimesh.triangles.closest_point(tri[candidates[:, 1]], q)
    d = np.linalg.norm(q - closest, axis=1)
    # The nearest triangle per point: sort by point, then distance.
    order = np.lexsort((d, candidates[:, 0]))
    first = order[np.r_[True, np.diff(candidates[order, 0]) != 0]]
    keep = first[d[first] <= radius]
    t = candidates[keep, 1]
    normal = mesh.face_normals[t]
    signed = np.einsum("ij,ij->i", q[keep] - closest[keep], normal)
    # On an edge or a corner the face normal gives no reliable sign: a point off the face's
    # own plane by less than its distance is outside.
    unsigned = d[keep]
    signed = np.where(np.abs(signed) < 0.999 * unsigned, unsigned, np.sign(signed) * unsigned)
    return Near(inside[candidates[keep, 0]], signed, closest[keep], t)


def smooth_patches(mesh: trimesh.Trimesh) -> np.ndarray:
    """A patch label per face: faces joined across edges whose dihedral angle is below
    :data:`SMOOTH_PATCH_DEG` (a tessellated ball or pin is one patch, a groove's flanks two)."""
    import trimesh

    adjacency = mesh.face_adjacency
    smooth = mesh.face_adjacency_angles < np.radians(SMOOTH_PATCH_DEG)
    return np.asarray(
        trimesh.graph.connected_component_labels(adjacency[smooth], node_count=len(mesh.faces))
    )


def closed_bodies(mesh: trimesh.Trimesh) -> list[ClosedBody]:
    """The mesh's edge-connected bodies, each with its volume and bounds."""
    import trimesh

    labels = trimesh.graph.connected_component_labels(
        mesh.face_adjacency, node_count=len(mesh.faces)
    )
    tri = mesh.triangles
    per_face = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0
    out = []
    for label in np.unique(labels):
        faces = labels == label
        pts = tri[faces].reshape(-1, 3)
        out.append(
            ClosedBody(float(per_face[faces].sum()), np.array([pts.min(axis=0), pts.max(axis=0)]))
        )
    return out


def _vertex_patch(
    mesh: trimesh.Trimesh, labels: np.ndarray, vertices: np.ndarray, facing: np.ndarray
) -> np.ndarray:
    """The patch each vertex lies on; on a sharp edge, that of the incident face whose normal
    is most opposite ``facing`` (the other surface's normal there: the face that touches)."""
    vf = mesh.vertex_faces[vertices]  # padded with -1
    valid = vf >= 0
    normals = mesh.face_normals[np.where(valid, vf, 0)]
    score = np.where(valid, np.einsum("ikd,id->ik", normals, facing), np.inf)
    best = vf[np.arange(len(vertices)), np.argmin(score, axis=1)]
    return labels[best]


def patch_fit(
    mesh: trimesh.Trimesh, labels: np.ndarray, patch: int
) -> tuple[Primitive | None, list[Primitive]]:
    """The simplest surface fitting a patch's vertices (and every fit tried)."""
    faces = np.flatnonzero(labels == patch)
    vertices = np.unique(mesh.faces[faces])
    return fit_surface(
        mesh.vertices[vertices], mesh.triangles_center[faces], mesh.face_normals[faces]
    )


def contact_regions(
    base: trimesh.Trimesh, body: trimesh.Trimesh, gap: float
) -> tuple[list[Region], float]:
    """The contact regions of ``body`` on ``base`` (vertices of either within ``gap`` of the
    other), each with its patches fitted; and the deepest interpenetration found (m, ≥ 0)."""
    body_labels = smooth_patches(body)
    base_labels = smooth_patches(base)
    a = surface_distances(body.vertices, base, gap)  # body vertices near the base
    b = surface_distances(base.vertices, body, gap)  # base vertices near the body
    depth = float(max(0.0, -min(a.signed.min(initial=0.0), b.signed.min(initial=0.0))))
    body_side = np.concatenate(
        [
            _vertex_patch(body, body_labels, a.index, base.face_normals[a.triangle]),
            body_labels[b.triangle],
        ]
    )
    base_side = np.concatenate(
        [
            base_labels[a.triangle],
            _vertex_patch(base, base_labels, b.index, body.face_normals[b.triangle]),
        ]
    )
    points = np.concatenate(
        [
            (body.vertices[a.index] + a.closest) / 2,
            (base.vertices[b.index] + b.closest) / 2,
        ]
    )
    signed = np.concatenate([a.signed, b.signed])
    regions = []
    pairs, inverse = np.unique(np.column_stack([body_side, base_side]), axis=0, return_inverse=True)
    inverse = np.ravel(inverse)
    fits: dict[tuple[str, int], tuple[Primitive | None, list[Primitive]]] = {}
    for k, (p_body, p_base) in enumerate(pairs):
        here = inverse == k
        region = Region(int(p_body), int(p_base), points[here], float(signed[here].min()))
        for side, mesh, labels, patch in (
            ("body", body, body_labels, region.body_patch),
            ("base", base, base_labels, region.base_patch),
        ):
            key = (side, patch)
            if key not in fits:
                fits[key] = patch_fit(mesh, labels, patch)
            fit, tried = fits[key]
            setattr(region, f"{side}_fit", fit)
            region.tried[side] = tried
        regions.append(region)
    return regions, depth
