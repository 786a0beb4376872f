"""`kcheck contacts` on planar couplings: extrusions along z generated here (trimesh boxes and
pins), whose contacts are lines along z; the planar scene's supports are the lines' middles
(x, y from the closed-form contact line, z the mean of the lines' middles, each the middle of
the pin's length where the other part spans it), normals in the xy-plane into the body; and
the refusals (lines not parallel, a part that is not an extrusion, 4 lines); an extrusion
axis other than z turned onto it."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact_assemblies import combine, pin, unit  # noqa: E402
from contact_comparison import assert_same_checks, checks  # noqa: E402

from kcheck.cli import main  # noqa: E402
from kcheck.scene.load import load_scene  # noqa: E402

BLOCK = (100.0, 60.0, 20.0)  # the planar-block fixture's block, mm, corner at the origin
R_PIN = 3.0


def _block():
    return trimesh.creation.box(extents=BLOCK).apply_translation(np.divide(BLOCK, 2))


def _base_pin(contact, normal, z0, z1, axis=(0, 0, 1)):
    """A pin of the base along ``axis`` touching the body at ``contact`` (normal ``normal``
    into the body), from z0 to z1 along the axis through it."""
    a = unit(axis)
    centre = np.asarray(contact, float) - R_PIN * unit(normal) + (z0 + z1) / 2 * a
    return pin(centre, a, R_PIN, length=z1 - z0)


def _strip(contact, normal, z0, z1, width=8.0, thickness=3.0):
    """A flat strip of the base (a box turned about z only, so an extrusion along z) whose
    face, normal ``normal`` in the xy-plane, holds ``contact``; from z0 to z1."""
    n = unit(normal)
    box = trimesh.creation.box(extents=[thickness, width, z1 - z0])
    box.apply_transform(trimesh.transformations.rotation_matrix(np.arctan2(n[1], n[0]), [0, 0, 1]))
    c = np.asarray(contact, float)
    return box.apply_translation([*(c[:2] - thickness / 2 * n[:2]), (z0 + z1) / 2])


def _run(tmp_path, base, body, capsys, *extra):
    base.export(tmp_path / "base.stl")
    body.export(tmp_path / "body.stl")
    out = tmp_path / "found.kcheck.yaml"
    args = ["contacts", str(tmp_path / "base.stl"), str(tmp_path / "body.stl"), "--units", "mm"]
    code = main([*args, "-o", str(out), *extra])
    return code, capsys.readouterr().err, out


def _assert_supports(path, expected):
    """The scene is planar and its supports are ``expected`` (point mm, unit normal), in any
    order: points to float32's rounding of 100 mm, normals to 1e-6."""
    scene = load_scene(path, allow_outside=True)
    assert scene.kind == "planar"
    got = [(s.position / scene.scale, s.normal) for s in scene.supports]
    assert len(got) == len(expected)
    for p, n in expected:
        k = int(np.argmin([np.linalg.norm(q - p) for q, _ in got]))
        q, m = got.pop(k)
        assert q == pytest.approx(p, abs=1e-4)
        assert m == pytest.approx(n, abs=1e-6)


def test_block_on_three_pins_of_the_base(tmp_path, capsys):
    # The planar-block fixture's layout: two pins under the long edge (y = 0) at x = 20, 80,
    # one at the short edge (x = 0) at y = 30. Each pin spans its own height on the 20 mm
    # block: the lines' middles are at z = 5, 10 and 15, so the supports sit at z = 10.
    contacts = [([20, 0], [0, 1], (2, 8)), ([80, 0], [0, 1], (6, 14)), ([0, 30], [1, 0], (9, 21))]
    base = combine([_base_pin([*p, 0], [*n, 0], z0, z1) for p, n, (z0, z1) in contacts])
    code, err, out = _run(tmp_path, base, _block(), capsys)
    assert code == 0, err
    # The third pin runs past the block's top (z = 20): its line ends there, its middle 14.5.
    middles = [5.0, 10.0, 14.5]
    z = np.mean(middles)
    _assert_supports(out, [(np.array([*p, z]), np.array([*n, 0.0])) for p, n, _ in contacts])
    assert "the body's plane on the base's cylinder, a line along z from 9 to 20 mm" in err
    # The scene as written checks.
    assert main(["check", str(out), "-j", "1"]) in (0, 1)
    capsys.readouterr()


