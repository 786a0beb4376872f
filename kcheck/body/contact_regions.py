"""Where two meshes in assembly position touch: the vertices of each within a gap of the other's
surface, grouped into contact regions by the smooth surface patches they lie on, and each
patch fitted with a plane, sphere, cylinder, cone or torus (:mod:`kcheck.body.surface_fit`).

Lengths are in metres (meshes from :func:`kcheck.body.meshio.load_surface` or trimesh's).
scipy is imported inside the functions, trimesh not at all. The distance of a point from a
mesh is exact (point to
triangle) where it decides whether the parts touch; the triangles near a point are found
through a KD-tree of points sampled on each triangle no farther apart than the triangles'
median edge, after a filter on a grid of cubes drops the points far from the other part.
Patches are the connected components (scipy's csgraph) of the faces sharing an edge at a
small dihedral angle.
"""

from __future__ import annotations

import functools
from dataclasses import field, replace
from typing import Any

import numpy as np

from kcheck.body.closest_point import closest_point
from kcheck.body.mesh_edges import Edges, edges_of, face_pairs
from kcheck.body.meshio import Surface
from kcheck.body.surface_fit import Primitive, fit_surface, residuals
from kcheck.numerics.thresholds import SMOOTH_PATCH_DEG
from kcheck.records import dataclass

