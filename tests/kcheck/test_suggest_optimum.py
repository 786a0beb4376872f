"""``kcheck suggest`` reaches the optimum: its best margin against an exhaustive grid.

The reference is computed here, independently of the search's sampling and of its continuous
refinement (Nelder–Mead): a regular grid over every face of the body (the fixtures' bodies are
boxes; the mesh's volume is checked to be the box's), each point's best margin over a dense
Fibonacci grid of directions, then the best grid points with their exact direction
(:func:`kcheck.mechanics.deepest.most_robust_direction`, in a plane
:func:`kcheck.mechanics.robust_angle.most_robust_angle`) on a 5 x 5 grid about each of the
four best, moved while it improves and halved when not, down to 1 % of the first spacing.
A grid can only fall short of the optimum, so the search must reach it less 0.05°; on the 3-2-1
block also the issue's own exhaustive value (24.63° was found where 25.49° is reachable).
"""

from __future__ import annotations

import numpy as np
import pytest

from kcheck.analysis.candidates import SurfaceSampler
from kcheck.analysis.cases import problem_for
from kcheck.analysis.suggest import (
    best_direction,
    caps_at,
    direction_grid,
    point_caps,
    point_margins,
    search,
)
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.robust_angle import most_robust_angle
from kcheck.scene import load_scene
from tests.conftest import FIXTURES

TOLERANCE_DEG = 0.05


def _box_faces(lo: np.ndarray, hi: np.ndarray, step: float) -> list[tuple[np.ndarray, int]]:
    """Grid points (n, 3) on each of the box's six faces, with the axis each face is normal to."""
    faces = []
    for axis in range(3):
        others = [i for i in range(3) if i != axis]
        u = np.linspace(lo[others[0]], hi[others[0]], int(round((hi - lo)[others[0]] / step)) + 1)
        v = np.linspace(lo[others[1]], hi[others[1]], int(round((hi - lo)[others[1]] / step)) + 1)
        uu, vv = np.meshgrid(u, v, indexing="ij")
        for level in (lo[axis], hi[axis]):
            points = np.empty((uu.size, 3))
            points[:, axis] = level
            points[:, others[0]], points[:, others[1]] = uu.ravel(), vv.ravel()
            faces.append((points, axis))
    return faces


def _exact(caps, points: np.ndarray) -> np.ndarray:
    return np.array([best_direction(caps, c)[1] for c in caps_at(caps, points)])


def exhaustive_margin(scene, mass, step: float, directions: int) -> float:
    """The best margin (rad) over a grid on the body's box, zoomed in about its best points."""
    mesh = SurfaceSampler(scene, 0).mesh
    lo, hi = mesh.bounds
    assert mesh.volume == pytest.approx(float(np.prod(hi - lo)), rel=1e-9)  # a box
    caps = point_caps(problem_for(scene, mass))
    grid = direction_grid(scene.dim, directions)
    faces = _box_faces(lo, hi, step)
    points = np.vstack([p for p, _ in faces])
    normal_axis = np.concatenate([np.full(len(p), a) for p, a in faces])
    coarse, _ = point_margins(caps, points, grid)
    best = -np.inf
    for j in np.argsort(-coarse)[:4]:
        centre, axis = points[j], normal_axis[j]
        free = np.array([i != axis for i in range(3)], float)
        width = step
        margin = float(_exact(caps, centre[None])[0])
        axes = np.eye(3)[free.astype(bool)]
        offsets = np.linspace(-1.0, 1.0, 5)
        du, dv = (g.ravel()[:, None] for g in np.meshgrid(offsets, offsets, indexing="ij"))
        while width > 0.01 * step:
            # a 5 x 5 grid about the best point so far, moved while it improves, then halved
            trial = np.clip(centre + width * (du * axes[0] + dv * axes[1]), lo, hi)
            values = _exact(caps, trial)
            k = int(np.argmax(values))
            if values[k] > margin + 1e-12:
                margin, centre = float(values[k]), trial[k]
            else:
                width /= 2.0
        best = max(best, margin)
    return best


def test_most_robust_angle_is_the_best_of_a_fine_circle() -> None:
    """The exact planar optimum against 20 001 angles: never worse, at most the grid's error."""
    from kcheck.mechanics.arcs import cap_margins

    rng = np.random.default_rng(0)
    angles = np.linspace(0.0, 2.0 * np.pi, 20_001)
    circle = np.column_stack([np.cos(angles), np.sin(angles)])
    for _ in range(50):
        k = int(rng.integers(1, 7))
        a, c = 0.5 * rng.normal(size=k), rng.normal(size=(k, 2))
        direction, margin = most_robust_angle(a, c)
        reference = float(cap_margins(a, c, circle).max())
        assert reference - 1e-9 <= margin <= reference + 2.0 * np.pi / 20_000
        # the same margin, to the rounding of arccos near its ends
        assert cap_margins(a, c, direction[None])[0] == pytest.approx(margin, abs=1e-7)


