"""Every rule of the Limits table (docs/scene-format.md) holds whatever the body's kind: a mesh,
parts, or explicit mass properties (issue 25: `body.material: unobtainium` passed with explicit
mass properties and no mesh, and a mesh's principal moments were never checked).

One base scene (a Maxwell three-vee coupling in mm, with gravity, a load, a preload, friction
and tolerances) is written with each kind of body; each rule breaks it once per kind (a body
rule in the way that kind can break it: an explicit mass, a mesh's mass, a part's mesh), and
every broken scene must be an input error at the rule's field (exit 2). Every scene runs in
one batch of the command line. The base scenes themselves must check (not exit 2).

The meshes are boxes whose mass properties follow in closed form (m = ρ a b c,
I = m (b² + c²) / 12 about the centre), which is how each is made to lie just past a limit.
"""

from __future__ import annotations

import copy
import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import trimesh
import yaml

from tests.conftest import ROOT

KINDS = ("mesh", "parts", "explicit")

BASE: dict[str, Any] = {
    "version": 1,
    "name": "limits",
    "units": "mm",
    "couplings": [
        {
            "name": f"v{i + 1}",
            "type": "ball-vee",
            "ball_on": "base",
            "ball": {"center": center, "radius": 6},
            "groove": {"axis": axis, "up": [0, 0, -1], "half_angle": 45},
        }
        for i, (center, axis) in enumerate(
            [
                ([0, 50, 0], [0, 1, 0]),
                ([-43.30127, -25, 0], [-0.8660254, -0.5, 0]),
                ([43.30127, -25, 0], [0.8660254, -0.5, 0]),
            ]
        )
    ],
    "friction": 0.1,
    "gravity": [0, 0, -9.81],
    "load": {"point": [0, 0, 16], "magnitude": 50, "direction": [0, 0, -1], "torque": [0, 0, 0]},
    "preloads": [{"name": "spring", "point": [0, 0, 10], "force": [0, 0, -5]}],
    "tolerances": {"position": 0.05, "normal": 0.5, "load_direction": 2},
}

BODIES: dict[str, dict[str, Any]] = {
    "mesh": {"mesh": "plate.stl", "material": "aluminium"},
    "parts": {
        "parts": [
            {"mesh": "plate.stl", "material": "aluminium"},
            {"mesh": "plate.stl", "material": "steel", "transform": {"translate": [0, 0, 20]}},
        ]
    },
    "explicit": {
        "mass": 1.7,
        "center_of_mass": [0, 0, 10],
        "inertia": [[0.0036, 0, 0], [0, 0.0036, 0], [0, 0, 0.0071]],
    },
}

#: Boxes (mm): (name, extents, centre). The plate is the base scenes' body (120 x 120 x 20).
MESHES = {
    "plate.stl": ((120, 120, 20), (0, 0, 10)),
    # 4 m cube: at 30 000 kg/m³ (the density limit) 1.92e6 kg, past the mass limit of 1e6.
    "heavy.stl": ((4000, 4000, 4000), (0, 0, 2000)),
    # 3 m cube: 8.1e5 kg at 30 000 kg/m³, within the mass limit; two of them are not.
    "big.stl": ((3000, 3000, 3000), (0, 0, 1500)),
    # 800 m x 800 m x 1 mm at 1000 kg/m³: 6.4e5 kg (within), I_zz = m (a² + b²) / 12 = 6.8e10
    # kg m² (past 1e9).
    "sheet.stl": ((800e3, 800e3, 1), (0, 0, 0.5)),
    # a 0.04 mm cube at 30 000 kg/m³: 1.92e-9 kg (within), I = m a² / 6 = 5.1e-19 kg m² (below
    # 1e-18).
    "speck.stl": ((0.04, 0.04, 0.04), (0, 0, 0.02)),
    # reaches 2000 m from the origin.
    "far.stl": ((100, 100, 100), (2e6, 0, 0)),
}

Edit = Callable[[dict[str, Any]], None]


