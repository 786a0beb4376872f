"""Errors sit at real fields (issue 25): every input error's field path exists in the scene's
JSON Schema, in the branch the file's data takes (a `ball-vee` has no `up` of its own: its
`up` is `groove.up`), and its line and column are where that field is written (or, for a
field that is missing, where the mapping it belongs in is written).

A corpus of bad inputs, one for each place kcheck makes a located input error (every
``Problems.add`` and range, coordinate, direction and length check, every coupling and mesh
error, every error of the runner, each at each of its call sites), runs through the runner; a
test fails when such a place is added without an input in the corpus (the places are found in
the source). The positions are found independently of kcheck's YAML reader, from PyYAML's
own node marks; the schema is walked here, not by kcheck (``docs/kcheck-scene.schema.json``,
the same as ``kcheck schema``).
"""

from __future__ import annotations

import ast
import copy
import os
import re
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh
import yaml

import kcheck
from kcheck.errors import SceneError, format_path
from kcheck.gate.runner import Settings, check_scene
from kcheck.plugin import load_checks
from kcheck.scene.couplings import CouplingError
from tests.fuzz.schema import in_schema

KCHECK = Path(kcheck.__file__).parent

# --- where a field is written, from PyYAML's nodes ------------------------------------------------


def written_at(text: str, path: tuple) -> tuple[int, int]:
    """Line and column (1-based) of a field as written (a mapping value: its key; a list item:
    the item), or of its nearest enclosing field that is written."""
    node = yaml.compose(text, Loader=yaml.SafeLoader)
    mark = node.start_mark
    for part in path:
        if isinstance(node, yaml.MappingNode) and isinstance(part, str):
            pair = next(((k, v) for k, v in node.value if k.value == part), None)
            if pair is None:
                break
            mark, node = pair[0].start_mark, pair[1]
        elif isinstance(node, yaml.SequenceNode) and isinstance(part, int):
            if part >= len(node.value):
                break
            node = node.value[part]
            mark = node.start_mark
        else:
            break
    return mark.line + 1, mark.column + 1


# --- the corpus -------------------------------------------------------------------------------

PLANAR: dict[str, Any] = {
    "version": 1,
    "units": "mm",
    "body": {"mass": 1, "center_of_mass": [50, 30, 0], "inertia": 0.001},
    "supports": [
        {"name": "y1", "position": [20, 0, 0], "normal": [0, 1, 0]},
        {"name": "y2", "position": [80, 0, 0], "normal": [0, 1, 0]},
        {"name": "x1", "position": [0, 30, 0], "normal": [1, 0, 0]},
    ],
    "friction": 0.1,
    "load": {"magnitude": 1, "angle": 225},
}

SPATIAL: dict[str, Any] = {
    "version": 1,
    "units": "mm",
    "body": {"mesh": "plate.stl", "material": "aluminium"},
    "couplings": [
        {
            "name": "t",
            "type": "ball-trihedral",
            "ball": {"center": [0, 50, 0], "radius": 6},
            "up": [0, 0, 1],
            "half_angle": 54.7356,
            "reference": [1, 0, 0],
        },
        {
            "name": "v",
            "type": "ball-vee",
            "ball": {"center": [-43.3, -25, 0], "radius": 6},
            "groove": {"axis": [-0.866, -0.5, 0], "up": [0, 0, 1], "half_angle": 45},
        },
        {
            "name": "f",
            "type": "ball-flat",
            "ball": {"center": [43.3, -25, 0], "radius": 6},
            "normal": [0, 0, 1],
        },
    ],
    "friction": 0.1,
    "gravity": [0, 0, -9.81],
    "load": {"point": [0, 0, 20], "magnitude": 10, "direction": [0, 0, -1], "torque": [0, 0, 0]},
    "preloads": [{"name": "spring", "point": [0, 0, 10], "force": [0, 0, -5]}],
    "sweep": {"normal": [0, -1, 0], "zero": [0, 0, -1]},
    "tolerances": {"position": 0.05, "normal": 0.5, "load_direction": 1},
}

CONE = {
    "name": "c",
    "type": "ball-cone",
    "ball": {"center": [0, 50, 0], "radius": 6},
    "up": [0, 0, 1],
    "half_angle": 45,
    "reference": [1, 0, 0],
}
CYLINDERS = {
    "name": "b",
    "type": "ball-cylinders",
    "ball": {"center": [0, 30, 0], "radius": 5},
    "cylinders": [
        {"point": [4.2, 30, -5.6], "axis": [0, 1, 0], "radius": 2},
        {"point": [-4.2, 30, -5.6], "axis": [0, 1, 0], "radius": 2},
    ],
}
SPHERES = {
    "name": "s",
    "type": "ball-sphere",
    "ball": {"center": [0, 30, 0], "radius": 5},
    "spheres": [{"center": [0, 30, -10], "radius": 5}],
}


