"""kcheck contacts on the command line: a generated three-vee assembly gives a scene that
checks exactly as the hand-written scene of the same coupling; refusals and bad input."""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact_assemblies import (  # noqa: E402
    THREE_VEE_CENTERS,
    R,
    ball,
    combine,
    flat,
    three_vee,
    trihedral_normals,
    unit,
    vee,
)

from kcheck.cli import main  # noqa: E402

HAND_WRITTEN = """\
version: 1
units: mm
body: {mesh: body.stl, material: aluminium}
couplings:
%s
friction: 0.1
gravity: [0, 0, -9.81]
load: {magnitude: 10, direction: [0, 0, -1]}
"""


def _write(tmp_path, base, body):
    base.export(tmp_path / "base.stl")
    body.export(tmp_path / "body.stl")


def _checks(path, capsys):
    assert main(["check", str(path), "--format", "json", "-j", "1"]) == 0
    scene = json.loads(capsys.readouterr().out)["scenes"][0]
    out = {}
    for c in scene["checks"]:
        # Cases are named by the supports they lift, and a groove's axis read either way round
        # swaps its two contacts' names: the check-level results are compared.
        c = {k: v for k, v in c.items() if k not in ("runtime_s", "cases")}
        out[c["id"]] = c
    return out


def _close(a, b, path=""):
    if isinstance(a, dict) and any("." in str(k) for k in a):
        # Per-support values: a groove's axis read either way round swaps its two contacts'
        # names, so compare each coupling's values as a set.
        def grouped(d):
            out = {}
            for k, v in d.items():
                out.setdefault(str(k).split(".")[0], []).append(v)
            return {k: sorted(v, key=repr) for k, v in out.items()}

        a, b = grouped(a), grouped(b)
    if isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            if k not in ("line", "column"):  # where in each file: the files differ
                _close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _close(x, y, f"{path}[{i}]")
    elif isinstance(a, float):
        assert a == pytest.approx(b, rel=1e-4, abs=1e-4), path
    elif isinstance(a, str) and path.endswith(".message"):
        # A symmetric coupling's supports tie: which one a message names as the worst
        # depends on the fits' last digits, so support names (b1.1, b2.2) are not compared.
        assert SUPPORT.sub("b?", a) == SUPPORT.sub("b?", b), path
    else:
        assert a == b, path


SUPPORT = re.compile(r"\bb\d\.\d\b")


def test_three_vee_scene_checks_as_the_hand_written_one(tmp_path, capsys):
    base, body = three_vee()
    _write(tmp_path, base, body)
    scene = tmp_path / "found.kcheck.yaml"
    code = main(
        [
            "contacts",
            str(tmp_path / "base.stl"),
            str(tmp_path / "body.stl"),
            "--units",
            "mm",
            "-o",
            str(scene),
        ]
    )
    assert code == 0, capsys.readouterr().err
    assert "ball-vee" in capsys.readouterr().err
    assert scene.read_text().count("type: ball-vee") == 3
    # Named and ordered as kcheck contacts names them (by the first contact's x), so that
    # support names in the results agree too.
    order = sorted(range(3), key=lambda k: THREE_VEE_CENTERS[k][0])
    entries = [
        f"  - {{name: b{j + 1}, type: ball-vee, ball: {{center: {c.tolist()}, radius: 6}}, "
        f"groove: {{axis: {unit([c[0], c[1], 0]).tolist()}, up: [0, 0, 1], half_angle: 45}}}}"
        for j, c in enumerate(THREE_VEE_CENTERS[k] for k in order)
    ]
    hand = tmp_path / "hand.kcheck.yaml"
    hand.write_text(HAND_WRITTEN % "\n".join(entries))
    found, written = _checks(scene, capsys), _checks(hand, capsys)
    assert found["analytical-3d"]["status"] == "pass"
    _close(found, written)


def _run(tmp_path, base, body, capsys):
    _write(tmp_path, base, body)
    code = main(
        ["contacts", str(tmp_path / "base.stl"), str(tmp_path / "body.stl"), "--units", "mm"]
    )
    return code, capsys.readouterr()


