"""Candidate attachment points for ``kcheck suggest``: a regular grid in a box, or points on
the body's mesh surface (uniform by area, seeded), and more points near the best ones."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from kcheck.scene import Scene

__all__ = ["SuggestError", "Sampler", "Chart", "BoxSampler", "SurfaceSampler"]


class SuggestError(ValueError):
    """The scene cannot be searched (planar, undetermined cases, no load)."""


class Sampler(Protocol):
    """Where candidate points come from: a first spread, then more near the best ones."""

    spacing: float

    def initial(self, count: int) -> tuple[np.ndarray, np.ndarray | None]:
        """``count`` points (m) and their surface normals (None off a surface)."""

    def near(
        self, centres: np.ndarray, radius: float, count: int
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """About ``count`` points within ``radius`` (m) of each centre (m, 3)."""

    def chart(self, start: np.ndarray, radius: float) -> Chart:
        """Local coordinates about ``start`` for a continuous search within ``radius`` (m)."""


class Chart:
    """Local coordinates of candidate points about a start: ``point(x)`` maps ``x``
    (``dims``,) in metres to a candidate point (m) and its surface normal (None off a
    surface); ``x = 0`` is the start."""

    def __init__(
        self,
        start: np.ndarray,
        axes: np.ndarray,
        place: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray | None]],
    ) -> None:
        self.start, self.axes, self.place = start, axes, place

    @property
    def dims(self) -> int:
        """Number of local coordinates."""
        return len(self.axes)

    def point(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """The candidate point (m) at local coordinates ``x`` and its normal."""
        return self.place(self.start + np.asarray(x, float) @ self.axes)


class BoxSampler:
    """A regular grid in the box [lo, hi] (m), then random points near the best, in the box;
    a flat box (some ``lo == hi``) is filled in its remaining dimensions."""

    def __init__(self, lo: np.ndarray, hi: np.ndarray, count: int, seed: int) -> None:
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)
        self.live = self.hi > self.lo
        self.rng = np.random.default_rng(seed)
        dims = max(1, int(self.live.sum()))
        self.per_axis = max(2, round(count ** (1.0 / dims)))
        self.spacing = float(np.max(self.hi - self.lo)) / (self.per_axis - 1)

    def initial(self, count: int) -> tuple[np.ndarray, None]:
        """The regular grid (``count`` fixed the points per axis)."""
        del count
        axes = [
            np.linspace(self.lo[i], self.hi[i], self.per_axis)
            if self.live[i]
            else self.lo[i : i + 1]
            for i in range(3)
        ]
        grid = np.meshgrid(*axes, indexing="ij")
        return np.column_stack([g.ravel() for g in grid]), None

    def near(self, centres: np.ndarray, radius: float, count: int) -> tuple[np.ndarray, None]:
        """Uniform points in cubes of half-side ``radius`` about the centres, clipped."""
        offsets = self.rng.uniform(-radius, radius, (len(centres), count, 3)) * self.live
        return np.clip(centres[:, None, :] + offsets, self.lo, self.hi).reshape(-1, 3), None

    def chart(self, start: np.ndarray, radius: float) -> Chart:
        """The box's live axes about ``start``; points clipped into the box."""
        del radius
        axes = np.eye(3)[self.live]
        return Chart(np.asarray(start, float), axes, lambda p: (np.clip(p, self.lo, self.hi), None))


class SurfaceSampler:
    """Points on the body's mesh surface, uniform by area, seeded; then near the best ones."""

    def __init__(self, scene: Scene, seed: int) -> None:
        import trimesh

        from kcheck.body.mass import placed_mesh

        if scene.body is None or not scene.body.parts:
            raise SuggestError("the scene's body has no mesh to sample: give --box")
        meshes = [placed_mesh(p) for p in scene.body.parts]
        mesh = trimesh.util.concatenate(meshes) if len(meshes) > 1 else meshes[0]
        assert isinstance(mesh, trimesh.Trimesh)  # meshes join into a mesh
        self.mesh = mesh
        self.rng = np.random.default_rng(seed)
        self.spacing = 0.0

    def _sample(self, count: int, weight: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        import trimesh

        points, faces = trimesh.sample.sample_surface(
            self.mesh, count, face_weight=weight, seed=self.rng
        )
        return np.asarray(points, float), np.asarray(self.mesh.face_normals[faces], float)

    def initial(self, count: int) -> tuple[np.ndarray, np.ndarray]:
        """``count`` points by area; the spacing is that of ``count`` points on the area."""
        self.spacing = float(np.sqrt(self.mesh.area / count))
        return self._sample(count, None)

    def near(self, centres: np.ndarray, radius: float, count: int) -> tuple[np.ndarray, np.ndarray]:
        """Random points within ``radius`` of each centre, moved onto the nearest face."""
        from trimesh.triangles import closest_point

        triangles = self.mesh.triangles
        points, normals = [], []
        for centre in centres:
            at_centre = closest_point(triangles, np.broadcast_to(centre, (len(triangles), 3)))
            near = np.flatnonzero(np.linalg.norm(at_centre - centre, axis=1) <= radius)
            if not len(near):
                continue
            step = self.rng.normal(size=(count, 3))
            step *= radius * self.rng.uniform(0, 1, (count, 1)) ** (1 / 3)
            step /= np.linalg.norm(step, axis=1, keepdims=True)
            cloud = centre + step
            # every cloud point against every near face; keep the closest face's point
            pairs = closest_point(
                np.repeat(triangles[near][None], count, 0).reshape(-1, 3, 3),
                np.repeat(cloud, len(near), axis=0),
            )
            dist = np.linalg.norm(pairs - np.repeat(cloud, len(near), axis=0), axis=1)
            pick = dist.reshape(count, len(near)).argmin(axis=1)
            points.append(pairs.reshape(count, len(near), 3)[np.arange(count), pick])
            normals.append(self.mesh.face_normals[near[pick]])
        if not points:
            return np.zeros((0, 3)), np.zeros((0, 3))
        return np.vstack(points), np.vstack(normals)

    def chart(self, start: np.ndarray, radius: float) -> Chart:
        """The tangent plane at ``start`` (of the face nearest it), each point moved onto the
        nearest face within ``radius`` of the start: the search may cross an edge."""
        from trimesh.triangles import closest_point

        triangles = self.mesh.triangles
        start = np.asarray(start, float)
        at_start = closest_point(triangles, np.broadcast_to(start, (len(triangles), 3)))
        gap = np.linalg.norm(at_start - start, axis=1)
        near = np.flatnonzero(gap <= gap.min() + radius)
        normal = self.mesh.face_normals[int(np.argmin(gap))]
        first = np.cross(normal, (1.0, 0.0, 0.0))
        if np.linalg.norm(first) < 0.5:
            first = np.cross(normal, (0.0, 1.0, 0.0))
        first /= np.linalg.norm(first)
        axes = np.vstack([first, np.cross(normal, first)])
        local = triangles[near]

        def place(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            on = closest_point(local, np.broadcast_to(p, (len(local), 3)))
            k = int(np.argmin(np.linalg.norm(on - p, axis=1)))
            return on[k], self.mesh.face_normals[near[k]]

        return Chart(start, axes, place)
