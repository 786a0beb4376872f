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
from typing import TYPE_CHECKING, Any

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
    "merged_pieces",
]

#: Most sample points per mesh for the triangle search (memory: 24 bytes each, plus the tree).
MAX_SAMPLES = 4_000_000
#: Points within this many gaps of the other surface are near: those beyond one gap are near
#: misses (a gap with no contact), those inside by more than one, interpenetration.
NEAR_GAPS = 5.0
#: Samples of the other surface whose triangles are tried for each point.
NEIGHBOURS = 8


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


def _samples(
    mesh: trimesh.Trimesh, spacing: float, faces: np.ndarray, most: int = MAX_SAMPLES
) -> tuple[np.ndarray, np.ndarray]:
    """Points on the triangles ``faces`` (ids) no farther than 2 ``spacing`` from any point of
    them (a grid, the centroid alone for a small triangle), and their triangle
    ids; the spacing widened when more than about ``most`` points would be needed."""
    tri = mesh.triangles[faces]
    if len(tri) == 0:
        return np.zeros((0, 3)), np.zeros(0, int)
    area = float(mesh.area_faces[faces].sum())
    spacing = max(spacing, float(np.sqrt(2 * area / most)))
    # Each triangle from the corner opposite its longest edge, along its two shorter edges:
    # a grid of n1 x n2 steps no longer than `spacing` (a long thin facet of a pin gets a row
    # of points, not a square grid), so every point of it is within 2 `spacing` of a sample.
    lengths = np.linalg.norm(np.roll(tri, -1, axis=1) - np.roll(tri, 1, axis=1), axis=2)
    start = np.argmax(lengths, axis=1)
    order = (start[:, None] + np.arange(3)) % 3
    tri = np.take_along_axis(tri, order[:, :, None], axis=1)
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    n1 = np.maximum(1, np.ceil(np.linalg.norm(e1, axis=1) / spacing)).astype(int)
    n2 = np.maximum(1, np.ceil(np.linalg.norm(e2, axis=1) / spacing)).astype(int)
    small = lengths.max(axis=1) <= spacing
    points = [tri[small].mean(axis=1)]
    ids = [faces[small]]
    grid = np.column_stack([n1, n2])[~small]
    rest = np.flatnonzero(~small)
    if len(rest):
        keys, inverse = np.unique(grid, axis=0, return_inverse=True)
        inverse = np.ravel(inverse)
        for g, (k1, k2) in enumerate(keys):
            which = rest[inverse == g]
            i, j = np.meshgrid(np.arange(k1 + 1) / k1, np.arange(k2 + 1) / k2, indexing="ij")
            keep = i + j <= 1 + 1e-12
            u, v = i[keep], j[keep]
            pts = (
                tri[which, 0][:, None]
                + u[None, :, None] * e1[which][:, None]
                + (v[None, :, None] * e2[which][:, None])
            )
            points.append(pts.reshape(-1, 3))
            ids.append(np.repeat(faces[which], len(u)))
    return np.concatenate(points), np.concatenate(ids)