def test_block_321_search_reaches_the_exhaustive_optimum() -> None:
    """The issue's case: the sampled search alone stopped at 24.63°; the grid reaches 25.49°."""
    scene = load_scene(FIXTURES / "block-321" / "block.kcheck.yaml")
    mass = body_mass_properties(scene.body, scene.scale)
    reference = np.degrees(exhaustive_margin(scene, mass, 0.01, 500))
    assert 25.4 < reference <= 25.495  # below the 25.49° by at most the grid's step
    found = search(scene, mass, SurfaceSampler(scene, 0), 2000)
    best = np.degrees(found.best[0].margin)
    assert best >= reference - TOLERANCE_DEG and best == pytest.approx(25.49, abs=0.005)


def test_planar_block_search_reaches_the_exhaustive_optimum() -> None:
    """A planar scene is searched (it was refused before); its optimum against the grid."""
    scene = load_scene(FIXTURES / "planar-block" / "block.kcheck.yaml")
    mass = body_mass_properties(scene.body, scene.scale)
    reference = np.degrees(exhaustive_margin(scene, mass, 0.002, 720))
    found = search(scene, mass, SurfaceSampler(scene, 0), 500)
    best = found.best[0]
    assert np.degrees(best.margin) >= reference - TOLERANCE_DEG
    assert best.direction[2] == 0.0  # in the plane


@pytest.mark.slow
@pytest.mark.parametrize(
    "name",
    [
        "block-321-balls/block.kcheck.yaml",
        "thesis-appendix-a/block.kcheck.yaml",
    ],
)
def test_other_box_fixtures_reach_the_exhaustive_optimum(name: str) -> None:
    """The other fixtures whose body is a box, the same way."""
    scene = load_scene(FIXTURES / name)
    mass = body_mass_properties(scene.body, scene.scale)
    reference = np.degrees(exhaustive_margin(scene, mass, 0.005, 1000))
    found = search(scene, mass, SurfaceSampler(scene, 0), 2000)
    assert np.degrees(found.best[0].margin) >= reference - TOLERANCE_DEG


def _onto(mesh, point: np.ndarray) -> np.ndarray:
    """The mesh's point nearest ``point`` (every triangle tried)."""
    from trimesh.triangles import closest_point

    on = closest_point(mesh.triangles, np.broadcast_to(point, (len(mesh.triangles), 3)))
    return on[int(np.argmin(np.linalg.norm(on - point, axis=1)))]


def dense_surface_margin(scene, mass, count: int, directions: int) -> float:
    """A reference for bodies that are not boxes: ``count`` points uniform on the mesh's
    surface (another seed than the search's), each with its best margin over ``directions``,
    then about the 8 best the same moving and halving 5 x 5 grid as on a box, in the plane of
    the face, each trial point moved onto the mesh (its nearest point)."""
    import trimesh

    mesh = SurfaceSampler(scene, 0).mesh
    caps = point_caps(problem_for(scene, mass))
    points, faces = trimesh.sample.sample_surface(mesh, count, seed=12345)
    coarse, _ = point_margins(caps, np.asarray(points), direction_grid(scene.dim, directions))
    step = float(np.sqrt(mesh.area / count))
    offsets = np.linspace(-1.0, 1.0, 5)
    du, dv = (g.ravel()[:, None] for g in np.meshgrid(offsets, offsets, indexing="ij"))
    best = -np.inf
    for j in np.argsort(-coarse)[:8]:
        normal = mesh.face_normals[faces[j]]
        first = np.cross(normal, (1.0, 0.0, 0.0))
        if np.linalg.norm(first) < 0.5:
            first = np.cross(normal, (0.0, 1.0, 0.0))
        first /= np.linalg.norm(first)
        second = np.cross(normal, first)
        centre, width = np.asarray(points[j], float), step
        margin = float(_exact(caps, centre[None])[0])
        while width > 0.01 * step:
            trial = centre + width * (du * first + dv * second)
            trial = np.array([_onto(mesh, p) for p in trial])
            values = _exact(caps, trial)
            k = int(np.argmax(values))
            if values[k] > margin + 1e-12:
                margin, centre = float(values[k]), trial[k]
            else:
                width /= 2.0
        best = max(best, margin)
    return best


@pytest.mark.slow
@pytest.mark.parametrize(
    "name",
    [
        "kelvin/coupling.kcheck.yaml",
        "maxwell-three-vee/coupling.kcheck.yaml",
        "three-groove/coupling.kcheck.yaml",
        "thesis-potato/potato.kcheck.yaml",
    ],
)
def test_meshed_fixtures_reach_a_dense_reference(name: str) -> None:
    """Fixtures whose body is no box, against 10 000 surface points refined locally."""
    scene = load_scene(FIXTURES / name)
    mass = body_mass_properties(scene.body, scene.scale)
    reference = np.degrees(dense_surface_margin(scene, mass, 10_000, 300))
    found = search(scene, mass, SurfaceSampler(scene, 0), 2000)
    assert np.degrees(found.best[0].margin) >= reference - TOLERANCE_DEG
