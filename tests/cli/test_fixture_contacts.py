"""Every bundled fixture round-trips through `kcheck contacts` (issue 29, "Real couplings ...
and on the bundled fixtures"): the assembly each fixture's scene describes is built here, in
assembly position, from trimesh primitives (tests/contact_assemblies.py) and the fixture's own
body mesh; `kcheck contacts BASE BODY` finds every contact of the scene within 0.01 mm and
every normal within 0.1 deg, and the scene it writes, given the fixture's body, load, friction
and materials, gets the fixture's verdicts and friction limits.

The assembly comes from the fixture's expanded supports (the scene loader's points and
normals) and nothing else: at each contact a ball (the shorthand's ball; for explicit supports
a ball of the radius below, on the side below, its centre r along the normal from the point),
and its mate on the other part, a flat (a box whose face holds the contact, facing the ball) or
a pin (the shorthand's cylinder). The body is the fixture's body mesh where it can sit on
those mates (its balls included where the mesh holds them), else the body's mates and balls
and a plate clear of the base (fixtures with explicit mass properties; the Maxwell plate,
whose grooves its mesh leaves out). The generated scene is checked with the fixture's own
body, so that only its contacts differ. The public designs with their own assembly meshes
(geometry.json beside them) are tested in tests/cli/test_public_couplings.py.

Planar fixtures are extrusions along z: in 3D each of their contacts is a line (a pin along z
on a flat), and `kcheck contacts` writes the planar scene whose supports are the lines' middles
(docs/from-cad-to-scene.md); the same comparisons are asserted for them.
"""

from __future__ import annotations

import copy
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
import yaml

trimesh = pytest.importorskip("trimesh")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact_assemblies import ball, combine, flat, pin  # noqa: E402
from contact_comparison import (  # noqa: E402
    NORMAL_TOL_DEG,
    POINT_TOL_MM,
    assert_same_checks,
    checks,
    matched,
    one_to_one,
    supports,
)

from kcheck.cli import main  # noqa: E402
from kcheck.scene.load import load_scene  # noqa: E402

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"
BLOCK_MM = (200.0, 150.0, 85.0)
PUBLIC = {"mostly-printed-probe", "aspe-kc-design-script", "voron-kinematic-bed"}


@dataclass(frozen=True)
class Fixture:
    scene: str  # the hand-written scene, under fixtures/
    # "mesh": the fixture's body mesh; "plate": the body's mates and balls and a plate;
    # "block": the 200 x 150 x 85 mm block of the thesis's experiments (corner at the origin)
    body: str
    explicit_ball: tuple[float, str] | None = None  # explicit supports: ball radius mm, side
    mesh_holds: bool = False  # the body mesh holds the body's side (its balls or faces)


SPATIAL = {
    # Balls (radius 6, icospheres of the fixture's mesh) on the body, in a trihedral seat,
    # a vee and on a flat.
    "kelvin": Fixture("kelvin/coupling.kcheck.yaml", "mesh", mesh_holds=True),
    # The same balls in three vees, written as six explicit supports (ball radius 6 mm, the
    # scene's comment).
    "three-groove": Fixture(
        "three-groove/coupling.kcheck.yaml", "mesh", (6.0, "body"), mesh_holds=True
    ),
    # Balls on the base, vees in the plate (its mesh leaves the grooves out: it reaches into
    # the balls, so the plate here is a primitive clear of them).
    "maxwell-three-vee": Fixture("maxwell-three-vee/coupling.kcheck.yaml", "plate"),
    # Balls on the body resting on pairs of dowel pins of the base.
    "tool-changer": Fixture("tool-changer/tool.kcheck.yaml", "mesh", mesh_holds=True),
    # The 3-2-1 block on six ball-ended pins: explicit supports (the balls of block-321-balls,
    # radius 5 mm, on the base) and the shorthand scene.
    "block-321": Fixture("block-321/block.kcheck.yaml", "mesh", (5.0, "base"), mesh_holds=True),
    "block-321-balls": Fixture("block-321-balls/block.kcheck.yaml", "mesh", mesh_holds=True),
    # Explicit mass properties, no mesh: the block its comment describes, on the balls of
    # block-321-balls; Patti & Vogels's grooves: balls, plate and mates from primitives.
    "thesis-block-5-2": Fixture(
        "thesis-block-5-2/block.kcheck.yaml", "block", (5.0, "base"), mesh_holds=True
    ),
    **{
        f"three-groove-beta-{b}": Fixture(f"three-groove-beta-{b}/coupling.kcheck.yaml", "plate")
        for b in (15, 25, 35, 45, 55, 65)
    },
}
PLANAR = {
    "planar-block": "planar-block/block.kcheck.yaml",
    "thesis-appendix-a": "thesis-appendix-a/block.kcheck.yaml",
    "thesis-block-4-2": "thesis-block-4-2/block.kcheck.yaml",
    "thesis-potato": "thesis-potato/potato.kcheck.yaml",
}