def _box(extents: tuple[float, ...], centre: tuple[float, ...] = (0, 0, 0)) -> trimesh.Trimesh:
    box = trimesh.creation.box(extents=extents)
    box.apply_translation(centre)
    return box


def _stl(mesh: trimesh.Trimesh) -> bytes:
    return mesh.export(file_type="stl")


def _open_box() -> bytes:
    box = _box((100, 100, 100))
    keep = [i for i, n in enumerate(box.face_normals) if n[0] < 0.5]
    return _stl(trimesh.Trimesh(box.vertices, box.faces[keep], process=False))


def _flipped_face() -> bytes:
    box = _box((100, 100, 100))
    faces = box.faces.copy()
    faces[0] = faces[0][::-1]
    return _stl(trimesh.Trimesh(box.vertices, faces, process=False))


def _inverted() -> bytes:
    box = _box((100, 100, 100))
    return _stl(trimesh.Trimesh(box.vertices, box.faces[:, ::-1], process=False))


def _no_volume() -> bytes:
    """Closed and consistently wound, yet no volume: a box and, apart from it, the same box
    wound inwards (a cavity cancelling it)."""
    box = _box((100, 100, 100))
    hollow = _box((100, 100, 100), (300, 0, 0))
    faces = [box.faces, hollow.faces[:, ::-1] + len(box.vertices)]
    vertices = [box.vertices, hollow.vertices]
    return _stl(trimesh.Trimesh(np.vstack(vertices), np.vstack(faces), process=False))


def _degenerate() -> bytes:
    """Triangles of zero area only (every vertex on one line)."""
    vertices = [[0, 0, 0], [50, 0, 0], [100, 0, 0], [25, 0, 0]]
    return _stl(trimesh.Trimesh(vertices, [[0, 1, 2], [0, 3, 1], [1, 3, 2]], process=False))


def _ascii_nan() -> bytes:
    return (
        b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex nan 0 0\n"
        b"   vertex 0 1 0\n  endloop\n endfacet\nendsolid x\n"
    )


MESHES: dict[str, Callable[[], bytes]] = {
    "plate.stl": lambda: _stl(_box((120, 120, 20), (0, 0, 10))),
    "heavy.stl": lambda: _stl(_box((4000, 4000, 4000))),
    "sheet.stl": lambda: _stl(_box((800e3, 800e3, 1))),
    "far.stl": lambda: _stl(_box((100, 100, 100), (2e6, 0, 0))),
    "open.stl": _open_box,
    "flipped.stl": _flipped_face,
    "inverted.stl": _inverted,
    "flat.stl": _no_volume,
    "line.stl": _degenerate,
    "nan.stl": _ascii_nan,
    "empty.stl": lambda: b"solid x\nendsolid x\n",
    "garbage.obj": lambda: b"v 1 2\nf 1 2 3 4 5\nthis is not a mesh\n",
    "garbage.step": lambda: b"ISO-10303-21;\nHEADER;\nnonsense\nENDSEC;\n",
    "part.step": lambda: b"ISO-10303-21;\n",
}

Edit = Callable[[dict], None]


def _parts(path: str) -> list[Any]:
    return [int(i) if i else n for n, i in re.findall(r"([^.\[\]]+)|\[(\d+)\]", path)]


def put(path: str, value: Any) -> Edit:
    """Set (None: delete) the field at ``path``."""
    parts = _parts(path)

    def edit(data: dict) -> None:
        holder = data
        for part in parts[:-1]:
            holder = holder[part]
        if value is None:
            del holder[parts[-1]]
        elif isinstance(holder, list) and parts[-1] == len(holder):
            holder.append(copy.deepcopy(value))
        else:
            holder[parts[-1]] = copy.deepcopy(value)

    return edit


def both(*edits: Edit) -> Edit:
    def edit(data: dict) -> None:
        for e in edits:
            e(data)

    return edit


#: id -> (base scene, edit or raw text, the field the error must be at, settings)
Entry = tuple[dict | None, Edit | str, str | None, dict[str, Any]]
C = "couplings"
CORPUS: dict[str, Entry] = {}


def case(name: str, base: dict | None, edit: Edit | str, field: str | None, **settings: Any):
    assert name not in CORPUS, name
    CORPUS[name] = (base, edit, field, settings)