def _set(path: str, value: Any) -> Edit:
    """An edit setting the field at ``path`` (``load.point``, ``couplings[0].ball.radius``)."""
    parts: list[Any] = []
    for name, index in re.findall(r"([^.\[\]]+)|\[(\d+)\]", path):
        parts.append(int(index) if index else name)

    def edit(data: dict[str, Any]) -> None:
        holder = data
        for part in parts[:-1]:
            holder = holder[part]
        holder[parts[-1]] = value

    return edit


def _body(**fields: Any) -> Edit:
    """Replace the body's fields (None deletes one)."""

    def edit(data: dict[str, Any]) -> None:
        for k, v in fields.items():
            if v is None:
                data["body"].pop(k, None)
            else:
                data["body"][k] = v

    return edit


def _part(i: int, **fields: Any) -> Edit:
    def edit(data: dict[str, Any]) -> None:
        for k, v in fields.items():
            if v is None:
                data["body"]["parts"][i].pop(k, None)
            else:
                data["body"]["parts"][i][k] = v

    return edit


def _all(*edits: Edit) -> Edit:
    def edit(data: dict[str, Any]) -> None:
        for e in edits:
            e(data)

    return edit


def _same(edit: Edit, field: str) -> dict[str, tuple[Edit, str]]:
    """A rule that does not concern the body: the same edit, the same field, every kind."""
    return {kind: (edit, field) for kind in KINDS}