def test_block_on_a_table_against_three_pins(tmp_path, capsys):
    # The same layout with the block lying on a table (z = 0) the pins stand on (z from 0 to
    # 15): the table is the plane of motion, an area contact square to the lines, said in the
    # report and left out of the scene; each line from z = 0 to 15, middle 7.5.
    contacts = [([20, 0], [0, 1]), ([80, 0], [0, 1]), ([0, 30], [1, 0])]
    table = trimesh.creation.box(extents=[160, 120, 5]).apply_translation([50, 30, -2.5])
    pins = [_base_pin([*p, 0], [*n, 0], 0, 15) for p, n in contacts]
    code, err, out = _run(tmp_path, combine([table, *pins]), _block(), capsys)
    assert code == 0, err
    assert err.count("the plane of motion: the body's plane on the base's") == 1
    # Where each pin stands on the table beside the block: said, not a contact.
    assert err.count("a line's end near") == 3 and "not used" not in err
    _assert_supports(out, [(np.array([*p, 7.5]), np.array([*n, 0.0])) for p, n in contacts])


def test_a_flat_on_a_flat_across_the_lines_is_refused(tmp_path, capsys):
    # The block's x = 0 pin replaced by a wall the block's face lies on: an area contact whose
    # normal is across the lines, over-constraint (the existing refusal).
    wall = trimesh.creation.box(extents=[5, 60, 20]).apply_translation([-2.5, 30, 10])
    pins = [_base_pin([x, 0, 0], [0, 1, 0], 2, 18) for x in (20, 80)]
    code, err, out = _run(tmp_path, combine([wall, *pins]), _block(), capsys)
    assert code == 1, err
    assert not out.exists()
    assert "no scene written: 3 line or area contact(s), together removing 7 freedoms" in err
    assert "planar coupling" not in err


def test_pins_of_the_body_on_flat_strips(tmp_path, capsys):
    # Three pins of the body (radius 3, z from 0 to 10) on flat strips of the base (z from -2
    # to 8) whose normals point at 90, 210 and 330 deg: each line from z = 0 to 8, middle 4;
    # the contact is the pin's axis less its radius along the strip's normal.
    angles = np.radians([90.0, 210.0, 330.0])
    normals = [np.array([np.cos(t), np.sin(t), 0.0]) for t in angles]
    contacts = [-30.0 * n + [50.0, 40.0, 0.0] for n in normals]
    pins = [
        pin(c + R_PIN * n + [0, 0, 5.0], [0, 0, 1], R_PIN, length=10.0)
        for c, n in zip(contacts, normals, strict=True)
    ]
    plate = trimesh.creation.box(extents=[90, 90, 4]).apply_translation([50, 40, 12])
    base = combine([_strip(c, n, -2.0, 8.0) for c, n in zip(contacts, normals, strict=True)])
    code, err, out = _run(tmp_path, base, combine([*pins, plate]), capsys)
    assert code == 0, err
    _assert_supports(out, [(c + [0, 0, 4.0], n) for c, n in zip(contacts, normals, strict=True)])


def test_pins_of_the_body_on_parallel_pins_of_the_base(tmp_path, capsys):
    # Each body pin (radius 3, z from 0 to 10) on a base pin (radius 2, z from -3 to 7) along
    # z: the contact is on the base pin's axis plus its radius towards the body pin's axis;
    # each line from z = 0 to 7, middle 3.5.
    r_base = 2.0
    angles = np.radians([80.0, 200.0, 320.0])
    normals = [np.array([np.cos(t), np.sin(t), 0.0]) for t in angles]
    axes = [-25.0 * n + [40.0, 30.0, 0.0] for n in normals]  # the base pins' axes (x, y)
    contacts = [a + r_base * n for a, n in zip(axes, normals, strict=True)]
    pins = [
        pin(c + R_PIN * n + [0, 0, 5.0], [0, 0, 1], R_PIN, length=10.0)
        for c, n in zip(contacts, normals, strict=True)
    ]
    plate = trimesh.creation.box(extents=[80, 80, 4]).apply_translation([40, 30, 12])
    base = combine([pin(a + [0, 0, 2.0], [0, 0, 1], r_base, length=10.0) for a in axes])
    code, err, out = _run(tmp_path, base, combine([*pins, plate]), capsys)
    assert code == 0, err
    assert "planar coupling: 3 line contacts along (0, 0, 1) (0 deg from z)" in err
    assert err.count("the body's cylinder on the base's cylinder, a line along z from 0 to 7") == 3
    assert err.count("body cylinder fit RMS") == err.count("radius 3 mm; base cylinder") == 3
    _assert_supports(out, [(c + [0, 0, 3.5], n) for c, n in zip(contacts, normals, strict=True)])


