"""`kcheck init`, `kcheck expand`, `kcheck mass` from the command line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import trimesh

from kcheck.cli.init import guess_units
from kcheck.scene import load_scene
from tests.conftest import FIXTURES


def _plate(path: Path, extents=(120.0, 80.0, 15.0)) -> Path:
    trimesh.creation.box(extents=extents).export(path)
    return path


@pytest.mark.parametrize("coupling", ["maxwell", "kelvin", "321", "planar"])
@pytest.mark.parametrize("with_mesh", [True, False])
def test_init_writes_a_scene_that_checks(cli, tmp_path, coupling, with_mesh):
    args = ["init", "--coupling", coupling, "-o", str(tmp_path / f"{coupling}.kcheck.yaml")]
    if with_mesh:
        args += ["--mesh", str(_plate(tmp_path / "part.stl"))]
    code, out, err = cli(*args)
    assert code == 0, err
    path = tmp_path / f"{coupling}.kcheck.yaml"
    text = path.read_text()
    assert text.startswith("# A ") and "kcheck init" in text
    scene = load_scene(path)
    assert scene.kind == ("planar" if coupling == "planar" else "spatial")
    code, doc = 0, None
    code, out, _ = cli("check", "--format", "json", str(path))
    doc = json.loads(out)["scenes"][0]
    balls_off_the_mesh = with_mesh and coupling in ("maxwell", "kelvin")
    if balls_off_the_mesh:
        # The template's balls hang under the plate, in no mesh: the mesh cannot tell their
        # contacts (support-unchecked, docs/scene-format.md), and says so; nothing else.
        assert doc["status"] == "warn" and doc["checks"], doc
        assert {w["code"] for w in doc["warnings"]} == {"support-unchecked"}
        assert all(c["status"] == "pass" for c in doc["checks"] if c["status"] != "skipped")
    else:
        assert doc["status"] == "pass" and doc["warnings"] == [], doc
    if with_mesh:
        assert "units: mm is a GUESS" in text and "largest extent 120" in text
        assert "x -60 … 60, y -40 … 40, z -7.5 … 7.5 mm" in text
        assert "centre of mass is [0, 0, 0] mm" in text


def test_init_refuses_to_overwrite(cli, tmp_path):
    target = tmp_path / "c.kcheck.yaml"
    target.write_text("keep me\n")
    code, _, err = cli("init", "-o", str(target))
    assert code == 2 and "--force" in err and target.read_text() == "keep me\n"
    code, out, _ = cli("init", "-o", "-")
    assert code == 0 and out.startswith("# A maxwell coupling")


def test_init_next_to_the_mesh_and_bad_input(cli, tmp_path):
    mesh = _plate(tmp_path / "bracket.stl")
    assert cli("init", "--mesh", str(mesh))[0] == 0
    assert (tmp_path / "bracket.kcheck.yaml").is_file()
    assert cli("init", "--mesh", str(tmp_path / "none.stl"))[0] == 2
    assert cli("init", "--material", "cheese", "-o", "-")[0] == 2


@pytest.mark.parametrize(
    ("extent", "unit"), [(0.12, "m"), (1.5, "m"), (120.0, "mm"), (3000.0, "mm"), (1.2e5, "um")]
)
def test_units_guess(extent, unit):
    assert guess_units(extent)[0] == unit


def test_expand_reports_bad_input(cli, write_scene):
    path = write_scene("version: 1\ncouplings: [{name: a, type: ball-vee}]\n")
    code, out, err = cli("expand", str(path))
    assert code == 2 and out == "" and "couplings[0].ball" in err and "Traceback" not in err


def test_mass_of_several_meshes_with_bounds(cli, tmp_path):
    a = _plate(tmp_path / "a.stl", (100.0, 50.0, 10.0))
    b = _plate(tmp_path / "b.stl", (10.0, 10.0, 10.0))
    code, out, _ = cli("mass", str(a), str(b), "--units", "mm", "--material", "steel")
    assert code == 0
    assert "bounds x -50 … 50, y -25 … 25, z -5 … 5 mm (size 100 × 50 × 10 mm)" in out
    assert "all 2 meshes together" in out
    code, out, _ = cli(
        "mass", str(a), str(b), "--units", "mm", "--material", "steel", "--format", "json"
    )
    doc = json.loads(out)
    masses = [m["mass"] for m in doc["meshes"]]
    assert masses[2] == pytest.approx(masses[0] + masses[1])
    assert cli("mass", str(a), "--material", "steel")[0] == 2  # STL needs --units


def test_expand_to_an_unwritable_output_is_a_usage_error(cli):
    # Fuzz finding (issue 13): `kcheck expand --output /dev/full` ended in a traceback.
    scene = str(FIXTURES / "kelvin" / "coupling.kcheck.yaml")
    for target in ("/dev/full", "/proc/kcheck.yaml"):
        code, out, err = cli("expand", scene, "--output", target)
        assert code == 2 and out == "" and err.startswith("kcheck: error:") and target in err
        assert "Traceback" not in err


def test_mass_with_a_material_per_file(cli, tmp_path):
    plate = _plate(tmp_path / "plate.stl", (100.0, 100.0, 10.0))
    balls = _plate(tmp_path / "balls.stl", (10.0, 10.0, 10.0))
    code, out, err = cli(
        "mass", f"{plate}:aluminium", f"{balls}:steel", "--units", "mm", "--format", "json"
    )
    assert code == 0, err
    doc = json.loads(out)
    plate_doc, balls_doc, together = doc["meshes"]
    assert doc["density"] is None
    assert plate_doc["mesh"] == str(plate) and plate_doc["material"] == "aluminium"
    assert plate_doc["mass"] == pytest.approx(2700.0 * 1e-4)  # 100 × 100 × 10 mm
    assert balls_doc["mesh"] == str(balls) and balls_doc["material"] == "steel"
    assert balls_doc["mass"] == pytest.approx(7850.0 * 1e-6)  # 10 mm cube of steel
    assert together["mass"] == pytest.approx(plate_doc["mass"] + balls_doc["mass"])
    # a file without its own material takes --material
    code, out, _ = cli(
        "mass", str(plate), f"{balls}:steel", "--units", "mm", "--material", "aluminium"
    )
    assert code == 0
    assert "aluminium 2700 kg/m^3" in out and "steel 7850 kg/m^3" in out
    assert "density 2700 kg/m^3;" not in out.splitlines()[0]  # no one density for both
    # ... or none at all: then every file must name its own
    code, out, err = cli("mass", str(plate), f"{balls}:steel", "--units", "mm")
    assert code == 2 and out == "" and f"{plate}: no material" in err
    code, _, err = cli("mass", f"{plate}:cheese", "--units", "mm")
    assert code == 2 and "unknown material `cheese`" in err and "aluminium" in err


def test_mass_reports_every_non_watertight_file(cli, tmp_path):
    good = _plate(tmp_path / "good.stl")
    holes = []
    for name in ("open1.stl", "open2.stl"):
        box = trimesh.creation.box(extents=(10.0, 10.0, 10.0))
        box.update_faces(list(range(2, len(box.faces))))  # two triangles off: a hole
        box.export(tmp_path / name)
        holes.append(tmp_path / name)
    code, out, err = cli(
        "mass", str(holes[0]), str(good), str(holes[1]), "--units", "mm", "--material", "steel"
    )
    assert code == 2
    errors = [line for line in err.splitlines() if line.startswith("kcheck: error:")]
    assert len(errors) == 2, err
    assert "open1.stl" in errors[0] and "open2.stl" in errors[1]
    assert "watertight" in err
    assert str(good) in out and "together" not in out  # the good file is still reported