def test_every_fixture_round_trips():
    """Every scene under fixtures/ is one of the fixtures here or a public design."""
    scenes = {p.parent.name for p in FIXTURES.glob("*/*.kcheck.yaml")}
    assert scenes == set(SPATIAL) | set(PLANAR) | PUBLIC
    for name in PLANAR:
        assert load_scene(FIXTURES / PLANAR[name]).kind == "planar"
    for fixture in SPATIAL.values():
        assert load_scene(FIXTURES / fixture.scene).kind == "spatial"


def _body_mesh(scene_path: Path) -> trimesh.Trimesh:
    """The fixture's body meshes as its scene places them (mm)."""
    doc = yaml.safe_load(scene_path.read_text())
    parts = doc["body"].get("parts") or [doc["body"]]
    meshes = []
    for part in parts:
        mesh = trimesh.load(scene_path.parent / part["mesh"], force="mesh")
        rotate = part.get("transform", {}).get("rotate")
        if rotate is not None:
            mesh.apply_transform(
                trimesh.transformations.rotation_matrix(np.radians(rotate["angle"]), rotate["axis"])
            )
        assert "translate" not in part.get("transform", {})
        meshes.append(mesh)
    return combine(meshes)


def _plate_above(pieces: list[trimesh.Trimesh]) -> trimesh.Trimesh:
    """A plate 0.5 mm above the pieces, over their extent (joins the body's pieces, clear of
    the base below)."""
    lo, hi = (
        np.min([p.bounds[0] for p in pieces], axis=0),
        np.max([p.bounds[1] for p in pieces], axis=0),
    )
    extent = hi - lo + [10.0, 10.0, 0.0]
    box = trimesh.creation.box(extents=[extent[0], extent[1], 6.0])
    return box.apply_translation([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 3.5])


def _assembly(name: str, folder: Path) -> tuple[Path, Path]:
    """The fixture's assembly: its base's and body's STL (mm) in ``folder``."""
    fixture = SPATIAL[name]
    scene = load_scene(FIXTURES / fixture.scene)
    base, body, balls = [], [], {}
    for s in scene.supports:
        p, n = s.position / scene.scale, s.normal / np.linalg.norm(s.normal)
        g = s.geometry
        if g is not None and g.ball_radius is not None:
            c, r, side = g.ball_center / scene.scale, g.ball_radius / scene.scale, g.ball_on
            mate = g.base if side == "body" else g.body
        else:
            assert fixture.explicit_ball is not None, s.name
            r, side = fixture.explicit_ball
            c, mate = (p + r * n if side == "body" else p - r * n), None
        facing = n if side == "body" else -n  # the mate's outward normal, towards the ball
        balls[tuple(np.round(c, 6))] = (c, r, side)
        mates = base if side == "body" else body if not fixture.mesh_holds else []
        if mate is None or np.isinf(mate.radii).all():
            mates.append(flat(c, facing, r))
        else:  # a pin: its axis the curved direction's normal, through p - r_pin (facing)
            (r_pin,) = [x / scene.scale for x in mate.radii if np.isfinite(x)]
            mates.append(pin(p - r_pin * facing, mate.direction, r_pin))
        assert np.linalg.norm(c - p) == pytest.approx(r, abs=1e-6), s.name
    for c, r, side in balls.values():
        if side == "base":
            base.append(ball(c, r))
        elif not fixture.mesh_holds:
            body.append(ball(c, r))
    if fixture.body == "mesh":
        body.append(_body_mesh(FIXTURES / fixture.scene))
    elif fixture.body == "block":
        block = trimesh.creation.box(extents=BLOCK_MM)
        body.append(block.apply_translation(np.divide(BLOCK_MM, 2)))
    else:
        body.append(_plate_above(body))
    combine(base).export(folder / "base.stl")
    combine(body).export(folder / "body.stl")
    return folder / "base.stl", folder / "body.stl"


def _absolute(body: dict, folder: Path) -> dict:
    """The scene's body with its mesh paths made absolute (the scene is written elsewhere)."""
    body = copy.deepcopy(body)
    for part in body.get("parts") or [body]:
        if "mesh" in part:
            part["mesh"] = str((folder / part["mesh"]).resolve())
    return body


def _materials(entry: dict, hand: list[dict]) -> dict:
    """The ball and seat materials of the hand-written coupling whose ball is this one's
    (centres within 0.01 mm)."""
    centre = np.asarray(entry["ball"]["center"], float)
    for c in hand:
        if np.linalg.norm(np.asarray(c["ball"]["center"], float) - centre) <= POINT_TOL_MM:
            return {k: c[k] for k in ("ball_material", "seat_material") if k in c}
    return {}