def _faces_in_box(mesh: trimesh.Trimesh, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Ids of the triangles whose bounding boxes meet the box ``lo``..``hi``."""
    tri = mesh.triangles
    return np.flatnonzero(np.all((tri.max(axis=1) >= lo) & (tri.min(axis=1) <= hi), axis=1))


def surface_distances(
    points: np.ndarray, mesh: trimesh.Trimesh, radius: float, spacing: float
) -> Near:
    """Distances from ``points`` (n, 3) to ``mesh``'s surface, for the points within
    ``radius`` of it; the sign from the closest triangle's outward normal.

    The triangles tried for a point are those of the :data:`NEIGHBOURS` samples (at most
    ``spacing`` apart) nearest to it, and the distance to each is exact (point to triangle)."""
    import trimesh
    from scipy.spatial import cKDTree

    lo, hi = mesh.bounds[0] - radius, mesh.bounds[1] + radius
    inside = np.flatnonzero(np.all((points >= lo) & (points <= hi), axis=1))
    empty = Near(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)), np.zeros(0, int))
    if len(inside) == 0:
        return empty
    box = points[inside]
    faces = _faces_in_box(mesh, box.min(axis=0) - radius, box.max(axis=0) + radius)
    samples, ids = _samples(mesh, spacing, faces)
    if len(samples) == 0:
        return empty
    tree = cKDTree(samples)
    # Points with no sample within reach first (most of them), cheaply, with one neighbour.
    first, _ = tree.query(box, k=1, distance_upper_bound=radius + 2 * spacing)
    close = np.isfinite(first)
    inside, box = inside[close], box[close]
    if len(box) == 0:
        return empty
    k = min(NEIGHBOURS, len(samples))
    dist, idx = tree.query(box, k=k, distance_upper_bound=radius + 2 * spacing)
    dist, idx = dist.reshape(len(box), k), idx.reshape(len(box), k)
    hit = np.isfinite(dist)
    if not hit.any():
        return empty
    rows = np.broadcast_to(np.arange(len(box))[:, None], hit.shape)[hit]
    # Unique (point, triangle) pairs, through one integer key (np.unique over rows is slow).
    count = np.int64(len(mesh.faces))
    key = np.unique(rows.astype(np.int64) * count + ids[idx[hit]])
    candidates = np.column_stack([key // count, key % count])
    tri = mesh.triangles
    q = box[candidates[:, 0]]
    closest = trimesh.triangles.closest_point(tri[candidates[:, 1]], q)
    d = np.linalg.norm(q - closest, axis=1)
    # The nearest triangle per point: sort by point, then distance.
    order = np.lexsort((d, candidates[:, 0]))
    first = order[np.r_[True, np.diff(candidates[order, 0]) != 0]]
    keep = first[d[first] <= radius]
    t = candidates[keep, 1]
    signed = np.einsum("ij,ij->i", q[keep] - closest[keep], mesh.face_normals[t])
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
    """The contact regions of ``body`` on ``base``, each with its patches fitted; and the
    deepest interpenetration found (m, ≥ 0).

    Points sampled on each mesh's triangles (at most ``3 gap`` apart, so that the touching
    point of two long facets crossing, as on tessellated pins, is not missed) within
    :data:`NEAR_GAPS` gaps of the other's surface are found; those within ``gap`` touch, the
    others are near misses (a region's ``least_distance`` says which)."""
    body_labels = smooth_patches(body)
    base_labels = smooth_patches(base)
    reach = NEAR_GAPS * gap
    sides = []
    for mesh, other in ((body, base), (base, body)):
        lo, hi = other.bounds[0] - reach, other.bounds[1] + reach
        points, faces = _samples(mesh, 3 * gap, _faces_in_box(mesh, lo, hi))
        near = surface_distances(points, other, reach, 3 * gap)
        sides.append((points[near.index], faces[near.index], near))
    (pa, fa, a), (pb, fb, b) = sides
    depth = float(max(0.0, -min(a.signed.min(initial=0.0), b.signed.min(initial=0.0))))
    body_side = np.concatenate([body_labels[fa], body_labels[b.triangle]])
    base_side = np.concatenate([base_labels[a.triangle], base_labels[fb]])
    points = np.concatenate([(pa + a.closest) / 2, (pb + b.closest) / 2])
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


def merged_pieces(
    body: trimesh.Trimesh, base: trimesh.Trimesh, gap: float
) -> list[tuple[ClosedBody, bool]]:
    """Each closed body of a body mesh made of several, and whether it looks like part of the
    base: it touches the base and sits in two or more grooves of the rest of the body file
    (the base's balls exported inside the plate's file). An empty list for a single body."""
    import trimesh

    pieces = closed_bodies(body)
    if len(pieces) < 2:
        return []
    split = body.split(only_watertight=False)
    out = []
    for piece in pieces:
        tol = 1e-9 * float(np.ptp(piece.bounds, axis=0).max())
        mesh = next((m for m in split if np.allclose(m.bounds, piece.bounds, atol=tol)), None)
        swallowed = False
        if mesh is not None and any(
            r.least_distance <= gap for r in contact_regions(base, mesh, gap)[0]
        ):
            rest: Any = trimesh.util.concatenate([m for m in split if m is not mesh])
            seated = contact_regions(rest, mesh, gap)[0]
            swallowed = sum(r.least_distance <= gap for r in seated) >= 2
        out.append((piece, swallowed))
    return out
