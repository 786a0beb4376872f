"""The cold path's shortcuts give the very numbers of what they replace (issue 24, cold
cache): the surface's volume against trimesh's ``mesh.volume``, the shadow and face boxes
against numpy's reductions, a mesh's mass properties against trimesh's own with the density
set, and the pruned closest-point query against the brute-force one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from kcheck.body import surface

trimesh = pytest.importorskip("trimesh")


def _meshes() -> list:
    rng = np.random.default_rng(7)
    out = []
    for i in range(40):
        sphere = trimesh.creation.icosphere(
            subdivisions=int(rng.integers(0, 3)), radius=float(rng.uniform(1e-3, 2))
        )
        sphere.apply_translation(rng.normal(size=3) * 10 ** rng.uniform(-3, 2))
        if i % 3 == 0:
            sphere.invert()  # wound inwards: a negative volume
        box = trimesh.creation.box(extents=rng.uniform(1e-3, 1, size=3))
        box.apply_transform(trimesh.transformations.random_rotation_matrix(rng.random(3)))
        box.apply_translation(rng.normal(size=3))
        out += [sphere, box]
    plate = Path(__file__).parents[2] / "fixtures" / "three-groove" / "top-plate.stl"
    if plate.exists():
        out.append(trimesh.load_mesh(plate).apply_scale(1e-3))  # mm to m
    return out


def test_volume_is_trimesh_volume_bit_for_bit() -> None:
    for mesh in _meshes():
        assert surface._volume(np.asarray(mesh.triangles)) == float(mesh.copy().volume)


@pytest.mark.parametrize("shared", [False, True])
def test_surface_triangles_are_the_placed_meshes(shared: bool) -> None:
    # body_surface places the vertices of the mesh read and indexes them by the faces, with no
    # copy of the mesh: the reference is placed_mesh's triangles (a copy with its vertices
    # placed), on every fixture with mesh parts, within shared_meshes and outside it.
    import contextlib

    from kcheck.body.mass import mesh_closure, placed_mesh, shared_meshes
    from kcheck.scene import load_scene

    fixtures = Path(__file__).parents[2] / "fixtures"
    seen = 0
    for path in sorted(fixtures.glob("*/*.kcheck.yaml")):
        try:
            scene = load_scene(path)
        except Exception:
            continue  # fixtures of bad input
        if scene.body is None or not scene.body.parts:
            continue
        with shared_meshes() if shared else contextlib.nullcontext():
            try:
                ours = surface.body_surface(scene.body)
            except Exception:
                continue  # meshes refused (their own fixtures)
            meshes = [placed_mesh(p) for p in scene.body.parts]
        assert ours is not None
        theirs = np.concatenate([np.asarray(m.triangles, dtype=float) for m in meshes])
        assert np.array_equal(ours.triangles, theirs)
        assert ours.vertices is not None  # the corners, each once
        corners = np.unique(theirs.reshape(-1, 3), axis=0)
        assert np.array_equal(np.unique(ours.vertices, axis=0), corners)
        closures = [mesh_closure(m) for m in meshes]
        volumes = [float(m.volume) for m in meshes]
        expected = all(c.watertight and c.consistent for c in closures) and all(
            v >= 0 for v in volumes
        )
        assert ours.closed == expected
        seen += 1
    assert seen >= 3


def test_ray_boxes_are_the_reductions() -> None:
    for mesh in _meshes():
        triangles = np.asarray(mesh.triangles, dtype=float)
        for ray in surface._RAYS:
            setup = surface._ray_setup(triangles, ray)
            uv = np.stack([triangles @ setup.e1, triangles @ setup.e2], axis=-1)
            np.testing.assert_array_equal(setup.lo, uv.min(axis=1))
            np.testing.assert_array_equal(setup.hi, uv.max(axis=1))


def test_inside_matches_the_winding_number() -> None:
    # Off the surface the generalised winding number is 1 inside, 0 outside (independent).
    rng = np.random.default_rng(3)
    for mesh in _meshes()[:20]:
        if mesh.volume < 0:
            continue
        triangles = np.asarray(mesh.triangles, dtype=float)
        lo, hi = mesh.bounds
        points = rng.uniform(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo), size=(100, 3))
        winding = surface.winding_numbers(triangles, points)
        clear = np.abs(winding - 0.5) > 0.1
        found = surface.inside(triangles, points)
        np.testing.assert_array_equal(found[clear], winding[clear] > 0.5)


def test_pruned_closest_point_is_the_brute_force_one() -> None:
    rng = np.random.default_rng(5)
    for mesh in _meshes():
        triangles = np.asarray(mesh.triangles, dtype=float)
        lo, hi = mesh.bounds
        points = rng.uniform(lo - 0.3 * (hi - lo), hi + 0.3 * (hi - lo), size=(30, 3))
        _, d, _ = surface.closest_point(triangles, points)
        _, d_all, _ = surface.closest_on_triangles(triangles, points)
        np.testing.assert_allclose(d, d_all, rtol=1e-12, atol=0)
        # the bound from the mesh's own vertices (each once) instead of every triangle's three
        # corners: the very same answers
        used = np.unique(np.asarray(mesh.faces))
        ours = surface.closest_point(triangles, points, np.asarray(mesh.vertices)[used])
        for a, b in zip(ours, surface.closest_point(triangles, points), strict=True):
            assert np.array_equal(a, b)


def test_box_distances_are_the_norms() -> None:
    # the closest-point query's box distances by axis: the reference is numpy's norm of the
    # gaps over the last axis, compared bit for bit on boxes around the meshes' faces
    rng = np.random.default_rng(9)
    for mesh in _meshes()[:12]:
        triangles = np.asarray(mesh.triangles, dtype=float)
        lo, hi = triangles.min(axis=1), triangles.max(axis=1)
        low, high = mesh.bounds
        points = rng.uniform(low - (high - low), high + (high - low), size=(7, 3))
        gaps = np.maximum(np.maximum(lo - points[:, None], points[:, None] - hi), 0)
        ours = surface._box_distance(np.ascontiguousarray(lo.T), np.ascontiguousarray(hi.T), points)
        assert np.array_equal(ours, np.linalg.norm(gaps, axis=2))


def test_mesh_mass_properties_are_trimeshs_own() -> None:
    from kcheck.body.mass import mesh_mass_properties

    for mesh in _meshes():
        if mesh.volume <= 0:
            continue
        reference = mesh.copy()
        reference.density = 2700.0
        expected = reference.mass_properties
        found = mesh_mass_properties(mesh.copy(), 2700.0, Path("m.stl"), "body")
        assert found.mass == float(expected.mass)
        assert found.volume == float(expected.volume)
        np.testing.assert_array_equal(found.center_of_mass, expected.center_mass)
        np.testing.assert_array_equal(found.inertia, expected.inertia)
