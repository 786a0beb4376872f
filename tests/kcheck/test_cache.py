"""The mass-property cache: hits skip the mesh, anything changed misses, and a corrupt,
tampered or implausible entry is recomputed, never trusted."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

import kcheck.body.mass
from kcheck.gate.cache import MassCache, body_key, body_mass_properties_cached
from kcheck.scene import load_scene
from tests.conftest import FIXTURES


@pytest.fixture
def scene(tmp_path: Path):
    """The planar-block fixture (a real STL) copied where the test may change it."""
    folder = tmp_path / "block"
    shutil.copytree(FIXTURES / "planar-block", folder)
    return load_scene(folder / "block.kcheck.yaml")


@pytest.fixture
def computed(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Counts the real computations (cache misses)."""
    calls: list[int] = []
    real = kcheck.body.mass.body_mass_properties

    def counting(body, scale, max_mesh_bytes=None):
        calls.append(1)
        return real(body, scale, max_mesh_bytes)

    monkeypatch.setattr(kcheck.body.mass, "body_mass_properties", counting)
    return calls


def _same(a, b) -> None:
    assert a.mass == b.mass and a.volume == b.volume and a.notes == b.notes
    assert np.array_equal(a.center_of_mass, b.center_of_mass)
    assert np.array_equal(a.inertia, b.inertia)


def test_second_run_is_a_hit_with_identical_values(scene, computed, tmp_path):
    folder = tmp_path / "cache"
    first = body_mass_properties_cached(scene.body, scene.scale, folder)
    second = body_mass_properties_cached(scene.body, scene.scale, folder)
    assert len(computed) == 1
    _same(first, second)
    assert (folder / "CACHEDIR.TAG").read_text().startswith("Signature: 8a477f597d28d172789f")
    assert (folder / ".gitignore").read_text().endswith("*\n")


def _entry(folder: Path, scene) -> Path:
    key = body_key(scene.body, scene.scale)
    return folder / "mass" / key[:2] / f"{key}.json"


def _tamper(path: Path, change) -> None:
    entry = json.loads(path.read_text())
    change(entry)
    path.write_text(json.dumps(entry))


@pytest.mark.parametrize(
    "damage",
    [
        lambda p: p.write_text("{not json"),
        lambda p: p.write_bytes(b"\x00\xff" * 10),
        lambda p: p.write_text("{}"),
        # a changed number without a matching checksum
        lambda p: _tamper(p, lambda e: e["payload"].update(mass=123.0)),
        # a matching checksum but an impossible body (negative mass)
        lambda p: _tamper(
            p,
            lambda e: (
                e["payload"].update(mass=-1.0),
                e.update(
                    checksum=__import__("kcheck.gate.cache").gate.cache._checksum(e["payload"])
                ),
            ),
        ),
        # another entry's content filed under this key
        lambda p: _tamper(p, lambda e: e.update(key="0" * 64)),
    ],
)
def test_corrupt_or_tampered_entries_are_rebuilt(scene, computed, tmp_path, damage):
    folder = tmp_path / "cache"
    reference = body_mass_properties_cached(scene.body, scene.scale, folder)
    entry = _entry(folder, scene)
    damage(entry)
    again = body_mass_properties_cached(scene.body, scene.scale, folder)
    assert len(computed) == 2  # recomputed, not read
    _same(reference, again)
    assert MassCache(folder).get(body_key(scene.body, scene.scale)) is not None  # rewritten


def test_a_changed_mesh_or_density_misses(scene, computed, tmp_path):
    import dataclasses

    folder = tmp_path / "cache"
    body_mass_properties_cached(scene.body, scene.scale, folder)
    heavier = dataclasses.replace(
        scene.body, parts=(dataclasses.replace(scene.body.parts[0], density=8000.0),)
    )
    assert body_key(heavier, scene.scale) != body_key(scene.body, scene.scale)
    assert body_key(scene.body, 1.0) != body_key(scene.body, scene.scale)
    steel = body_mass_properties_cached(heavier, scene.scale, folder)
    assert len(computed) == 2
    import trimesh

    mesh = scene.body.parts[0].mesh
    trimesh.creation.box(extents=(100.0, 60.0, 40.0)).export(mesh)  # the mesh changes on disk
    taller = body_mass_properties_cached(heavier, scene.scale, folder)
    assert len(computed) == 3
    assert taller.mass == pytest.approx(2 * steel.mass, rel=1e-6)  # twice the height


def test_explicit_mass_and_no_folder_bypass_the_cache(scene, computed, tmp_path):
    body_mass_properties_cached(scene.body, scene.scale, None)
    body_mass_properties_cached(scene.body, scene.scale, None)
    assert len(computed) == 2 and not (tmp_path / "cache").exists()


def test_cli_cache_in_the_user_cache_folder_and_no_cache(cli, tmp_path, monkeypatch):
    # One default, with or without a configuration file: the user cache folder (platformdirs;
    # XDG_CACHE_HOME on Linux), never a folder beside the configuration (issue 23).
    project = tmp_path / "project"
    shutil.copytree(FIXTURES / "planar-block", project / "block")
    (project / "kcheck.toml").write_text("jobs = 1\n")
    monkeypatch.chdir(project)
    monkeypatch.delenv("KCHECK_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cli("check", "--no-cache")[0] == 0
    assert not (tmp_path / "xdg").exists()
    assert cli("check")[0] == 0
    entries = list((tmp_path / "xdg" / "kcheck" / "mass").rglob("*.json"))
    assert len(entries) == 1 and not (project / ".kcheck_cache").exists()