def test_five_contacts_refused(tmp_path, capsys):
    # Two vees and a flat: 5 point contacts.
    cs = THREE_VEE_CENTERS
    base = combine([*vee(cs[0], [0, 1, 0]), *vee(cs[1], [1, 0, 0]), flat(cs[2], [0, 0, 1])])
    body = combine([ball(c) for c in cs])
    code, out = _run(tmp_path, base, body, capsys)
    assert code == 1 and out.out == ""
    assert "5 point contact(s) found" in out.err


def test_seven_contacts_refused(tmp_path, capsys):
    cs = THREE_VEE_CENTERS
    base = combine(
        [*vee(cs[0], [0, 1, 0]), *vee(cs[1], [1, 0, 0])]
        + [flat(cs[2], n, side=6.0) for n in trihedral_normals()]
    )
    body = combine([ball(c) for c in cs])
    code, out = _run(tmp_path, base, body, capsys)
    assert code == 1 and "7 point contact(s) found" in out.err


def test_area_contact_refused_with_its_constraints(tmp_path, capsys):
    base = trimesh.creation.box(extents=[20, 20, 10]).apply_translation([0, 0, -5])
    body = trimesh.creation.box(extents=[10, 10, 10]).apply_translation([0, 0, 5])
    code, out = _run(tmp_path, base, body, capsys)
    assert code == 1
    assert "an area contact (flat on flat) (removes 3 freedoms)" in out.err


def test_parts_not_in_contact(tmp_path, capsys):
    base, body = three_vee(lift=5.0)
    code, out = _run(tmp_path, base, body, capsys)
    assert code == 2 and "does not touch" in out.err and "Traceback" not in out.err
    assert "they come nowhere within" in out.err


def test_parts_nearly_in_contact_say_how_near(tmp_path, capsys):
    # Lifted 0.6 mm: each ball is 0.6 cos 45 = 0.424 mm off its flanks (closed form), a
    # little more between the meshes (the icosphere's facets lie inside its sphere).
    base, body = three_vee(lift=0.6)
    code, out = _run(tmp_path, base, body, capsys)
    assert code == 2 and "does not touch" in out.err
    near = float(re.search(r"no closer than ([0-9.]+) mm", out.err).group(1))
    assert 0.6 * np.cos(np.radians(45)) <= near <= 0.6 * np.cos(np.radians(45)) + 0.01


def test_interpenetrating_parts(tmp_path, capsys):
    base, body = three_vee(lift=-1.0)
    code, out = _run(tmp_path, base, body, capsys)
    assert code == 2 and "interpenetrate by" in out.err
    # Lowered 1 mm: 1 cos 45 = 0.707 mm into each flank (closed form), a little less for
    # the icosphere's facets.
    depth = float(re.search(r"interpenetrate by ([0-9.]+) mm", out.err).group(1))
    assert np.cos(np.radians(45)) - 0.01 <= depth <= np.cos(np.radians(45))


def test_empty_and_open_meshes(tmp_path, capsys):
    base, body = three_vee()
    _write(tmp_path, base, body)
    (tmp_path / "empty.stl").write_text("solid x\nendsolid x\n")
    code = main(["contacts", str(tmp_path / "base.stl"), str(tmp_path / "empty.stl")])
    err = capsys.readouterr().err
    assert code == 2 and "empty.stl" in err and "empty" in err.split("empty.stl", 1)[1]
    open_body = body.copy()
    open_body.update_faces(np.arange(len(open_body.faces)) > 0)
    open_body.export(tmp_path / "open.stl")
    code = main(["contacts", str(tmp_path / "base.stl"), str(tmp_path / "open.stl")])
    assert code == 2 and "not watertight" in capsys.readouterr().err


def test_step_without_the_extra(tmp_path, capsys, monkeypatch):
    base, body = three_vee()
    _write(tmp_path, base, body)
    (tmp_path / "body.step").write_text("ISO-10303-21;\nEND-ISO-10303-21;\n")
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "cascadio" else real(name, *a)
    )
    code = main(["contacts", str(tmp_path / "base.stl"), str(tmp_path / "body.step")])
    assert code == 2 and "kcheck[step]" in capsys.readouterr().err