def _generated_scene(found: Path, hand: Path, out: Path) -> None:
    """The scene `kcheck contacts` wrote, with what a designer sets by hand copied from the
    fixture: its body (mass, materials, meshes), friction, gravity, load, preloads, sweep,
    tolerances, check options, and each coupling's ball and seat materials. Only the contacts
    (supports, couplings) are the generated ones."""
    hand_doc = yaml.safe_load(hand.read_text())
    found_doc = yaml.safe_load(found.read_text())
    doc = {k: v for k, v in hand_doc.items() if k not in ("supports", "couplings", "name")}
    doc["body"] = _absolute(hand_doc["body"], hand.parent)
    hand_couplings = hand_doc.get("couplings", [])
    couplings = [{**c, **_materials(c, hand_couplings)} for c in found_doc.get("couplings", [])]
    if couplings:
        doc["couplings"] = couplings
    if found_doc.get("supports"):
        doc["supports"] = found_doc["supports"]
    out.write_text(yaml.safe_dump(doc))


@pytest.mark.parametrize("name", sorted(SPATIAL))
def test_contacts_found_on_a_bundled_fixture(name, tmp_path, capsys):
    fixture = SPATIAL[name]
    hand = FIXTURES / fixture.scene
    base, body = _assembly(name, tmp_path)
    found = tmp_path / "found.kcheck.yaml"
    code = main(["contacts", str(base), str(body), "--units", "mm", "-o", str(found)])
    assert code == 0, capsys.readouterr().err
    capsys.readouterr()
    got, want = supports(found), supports(hand)
    assert len(got) == len(want) == 6
    # Every contact of the fixture is found, one to one.
    assert one_to_one(got, want)
    pairs = matched(got, want)
    assert max(d for d, _ in pairs) <= POINT_TOL_MM, pairs
    assert max(a for _, a in pairs) <= NORMAL_TOL_DEG, pairs
    # The scene as written checks (the assembly's body, the proposed push): not bad input.
    assert checks(found, capsys)["analytical-3d"]["status"] in ("pass", "fail")
    # Its scene checks as the fixture: same verdicts, same friction limits and margins.
    scene = tmp_path / "generated.kcheck.yaml"
    _generated_scene(found, hand, scene)
    assert_same_checks(
        checks(scene, capsys, "--allow-outside-paths"),
        checks(hand, capsys),
    )


def _planar_assembly(scene_path: Path, folder: Path) -> tuple[Path, Path]:
    """The planar fixture as an extrusion: at each support a pin along z on the body
    (radius 1 mm, its axis 1 mm from the point along the normal) lying on a flat of the base,
    the pins joined by a plate above; base and body STL (mm) in ``folder``."""
    scene = load_scene(scene_path)
    r, base, body = 1.0, [], []
    for s in scene.supports:
        p, n = s.position / scene.scale, s.normal / np.linalg.norm(s.normal)
        assert n[2] == 0.0  # in the plane of motion
        body.append(pin(p + r * n, [0, 0, 1], r, length=4.0))
        base.append(flat(p + r * n, n, r, side=6.0))  # wider than the pin is long
    body.append(_plate_above(body + base))
    combine(base).export(folder / "base.stl")
    combine(body).export(folder / "body.stl")
    return folder / "base.stl", folder / "body.stl"


@pytest.mark.parametrize("name", sorted(PLANAR))
def test_planar_fixture_round_trips(name, tmp_path, capsys):
    """A planar coupling's contacts are lines along z in 3D (both parts extrusions): written
    as the planar scene's three supports, each within 0.01 mm and 0.1 deg of the fixture's,
    and that scene, given the fixture's body, load and friction, checks as the fixture."""
    hand = FIXTURES / PLANAR[name]
    base, body = _planar_assembly(hand, tmp_path)
    found = tmp_path / "found.kcheck.yaml"
    code = main(["contacts", str(base), str(body), "--units", "mm", "-o", str(found)])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "planar coupling: 3 line contacts along" in err
    assert load_scene(found, allow_outside=True).kind == "planar"
    got, want = supports(found), supports(hand)
    assert len(got) == len(want) == 3
    assert one_to_one(got, want)
    pairs = matched(got, want)
    assert max(d for d, _ in pairs) <= POINT_TOL_MM, pairs
    assert max(a for _, a in pairs) <= NORMAL_TOL_DEG, pairs
    # The scene as written checks (the assembly's body, the proposed push): not bad input.
    assert checks(found, capsys)["analytical-2d"]["status"] in ("pass", "marginal", "fail")
    scene = tmp_path / "generated.kcheck.yaml"
    _generated_scene(found, hand, scene)
    assert_same_checks(
        checks(scene, capsys, "--allow-outside-paths"),
        checks(hand, capsys),
    )
