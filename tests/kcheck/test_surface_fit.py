"""Cone and torus fits on meshes generated here (trimesh's revolve and torus), whose vertices
lie exactly on the surface: the fit must give the generating geometry to rounding, with an
RMS residual at rounding."""

from __future__ import annotations

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

from kcheck.body.contact_regions import Faces, _smooth, patch_fit  # noqa: E402
from kcheck.body.surface_fit import fit_cone, fit_torus  # noqa: E402


def _rotated(mesh, axis, point):
    mesh.apply_transform(trimesh.geometry.align_vectors([0, 0, 1], axis))
    return mesh.apply_translation(point)


def _patches(mesh):
    faces = Faces.of(mesh)
    labels, facet = _smooth(mesh, faces)
    out = []
    for p in np.unique(labels):
        fit, _ = patch_fit(mesh, labels, p, faces, float(facet[p]))
        out.append(fit)
    return out


def test_countersink_is_a_cone_not_the_sphere_through_its_two_circles():
    # A block with a 70 deg countersink (generator 35 deg from the axis): the apex is where
    # the generator (r = 9 at z = 0, r = 9 - 7 tan 35 at z = -7) meets the axis.
    half = np.radians(35.0)
    bottom = 9 - 7 * np.tan(half)
    profile = [[0, -12], [20, -12], [20, 0], [9, 0], [bottom, -7], [0, -7]]
    axis, point = np.array([1.0, 2.0, 2.0]) / 3.0, np.array([3.0, -4.0, 5.0])
    seat = _rotated(trimesh.creation.revolve(profile, sections=96), axis, point)
    cones = [f for f in _patches(seat) if f is not None and f.kind == "cone"]
    assert len(cones) == 1
    cone = cones[0]
    apex = point - (9 / np.tan(half)) * axis
    assert np.allclose(cone.point, apex, atol=1e-9)
    assert abs(abs(cone.axis @ axis) - 1) < 1e-12
    assert cone.half_angle == pytest.approx(half, abs=1e-10)
    assert cone.outward == -1.0  # the seat's normals point into the hollow, to the axis
    assert cone.rms < 1e-9


def test_torus_fit_gives_both_radii():
    axis, point = np.array([0.0, 0.6, 0.8]), np.array([1.0, 2.0, -3.0])
    mesh = trimesh.creation.torus(
        major_radius=30.0, minor_radius=7.0, major_sections=256, minor_sections=64
    )
    mesh = _rotated(mesh, axis, point)
    fit = fit_torus(mesh.vertices, mesh.triangles_center, mesh.face_normals)
    assert np.allclose(fit.point, point, atol=1e-9)
    assert abs(abs(fit.axis @ axis) - 1) < 1e-12
    assert fit.radius == pytest.approx(30.0, abs=1e-9)
    assert fit.tube == pytest.approx(7.0, abs=1e-9)
    assert fit.outward == 1.0
    assert fit.rms < 1e-9


def test_cone_fit_on_a_convex_cone():
    # trimesh's cone: apex at z = h on the axis, base radius r: generator atan(r / h).
    mesh = trimesh.creation.cone(radius=4.0, height=10.0, sections=128)
    side = mesh.face_normals[:, 2] > -0.5
    pts = np.unique(mesh.faces[side])
    fit = fit_cone(mesh.vertices[pts], mesh.triangles_center[side], mesh.face_normals[side])
    assert np.allclose(fit.point, [0, 0, 10.0], atol=1e-9)
    assert np.allclose(fit.axis, [0, 0, -1.0], atol=1e-12)
    assert fit.half_angle == pytest.approx(np.arctan2(4.0, 10.0), abs=1e-10)
    assert fit.outward == 1.0