#: Limits-table row (its first words in docs/scene-format.md) -> cases; a case is, per body
#: kind, the edit and the field of the expected error.
Case = dict[str, tuple[Edit, str]]
POINT_MASS = {"name": "lead", "mass": 5e5, "point": [0, 0, 10]}
RULES: dict[str, dict[str, Case]] = {
    "coordinates": {
        "load point": _same(_set("load.point", [2e6, 0, 0]), "load.point"),
        "the body": {
            "mesh": (_body(mesh="far.stl"), "body.mesh"),
            "parts": (
                _part(1, transform={"translate": [2e6, 0, 0]}),
                "body.parts[1].transform.translate",
            ),
            "explicit": (_body(center_of_mass=[2e6, 0, 0]), "body.center_of_mass"),
        },
        "a placed part or mesh": {
            "mesh": (_body(mesh="far.stl"), "body.mesh"),
            # 999.99 m + the plate's 60 mm: the placed mesh reaches past 1000 m
            "parts": (_part(1, transform={"translate": [999.99e3, 0, 0]}), "body.parts[1].mesh"),
            "explicit": (
                _set("body.point_masses", [{**POINT_MASS, "point": [2e6, 0, 0]}]),
                "body.point_masses[0].point",
            ),
        },
    },
    "radii": {"ball": _same(_set("couplings[0].ball.radius", 1e-4), "couplings[0].ball.radius")},
    "mass": {
        "the body's own": {
            "mesh": (_body(mesh="heavy.stl", material=None, density=30000), "body.mesh"),
            "parts": (
                _part(0, mesh="heavy.stl", material=None, density=30000),
                "body.parts[0].mesh",
            ),
            "explicit": (_body(mass=1e7), "body.mass"),
        },
        "a point mass": _same(
            _set("body.point_masses", [{**POINT_MASS, "mass": 1e7}]), "body.point_masses[0].mass"
        ),
        "the total": {
            "mesh": (
                _all(
                    _body(mesh="big.stl", material=None, density=30000),
                    _set("body.point_masses", [POINT_MASS]),
                ),
                "body",
            ),
            "parts": (
                _all(
                    _part(0, mesh="big.stl", material=None, density=30000),
                    _part(1, mesh="big.stl", material=None, density=30000),
                ),
                "body",
            ),
            "explicit": (
                _all(_body(mass=8e5), _set("body.point_masses", [POINT_MASS])),
                "body",
            ),
        },
    },
    "density": {
        "too dense": {
            "mesh": (_body(material=None, density=1e5), "body.density"),
            "parts": (_part(0, material=None, density=1e5), "body.parts[0].density"),
            "explicit": (_body(density=1e5), "body.density"),
        }
    },
    "principal moments": {
        "too large": {
            "mesh": (_body(mesh="sheet.stl", material=None, density=1000), "body.mesh"),
            "parts": (
                _part(0, mesh="sheet.stl", material=None, density=1000),
                "body.parts[0].mesh",
            ),
            "explicit": (_body(inertia=[[1e10, 0, 0], [0, 1e10, 0], [0, 0, 1e10]]), "body.inertia"),
        },
        "too small": {
            "mesh": (_body(mesh="speck.stl", material=None, density=30000), "body.mesh"),
            "parts": (
                _part(0, mesh="speck.stl", material=None, density=30000),
                "body.parts[0].mesh",
            ),
            "explicit": (
                _body(inertia=[[5e-19, 0, 0], [0, 5e-19, 0], [0, 0, 5e-19]]),
                "body.inertia",
            ),
        },
    },
    "force": {
        "load": _same(_set("load.magnitude", 1e8), "load.magnitude"),
        "tiny load": _same(_set("load.magnitude", 1e-9), "load.magnitude"),
        "preload": _same(_set("preloads[0].force", [0, 0, -1e8]), "preloads[0].force"),
    },
    "torque": {"load": _same(_set("load.torque", [0, 0, 1e8]), "load.torque")},
    "gravity": {"length": _same(_set("gravity", [0, 0, -1e4]), "gravity")},
    "friction": {
        "scene": _same(_set("friction", 200), "friction"),
        "range": _same(
            _set("couplings[0].friction", {"min": 0, "max": 200}), "couplings[0].friction.max"
        ),
        "static": _same(_set("friction", {"static": 200, "kinetic": 0.1}), "friction.static"),
    },
    "angles": {
        "load angle": _same(
            _all(_set("load.direction", None), _set("load.angle", 400)), "load.angle"
        ),
    },
    "`half_angle`": {
        "groove": _same(
            _set("couplings[0].groove.half_angle", 90), "couplings[0].groove.half_angle"
        )
    },
    "tolerance of positions": {
        "2 m": _same(_set("tolerances.position", 2000), "tolerances.position")
    },
    "tolerance of angles": {"45 deg": _same(_set("tolerances.normal", 45), "tolerances.normal")},
    "directions": {
        "huge": _same(_set("couplings[0].groove.axis", [1e200, 0, 0]), "couplings[0].groove.axis"),
        "zero": _same(_set("load.direction", [0, 0, 0]), "load.direction"),
    },
    "layout": {
        # every ball at the origin, 1.1 µm across: the contacts lie within 0.8 µm of their
        # centroid (radius 1.1 µm is itself allowed)
        "a micrometre": _same(
            _all(
                *(_set(f"couplings[{i}].ball.center", [0, 0, 0]) for i in range(3)),
                *(_set(f"couplings[{i}].ball.radius", 0.0011) for i in range(3)),
            ),
            "couplings",
        )
    },
}

#: The rules below the table ("Further rules"), each with its words in the document.
FURTHER: dict[str, tuple[str, Case]] = {
    "version": ("`version` must be the integer 1", _same(_set("version", 2), "version")),
    "material and density": (
        "`material` and `density` are never both given",
        {
            "mesh": (_body(density=2700), "body"),
            "parts": (_part(0, density=2700), "body.parts[0]"),
            "explicit": (_body(material="steel", density=7850), "body"),
        },
    ),
    "material names": (
        "material names must be in the table",
        {
            "mesh": (_body(material="unobtainium"), "body.material"),
            "parts": (_part(0, material="unobtainium"), "body.parts[0].material"),
            "explicit": (_body(material="unobtainium"), "body.material"),
        },
    ),
    "strings": ("strings must\nbe valid text", _same(_set("name", "a\x00b"), "name")),
    "counts": (
        "100\n`preloads` are accepted",
        _same(
            _set(
                "preloads",
                [{"name": f"p{i}", "point": [0, 0, 0], "force": [0, 0, -1]} for i in range(101)],
            ),
            "preloads",
        ),
    ),
}


