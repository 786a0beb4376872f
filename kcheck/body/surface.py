"""Where points lie against the body's surface: distance to it (m), the closest point, the
surface's outward normal there, and whether a point is inside (the generalised winding
number). Plain numpy over the placed triangles, so that no spatial index (rtree, embree) is
needed; a scene has a few supports, and each query is one pass over the faces.

A planar scene's body is its section in the plane of motion: :func:`section_segments` cuts
it, and :func:`closest_on_segments` measures in that plane.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from kcheck.records import dataclass

if TYPE_CHECKING:
    from kcheck.scene import Body

__all__ = [
    "Surface",
    "body_surface",
    "closest_on_triangles",
    "closest_point",
    "inside",
    "closest_on_segments",
    "section_segments",
    "winding_numbers",
]

#: Faces per block of a query: bounds the temporary arrays (points x faces x 3 floats).
_BLOCK = 200_000


@dataclass(frozen=True)
class Surface:
    """The body's placed triangles (F, 3, 3), in metres, and whether every part is closed
    (watertight, consistently wound: inside and outside are then defined); ``vertices``, if
    known, the triangles' corners (V, 3) each once (the closest-point query's bound)."""

    triangles: np.ndarray
    closed: bool
    vertices: np.ndarray | None = None

    @property
    def bounds(self) -> np.ndarray:
        """Axis-aligned bounds (rows min, max), m."""
        flat = self.triangles.reshape(-1, 3)
        return np.array([flat.min(axis=0), flat.max(axis=0)])


def body_surface(body: Body, max_mesh_bytes: int | None = None) -> Surface | None:
    """The surface of the body's mesh parts in the scene's frame, in metres; None without
    mesh parts. Raises MeshError for a mesh that cannot be read (as mass properties do)."""
    from kcheck.body.mass import mesh_closure, place, placed_mesh, read_mesh

    if not body.parts:
        return None
    triangles = []
    corners = []
    closed = True
    for part in body.parts:
        mesh = read_mesh(part, max_mesh_bytes)  # shared: read here, changed nowhere
        closure = mesh_closure(mesh)
        if part.repair and not (closure.watertight and closure.consistent):
            import trimesh  # the repair mass properties apply (kcheck.body.mass)

            mesh = placed_mesh(part, max_mesh_bytes)  # a copy, placed, to repair
            with np.errstate(divide="ignore", invalid="ignore"):
                trimesh.repair.fix_winding(mesh)
                trimesh.repair.fill_holes(mesh)
                trimesh.repair.fix_normals(mesh, multibody=True)
            closure = mesh_closure(mesh)
            vertices = np.asarray(mesh.vertices, dtype=float)
            placed = np.asarray(mesh.triangles, dtype=float)
        else:
            # placed_mesh's triangles (its vertices placed, then indexed by the faces), without
            # copying the mesh: the same numbers
            vertices = np.asarray(mesh.vertices)
            if part.rotation is not None or any(part.translation):
                vertices = place(vertices, part)
            placed = np.asarray(vertices[np.asarray(mesh.faces)], dtype=float)
        closed = closed and closure.watertight and closure.consistent
        if closed and _volume(placed) < 0:
            closed = False  # wound inwards: inside and outside swapped
        triangles.append(placed)
        used = np.zeros(len(vertices), dtype=bool)
        used[np.asarray(mesh.faces)] = True
        corners.append(np.asarray(vertices[used], dtype=float))
    return Surface(np.concatenate(triangles), closed, np.concatenate(corners))


def _volume(triangles: np.ndarray) -> float:
    """The mesh's volume (m³) from its triangles (F, 3, 3), bit for bit as ``mesh.volume``
    computes it (trimesh's first surface integral: the faces' cross products' x times their
    vertices' x summed, over 6) without the centre of mass and inertia it computes alongside."""
    from trimesh.triangles import cross  # what trimesh's ``triangles_cross`` is

    with np.errstate(all="ignore"):
        f1 = triangles[:, 0, 0] + triangles[:, 1, 0] + triangles[:, 2, 0]
        return float(np.sum(cross(triangles)[:, 0] * f1) / 6.0)


def closest_point(
    triangles: np.ndarray, points: np.ndarray, vertices: np.ndarray | None = None
) -> tuple[np.ndarray, ...]:
    """:func:`closest_on_triangles`, measuring only the triangles whose bounding box is no
    farther than the nearest vertex (the others cannot hold the closest point): for a large
    mesh a few triangles per point instead of all. ``vertices``: the triangles' corners each
    once, if known (else every triangle's three: the same nearest one, found slower)."""
    points = np.asarray(points, dtype=float)
    if vertices is None:
        vertices = triangles.reshape(-1, 3)
    lo, hi = _corner_min(triangles), _corner_max(triangles)  # each face's box
    # per axis, contiguous: the box distances without a norm's reduction over a short last axis
    lo_axes, hi_axes = np.ascontiguousarray(lo.T), np.ascontiguousarray(hi.T)
    q = np.zeros_like(points)
    d = np.zeros(len(points))
    f = np.zeros(len(points), dtype=int)
    step = max(1, _BLOCK // max(len(triangles), 1))  # points per block of the (P, F) arrays
    for k in range(0, len(points), step):
        p = points[k : k + step]
        to_vertex = vertices[None] - p[:, None]
        nearest_vertex = np.sqrt(np.min(np.einsum("pij,pij->pi", to_vertex, to_vertex), axis=1))
        box = _box_distance(lo_axes, hi_axes, p)
        owner, near = np.nonzero(box <= nearest_vertex[:, None] * (1 + 1e-9) + 1e-300)
        tri = triangles[near]
        qs = _closest(tri[:, 0], tri[:, 1], tri[:, 2], p[owner])
        ds = np.linalg.norm(qs - p[owner], axis=1)
        for i in range(len(p)):
            mine = np.flatnonzero(owner == i)  # in ascending face order, as one point's query
            best = mine[np.argmin(ds[mine])]
            q[k + i], d[k + i], f[k + i] = qs[best], ds[best], near[best]
    return q, d, f


def _corner_min(values: np.ndarray) -> np.ndarray:
    """``values.min(axis=1)`` of values per triangle corner (F, 3, ...), by pairwise minima:
    the same values, without numpy's slow reduction over a short middle axis."""
    return np.minimum(np.minimum(values[:, 0], values[:, 1]), values[:, 2])


def _corner_max(values: np.ndarray) -> np.ndarray:
    """``values.max(axis=1)`` of values per triangle corner (F, 3, ...), as :func:`_corner_min`."""
    return np.maximum(np.maximum(values[:, 0], values[:, 1]), values[:, 2])


def _first_edges(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The triangles' (F, 3, 3) edges from their first vertex: to the second, to the third."""
    return triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]


def _box_distance(lo: np.ndarray, hi: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Distance (P, F) of each point (P, 3) from each box, its corners by axis ``lo`` and
    ``hi`` (3, F): the norm of the per-axis gaps, summed x, y, z (as numpy's norm over the
    last axis does)."""
    squared = np.zeros((len(points), lo.shape[1]))
    for k in range(3):
        p = points[:, k, None]
        gap = np.maximum(np.maximum(lo[k] - p, p - hi[k]), 0)
        squared += gap * gap
    return np.sqrt(squared)


#: Ray directions of the inside test: generic (no axis, no diagonal of a box's faces), so that a
#: ray from a point off the surface meets no edge or vertex; the majority of three decides.
_RAYS = np.array([[0.5377, 0.3189, 0.7806], [-0.6431, 0.5207, 0.5615], [0.2113, -0.7904, 0.5748]])


#: Faces up to which a surface's per-ray set-up is kept (:func:`_rays_of`): about 1 kB a face.
_KEEP_FACES = 20_000
#: The per-ray set-up of the last few surfaces, by the triangles' array (a study's variants
#: query the one surface of their body over and over).
_RAY_SETUPS: list[tuple[np.ndarray, list[_RaySetup]]] = []


@dataclass(frozen=True)
class _RaySetup:
    """What a ray direction's inside test needs of every face: the unit direction, the plane
    across it (``e1``, ``e2``), each face's shadow box in that plane (``lo``, ``hi``) and its
    Möller–Trumbore vectors (edges from the first vertex, ``direction x edge2``)."""

    d: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    edge1: np.ndarray
    edge2: np.ndarray
    h: np.ndarray


def _ray_setup(
    triangles: np.ndarray, ray: np.ndarray, edges: tuple[np.ndarray, np.ndarray] | None = None
) -> _RaySetup:
    """The set-up of one ray direction; ``edges``: the triangles' edges from the first vertex
    (to the second, to the third), if worked out already (they do not depend on the ray)."""
    d = ray / np.linalg.norm(ray)
    e1 = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    u, v = triangles @ e1, triangles @ e2  # (F, 3) each: the vertices' shadow coordinates
    # the boxes over the three vertices (what the stacked coordinates' min/max over axis 1
    # give, without the stacking)
    lo = np.column_stack([_corner_min(u), _corner_min(v)])
    hi = np.column_stack([_corner_max(u), _corner_max(v)])
    edge1, edge2 = _first_edges(triangles) if edges is None else edges
    h = np.cross(d, edge2)
    return _RaySetup(d, e1, e2, lo, hi, edge1, edge2, h)


def _rays_of(triangles: np.ndarray) -> list[_RaySetup]:
    """The set-up of every ray of :data:`_RAYS` for these triangles, kept for a small
    surface (the same array object asked again gets the same arrays)."""
    for kept, setups in _RAY_SETUPS:
        if kept is triangles:
            return setups
    edges = _first_edges(triangles)
    setups = [_ray_setup(triangles, ray, edges) for ray in _RAYS]
    if len(triangles) <= _KEEP_FACES:
        _RAY_SETUPS.insert(0, (triangles, setups))
        del _RAY_SETUPS[4:]
    return setups


def inside(triangles: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Whether each point lies inside a closed outward-wound surface (or a union of such
    parts, overlapping or not): the signed count of the triangles a ray from it crosses
    (Möller–Trumbore), the majority of three rays; only the triangles whose shadow along the
    ray covers the point are tested, all points' at once."""
    points = np.asarray(points, dtype=float)
    votes = np.zeros(len(points), dtype=int)
    for ray in _rays_of(triangles):
        lo, hi = ray.lo, ray.hi
        # each point's own dot products, as one point's query rounds them
        pu = np.array([[p @ ray.e1, p @ ray.e2] for p in points]).reshape(-1, 2)  # (P, 2)
        winding = np.zeros(len(points), dtype=int)
        step = max(1, _BLOCK // max(len(triangles), 1))  # points per block of the masks
        for k in range(0, len(points), step):
            u, v = pu[k : k + step, 0, None], pu[k : k + step, 1, None]
            # the shadow boxes covering each point (the two coordinates' tests and-ed: what
            # np.all over them gives, without its reduction over an axis of two)
            owner, near = np.nonzero(
                (lo[:, 0] <= u) & (u <= hi[:, 0]) & (lo[:, 1] <= v) & (v <= hi[:, 1])
            )
            owner += k
            hits = _crossings(triangles[near, 0], ray, near, points[owner])
            np.add.at(winding, owner, hits)
        votes += winding > 0
    return np.asarray(votes >= 2)


def _crossings(a: np.ndarray, ray: _RaySetup, near: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """Per triangle ``near`` (first vertices ``a``), its share of the winding number along the
    ray ``origin + t direction`` (t > 0; ``origin`` one row per triangle): +1 where the ray
    leaves through it, -1 where it enters, 0 where it misses (outward-wound closed parts:
    summed, 1 inside one part, 2 where two overlap, 0 outside)."""
    e1, e2, h = ray.edge1[near], ray.edge2[near], ray.h[near]
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 0
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - a
    u = inv * np.einsum("ij,ij->i", s, h)
    q = np.cross(s, e1)
    v = inv * (q @ ray.d)
    t = inv * np.einsum("ij,ij->i", e2, q)
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return np.where(hit, -np.sign(det), 0.0).astype(int)  # det = -direction · (outward normal)


def _blocks(count: int) -> list[slice]:
    return [slice(i, min(i + _BLOCK, count)) for i in range(0, max(count, 1), _BLOCK)]


def closest_on_triangles(
    triangles: np.ndarray, points: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each point (P, 3): the closest point on the triangles (F, 3, 3), its distance
    (m) and the index of its triangle (Ericson, *Real-Time Collision Detection*, §5.1.5)."""
    points = np.asarray(points, dtype=float)
    best_d = np.full(len(points), np.inf)
    best_q = np.zeros_like(points)
    best_f = np.zeros(len(points), dtype=int)
    for block in _blocks(len(triangles)):
        tri = triangles[block]
        q = _closest_block(tri, points)  # (P, F, 3)
        d = np.linalg.norm(q - points[:, None, :], axis=2)
        f = np.argmin(d, axis=1)
        rows = np.arange(len(points))
        better = d[rows, f] < best_d
        best_d = np.where(better, d[rows, f], best_d)
        best_q[better] = q[rows, f][better]
        best_f[better] = f[better] + block.start
    return best_q, best_d, best_f


def _closest_block(tri: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Closest points (P, F, 3) of each point on each triangle, by Voronoi region."""
    return _closest(tri[None, :, 0, :], tri[None, :, 1, :], tri[None, :, 2, :], p[:, None, :])


def _closest(a: np.ndarray, b: np.ndarray, c: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Closest points of points ``p`` on triangles ``a b c`` (vertex arrays, ``(..., 3)``,
    broadcast against each other), by Voronoi region (Ericson §5.1.5)."""
    ab, ac, ap = b - a, c - a, p - a

    def dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return np.einsum("...k,...k->...", u, v)

    d1, d2 = dot(ab, ap), dot(ac, ap)
    bp = p - b
    d3, d4 = dot(ab, bp), dot(ac, bp)
    cp = p - c
    d5, d6 = dot(ab, cp), dot(ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v = np.where(denom != 0, vb / denom, 0.0)
        w = np.where(denom != 0, vc / denom, 0.0)
        out = a + ab * v[..., None] + ac * w[..., None]  # inside the face
        # edges
        t_bc = np.clip((d4 - d3) / ((d4 - d3) + (d5 - d6)), 0, 1)
        on_bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
        out = np.where(on_bc[..., None], b + (c - b) * t_bc[..., None], out)
        t_ac = np.clip(d2 / (d2 - d6), 0, 1)
        on_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        out = np.where(on_ac[..., None], a + ac * t_ac[..., None], out)
        t_ab = np.clip(d1 / (d1 - d3), 0, 1)
        on_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        out = np.where(on_ab[..., None], a + ab * t_ab[..., None], out)
    # vertices
    out = np.where(((d6 >= 0) & (d5 <= d6))[..., None], np.broadcast_to(c, out.shape), out)
    out = np.where(((d3 >= 0) & (d4 <= d3))[..., None], np.broadcast_to(b, out.shape), out)
    out = np.where(((d1 <= 0) & (d2 <= 0))[..., None], np.broadcast_to(a, out.shape), out)
    return np.asarray(out)


def winding_numbers(triangles: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised winding number of a closed outward-wound surface about each point: 1
    inside, 0 outside, ½ on the surface (solid angles of the triangles, Van Oosterom and
    Strackee 1983, summed over 4π)."""
    points = np.asarray(points, dtype=float)
    total = np.zeros(len(points))
    for block in _blocks(len(triangles)):
        tri = triangles[block]
        r = tri[None, :, :, :] - points[:, None, None, :]  # (P, F, 3, 3)
        n = np.linalg.norm(r, axis=3)
        a, b, c = r[:, :, 0], r[:, :, 1], r[:, :, 2]
        la, lb, lc = n[:, :, 0], n[:, :, 1], n[:, :, 2]
        numerator = np.einsum("pfk,pfk->pf", a, np.cross(b, c))
        denominator = (
            la * lb * lc
            + np.einsum("pfk,pfk->pf", a, b) * lc
            + np.einsum("pfk,pfk->pf", a, c) * lb
            + np.einsum("pfk,pfk->pf", b, c) * la
        )
        total += 2 * np.arctan2(numerator, denominator).sum(axis=1)
    return total / (4 * np.pi)


def face_normals(triangles: np.ndarray) -> np.ndarray:
    """Unit outward normals of outward-wound triangles (zero for a degenerate face)."""
    n = np.cross(*_first_edges(triangles))
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.asarray(np.where(length > 0, n / np.where(length > 0, length, 1.0), 0.0))


def section_segments(triangles: np.ndarray, z: float) -> np.ndarray:
    """The surface's section by the plane at height ``z`` (m): segments (S, 2, 2) in x, y.
    A triangle lying in the plane gives none (its neighbours give the outline)."""
    height = triangles[:, :, 2] - z
    above = height > 0
    crossing = above.any(axis=1) & ~above.all(axis=1)
    out = []
    for tri, h in zip(triangles[crossing], height[crossing], strict=True):
        points = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            if (h[i] > 0) != (h[j] > 0):
                t = h[i] / (h[i] - h[j])
                points.append(tri[i, :2] + t * (tri[j, :2] - tri[i, :2]))
        if len(points) == 2:
            out.append(points)
    return np.asarray(out, dtype=float).reshape(-1, 2, 2)


def closest_on_segments(segments: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each point (P, 2): the closest point on the segments (S, 2, 2) and its distance."""
    a, b = segments[None, :, 0], segments[None, :, 1]
    p = np.asarray(points, dtype=float)[:, None, :]
    ab = b - a
    length_sq = np.einsum("...k,...k->...", ab, ab)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(length_sq > 0, np.einsum("...k,...k->...", p - a, ab) / length_sq, 0.0)
    q = a + np.clip(t, 0, 1)[..., None] * ab
    d = np.linalg.norm(q - p, axis=2)
    k = np.argmin(d, axis=1)
    rows = np.arange(len(points))
    return q[rows, k], d[rows, k]
