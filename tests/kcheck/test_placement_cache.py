"""The supports against the body's mesh through the cache: a warm run reads no mesh for them
and gives the cold run's warnings, word for word; a changed support misses; an input error is
never stored; a corrupt entry is recomputed."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest
import trimesh

import kcheck.body.surface
from kcheck.gate.cache import PlacementCache, body_key, placement_key
from kcheck.scene import load_scene

BLOCK_MM = (200.0, 150.0, 85.0)

# The block of tests/kcheck/test_placement.py with its mesh declared in cm: every support
# on a face through the origin, crowded into a corner: a `mesh-units-suspect` warning.
SCENE = """
version: 1
units: mm
body:
  parts:
    - {mesh: block.stl, material: aluminium, units: cm}
supports:
  - {name: x1, position: [0, 75, 42.5], normal: [1, 0, 0]}
  - {name: y1, position: [40, 0, 42.5], normal: [0, 1, 0]}
  - {name: y2, position: [160, 0, 42.5], normal: [0, 1, 0]}
  - {name: z1, position: [30, 30, 0], normal: [0, 0, 1]}
  - {name: z2, position: [170, 30, 0], normal: [0, 0, 1]}
  - {name: z3, position: [100, 130, 0], normal: [0, 0, 1]}
friction: 0.11
gravity: [0, 0, -9.81]
load:
  point: [100, 75, 85]
  magnitude: 50
  direction: [-0.57, -0.82, 0.04]
"""


@pytest.fixture
def scene_file(tmp_path: Path) -> Path:
    box = trimesh.creation.box(extents=BLOCK_MM)
    box.apply_translation(np.asarray(BLOCK_MM) / 2)
    box.export(tmp_path / "block.stl")
    path = tmp_path / "block.kcheck.yaml"
    path.write_text(textwrap.dedent(SCENE).lstrip())
    return path


def _scene_json(cli, path: Path, cache: Path) -> dict:
    code, out, _ = cli(
        "check", str(path), "--format", "json", "--jobs", "1", "--cache-dir", str(cache)
    )
    (scene,) = json.loads(out)["scenes"]
    return scene


def _entries(cache: Path) -> list[Path]:
    return sorted((cache / "placement").rglob("*.json"))


def _no_surface(monkeypatch) -> None:
    def refuse(*args, **kwargs):
        raise AssertionError("the mesh was read for the supports")

    monkeypatch.setattr(kcheck.body.surface, "body_surface", refuse)


def test_a_warm_run_reads_no_mesh_and_gives_the_cold_runs_warnings(
    cli, scene_file, tmp_path, monkeypatch
):
    cache = tmp_path / "cache"
    cold = _scene_json(cli, scene_file, cache)
    assert "mesh-units-suspect" in {w["code"] for w in cold["warnings"]}
    assert len(_entries(cache)) == 1
    _no_surface(monkeypatch)
    warm = _scene_json(cli, scene_file, cache)
    assert warm["warnings"] == cold["warnings"] and warm["status"] == cold["status"]


def test_a_moved_support_misses(scene_file, tmp_path):
    scene = load_scene(scene_file)
    assert scene.body is not None
    body = body_key(scene.body, scene.scale)
    moved = scene_file.with_name("moved.kcheck.yaml")
    moved.write_text(scene_file.read_text().replace("[100, 130, 0]", "[100, 131, 0]"))
    other = load_scene(moved)
    assert placement_key(body, other) != placement_key(body, scene)
    assert placement_key(body, load_scene(scene_file)) == placement_key(body, scene)


def test_an_input_error_is_not_stored(cli, scene_file, tmp_path):
    # a support 30 mm above the block's top: off the body, an input error
    scene_file.write_text(scene_file.read_text().replace("units: cm}", "}"))
    scene_file.write_text(scene_file.read_text().replace("[100, 130, 0]", "[100, 130, 115]"))
    cache = tmp_path / "cache"
    result = _scene_json(cli, scene_file, cache)
    assert result["status"] == "error" and "z3" in result["error"]
    assert _entries(cache) == []


def test_a_corrupt_entry_is_recomputed(cli, scene_file, tmp_path):
    cache = tmp_path / "cache"
    cold = _scene_json(cli, scene_file, cache)
    (entry,) = _entries(cache)
    document = json.loads(entry.read_text())
    document["payload"]["warnings"] = []  # tampered: its checksum no longer matches
    entry.write_text(json.dumps(document))
    key = document["key"]
    assert PlacementCache(cache).get(key) is None
    again = _scene_json(cli, scene_file, cache)
    assert again["warnings"] == cold["warnings"]
    assert PlacementCache(cache).get(key) is not None  # rewritten
