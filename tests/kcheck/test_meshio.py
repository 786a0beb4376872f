"""Reading mesh files: what the fuzzer of issue 13 found broken, each as a regression test.

A mesh file is gated before trimesh sees it (a regular file within the size limit), its
coordinates are checked before trimesh processes them (processing casts them to integers),
OpenCASCADE's diagnostics never reach the terminal, and the mass a mesh gives must lie in
the range an explicit mass must (docs/scene-format.md, "Limits").
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from kcheck.body.mass import body_mass_properties, mesh_mass_properties
from kcheck.body.meshio import load_mesh
from kcheck.errors import MeshError
from kcheck.scene import load_scene
from tests.conftest import FIXTURES


def _box(path: Path, size: float) -> Path:
    trimesh.creation.box(extents=(size, size, size)).export(path)
    return path


def test_a_mesh_past_the_size_limit_is_refused_unread(tmp_path):
    path = _box(tmp_path / "box.stl", 10.0)
    size = path.stat().st_size
    with pytest.raises(MeshError) as info:
        load_mesh(path, 1e-3, ("body", "mesh"), max_bytes=size - 1)
    assert "more than the limit" in info.value.message and "max_mesh_size" in info.value.message
    assert load_mesh(path, 1e-3, ("body", "mesh"), max_bytes=size).faces.shape == (12, 3)


def test_a_sparse_file_of_gigabytes_is_refused_at_once(tmp_path):
    # Fuzz finding: a 200 MiB STL of zero bytes took 530 MB of memory before it was refused.
    path = tmp_path / "huge.stl"
    with open(path, "wb") as handle:
        handle.truncate(2 * 2**30)
    with pytest.raises(MeshError) as info:
        load_mesh(path, 1e-3, ("body", "mesh"))
    assert "2048.0 MiB" in info.value.message


def test_a_pipe_is_not_a_mesh(tmp_path):
    pipe = tmp_path / "pipe.stl"
    os.mkfifo(pipe)
    with pytest.raises(MeshError) as info:
        load_mesh(pipe, 1.0, ("body", "mesh"))
    assert "not a regular file" in info.value.message


@pytest.mark.parametrize("size", [1e12, 1e30])
@pytest.mark.parametrize("reader", ["load_mesh", "load_surface"])
def test_huge_coordinates_are_refused_without_a_warning(tmp_path, size, reader):
    # Fuzz finding: trimesh's vertex merging cast 1e12 mm * 1e8 to int64 and printed
    # "RuntimeWarning: invalid value encountered in cast" on stderr. The same for kcheck's
    # own reader of binary STLs.
    from kcheck.body import meshio

    path = _box(tmp_path / "box.stl", size)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(MeshError) as info:
            getattr(meshio, reader)(path, 1e-3, ("body", "mesh"))
    assert "beyond 1000 m" in info.value.message and "units" in info.value.message


@pytest.mark.parametrize("reader", ["load_mesh", "load_surface"])
def test_non_finite_vertices_are_refused_without_a_warning(tmp_path, reader):
    from kcheck.body import meshio

    mesh = trimesh.creation.box(extents=(1, 1, 1))
    vertices = mesh.vertices.copy()
    vertices[3, 1] = np.nan
    path = tmp_path / "nan.stl"
    trimesh.Trimesh(vertices, mesh.faces, process=False).export(path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(MeshError) as info:
            getattr(meshio, reader)(path, 1.0, ("body", "mesh"))
    assert "non-finite" in info.value.message


def test_a_mass_outside_the_documented_range_is_refused(tmp_path):
    # A 10 um aluminium cube weighs 2.7e-12 kg: below 1e-9 kg, the least an explicit mass may
    # be; computed from a mesh it is refused the same way (a wrong unit, most likely).
    mesh = load_mesh(_box(tmp_path / "tiny.stl", 10.0), 1e-6, ("body", "mesh"))
    with pytest.raises(MeshError) as info:
        mesh_mass_properties(mesh, 2700.0, tmp_path / "tiny.stl", ("body", "mesh"))
    assert "1e-09 ≤ mass ≤ 1e+06 kg" in info.value.message and "2.7e-12 kg" in info.value.message


def test_broken_step_says_why_and_prints_nothing(tmp_path, capfd):
    # Fuzz finding: OpenCASCADE printed its diagnostics straight to file descriptors 1 and 2
    # (into a JSON report on stdout), and the error named a missing temporary file.
    pytest.importorskip("cascadio")
    path = tmp_path / "broken.step"
    path.write_text("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=GARBAGE((((;\n")
    with pytest.raises(MeshError) as info:
        load_mesh(path, 1.0, ("body", "mesh"))
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    # OpenCASCADE's reason is quoted after kcheck's words; its wording is OpenCASCADE's.
    error = info.value
    assert (error.path, error.field) == (str(path), "body.mesh")
    prefix = "cannot read the STEP file (OpenCASCADE: "
    assert error.message.startswith(prefix) and error.message.endswith(")")
    reason = error.message[len(prefix) : -1]
    assert reason.strip() and reason != "no solid found"  # what OpenCASCADE printed, caught
    assert "converted.glb" not in error.message


def test_a_mesh_trimesh_cannot_read_says_what_was_expected(tmp_path, monkeypatch):
    # trimesh's reason alone was the explanation ("IndexError: list index out of range" for
    # a damaged PLY); kcheck says what it expected, and quotes trimesh after.
    path = tmp_path / "part.ply"
    path.write_text("ply\n")

    def refuse(*args, **kwargs):
        raise IndexError("what trimesh says")

    monkeypatch.setattr(trimesh, "load_scene", refuse)
    with pytest.raises(MeshError) as info:
        load_mesh(path, 1.0, ("body", "mesh"))
    assert (info.value.path, info.value.field) == (str(path), "body.mesh")
    assert info.value.message == (
        "cannot read the mesh: not a valid PLY file (trimesh: IndexError: what trimesh says)"
    )


def test_running_out_of_memory_while_reading_is_not_a_bad_mesh(tmp_path, monkeypatch):
    """A MemoryError inside trimesh is the scene's memory budget running out (the gate
    reports it as such), not an unreadable file: it is not turned into an input error."""
    path = _box(tmp_path / "box.ply", 10.0)

    def exhausted(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(trimesh, "load_scene", exhausted)
    with pytest.raises(MemoryError):
        load_mesh(path, 1.0, ("body", "mesh"))


def test_mass_properties_of_a_scene_respect_the_configured_limit(tmp_path):
    _box(tmp_path / "box.stl", 10.0)
    (tmp_path / "s.kcheck.yaml").write_text(
        "version: 1\nunits: mm\nbody: {mesh: box.stl, material: steel}\n"
        "supports:\n"
        "  - {name: a, position: [0, 0, 0], normal: [1, 0, 0]}\n"
        "  - {name: b, position: [0, 1, 0], normal: [1, 0, 0]}\n"
        "  - {name: c, position: [1, 0, 0], normal: [0, 1, 0]}\n"
    )
    scene = load_scene(tmp_path / "s.kcheck.yaml")
    assert body_mass_properties(scene.body).mass == pytest.approx(7850 * 1e-6)
    with pytest.raises(MeshError):
        body_mass_properties(scene.body, max_mesh_bytes=100)


def test_repairing_a_flat_mesh_is_refused_without_a_warning(tmp_path):
    # Fuzz finding: `repair: true` on a mesh flattened to a plane printed trimesh's
    # "RuntimeWarning: invalid value encountered in divide" (centre of mass over volume 0).
    plate = trimesh.load_mesh(FIXTURES / "maxwell-three-vee" / "plate.stl", process=False)
    vertices = plate.vertices.copy()
    vertices[:, 0] = 0.0  # the round plate squashed flat: its outline is kept, its volume not
    path = tmp_path / "flat.stl"
    trimesh.Trimesh(vertices, plate.faces, process=False).export(path)
    mesh = load_mesh(path, 1e-3, ("body", "mesh"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(MeshError) as info:
            mesh_mass_properties(mesh, 2700.0, path, ("body", "mesh"), repair=True)
    assert "degenerate" in info.value.message or "volume" in info.value.message


def test_signalling_nan_face_normals_in_a_binary_stl_are_read_without_a_warning(tmp_path):
    # Fuzz finding (campaign seed 4242, mesh-4242-815, 134 random bytes): a binary STL whose
    # stored face normals are signalling NaNs printed numpy's "RuntimeWarning: invalid value
    # encountered in cast" from trimesh. kcheck never uses the stored normals.
    raw = bytearray(_box(tmp_path / "box.stl", 10.0).read_bytes())
    count = int.from_bytes(raw[80:84], "little")
    for i in range(count):  # 84-byte head, then 50 bytes a facet: normal first
        raw[84 + 50 * i : 88 + 50 * i] = (0x7FA00000).to_bytes(4, "little")  # sNaN (float32)
    path = tmp_path / "nan-normals.stl"
    path.write_bytes(raw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = load_mesh(path, 1e-3, ("body", "mesh"))
    assert mesh.faces.shape == (12, 3) and np.allclose(mesh.extents, 0.01)


def test_stl_vertex_merge_is_trimeshs():
    # kcheck merges an STL's vertices itself (faster): the reference is trimesh's own
    # process() on the same soup, which must give the same vertices in the same order.
    from kcheck.body.meshio import _merge_equal

    rng = np.random.default_rng(29)
    sphere = trimesh.creation.icosphere(subdivisions=2)
    soup = sphere.vertices[sphere.faces[rng.permutation(len(sphere.faces))]].reshape(-1, 3)
    soup[::7] += 1e-10  # within trimesh's 1e-8 rounding: joined
    soup = np.vstack([soup, [[5.0, 5.0, 5.0]]])  # not referenced by a face: dropped
    faces = np.arange(len(soup) - 1).reshape(-1, 3)
    ours = trimesh.Trimesh(soup.copy(), faces.copy(), process=False)
    _merge_equal(ours)
    theirs = trimesh.Trimesh(soup.copy(), faces.copy(), process=False).process()
    assert len(ours.vertices) == len(sphere.vertices)
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)
    assert ours.is_watertight


def _soup_stl(path: Path, binary: bool = True) -> Path:
    """An STL of a ball and a box apart, some of the ball's vertices moved by 5e-7 (joined by
    the closeness merge: within 1e-6 of the size, beyond the 1e-8 rounding)."""
    rng = np.random.default_rng(7)
    ball = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    box = trimesh.creation.box(extents=(1.0, 2.0, 0.5)).apply_translation([3.0, 0, 0])
    both = trimesh.util.concatenate([ball, box])
    soup = both.vertices[both.faces].reshape(-1, 3)
    moved = rng.choice(len(ball.faces) * 3, 40, replace=False)
    soup[moved] += 5e-7
    faces = np.arange(len(soup)).reshape(-1, 3)
    data = trimesh.exchange.stl.export_stl(trimesh.Trimesh(soup, faces, process=False))
    if not binary:
        data = trimesh.exchange.stl.export_stl_ascii(
            trimesh.Trimesh(soup, faces, process=False)
        ).encode()
    path.write_bytes(data)
    return path


@pytest.mark.parametrize("binary", [True, False])
def test_stl_read_by_kcheck_is_load_meshs(tmp_path, binary):
    # The contact finder reads a binary STL without trimesh (meshio.load_surface): the
    # reference is load_mesh (trimesh's reader, kcheck's merges) on the same file.
    from kcheck.body.meshio import load_surface

    path = _soup_stl(tmp_path / "soup.stl", binary)
    theirs = load_mesh(path, 1e-3, "BODY")
    ours = load_surface(path, 1e-3, "BODY")
    assert (ours.mesh is None) == binary  # a binary file never went through trimesh
    assert ours.merged == theirs.metadata.get("kcheck_merged", 0) > 0
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)
    assert np.array_equal(ours.bounds, theirs.bounds)
    assert ours.is_watertight and theirs.is_watertight


def test_watertightness_is_trimeshs():
    # Every edge shared by exactly two faces: trimesh's is_watertight, on a closed ball, the
    # ball with a face removed (open edges) and with a face doubled (crowded edges).
    from kcheck.body.mesh_edges import edges_of

    ball = trimesh.creation.icosphere(subdivisions=1)
    for faces in (ball.faces, ball.faces[1:], np.vstack([ball.faces, ball.faces[:1]])):
        mesh = trimesh.Trimesh(ball.vertices, faces, process=False)
        assert edges_of(np.asarray(faces)).closed == mesh.is_watertight


def test_closure_is_trimeshs():
    # Watertight and consistently wound from the faces alone (kcheck.body.mesh_edges): the
    # reference is trimesh's is_watertight and is_winding_consistent (the latter only means
    # something for a watertight mesh), on closed meshes of two bodies, with a face removed,
    # a face flipped, three faces flipped, a face doubled, and no faces.
    from kcheck.body.mesh_edges import closure_of

    rng = np.random.default_rng(5)
    shapes = [
        trimesh.creation.icosphere(subdivisions=2),
        trimesh.creation.box(),
        trimesh.creation.annulus(1, 2, 1),
    ]
    for shape in shapes:
        f = np.asarray(shape.faces)
        flipped = f.copy()
        flipped[0] = flipped[0, ::-1]
        three = f.copy()
        pick = rng.choice(len(f), 3, replace=False)
        three[pick] = three[pick, ::-1]
        variants = (f, f[1:], flipped, three, np.vstack([f, f[:2]]), f[:0])
        for faces in variants:
            mesh = trimesh.Trimesh(shape.vertices, faces, process=False)
            ours = closure_of(faces)
            assert ours.watertight == mesh.is_watertight
            if ours.watertight:
                assert ours.consistent == mesh.is_winding_consistent
    assert sum(closure_of(np.asarray(s.faces)).consistent for s in shapes) == 3


def test_close_vertex_pairs_are_the_kd_trees():
    # The sweep finding vertices closer than a tolerance: the reference is scipy's KD-tree,
    # on points in clusters (many close pairs) and on a grid (many on one plane).
    from scipy.spatial import cKDTree

    from kcheck.body.meshio import _close_pairs

    rng = np.random.default_rng(3)
    centres = rng.uniform(-1, 1, (500, 3))
    clusters = np.repeat(centres, 4, axis=0) + rng.normal(0, 3e-3, (2000, 3))
    grid = np.stack(np.meshgrid(*[np.arange(12) * 0.01] * 3), -1).reshape(-1, 3)
    for points, tol in ((clusters, 5e-3), (grid, 0.0101), (grid, 0.005)):
        ours = {tuple(sorted(p)) for p in _close_pairs(points, tol).tolist()}
        theirs = {tuple(p) for p in cKDTree(points).query_pairs(tol, output_type="ndarray")}
        assert ours == theirs


def test_closest_points_are_trimeshs():
    # kcheck's copy of trimesh's closest_point (Ericson's method): the same points to the
    # last bit, on random triangles and on ones with coinciding corners.
    from kcheck.body.closest_point import closest_point

    rng = np.random.default_rng(5)
    triangles = rng.normal(size=(20000, 3, 3))
    points = rng.normal(size=(20000, 3)) * 2
    triangles[:50, 1] = triangles[:50, 0]
    triangles[50:100, 2] = triangles[50:100, 1]
    got = closest_point(triangles, points)
    # Proper triangles: trimesh's answer, bit for bit.
    expected = trimesh.triangles.closest_point(triangles[100:], points[100:])
    assert np.array_equal(got[100:], expected)
    # Coinciding corners make a segment, where trimesh's answer depends on its version (NaN
    # at the declared lower bound): the closest point on that segment, computed here.
    a = np.concatenate([triangles[:50, 0], triangles[50:100, 0]])
    b = np.concatenate([triangles[:50, 2], triangles[50:100, 1]])
    t = np.clip(
        np.einsum("ij,ij->i", points[:100] - a, b - a) / np.einsum("ij,ij->i", b - a, b - a), 0, 1
    )
    assert np.allclose(got[:100], a + t[:, None] * (b - a), rtol=0, atol=1e-12)


def test_vertex_merge_when_two_vertices_mix_alike(monkeypatch):
    # The merge sorts a 64-bit mix of the coordinates; where two different vertices mix
    # alike it must fall back to a lexsort and give the same merge. A mix of the z
    # coordinate alone (multipliers 0) makes every vertex of a grid level collide.
    from kcheck.body import meshio

    ball = trimesh.creation.icosphere(subdivisions=2)
    soup = ball.vertices[ball.faces].reshape(-1, 3)
    faces = np.arange(len(soup)).reshape(-1, 3)
    expected = meshio._merged_equal(soup, faces)
    # Different vertices at one height: they collide.
    assert len(np.unique(np.round(ball.vertices[:, 2] * 1e8))) < len(ball.vertices)
    monkeypatch.setattr(meshio, "_MIX", (np.uint64(0), np.uint64(0)))
    got = meshio._merged_equal(soup, faces)
    assert len(expected[0]) == len(ball.vertices)
    assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])