# the file as a whole
case("not a mapping", None, "[1, 2, 3]\n", None)
# field models (pydantic): one per kind of error
case("missing version", PLANAR, put("version", None), "version")
case("unknown key", PLANAR, put("fricton", 0.1), "fricton")
case("string for a number", PLANAR, put("friction", "0.1"), "friction")
case("bool for a number", PLANAR, put("load.magnitude", True), "load.magnitude")
case("short vector", PLANAR, put("supports[0].position", [1, 2]), "supports[0].position")
case("mass zero", PLANAR, put("body.mass", 0), "body.mass")
case("friction past 100", PLANAR, put("friction", 200), "friction")
case("range past 100", PLANAR, put("friction", {"min": 0, "max": 200}), "friction.max")
case("pair past 100", PLANAR, put("friction", {"static": 200, "kinetic": 1}), "friction.static")
case("unknown coupling type", SPATIAL, put("couplings[0].type", "ball-foo"), "couplings[0].type")
case("coupling without a type", SPATIAL, put("couplings[2].type", None), "couplings[2].type")
case("unknown unit", PLANAR, put("units", "furlong"), "units")
case("version 1.0", PLANAR, put("version", 1.0), "version")
case("too many preloads", SPATIAL, put("preloads", [SPATIAL["preloads"][0]] * 101), "preloads")
case(
    "half angle 90",
    SPATIAL,
    put("couplings[1].groove.half_angle", 90),
    "couplings[1].groove.half_angle",
)
case("unknown key in a coupling", SPATIAL, put("couplings[1].up", [0, 0, 1]), "couplings[1].up")
# plain values
case("nan", PLANAR, put("load.angle", float("nan")), "load.angle")
case("huge integer", PLANAR, put("body.mass", 10**400), "body.mass")
case("NUL in a string", PLANAR, put("supports[0].name", "a\x00b"), "supports[0].name")
# supports, forces, frames (load.py)
case(
    "support position far", PLANAR, put("supports[0].position", [2e6, 0, 0]), "supports[0].position"
)
case("support normal zero", PLANAR, put("supports[0].normal", [0, 0, 0]), "supports[0].normal")
case("support normal tiny", PLANAR, put("supports[0].normal", [1e-200, 0, 0]), "supports[0].normal")
case("support named twice", PLANAR, put("supports[1].name", "y1"), "supports[1].name")
case(
    "contact named like a support",
    SPATIAL,
    put("supports", [{"name": "v.1", "position": [0, 0, 0], "normal": [0, 0, 1]}]),
    "couplings[1].name",
)
case("four supports", PLANAR, put("supports[3]", PLANAR["supports"][0] | {"name": "z"}), "supports")
case("seven contacts", SPATIAL, put("couplings[3]", {**SPATIAL["couplings"][2], "name": "g"}), C)
case("planar normal with z", PLANAR, put("supports[0].normal", [0, 1, 1]), "supports[0].normal")
case(
    "planar coupling with z",
    PLANAR,
    both(put("supports", None), put("couplings", [SPATIAL["couplings"][0]])),
    "couplings[0]",
)
case("planar z differ", PLANAR, put("supports[0].position", [20, 0, 5]), "supports")
# materials and explicit contact radii (issue 21 items 1, 13)
case(
    "unknown ball material",
    SPATIAL,
    put("couplings[1].ball_material", "mithril"),
    "couplings[1].ball_material",
)
case(
    "contact ball radius zero-ish",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 1e-30}),
    "supports[0].contact.ball_radius",
)
case(
    "contact seat radius huge",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "seat_radii": [None, 1e30]}),
    "supports[0].contact.seat_radii[1]",
)
case(
    "contact seat radii without a direction",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "seat_radii": [None, 2]}),
    "supports[0].contact.seat_direction",
)
case(
    "contact seat direction zero",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "seat_direction": [0, 0, 0]}),
    "supports[0].contact.seat_direction",
)
case(
    "contact ball radii huge",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "ball_radii": [5, 1e30]}),
    "supports[0].contact.ball_radii[1]",
)
case(
    "contact ball radii without a direction",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "ball_radii": [5, 50]}),
    "supports[0].contact.ball_direction",
)
case(
    "contact ball direction zero",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "ball_direction": [0, 0, 0]}),
    "supports[0].contact.ball_direction",
)
case(
    "groove radius below the ball's",
    SPATIAL,
    put("couplings[1].groove.radius", 5),
    "couplings[1].groove.radius",
)
case(
    "canoe radius huge",
    SPATIAL,
    put("couplings[1].ball.surface_radii", [500, 1e30]),
    "couplings[1].ball.surface_radii[1]",
)
case(
    "canoe radii without a direction",
    SPATIAL,
    put("couplings[1].ball.surface_radii", [500, 50]),
    "couplings[1].ball.surface_direction",
)
case(
    "canoe direction zero",
    SPATIAL,
    both(
        put("couplings[1].ball.surface_radii", [500, 50]),
        put("couplings[1].ball.surface_direction", [0, 0, 0]),
    ),
    "couplings[1].ball.surface_direction",
)
case(
    "canoe direction without radii",
    SPATIAL,
    put("couplings[1].ball.surface_direction", [0, 0, 1]),
    "couplings[1].ball.surface_direction",
)
case(
    "contact seat direction along the normal",
    PLANAR,
    put("supports[0].contact", {"ball_radius": 5, "seat_direction": [0, 2, 0]}),
    "supports[0].contact.seat_direction",
)
case(
    "layout of a micrometre",
    PLANAR,
    both(*(put(f"supports[{i}].position", [i * 1e-4, 0, 0]) for i in range(3))),
    "supports",
)
case("sweep normal zero", SPATIAL, put("sweep.normal", [0, 0, 0]), "sweep.normal")
case("sweep zero tiny", SPATIAL, put("sweep.zero", [0, 0, 1e-200]), "sweep.zero")
case("sweep zero along its normal", SPATIAL, put("sweep.zero", [0, -2, 0]), "sweep.zero")
case("planar sweep tilted", PLANAR, put("sweep", {"normal": [0, 1, 0]}), "sweep.normal")
case("load direction and angle", SPATIAL, put("load.angle", 10), "load")
case("load direction zero", SPATIAL, put("load.direction", [0, 0, 0]), "load.direction")
case(
    "planar load direction with z",
    PLANAR,
    both(put("load.angle", None), put("load.direction", [0, 1, 1])),
    "load.direction",
)
case("load torque huge", SPATIAL, put("load.torque", [0, 0, 1e9]), "load.torque")
case("load point far", SPATIAL, put("load.point", [2e6, 0, 0]), "load.point")
case("load magnitude tiny", SPATIAL, put("load.magnitude", 1e-9), "load.magnitude")
case("gravity huge", SPATIAL, put("gravity", [0, 0, -1e4]), "gravity")
case("gravity component huge", SPATIAL, put("gravity", [0, 0, -1e300]), "gravity")
case("gravity long", SPATIAL, put("gravity", [900, 0, -900]), "gravity")
case("preload named twice", SPATIAL, put("preloads[1]", SPATIAL["preloads"][0]), "preloads[1].name")
case("preload point far", SPATIAL, put("preloads[0].point", [2e6, 0, 0]), "preloads[0].point")
case("preload force huge", SPATIAL, put("preloads[0].force", [0, 0, -1e9]), "preloads[0].force")
case("preload force tiny", SPATIAL, put("preloads[0].force", [0, 0, -1e-9]), "preloads[0].force")
case("tolerance of 2 m", SPATIAL, put("tolerances.position", 2000), "tolerances.position")
# friction (coefficients.py), at each place a coefficient is given
case("scene range reversed", PLANAR, put("friction", {"min": 0.3, "max": 0.1}), "friction")
case(
    "support static below kinetic",
    PLANAR,
    put("supports[0].friction", {"static": 0.1, "kinetic": 0.2}),
    "supports[0].friction",
)
case(
    "coupling range reversed in a pair",
    SPATIAL,
    put("couplings[0].friction", {"static": {"min": 0.3, "max": 0.2}, "kinetic": 0.1}),
    "couplings[0].friction.static",
)
# coupling shorthands (shorthands.py, couplings.py)
case(
    "ball centre far",
    SPATIAL,
    put("couplings[0].ball.center", [2e6, 0, 0]),
    "couplings[0].ball.center",
)
case("ball radius tiny", SPATIAL, put("couplings[0].ball.radius", 1e-4), "couplings[0].ball.radius")
case(
    "groove axis zero",
    SPATIAL,
    put("couplings[1].groove.axis", [0, 0, 0]),
    "couplings[1].groove.axis",
)
case("groove up zero", SPATIAL, put("couplings[1].groove.up", [0, 0, 0]), "couplings[1].groove.up")
case(
    "groove up along its axis",
    SPATIAL,
    put("couplings[1].groove.up", [-0.866, -0.5, 0]),
    "couplings[1].groove.up",
)
case("trihedral up zero", SPATIAL, put("couplings[0].up", [0, 0, 0]), "couplings[0].up")
case(
    "trihedral reference zero",
    SPATIAL,
    put("couplings[0].reference", [0, 0, 0]),
    "couplings[0].reference",
)
case(
    "trihedral reference along up",
    SPATIAL,
    put("couplings[0].reference", [0, 0, 3]),
    "couplings[0].reference",
)
case(
    "cone reference along up",
    SPATIAL,
    put("couplings[0]", {**CONE, "reference": [0, 0, -1]}),
    "couplings[0].reference",
)
case("flat normal zero", SPATIAL, put("couplings[2].normal", [0, 0, 0]), "couplings[2].normal")
case(
    "cylinder point far",
    SPATIAL,
    put(
        "couplings[0]",
        {**CYLINDERS, "cylinders": [{**CYLINDERS["cylinders"][0], "point": [2e6, 0, 0]}]},
    ),
    "couplings[0].cylinders[0].point",
)
case(
    "cylinder axis zero",
    SPATIAL,
    put(
        "couplings[0]",
        {**CYLINDERS, "cylinders": [{**CYLINDERS["cylinders"][0], "axis": [0, 0, 0]}]},
    ),
    "couplings[0].cylinders[0].axis",
)
case(
    "cylinder radius tiny",
    SPATIAL,
    put(
        "couplings[0]", {**CYLINDERS, "cylinders": [{**CYLINDERS["cylinders"][0], "radius": 1e-4}]}
    ),
    "couplings[0].cylinders[0].radius",
)
case(
    "ball does not touch a cylinder",
    SPATIAL,
    put(
        "couplings[0]",
        {
            **CYLINDERS,
            "cylinders": [
                CYLINDERS["cylinders"][0],
                {**CYLINDERS["cylinders"][1], "point": [-4.2, 30, -6.6]},
            ],
        },
    ),
    "couplings[0].cylinders[1]",
)
case(
    "sphere centre far",
    SPATIAL,
    put("couplings[0]", {**SPHERES, "spheres": [{"center": [2e6, 0, 0], "radius": 5}]}),
    "couplings[0].spheres[0].center",
)
case(
    "sphere radius tiny",
    SPATIAL,
    put("couplings[0]", {**SPHERES, "spheres": [{"center": [0, 30, -10], "radius": 1e-4}]}),
    "couplings[0].spheres[0].radius",
)
case(
    "ball does not touch a sphere",
    SPATIAL,
    put("couplings[0]", {**SPHERES, "spheres": [{"center": [0, 30, -12], "radius": 5}]}),
    "couplings[0].spheres[0]",
)
# the body (body.py)
case("mesh and parts", SPATIAL, put("body.parts", [{"mesh": "plate.stl", "density": 1000}]), "body")
case(
    "parts with the body's material",
    SPATIAL,
    both(put("body.mesh", None), put("body.parts", [{"mesh": "plate.stl", "density": 1000}])),
    "body",
)
case("no mass at all", PLANAR, put("body", {"repair": False}), "body")
case("repair without a mesh", PLANAR, put("body.repair", True), "body.repair")
case(
    "point mass named twice",
    PLANAR,
    put("body.point_masses", [{"name": "m", "mass": 0.1, "point": [0, 0, 0]}] * 2),
    "body.point_masses[1].name",
)
case(
    "point mass heavy",
    PLANAR,
    put("body.point_masses", [{"name": "m", "mass": 1e7, "point": [0, 0, 0]}]),
    "body.point_masses[0].mass",
)
case(
    "point mass far",
    PLANAR,
    put("body.point_masses", [{"name": "m", "mass": 1, "point": [2e6, 0, 0]}]),
    "body.point_masses[0].point",
)
case("material and density with a mesh", SPATIAL, put("body.density", 2700), "body")
case(
    "material and density without a mesh",
    PLANAR,
    both(put("body.material", "steel"), put("body.density", 2700)),
    "body",
)
case(
    "material and density on a part",
    SPATIAL,
    both(
        put("body.mesh", None),
        put("body.material", None),
        put("body.parts", [{"mesh": "plate.stl", "density": 1000, "material": "steel"}]),
    ),
    "body.parts[0]",
)
case("neither material nor density", SPATIAL, put("body.material", None), "body")
case("unknown material with a mesh", SPATIAL, put("body.material", "unobtainium"), "body.material")
case(
    "unknown material without a mesh", PLANAR, put("body.material", "unobtainium"), "body.material"
)
PART = {"mesh": "plate.stl", "material": "aluminium"}
ONE_PART = both(put("body.mesh", None), put("body.material", None), put("body.parts", [PART]))