def _scene(kind: str) -> dict[str, Any]:
    data = copy.deepcopy(BASE)
    data["body"] = copy.deepcopy(BODIES[kind])
    return data


def _limits_rows() -> list[str]:
    doc = (ROOT / "docs" / "scene-format.md").read_text()
    table = doc.split("## Limits", 1)[1].split("| quantity | allowed |", 1)[1]
    rows = []
    for line in table.splitlines()[2:]:
        if not line.startswith("|"):
            break
        rows.append(line.split("|")[1].strip())
    return rows


def test_every_row_of_the_limits_table_has_cases():
    rows = _limits_rows()
    assert len(rows) == len(RULES), rows
    for row in rows:
        assert any(row.startswith(rule) for rule in RULES), f"no cases for the row {row!r}"
    doc = " ".join((ROOT / "docs" / "scene-format.md").read_text().split())
    for words, _ in FURTHER.values():
        assert " ".join(words.split()) in doc, words


@pytest.fixture(scope="module")
def batch(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Every case of every rule for every kind, and the three base scenes, in one run of
    ``kcheck check --format json``; the scene's result by its folder name."""
    from kcheck.cli import main

    root = tmp_path_factory.mktemp("limits")
    meshes = {}
    for name, (extents, centre) in MESHES.items():
        box = trimesh.creation.box(extents=extents)
        box.apply_translation(centre)
        meshes[name] = box.export(file_type="stl")

    def write(name: str, data: dict[str, Any]) -> None:
        folder = root / name
        folder.mkdir()
        for mesh, raw in meshes.items():
            (folder / mesh).write_bytes(raw)
        (folder / "s.kcheck.yaml").write_text(yaml.safe_dump(data, allow_unicode=False))

    for kind in KINDS:
        write(f"base-{kind}", _scene(kind))
    cases = {**{r: c for r, c in RULES.items()}, **{r: {r: c} for r, (_, c) in FURTHER.items()}}
    for rule, variants in cases.items():
        for variant, per_kind in variants.items():
            for kind, (edit, _) in per_kind.items():
                data = _scene(kind)
                edit(data)
                write(_name(rule, variant, kind), data)
    out = root / "out.json"
    import contextlib
    import io

    with contextlib.redirect_stderr(io.StringIO()):
        code = main(
            ["check", "--format", "json", "--no-cache", "-j", "2", "--output", str(out), str(root)]
        )
    results = {Path(s["path"]).parent.name: s for s in json.loads(out.read_text())["scenes"]}
    return {"code": code, "results": results}


def _name(rule: str, variant: str, kind: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", f"{rule} {variant} {kind}".lower()).strip("-")


def test_the_base_scene_of_every_kind_checks(batch):
    for kind in KINDS:
        result = batch["results"][f"base-{kind}"]
        assert result["status"] in ("pass", "marginal", "warn", "fail"), (kind, result.get("error"))
    assert batch["code"] == 2  # the broken ones


def _params() -> list[Any]:
    out = []
    for rule, variants in RULES.items():
        for variant, per_kind in variants.items():
            for kind, (_, field) in per_kind.items():
                out.append(pytest.param(rule, variant, kind, field, id=_name(rule, variant, kind)))
    for rule, (_, per_kind) in FURTHER.items():
        for kind, (_, field) in per_kind.items():
            out.append(pytest.param(rule, rule, kind, field, id=_name(rule, rule, kind)))
    return out


@pytest.mark.parametrize(("rule", "variant", "kind", "field"), _params())
def test_a_rule_holds_for_every_kind_of_body(batch, rule, variant, kind, field):
    result = batch["results"][_name(rule, variant, kind)]
    assert result["status"] == "error", (result["status"], [c["status"] for c in result["checks"]])
    assert not any(c["status"] == "error" for c in result["checks"])  # input, not a crash
    fields = [e.get("field") for e in result["errors"]]
    assert field in fields, (fields, [e["message"] for e in result["errors"]])
    assert "internal error" not in (result["error"] or "")