__all__ = [
    "Near",
    "Faces",
    "Region",
    "ClosedBody",
    "surface_distances",
    "face_pairs",
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
#: A merged piece sits in the rest of the body (a ball in a groove) only on regions whose two
#: sides face each other: the mean cosine of their normals below this (normals within 60
#: degrees of opposite).
SEATED_FACING = -0.5
#: Samples of the other surface whose triangles are tried for each point.
NEIGHBOURS = 8
#: Most cubes of the grid that drops far points held as a dense array of flags (1 byte each).
DENSE_CELLS = 2**24


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
    signed distance between the surfaces there (m); ``facing``, the mean cosine between the
    two sides' face normals at those points (-1 for surfaces that face each other, as
    touching ones do; +1 for a surface lying on another of the same orientation, one body
    overlapping another); once fitted, each side's fit, the fits tried and the patch's
    vertices (m; where a line contact ends)."""

    body_patch: int
    base_patch: int
    points: np.ndarray
    least_distance: float
    facing: float = -1.0
    body_fit: Primitive | None = None
    base_fit: Primitive | None = None
    tried: dict[str, list[Primitive]] = field(default_factory=dict)
    vertices: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass(frozen=True)
class ClosedBody:
    """One edge-connected closed body of a mesh: its volume (m³) and bounds (2×3, m)."""

    volume: float
    bounds: np.ndarray


#: A triangle mesh: a Trimesh, or a :class:`kcheck.body.meshio.Surface` (vertices, faces).
Mesh = Any


@dataclass(frozen=True)
class Faces:
    """A mesh's triangles (n, 3, 3), outward unit normals (n, 3), per-triangle bounds (n, 3
    each), areas and vertex ids (n, 3), read once from the mesh (trimesh's cached properties
    re-hash the mesh per read); the shared edges when first asked for."""

    triangles: np.ndarray
    normals: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    areas: np.ndarray
    bounds: np.ndarray
    ids: np.ndarray

    @classmethod
    def of(cls, mesh: Mesh) -> Faces:
        vertices, f = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
        tri = np.take(vertices, f, axis=0)
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        cross = _cross(b - a, c - a)
        double = np.sqrt(np.einsum("ij,ij->i", cross, cross))
        normals = cross / np.where(double > 0, double, 1.0)[:, None]
        lo, hi = np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)
        bounds = np.array([lo.min(axis=0, initial=np.inf), hi.max(axis=0, initial=-np.inf)])
        faces = cls(tri, normals, lo, hi, double / 2, bounds, f)
        if isinstance(mesh, Surface) and "edges" in mesh.__dict__:
            faces.__dict__["edges"] = mesh.edges  # already sorted out for watertightness
        return faces

    @functools.cached_property
    def edges(self) -> Edges:
        """The faces' shared edges."""
        return edges_of(self.ids)

    def facts(self, which: np.ndarray) -> np.ndarray:
        """Of the triangles ``which`` (ids): centroid (3 columns), longest edge, farthest
        corner from the centroid squared, (k, 5); each triangle's worked out once, when
        first asked for (the sampling asks for the triangles near the other part, a few
        times each)."""
        known = self.__dict__.get("_facts")
        if known is None:
            known = self.__dict__["_facts"] = np.full((len(self.ids), 5), np.nan)
        new = which[np.isnan(known[which, 3])]
        if len(new):
            known[new] = _facts(self.triangles[new])
        return known[which]

    def subset(self, which: np.ndarray) -> Faces:
        """The triangles ``which`` (ids) alone (with what is already known of each)."""
        lo, hi = self.lo[which], self.hi[which]
        bounds = np.array([lo.min(axis=0, initial=np.inf), hi.max(axis=0, initial=-np.inf)])
        out = Faces(
            self.triangles[which],
            self.normals[which],
            lo,
            hi,
            self.areas[which],
            bounds,
            self.ids[which],
        )
        if "_facts" in self.__dict__:
            out.__dict__["_facts"] = self.__dict__["_facts"][which]
        return out

    def in_box(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Ids of the triangles whose bounding boxes meet the box ``lo``..``hi``."""
        return np.flatnonzero(_rows_all((self.hi >= lo) & (self.lo <= hi)))


def _samples(
    faces: Faces, spacing: float, which: np.ndarray, most: int = MAX_SAMPLES
) -> tuple[np.ndarray, np.ndarray, float]:
    """Points on the triangles ``which`` (ids) no farther than 2 ``spacing`` from any point of
    them (a grid, the centroid alone for a small triangle), their triangle ids, and how far
    any point of those triangles may be from its nearest sample (the cover, m); the spacing
    widened when more than about ``most`` points would be needed."""
    if len(which) == 0:
        return np.zeros((0, 3)), np.zeros(0, int), 0.0
    area = float(faces.areas[which].sum())
    spacing = max(spacing, float(np.sqrt(2 * area / most)))
    # Each triangle from the corner opposite its longest edge, along its two shorter edges:
    # a grid of n1 x n2 steps no longer than `spacing` (a long thin facet of a pin gets a row
    # of points, not a square grid), so every point of it is within 2 `spacing` of a sample.
    facts = faces.facts(which)
    small = facts[:, 3] <= spacing
    points = [facts[small, :3]]
    ids = [which[small]]
    # A point of a triangle is at most its farthest corner's distance from the centroid.
    cover = float(np.sqrt(np.max(facts[small, 4], initial=0.0)))
    rest = np.flatnonzero(~small)
    if len(rest):
        tri = faces.triangles[which[rest]]
        lengths = _edge_lengths(tri)
        start = np.argmax(lengths, axis=1)
        order = (start[:, None] + np.arange(3)) % 3
        tri = np.take_along_axis(tri, order[:, :, None], axis=1)
        e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
        n1 = np.maximum(1, np.ceil(np.linalg.norm(e1, axis=1) / spacing)).astype(int)
        n2 = np.maximum(1, np.ceil(np.linalg.norm(e2, axis=1) / spacing)).astype(int)
        # A point of a grid cell (a triangle of sides d1, d2, d2 - d1) is within the cell's
        # longest side of one of its corners.
        d1, d2 = e1 / n1[:, None], e2 / n2[:, None]
        cell = np.linalg.norm(np.stack([d1, d2, d2 - d1]), axis=2).max()
        cover = max(cover, float(cell))
        keys, inverse = np.unique(np.column_stack([n1, n2]), axis=0, return_inverse=True)
        inverse = np.ravel(inverse)
        for g, (k1, k2) in enumerate(keys):
            here = inverse == g
            i, j = np.meshgrid(np.arange(k1 + 1) / k1, np.arange(k2 + 1) / k2, indexing="ij")
            keep = i + j <= 1 + 1e-12
            u, v = i[keep], j[keep]
            pts = (
                tri[here, 0][:, None]
                + u[None, :, None] * e1[here][:, None]
                + (v[None, :, None] * e2[here][:, None])
            )
            points.append(pts.reshape(-1, 3))
            ids.append(np.repeat(which[rest[here]], len(u)))
    return np.concatenate(points), np.concatenate(ids), cover


def _rows_all(b: np.ndarray) -> np.ndarray:
    """Whether each row of three booleans (n, 3) is all true (np.all over rows of three is
    twice as slow)."""
    return b[:, 0] & b[:, 1] & b[:, 2]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross products of vectors (n, 3): np.cross's arithmetic (the same bits) without its
    axis handling, which takes five times as long on 500,000 rows."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    out[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    out[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return out


def _facts(t: np.ndarray) -> np.ndarray:
    """Of triangles (k, 3, 3): centroid, longest edge, farthest corner from the centroid
    squared, (k, 5)."""
    out = np.empty((len(t), 5))
    # Coordinates as rows (corner, axis, k): each pass below runs over contiguous memory
    # (a third faster than columns of (k, 3) arrays), in the same order of operations.
    a, b, c = np.ascontiguousarray(t.transpose(1, 2, 0))
    centroids = a + b
    centroids += c
    centroids /= 3
    out[:, :3] = centroids.T
    # einsum's "ij,ij->i" over three coordinates sums x, z, then y: the same bits.
    longest = _square_rows(c - b, (0, 2, 1))
    np.maximum(longest, _square_rows(a - c, (0, 2, 1)), out=longest)
    np.maximum(longest, _square_rows(b - a, (0, 2, 1)), out=longest)
    # The square root of the largest square is the largest length (sqrt is monotone).
    out[:, 3] = np.sqrt(longest)
    # Summed in order, as numpy's sum over three coordinates does (the same bits).
    far = _square_rows(a - centroids, (0, 1, 2))
    np.maximum(far, _square_rows(b - centroids, (0, 1, 2)), out=far)
    np.maximum(far, _square_rows(c - centroids, (0, 1, 2)), out=far)
    out[:, 4] = far
    return out


def _square_rows(d: np.ndarray, order: tuple[int, int, int]) -> np.ndarray:
    """Squared lengths of vectors given as coordinate rows ``d`` (3, k), overwritten, summed
    in the coordinates' ``order``."""
    d *= d
    s = d[order[0]] + d[order[1]]
    s += d[order[2]]
    return s


def _sub_edges(edges: Edges, which: np.ndarray, count: int) -> Edges:
    """The shared edges among the faces ``which`` of a mesh of ``count`` faces whose shared
    edges are ``edges`` (no edge of three faces): the pairs with both faces among them,
    numbered as in ``which``."""
    local = np.full(count, -1)
    local[which] = np.arange(len(which))
    pairs = local[edges.pairs]
    pairs = pairs[(pairs[:, 0] >= 0) & (pairs[:, 1] >= 0)]
    return Edges(pairs, closed=2 * len(pairs) == 3 * len(which), manifold=True)


def _edge_lengths(tri: np.ndarray) -> np.ndarray:
    """The length of the edge opposite each corner of triangles (n, 3, 3), (n, 3)."""
    edges = np.stack([tri[:, 2] - tri[:, 1], tri[:, 0] - tri[:, 2], tri[:, 1] - tri[:, 0]], 1)
    return np.sqrt(np.einsum("ijk,ijk->ij", edges, edges))


def _to_triangles(
    q: np.ndarray, faces: Faces, t: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest points of triangles ``t`` to points ``q`` (pairwise), the distances and the
    signed distances (from the triangle's outward normal)."""
    closest = closest_point(faces.triangles[t], q)
    offset = q - closest
    squares = offset * offset
    # np.linalg.norm's sum, in its order (the same bits), without its reduction over rows of
    # three, which costs more than the arithmetic.
    d = np.sqrt(squares[:, 0] + squares[:, 1] + squares[:, 2])
    signed = np.einsum("ij,ij->i", offset, faces.normals[t])
    # On an edge or a corner the face normal gives no reliable sign: a point off the face's
    # own plane by less than its distance is outside.
    signed = np.where(np.abs(signed) < 0.999 * d, d, np.sign(signed) * d)
    return closest, d, signed


def _near_voxels(
    points: np.ndarray, samples: np.ndarray, reach: float
) -> tuple[np.ndarray, np.ndarray]:
    """Whether each point may be within ``reach`` of a sample, and each sample within
    ``reach`` of a point: its cube is within ``reach`` (in cubes, along each axis) of one of
    the other set's cubes (a cheap filter before the KD-tree: most of a part is far from
    the other part, and a tree of the samples near the points alone is built and searched
    faster). Cubes of side ``reach``: a dense grid of flags when it has at most
    :data:`DENSE_CELLS`, else the occupied ones sorted.

    Why not finer cubes: they drop more of the far points (on the benchmark's assembly
    83,134 instead of 95,538 of 149,406 body points kept with half-reach cubes; 44,514 are
    within reach) but keep fewer samples in the KD-tree, whose shape then differs, and so
    which of two equally near samples of a regular tessellation a query returns: a point is
    then measured against another triangle, maybe of another patch (a block on a table
    against three pins lost one of its 3 line ends)."""
    origin = np.minimum(points.min(axis=0), samples.min(axis=0)) - 2 * reach
    span = np.maximum(points.max(axis=0), samples.max(axis=0)) + 2 * reach - origin
    shape = np.floor(span / reach).astype(np.int64) + 3
    cells = float(np.prod(shape.astype(float)))
    if cells > 2.0**62:
        return np.ones(len(points), bool), np.ones(len(samples), bool)

    def keys(x: np.ndarray) -> np.ndarray:
        cell = np.floor((x - origin) / reach).astype(np.int64)
        return (cell[:, 0] * shape[1] + cell[:, 1]) * shape[2] + cell[:, 2]

    kp, ks = keys(points), keys(samples)
    if cells <= DENSE_CELLS:
        # Flags grown by one cube along each axis in turn: no sort.
        dims = tuple(int(n) for n in shape)

        def grown(k: np.ndarray) -> np.ndarray:
            flags = np.zeros(dims, bool)
            flags.reshape(-1)[k] = True
            for axis in range(3):
                lower = [slice(None)] * 3
                upper = [slice(None)] * 3
                lower[axis], upper[axis] = slice(0, -1), slice(1, None)
                spread = flags.copy()
                spread[tuple(lower)] |= flags[tuple(upper)]
                spread[tuple(upper)] |= flags[tuple(lower)]
                flags = spread
            return flags.reshape(-1)

        near_points = grown(ks)[kp]
        return near_points, grown(kp[near_points])[ks]
    step = np.array([shape[1] * shape[2], shape[2], 1])
    offsets = (np.stack(np.meshgrid(*[[-1, 0, 1]] * 3, indexing="ij"), -1).reshape(-1, 3)) @ step

    def around(k: np.ndarray) -> np.ndarray:
        occupied = np.unique(k)
        return np.unique((occupied[:, None] + offsets[None, :]).ravel())

    near_points = np.isin(kp, around(ks))
    return near_points, np.isin(ks, around(kp[near_points]))


def surface_distances(
    points: np.ndarray,
    faces: Faces,
    radius: float,
    spacing: float,
    exact_within: float | None = None,
) -> Near:
    """Distances from ``points`` (n, 3) to a mesh's surface (its ``faces``), for the points
    within ``radius`` of it; the sign from the closest triangle's outward normal.

    Each point's nearest sample (at most ``spacing`` apart) gives a triangle, and the exact
    distance to it an upper bound. Points that may be within ``exact_within`` (default
    ``radius``) of the surface, or inside it, are then measured exactly against the triangles
    of their :data:`NEIGHBOURS` nearest samples; the others keep the bound, which exceeds the
    true distance by at most the samples' cover (their nearest sample is within the cover
    of their closest point)."""
    from scipy.spatial import cKDTree

    exact = radius if exact_within is None else exact_within
    lo, hi = faces.bounds[0] - radius, faces.bounds[1] + radius
    inside = np.flatnonzero(_rows_all((points >= lo) & (points <= hi)))
    empty = Near(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)), np.zeros(0, int))
    if len(inside) == 0:
        return empty
    box = points[inside]
    which = faces.in_box(box.min(axis=0) - radius, box.max(axis=0) + radius)
    samples, ids, cover = _samples(faces, spacing, which)
    if len(samples) == 0:
        return empty
    near, useful = _near_voxels(box, samples, radius + cover)
    inside, box = inside[near], box[near]
    if len(box) == 0:
        return empty
    # Samples farther than radius + cover from every point are never an answer below.
    samples, ids = samples[useful], ids[useful]
    # Sliding-midpoint splits without shrinking the boxes: built and queried about twice as
    # fast on surface samples as the default median splits, same answers.
    tree = cKDTree(samples, balanced_tree=False, compact_nodes=False)
    # The closest point of the surface is within `cover` of a sample: a point with no sample
    # within radius + cover is farther than radius.
    first, nearest = tree.query(box, k=1, distance_upper_bound=radius + cover)
    close = np.isfinite(first)
    inside, box, first, nearest = inside[close], box[close], first[close], nearest[close]
    if len(box) == 0:
        return empty
    t = ids[nearest]
    closest, d, signed = _to_triangles(box, faces, t)
    again = np.flatnonzero((first - cover <= exact) | (signed < 0))
    k = min(NEIGHBOURS, len(samples))
    if len(again) and k > 1:
        dist, idx = tree.query(box[again], k=k, distance_upper_bound=radius + cover)
        # A sample farther than the bound plus the cover cannot stand for a closer triangle.
        hit = np.isfinite(dist) & (dist <= (d[again] + cover)[:, None])
        rows = np.broadcast_to(again[:, None], hit.shape)[hit]
        # Unique (point, triangle) pairs, through one integer key (np.unique over rows is slow).
        count = np.int64(len(faces.triangles))
        key = np.unique(rows.astype(np.int64) * count + ids[idx[hit]])
        pair_point, pair_tri = key // count, key % count
        c2, d2, s2 = _to_triangles(box[pair_point], faces, pair_tri)
        # The nearest triangle per point: sort by point, then distance.
        order = np.lexsort((d2, pair_point))
        best = order[np.r_[True, np.diff(pair_point[order]) != 0]]
        p = pair_point[best]
        better = d2[best] < d[p]
        p, best = p[better], best[better]
        closest[p], d[p], signed[p], t[p] = c2[best], d2[best], s2[best], pair_tri[best]
    keep = d <= radius
    return Near(inside[keep], signed[keep], closest[keep], t[keep])


def _components(pairs: np.ndarray, count: int) -> np.ndarray:
    """A label per node of the graph of ``count`` nodes and edges ``pairs``."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    graph = coo_matrix((np.ones(len(pairs), bool), (pairs[:, 0], pairs[:, 1])), (count, count))
    return np.asarray(connected_components(graph, directed=False)[1])


def smooth_patches(mesh: Mesh, faces: Faces | None = None) -> np.ndarray:
    """A patch label per face: faces joined across edges whose dihedral angle is below
    :data:`SMOOTH_PATCH_DEG` (a tessellated ball or pin is one patch, a groove's flanks two)."""
    return _smooth(mesh, faces or Faces.of(mesh))[0]


def _smooth(
    mesh: Mesh, faces: Faces, which: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The patch label per face (-1 for faces not in ``which``, default all), and per label
    the largest angle between two of its faces sharing an edge (deg): the tessellation's own
    angular step there."""
    count = len(faces.normals)
    edges = faces.edges
    if which is None:
        which, pairs = np.arange(count), edges.pairs
    elif edges.manifold:
        # The pairs among ``which``: those of the whole mesh with both faces in it (no edge
        # has a third face that would chain differently).
        pairs = _sub_edges(edges, which, count).pairs
    else:
        pairs = face_pairs(faces.ids[which])
    normals = faces.normals[which]
    cos = np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])
    smooth = cos > np.cos(np.radians(SMOOTH_PATCH_DEG))
    local = _components(pairs[smooth], len(which))
    facet = np.zeros(int(local.max(initial=0)) + 1)
    angle = np.degrees(np.arccos(np.clip(cos[smooth], -1.0, 1.0)))
    np.maximum.at(facet, local[pairs[smooth, 0]], angle)
    labels = np.full(count, -1, dtype=np.int64)
    labels[which] = local
    return labels, facet


def closed_bodies(mesh: Mesh) -> list[ClosedBody]:
    """The mesh's edge-connected bodies, each with its volume and bounds."""
    return _split(mesh, Faces.of(mesh))[0]


def _split(mesh: Mesh, faces: Faces) -> tuple[list[ClosedBody], np.ndarray]:
    """The mesh's edge-connected bodies (volume, bounds) and the body label of each face,
    from one labelling and per-label sums (no submeshes)."""
    labels = _components(faces.edges.pairs, len(faces.ids))
    tri = faces.triangles
    per_face = np.einsum("ij,ij->i", tri[:, 0], _cross(tri[:, 1], tri[:, 2])) / 6.0
    count = int(labels.max(initial=-1)) + 1
    if count == 0:
        return [], labels
    volume = np.bincount(labels, weights=per_face, minlength=count)
    # Per-label extremes over the faces sorted by label (ufunc.at took twice as long).
    order = np.argsort(labels, kind="stable")
    starts = np.flatnonzero(np.r_[True, labels[order][1:] != labels[order][:-1]])
    lo = np.minimum.reduceat(faces.lo[order], starts)
    hi = np.maximum.reduceat(faces.hi[order], starts)
    bodies = [ClosedBody(float(volume[k]), np.array([lo[k], hi[k]])) for k in range(count)]
    return bodies, labels


def patch_fit(
    mesh: Mesh,
    labels: np.ndarray,
    patch: int,
    faces: Faces | None = None,
    facet_deg: float | None = None,
) -> tuple[Primitive | None, list[Primitive]]:
    """The simplest surface fitting a patch's vertices (and every fit tried); ``facet_deg``
    as :func:`kcheck.body.surface_fit.fit_surface` takes it."""
    return _patch_fit(mesh, labels, patch, faces, facet_deg)[:2]


def _patch_fit(
    mesh: Mesh,
    labels: np.ndarray,
    patch: int,
    faces: Faces | None = None,
    facet_deg: float | None = None,
) -> tuple[Primitive | None, list[Primitive], np.ndarray]:
    """:func:`patch_fit`, and the patch's vertices."""
    f = faces or Faces.of(mesh)
    which = np.flatnonzero(labels == patch)
    vertices = np.asarray(mesh.vertices, dtype=float)[np.unique(np.asarray(mesh.faces)[which])]
    fit, tried = fit_surface(
        vertices,
        f.triangles[which].sum(axis=1) / 3,
        f.normals[which],
        facet_deg,
    )
    return fit, tried, vertices


def contact_regions(
    base: Mesh,
    body: Mesh,
    gap: float,
    faces: tuple[Faces, Faces] | None = None,
    touching: list[np.ndarray] | None = None,
) -> tuple[list[Region], float]:
    """The contact regions of ``body`` on ``base``, each with its patches fitted; and the
    deepest interpenetration found (m, ≥ 0). ``touching``, if given, gets the ids of the
    body's faces that come within ``gap`` of the base (for :func:`merged_pieces`).

    Points sampled on each mesh's triangles (at most ``3 gap`` apart, so that the touching
    point of two long facets crossing, as on tessellated pins, is not missed) within
    :data:`NEAR_GAPS` gaps of the other's surface are found; those within ``gap`` touch, the
    others are near misses (a region's ``least_distance`` says which). ``faces``: the base's
    and the body's :class:`Faces`, when the caller has them."""
    base_faces, body_faces = faces or (Faces.of(base), Faces.of(body))
    near = _near_patches(base, body, base_faces, body_faces, gap)
    regions = []
    fits: dict[tuple[str, int], tuple[Primitive | None, list[Primitive], np.ndarray]] = {}
    for region in near.regions:
        for side, mesh, labels, patch, surface, facet in (
            ("body", body, near.body_labels, region.body_patch, body_faces, near.body_facet),
            ("base", base, near.base_labels, region.base_patch, base_faces, near.base_facet),
        ):
            key = (side, patch)
            if key not in fits:
                fits[key] = _patch_fit(mesh, labels, patch, surface, float(facet[patch]))
            fit, tried, vertices = fits[key]
            setattr(region, f"{side}_fit", fit)
            region.tried[side] = tried
            region.vertices[side] = vertices
        regions.append(region)
    if touching is not None:
        touching.append(near.touching)
    return _one_per_place(regions, gap), near.depth


def _one_per_place(regions: list[Region], gap: float) -> list[Region]:
    """The regions with those that repeat another joined into it: the same patch on one side
    and, on the other, a patch on the same fitted surface (within ``gap``) at the same place
    (points within ``gap``). Two closed bodies of one mesh whose faces coincide where the
    other part touches give two patches there, one contact."""
    out: list[Region] = []
    for region in regions:
        for k, kept in enumerate(out):
            if _repeats(kept, region, gap):
                out[k] = replace(
                    kept,
                    points=np.concatenate([kept.points, region.points]),
                    least_distance=min(kept.least_distance, region.least_distance),
                )
                break
        else:
            out.append(region)
    return out


def _repeats(a: Region, b: Region, gap: float) -> bool:
    """Whether region ``b`` is region ``a`` again (:func:`_one_per_place`)."""
    if a.base_patch == b.base_patch and a.body_patch != b.body_patch:
        side = "body"
    elif a.body_patch == b.body_patch and a.base_patch != b.base_patch:
        side = "base"
    else:
        return False
    fa, fb = getattr(a, f"{side}_fit"), getattr(b, f"{side}_fit")
    if fa is None or fb is None or fa.kind != fb.kind:
        return False
    if fa.kind == "plane":
        if float(fa.axis @ fb.axis) < np.cos(np.radians(SMOOTH_PATCH_DEG)):
            return False
    elif fa.outward != fb.outward:
        return False
    # Each patch's vertices on the other's fitted surface.
    for fit, vertices in ((fa, b.vertices.get(side)), (fb, a.vertices.get(side))):
        if vertices is None or np.max(np.abs(residuals(fit, vertices)), initial=0.0) > gap:
            return False
    from scipy.spatial import cKDTree

    near, _ = cKDTree(a.points).query(b.points, k=1, distance_upper_bound=gap)
    return bool(np.any(np.isfinite(near)))


@dataclass(frozen=True)
class _NearPatches:
    """The regions (not yet fitted), each side's patch labels and facet angles, the depth."""

    regions: list[Region]
    body_labels: np.ndarray
    body_facet: np.ndarray
    base_labels: np.ndarray
    base_facet: np.ndarray
    depth: float
    touching: np.ndarray


def _near_patches(
    base: Mesh,
    body: Mesh,
    base_faces: Faces,
    body_faces: Faces,
    gap: float,
) -> _NearPatches:
    """Where the two meshes come within :data:`NEAR_GAPS` gaps, by distances alone: the
    regions (pairs of smooth patches) with their points and least distances, unfitted."""
    reach = NEAR_GAPS * gap
    # Only the faces within reach of the other part's bounds can touch it: the patches are
    # the smooth pieces of those (a ball's cap in a groove, not the whole plate it is on).
    body_near = body_faces.in_box(base_faces.bounds[0] - reach, base_faces.bounds[1] + reach)
    base_near = base_faces.in_box(body_faces.bounds[0] - reach, body_faces.bounds[1] + reach)
    body_labels, body_facet = _smooth(body, body_faces, body_near)
    base_labels, base_facet = _smooth(base, base_faces, base_near)
    sides = []
    for mine, near_other in ((body_faces, body_near), (base_faces, base_near)):
        other = base_faces if mine is body_faces else body_faces
        points, faces, _ = _samples(mine, 3 * gap, near_other)
        near = surface_distances(points, other, reach, 3 * gap, exact_within=gap)
        sides.append((points[near.index], faces[near.index], near))
    (pa, fa, a), (pb, fb, b) = sides
    depth = float(max(0.0, -min(a.signed.min(initial=0.0), b.signed.min(initial=0.0))))
    body_side = np.concatenate([body_labels[fa], body_labels[b.triangle]])
    base_side = np.concatenate([base_labels[a.triangle], base_labels[fb]])
    points = np.concatenate([(pa + a.closest) / 2, (pb + b.closest) / 2])
    signed = np.concatenate([a.signed, b.signed])
    cos = np.concatenate(
        [
            np.einsum("ij,ij->i", body_faces.normals[fa], base_faces.normals[a.triangle]),
            np.einsum("ij,ij->i", base_faces.normals[fb], body_faces.normals[b.triangle]),
        ]
    )
    regions = []
    # Unique (body patch, base patch) rows in row order, through one integer key (labels
    # from -1, for a triangle outside the patches).
    width = np.int64(max(int(base_side.max(initial=0)), 0) + 2)
    key = (body_side.astype(np.int64) + 1) * width + (base_side.astype(np.int64) + 1)
    unique, inverse = np.unique(key, return_inverse=True)
    pairs = np.column_stack([unique // width - 1, unique % width - 1])
    inverse = np.ravel(inverse)
    for k, (p_body, p_base) in enumerate(pairs):
        here = inverse == k
        regions.append(
            Region(
                int(p_body),
                int(p_base),
                points[here],
                float(signed[here].min()),
                float(cos[here].mean()),
            )
        )
    touching = np.unique(fa[np.abs(a.signed) <= gap])
    return _NearPatches(regions, body_labels, body_facet, base_labels, base_facet, depth, touching)


def merged_pieces(
    body: Mesh,
    base: Mesh,
    gap: float,
    faces: tuple[Faces, Faces] | None = None,
    touching: np.ndarray | None = None,
) -> list[tuple[ClosedBody, bool]]:
    """Each closed body of a body mesh made of several, and whether it looks like part of the
    base: it touches the base and sits in two or more grooves of the rest of the body file
    (the base's balls exported inside the plate's file). An empty list for a single body.

    The body is labelled once; each piece is tried on the base by distances alone, and a
    piece that touches it against only the rest's faces within reach of it (the others
    cannot come within :data:`NEAR_GAPS` gaps), with no fitting. ``faces``: the base's and
    the body's :class:`Faces`, when the caller has them; ``touching``: the body's faces that
    come within ``gap`` of the base, when :func:`contact_regions` found them."""
    base_faces, body_faces = faces or (Faces.of(base), Faces.of(body))
    pieces, labels = _split(body, body_faces)
    if len(pieces) < 2:
        return []
    f = np.asarray(body.faces)
    reach = NEAR_GAPS * gap
    out = []
    for k, piece in enumerate(pieces):
        mine = np.flatnonzero(labels == k)
        swallowed = False
        if (
            np.any(labels[touching] == k)
            if touching is not None
            else _touches(body_faces.subset(mine), base_faces, gap)
        ):
            others = body_faces.in_box(piece.bounds[0] - reach, piece.bounds[1] + reach)
            others = others[labels[others] != k]
            if len(others):
                rest = Surface(np.asarray(body.vertices), f[others])
                mesh = Surface(np.asarray(body.vertices), f[mine])
                seated = _near_patches(
                    rest, mesh, body_faces.subset(others), body_faces.subset(mine), gap
                ).regions
                # Seated: on surfaces that face each other; a face lying on the rest's face of
                # the same orientation, or crossing it, is two bodies overlapping there, not a
                # ball in a groove.
                swallowed = (
                    sum(r.least_distance <= gap and r.facing < SEATED_FACING for r in seated) >= 2
                )
        out.append((piece, swallowed))
    return out


def _touches(piece: Faces, base: Faces, gap: float) -> bool:
    """Whether points sampled on ``piece`` (at most ``3 gap`` apart) come within ``gap`` of
    ``base``'s surface."""
    near = piece.in_box(base.bounds[0] - gap, base.bounds[1] + gap)
    points, _, _ = _samples(piece, 3 * gap, near)
    return len(surface_distances(points, base, gap, 3 * gap).index) > 0