def test_balls_of_the_base_merged_into_the_body_are_named(tmp_path, capsys):
    # The base's balls exported inside the body's file: each sits in the body's own vee
    # (opening downwards) and on a flat of the base.
    cs = THREE_VEE_CENTERS
    body = combine(
        [part for c in cs for part in vee(c, unit([c[0], c[1], 0]), up=[0, 0, -1])]
        + [ball(c) for c in cs]
    )
    base = combine([flat(c, [0, 0, 1]) for c in cs])
    code, out = _run(tmp_path, base, body, capsys)
    assert "looks like part of the base" in out.err
    assert out.err.count("looks like part of the base") == 3
    assert "volume 902.8 mm^3" in out.err  # the icosphere's, 4/3 pi 6^3 less its facets


@pytest.mark.parametrize(
    ("option", "said"),
    [
        (["--gap", "-1"], "--gap -1.0: expected a positive length"),
        (["--units", "furlong"], "--units furlong: expected one of"),
        (["--material", "cheese"], "unknown material `cheese`"),
    ],
)
def test_bad_options(tmp_path, capsys, option, said):
    base, body = three_vee()
    _write(tmp_path, base, body)
    code = main(["contacts", str(tmp_path / "base.stl"), str(tmp_path / "body.stl"), *option])
    assert code == 2 and said in capsys.readouterr().err


def test_init_assembly_writes_the_contacts_scene(tmp_path, capsys):
    base, body = three_vee()
    _write(tmp_path, base, body)
    parts = [str(tmp_path / "base.stl"), str(tmp_path / "body.stl")]
    direct = tmp_path / "direct.kcheck.yaml"
    assert main(["contacts", *parts, "--units", "mm", "-o", str(direct)]) == 0
    capsys.readouterr()
    # Without -o, init writes next to the body, as `init --mesh` does.
    assert main(["init", "--assembly", *parts, "--units", "mm"]) == 0
    assert "wrote" in capsys.readouterr().err
    assert (tmp_path / "body.kcheck.yaml").read_text() == direct.read_text()
    # An existing file is kept without --force; --mesh and --assembly exclude each other.
    assert main(["init", "--assembly", *parts, "--units", "mm"]) == 2
    assert "exists" in capsys.readouterr().err
    assert main(["init", "--assembly", *parts, "--mesh", parts[1], "-o", "-"]) == 2
    assert "exclude each other" in capsys.readouterr().err
    # Bad input reaches the same refusal (exit 2) through init.
    lifted_base, lifted_body = three_vee(lift=5.0)
    lifted_body.export(tmp_path / "lifted.stl")
    code = main(["init", "--assembly", parts[0], str(tmp_path / "lifted.stl"), "-o", "-"])
    assert code == 2 and "does not touch" in capsys.readouterr().err


def _canoe(center, axis, circle=20.0):
    """A canoe ball: a torus (tube radius R) standing in the vertical plane of ``axis``, the
    lowest point of its tube's circle at ``center``."""
    side = np.cross([0, 0, 1.0], axis)
    torus = trimesh.creation.torus(
        major_radius=circle, minor_radius=R, major_sections=256, minor_sections=96
    )
    torus.apply_transform(trimesh.geometry.align_vectors([0, 0, 1], side))
    return torus.apply_translation(np.asarray(center) + [0, 0, circle])


def test_three_canoe_balls_scene_checks_as_the_hand_written_one(tmp_path, capsys):
    # Three canoe balls (tube circle 20, tube R) in the three radial vees: the contacts are
    # the three-vee's; along the groove the surface radius is 20 / cos 45 + R (the torus's
    # principal curvature cos v / (20 + R cos v) at v = 45 deg), across it R.
    base, _ = three_vee()
    body = combine([_canoe(c, unit([c[0], c[1], 0])) for c in THREE_VEE_CENTERS])
    _write(tmp_path, base, body)
    scene = tmp_path / "found.kcheck.yaml"
    parts = [str(tmp_path / "base.stl"), str(tmp_path / "body.stl")]
    code = main(["contacts", *parts, "--units", "mm", "-o", str(scene)])
    assert code == 0, capsys.readouterr().err
    assert "canoe ball" in capsys.readouterr().err
    assert scene.read_text().count("surface_radii") == 3
    along = 20 / np.cos(np.radians(45)) + R
    order = sorted(range(3), key=lambda k: THREE_VEE_CENTERS[k][0])
    entries = []
    for j, k in enumerate(order):
        c = THREE_VEE_CENTERS[k]
        a = unit([c[0], c[1], 0])
        entries.append(
            f"  - {{name: b{j + 1}, type: ball-vee, ball: {{center: {c.tolist()}, radius: {R}, "
            f"surface_radii: [{along}, {R}], surface_direction: {a.tolist()}}}, "
            f"groove: {{axis: {a.tolist()}, up: [0, 0, 1], half_angle: 45}}}}"
        )
    hand = tmp_path / "hand.kcheck.yaml"
    hand.write_text(HAND_WRITTEN % "\n".join(entries))
    found, written = _checks(scene, capsys), _checks(hand, capsys)
    assert found["analytical-3d"]["status"] == "pass"
    _close(found, written)