def part(**fields: Any) -> Edit:
    return both(ONE_PART, put("body.parts[0]", {**PART, **fields}))


case("unknown material on a part", SPATIAL, part(material="unobtainium"), "body.parts[0].material")
case("a STEP part with units", SPATIAL, part(mesh="part.step", units="mm"), "body.parts[0].units")
case(
    "rotation entries past 1",
    SPATIAL,
    part(transform={"rotate": [[2, 0, 0], [0, 1, 0], [0, 0, 1]]}),
    "body.parts[0].transform.rotate",
)
case(
    "rotation not orthonormal",
    SPATIAL,
    part(transform={"rotate": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]}),
    "body.parts[0].transform.rotate",
)
case(
    "rotation mirrors",
    SPATIAL,
    part(transform={"rotate": [[-1, 0, 0], [0, 1, 0], [0, 0, 1]]}),
    "body.parts[0].transform.rotate",
)
case(
    "rotation axis zero",
    SPATIAL,
    part(transform={"rotate": {"axis": [0, 0, 0], "angle": 10}}),
    "body.parts[0].transform.rotate.axis",
)
case(
    "translation far",
    SPATIAL,
    part(transform={"translate": [2e6, 0, 0]}),
    "body.parts[0].transform.translate",
)
case("part mesh not found", SPATIAL, part(mesh="nope.stl"), "body.parts[0].mesh")
case("part without material", SPATIAL, part(material=None), "body.parts[0]")
case("mesh leaves the folder", SPATIAL, put("body.mesh", "../plate.stl"), "body.mesh")
case("mesh not found", SPATIAL, put("body.mesh", "nope.stl"), "body.mesh")
case("mesh is a folder", SPATIAL, put("body.mesh", "folder.stl"), "body.mesh")
case("mesh is a pipe", SPATIAL, put("body.mesh", "pipe.stl"), "body.mesh")
if os.geteuid() != 0:  # root reads any file
    case("mesh unreadable", SPATIAL, put("body.mesh", "secret.stl"), "body.mesh")