def test_lines_not_parallel_are_refused(tmp_path, capsys):
    # The block's x = 0 pin turned to lie along y: lines along z, z and y.
    base = combine(
        [
            _base_pin([20, 0, 0], [0, 1, 0], 2, 18),
            _base_pin([80, 0, 0], [0, 1, 0], 2, 18),
            _base_pin([0, 0, 10], [1, 0, 0], 10, 50, axis=(0, 1, 0)),
        ]
    )
    code, err, out = _run(tmp_path, base, _block(), capsys)
    assert code == 1, err
    assert not out.exists()
    assert "no scene written: 3 line or area contact(s)" in err
    assert "the 3 line contacts are not parallel (up to 90 deg apart)" in err


def test_a_body_that_is_not_an_extrusion_is_refused(tmp_path, capsys):
    # The block with a 45 deg chamfer along its top back edge: its faces there are neither
    # parallel nor perpendicular to z.
    corners = [
        [x, y, z]
        for x in (0.0, BLOCK[0])
        for y, z in ((0, 0), (60, 0), (0, 20), (60, 10), (50, 20))
    ]
    body = trimesh.convex.convex_hull(np.array(corners))
    assert body.is_watertight
    base = combine(
        [
            _base_pin([20, 0, 0], [0, 1, 0], 2, 18),
            _base_pin([80, 0, 0], [0, 1, 0], 2, 18),
            _base_pin([0, 30, 0], [1, 0, 0], 2, 18),
        ]
    )
    code, err, out = _run(tmp_path, base, body, capsys)
    assert code == 1, err
    assert not out.exists()
    assert "but the body is not an extrusion along them: 2 of its" in err


def test_four_lines_are_refused(tmp_path, capsys):
    base = combine(
        [
            _base_pin([20, 0, 0], [0, 1, 0], 2, 18),
            _base_pin([80, 0, 0], [0, 1, 0], 2, 18),
            _base_pin([0, 30, 0], [1, 0, 0], 2, 18),
            _base_pin([100, 30, 0], [-1, 0, 0], 2, 18),
        ]
    )
    code, err, out = _run(tmp_path, base, _block(), capsys)
    assert code == 1, err
    assert not out.exists()
    assert "4 line contacts of two extrusions (a planar coupling); a planar kinematic " in err
    assert "coupling has exactly 3" in err


def test_an_extrusion_axis_other_than_z_is_turned_onto_z(tmp_path, capsys):
    # A block on three pins (z from 2 to 18, middles 10), the assembly turned 90 deg about y:
    # the extrusions run along x. The scene is the assembly turned back (90 deg about -y, the
    # least rotation taking x to z), the body's mesh by its transform: its supports are the
    # unturned layout's, and it checks exactly as the scene of the unturned assembly.
    contacts = [([20, 0], [0, 1]), ([80, 0], [0, 1]), ([0, 30], [1, 0])]
    turn = trimesh.transformations.rotation_matrix(np.radians(90), [0, 1, 0])
    scenes = []
    for turned in (False, True):
        folder = tmp_path / ("turned" if turned else "upright")
        folder.mkdir()
        base = combine([_base_pin([*p, 0], [*n, 0], 2, 18) for p, n in contacts])
        body = _block()
        if turned:
            base, body = base.apply_transform(turn), body.apply_transform(turn)
        code, err, out = _run(folder, base, body, capsys)
        assert code == 0, err
        scenes.append(out)
    assert "planar coupling: 3 line contacts along (1, 0, 0) (90 deg from z)" in err
    assert "the scene is the assembly turned by 90 deg about (0, -1, 0)" in err
    expected = [(np.array([*p, 10.0]), np.array([*n, 0.0])) for p, n in contacts]
    _assert_supports(scenes[1], expected)
    assert_same_checks(checks(scenes[1], capsys), checks(scenes[0], capsys))