def _couplings(text):
    """The scene's couplings block (the fitted geometry), without the comments."""
    lines = text.split("couplings:\n", 1)[1].splitlines()
    return [line for line in lines if line.startswith("  - ")]


def test_one_assembly_file_with_named_parts_gives_the_two_files_scene(tmp_path, capsys):
    # The same assembly as one glTF file of two named parts, the body's vertices kept in its
    # own frame and placed by its node's transform (a quarter turn about z and a shift): the
    # scene must be the two STLs' one, with the body's part written beside it.
    base, body = three_vee()
    _write(tmp_path, base, body)
    place = trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1])
    place[:3, 3] = [7.0, -3.0, 2.0]
    local = body.copy().apply_transform(np.linalg.inv(place))
    scene = trimesh.Scene()
    scene.add_geometry(base, node_name="seat", geom_name="seat")
    scene.add_geometry(local, node_name="plate", geom_name="plate", transform=place)
    scene.export(tmp_path / "assembly.glb")
    two = tmp_path / "two.kcheck.yaml"
    parts = [str(tmp_path / "base.stl"), str(tmp_path / "body.stl")]
    assert main(["contacts", *parts, "--units", "mm", "-o", str(two)]) == 0
    one = tmp_path / "one.kcheck.yaml"
    named = ["--base-part", "seat", "--body-part", "plate"]
    code = main(
        ["contacts", str(tmp_path / "assembly.glb"), *named, "--units", "mm", "-o", str(one)]
    )
    assert code == 0, capsys.readouterr().err
    assert "mesh: assembly.plate.stl" in one.read_text()
    # init --assembly with one file writes the same scene next to the assembly.
    assert (
        main(["init", "--assembly", str(tmp_path / "assembly.glb"), *named, "--units", "mm"]) == 0
    )
    assert (tmp_path / "assembly.kcheck.yaml").read_text() == one.read_text()
    a, b = _couplings(two.read_text()), _couplings(one.read_text())
    assert len(a) == 3 and len(a) == len(b)
    numbers = [[float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", line)] for line in a]
    again = [[float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", line)] for line in b]
    # glTF stores float32 coordinates: the fits agree within its rounding (1e-6 mm here).
    assert np.allclose(np.concatenate(numbers), np.concatenate(again), atol=1e-5)
    # The same verdicts (the body's mass differs in float32's last digits).
    verdicts = {k: c["status"] for k, c in _checks(one, capsys).items()}
    assert verdicts == {k: c["status"] for k, c in _checks(two, capsys).items()}


def test_assembly_part_names(tmp_path, capsys):
    base, body = three_vee()
    scene = trimesh.Scene()
    scene.add_geometry(base, node_name="seat", geom_name="seat")
    scene.add_geometry(body, node_name="plate", geom_name="plate")
    scene.export(tmp_path / "assembly.glb")
    path = str(tmp_path / "assembly.glb")
    code = main(["contacts", path, "--base-part", "seat", "--body-part", "lid"])
    err = capsys.readouterr().err
    assert code == 2 and "no part named `lid`" in err and "plate, seat" in err
    assert main(["contacts", path, "--base-part", "seat"]) == 2
    assert "--body-part" in capsys.readouterr().err


def test_step_assembly_with_named_parts_gives_the_two_files_scene(tmp_path, capsys):
    # A STEP assembly of two named products in millimetres (written by tests/step_writer.py,
    # read through the step extra, which converts to metres): the same couplings as the two
    # STLs of the same meshes, within the float32 the conversion passes through.
    pytest.importorskip("cascadio")
    from step_writer import step_text

    base = combine([p for c in THREE_VEE_CENTERS for p in vee(c, axis=unit([c[0], c[1], 0]))])
    balls = [
        trimesh.creation.icosphere(subdivisions=2, radius=R).apply_translation(c)
        for c in THREE_VEE_CENTERS
    ]
    plate = trimesh.creation.box(extents=[130, 130, 6]).apply_translation([0, 0, 9])
    body = combine([*balls, plate])
    _write(tmp_path, base, body)
    (tmp_path / "assembly.step").write_text(step_text([("seat", base), ("carrier", body)]))
    two, one = tmp_path / "two.kcheck.yaml", tmp_path / "one.kcheck.yaml"
    parts = [str(tmp_path / "base.stl"), str(tmp_path / "body.stl")]
    assert main(["contacts", *parts, "--units", "mm", "-o", str(two)]) == 0
    step = [str(tmp_path / "assembly.step"), "--base-part", "seat", "--body-part", "carrier"]
    assert main(["contacts", *step, "--units", "mm", "-o", str(one)]) == 0, capsys.readouterr().err
    assert "mesh: assembly.carrier.stl" in one.read_text()
    a, b = _couplings(two.read_text()), _couplings(one.read_text())
    assert len(a) == 3 and len(b) == 3
    number = r"-?\d+\.?\d*(?:e-?\d+)?"
    x = np.concatenate([[float(v) for v in re.findall(number, line)] for line in a])
    y = np.concatenate([[float(v) for v in re.findall(number, line)] for line in b])
    assert np.allclose(x, y, atol=1e-5)
    verdicts = {k: c["status"] for k, c in _checks(one, capsys).items()}
    assert verdicts == {k: c["status"] for k, c in _checks(two, capsys).items()}


def test_written_by_line_gives_the_options_that_shaped_the_scene(tmp_path, capsys):
    # The scene's first comment is a command that re-makes it: material, friction and gap
    # when given.
    base, body = three_vee()
    _write(tmp_path, base, body)
    paths = [str(tmp_path / "base.stl"), str(tmp_path / "body.stl")]
    options = ["--units", "mm", "--material", "steel", "--friction", "0.2", "--gap", "0.05"]
    assert main(["contacts", *paths, *options]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == (
        f"# Written by `kcheck contacts {paths[0]} {paths[1]} --units mm --gap 0.05 "
        "--material steel --friction 0.2`:"
    )


def test_files_read_in_two_threads_give_the_same_scene_and_errors(tmp_path, capsys, monkeypatch):
    """kcheck.cli.contacts.READ_IN_THREADS (on by default): the same scene and report as
    the files read one after the other; the base's error said first when both are bad."""
    import kcheck.cli.contacts as contacts

    base, body = three_vee()
    _write(tmp_path, base, body)
    args = ["contacts", str(tmp_path / "base.stl"), str(tmp_path / "body.stl"), "--units", "mm"]
    out = {}
    for threads in (False, True):
        monkeypatch.setattr(contacts, "READ_IN_THREADS", threads)
        assert main(args) == 0
        out[threads] = capsys.readouterr()
    assert out[True].out == out[False].out and out[True].err == out[False].err
    open_body = body.copy()
    open_body.update_faces(np.arange(len(open_body.faces)) > 0)
    open_body.export(tmp_path / "open.stl")
    monkeypatch.setattr(contacts, "READ_IN_THREADS", True)
    # A binary STL of one face with a NaN corner: read in a thread, its error said first.
    face = np.zeros(12, "<f4")
    face[3] = np.nan
    (tmp_path / "nan.stl").write_bytes(
        b"\0" * 80 + (1).to_bytes(4, "little") + face.tobytes() + b"\0\0"
    )
    code = main(["contacts", str(tmp_path / "nan.stl"), str(tmp_path / "open.stl")])
    err = capsys.readouterr().err
    assert code == 2 and "nan.stl" in err and "non-finite" in err and "open.stl" not in err
    code = main(["contacts", str(tmp_path / "base.stl"), str(tmp_path / "open.stl")])
    assert code == 2 and "not watertight" in capsys.readouterr().err