case("explicit without inertia", PLANAR, put("body.inertia", None), "body.inertia")
case("explicit mass heavy", PLANAR, put("body.mass", 1e7), "body.mass")
case("centre of mass far", PLANAR, put("body.center_of_mass", [2e6, 0, 0]), "body.center_of_mass")
case("lone I_zz tiny", PLANAR, put("body.inertia", 1e-20), "body.inertia")
case(
    "lone I_zz in a spatial scene",
    SPATIAL,
    both(put("body", {"mass": 1, "center_of_mass": [0, 0, 10]}), put("body.inertia", 0.1)),
    "body.inertia",
)
EXPLICIT = both(put("body", {"mass": 1, "center_of_mass": [0, 0, 10]}))


def inertia(value: Any) -> Edit:
    return both(EXPLICIT, put("body.inertia", value))


case(
    "inertia entries huge",
    SPATIAL,
    inertia([[1e10, 0, 0], [0, 1e10, 0], [0, 0, 1e10]]),
    "body.inertia",
)
case("inertia asymmetric", SPATIAL, inertia([[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "body.inertia")
case("inertia not positive", SPATIAL, inertia([[1, 0, 0], [0, -1, 0], [0, 0, 1]]), "body.inertia")
case(
    "inertia moments tiny",
    SPATIAL,
    inertia([[1e-20, 0, 0], [0, 1e-20, 0], [0, 0, 1e-20]]),
    "body.inertia",
)
case("inertia not a body", SPATIAL, inertia([[1, 0, 0], [0, 1, 0], [0, 0, 3]]), "body.inertia")
# meshes, when read (kcheck/body/), and the runner
case("mesh open", SPATIAL, put("body.mesh", "open.stl"), "body.mesh")
case("mesh winding inconsistent", SPATIAL, put("body.mesh", "flipped.stl"), "body.mesh")
case("mesh inverted", SPATIAL, put("body.mesh", "inverted.stl"), "body.mesh")
case("mesh of no volume", SPATIAL, put("body.mesh", "flat.stl"), "body.mesh")
case("mesh of zero-area faces", SPATIAL, put("body.mesh", "line.stl"), "body.mesh")
case("mesh with NaN", SPATIAL, put("body.mesh", "nan.stl"), "body.mesh")
case("mesh empty", SPATIAL, put("body.mesh", "empty.stl"), "body.mesh")
case("mesh unreadable garbage", SPATIAL, put("body.mesh", "garbage.obj"), "body.mesh")
case("STEP garbage", SPATIAL, both(put("body.mesh", "garbage.step")), "body.mesh")
case("mesh far", SPATIAL, put("body.mesh", "far.stl"), "body.mesh")
case(
    "mesh too large a file", SPATIAL, put("body.mesh", "plate.stl"), "body.mesh", max_mesh_bytes=100
)
case(
    "mesh heavy",
    SPATIAL,
    both(put("body.material", None), put("body.density", 30000), put("body.mesh", "heavy.stl")),
    "body.mesh",
)
case(
    "mesh inertia huge",
    SPATIAL,
    both(put("body.material", None), put("body.density", 1000), put("body.mesh", "sheet.stl")),
    "body.mesh",
)
case(
    "part placed far",
    SPATIAL,
    part(transform={"translate": [999.99e3, 0, 0]}),
    "body.parts[0].mesh",
)
case(
    "body as a whole heavy",
    SPATIAL,
    put("body.point_masses", [{"name": "m", "mass": 9e5}, {"name": "n", "mass": 9e5}]),
    "body",
)
case(
    "severity unknown",
    PLANAR,
    put("checks", {"maxwell": {"severity": "fatal"}}),
    "checks.maxwell.severity",
)
case(
    "option mistyped",
    PLANAR,
    put("checks", {"maxwell": {"min_cos": "x"}}),
    "checks.maxwell.min_cos",
)
case("unknown check", PLANAR, put("checks", {"maxwel": {}}), "checks.maxwel")
# supports against the body's mesh (kcheck/analysis/placement.py)
case(
    "contact off the body",
    SPATIAL,
    put(f"{C}[2].ball.center", [43.3, -25, -500]),
    f"{C}[2]",
)
case(
    "mesh unreadable for the supports alone",
    SPATIAL,
    put("body.mesh", "garbage.obj"),
    "body.mesh",
    selected=frozenset({"maxwell"}),
)
for name in ("body as a whole heavy",):  # point masses need their points
    base, edit, field, settings = CORPUS[name]
    CORPUS[name] = (
        base,
        put("body.point_masses", [{"name": n, "mass": 9e5, "point": [0, 0, 10]} for n in "mn"]),
        field,
        settings,
    )

#: Places that make an input error but that no scene file can reach; each with why.
UNREACHABLE = {
    ("body/meshio.py", "cannot read the mesh ({describe_os_error(exc)})"): "the loader refuses "
    "a missing mesh first "
    "(body.mesh_path); reached only when the file goes away between loading and reading",
    ("body/meshio.py", "not a regular file"): "likewise for a file replaced by a pipe",
    ("body/meshio.py", "STEP files need the optional"): "the test environment has the step extra",
    # Parts of an assembly are named only on kcheck contacts' command line (--base-part,
    # --body-part), never in a scene; tests/cli/test_contacts_cli.py runs an unknown name.
    ("body/meshio.py", "no part named"): "named on the command line only",
    ("body/meshio.py", "has no triangles"): "named on the command line only",
    ("body/meshio.py", "MeshError(path, exc.message, field=field)"): "re-raises the two above "
    "with the file's path",
    ("body/mass.py", "non-finite mass properties"): "defensive: finite vertices and a checked "
    "volume give finite mass properties",
    ("gate/runner.py", "a check needs the body's mass properties"): "every built-in check "
    "that needs mass properties is skipped, with its reason, when a scene has no body",
}
if os.geteuid() == 0:
    UNREACHABLE[("scene/body.py", "cannot be read (permission denied)")] = "root reads any file"


# --- running the corpus --------------------------------------------------------------------------


class _Plain(yaml.SafeDumper):
    """Every value written out where it is (no anchors and aliases)."""

    def ignore_aliases(self, data: Any) -> bool:
        return True


def _write(folder: Path, name: str, entry: Entry) -> tuple[Path, str, Any]:
    base, edit, _, _ = entry
    scene_folder = folder / re.sub(r"[^a-z0-9]+", "-", name.lower())
    scene_folder.mkdir(parents=True)
    for mesh, make in MESHES.items():
        (scene_folder / mesh).write_bytes(make())
    (scene_folder / "folder.stl").mkdir()
    os.mkfifo(scene_folder / "pipe.stl")
    (scene_folder / "secret.stl").write_bytes(MESHES["plate.stl"]())
    (scene_folder / "secret.stl").chmod(0)
    (folder / "plate.stl").write_bytes(MESHES["plate.stl"]())  # outside the scene's folder
    if isinstance(edit, str):
        text = edit
    else:
        data = copy.deepcopy(base)
        edit(data)
        text = yaml.dump(data, Dumper=_Plain, sort_keys=False, allow_unicode=False, width=200)
    path = scene_folder / "s.kcheck.yaml"
    path.write_text(text)
    return path, text, yaml.safe_load(text)


@pytest.fixture(scope="module")
def corpus(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Every entry's result, and every place in kcheck's source an error was made from."""
    folder = tmp_path_factory.mktemp("errors")
    checks = load_checks()
    stacks: list[traceback.StackSummary] = []
    scene_init, coupling_init = SceneError.__init__, CouplingError.__init__

    def record_scene(self, *args, **kwargs):
        stacks.append(traceback.extract_stack())
        scene_init(self, *args, **kwargs)

    def record_coupling(self, *args, **kwargs):
        stacks.append(traceback.extract_stack())
        coupling_init(self, *args, **kwargs)

    results = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(SceneError, "__init__", record_scene)
        mp.setattr(CouplingError, "__init__", record_coupling)
        for name, entry in CORPUS.items():
            path, text, data = _write(folder, name, entry)
            settings = Settings(**entry[3]) if entry[3] else None
            result = check_scene(path, checks, settings=settings)
            results[name] = (result, text, data)
    hit = {(Path(f.filename).resolve(), f.lineno) for s in stacks for f in s}
    return {"results": results, "hit": hit}


def test_the_bases_are_valid(tmp_path):
    checks = load_checks()
    for name, base in (("planar", PLANAR), ("spatial", SPATIAL)):
        path, _, _ = _write(tmp_path, name, (base, lambda d: None, None, {}))
        result = check_scene(path, checks)
        assert result.status.value != "error", (name, result.error)


@pytest.mark.parametrize("name", list(CORPUS))
def test_an_error_sits_at_a_real_field(corpus, name):
    result, text, data = corpus["results"][name]
    expected = CORPUS[name][2]
    assert result.status.value == "error", result.status
    assert not any(c.status.value == "error" for c in result.checks)
    assert "internal error" not in (result.error or "")
    fields = [None if e.field is None else format_path(e.field) for e in result.errors]
    assert expected in fields, (fields, [e.message for e in result.errors])
    for e in result.errors:
        path = e.field or ()
        if e.message.startswith("unknown field"):
            # the unknown key itself is where to fix it; its mapping is a real field
            assert in_schema(path[:-1], data) and not in_schema(path, data), path
        else:
            assert in_schema(path, data), (format_path(path), e.message)
        assert (e.line, e.column) == written_at(text, path), (format_path(path), e.message)


def test_the_groove_up_along_its_axis_is_named_as_such(corpus):
    result, _, _ = corpus["results"]["groove up along its axis"]
    (error,) = result.errors
    assert error.field == ("couplings", 1, "groove", "up")
    assert "`up`" in error.message and "`axis`" in error.message
    assert "parallel to `up`" not in error.message


# --- every place an error is made has an entry ---------------------------------------------------

SOURCES = (
    "scene/body.py",
    "scene/load.py",
    "scene/coefficients.py",
    "scene/shorthands.py",
    "scene/couplings.py",
    "scene/validate.py",
    "gate/runner.py",
    "body/mass.py",
    "body/meshio.py",
)
#: Calls that make a located error or apply a rule that makes one, at the field given.
ERROR_METHODS = {"add", "in_range", "coordinates", "direction", "magnitude", "error"}
RULE_METHODS = {"density", "mesh_path", "rotation", "inertia", "unique_name"}
ERROR_FUNCTIONS = {
    "MeshError",
    "CouplingError",
    "_perpendicular",
    "_touching",
    "not_watertight",
    "resolve_friction",
}
RECEIVERS = {"p", "self.p", "problems", "scene", "self"}
#: Plumbing, not rules: Problems.add making its error, Problems.error itself.
PLUMBING = {("scene/validate.py", "add"), ("scene/validate.py", "error")}


def _sites() -> dict[tuple[Path, int, int], str]:
    """(file, first line, last line) -> the source of each place an error is made."""
    out = {}
    for rel in SOURCES:
        path = KCHECK / rel
        tree = ast.parse(path.read_text())
        parents = {}
        for node in ast.walk(tree):
            for child in ast.iter_child_nodes(node):
                parents[child] = node
        for node in ast.walk(tree):
            if not isinstance(node, ast.Call):
                continue
            func = node.func
            wanted = False
            if isinstance(func, ast.Attribute) and ast.unparse(func.value) in RECEIVERS:
                wanted = func.attr in ERROR_METHODS or (
                    func.attr in RULE_METHODS and ast.unparse(func.value) == "self"
                )
            elif isinstance(func, ast.Name):
                wanted = func.id in ERROR_FUNCTIONS or (
                    func.id == "direction" and rel == "scene/shorthands.py"
                )
            if not wanted:
                continue
            owner = parents.get(node)
            while owner is not None and not isinstance(owner, (ast.FunctionDef, ast.ClassDef)):
                owner = parents.get(owner)
            if owner is not None and (rel, owner.name) in PLUMBING:
                continue
            if isinstance(owner, ast.FunctionDef) and owner.name == "__init__":
                continue
            out[(path.resolve(), node.lineno, node.end_lineno or node.lineno)] = (
                f"{rel}:{node.lineno}: {ast.get_source_segment(path.read_text(), node)}"
            )
    return out


def test_every_place_an_error_is_made_has_an_input(corpus):
    hit = corpus["hit"]
    missed = []
    for (path, first, last), source in _sites().items():
        if any((path, line) in hit for line in range(first, last + 1)):
            continue
        rel = str(path.relative_to(KCHECK))
        if any(rel == f and fragment in source for f, fragment in UNREACHABLE):
            continue
        missed.append(source.replace("\n", " ")[:160])
    assert not missed, "no input in the corpus reaches:\n" + "\n".join(missed)
    assert len(_sites()) > 100  # the scan finds them
