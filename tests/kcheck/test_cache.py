"""The mass-property cache: hits skip the mesh, anything changed misses, and a corrupt,
tampered or implausible entry is recomputed, never trusted."""

from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

import kcheck.body.mass
from kcheck.gate.cache import FORMAT, MassCache, body_key, body_mass_properties_cached
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
    """Every field of two mass properties identical (bit for bit)."""
    assert dataclasses.fields(a) == dataclasses.fields(b)
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "part_bounds":
            assert len(x) == len(y)
            assert all(np.array_equal(p, q) for p, q in zip(x, y, strict=True))
        elif isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            assert np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


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


# --- issue 25: a result from the cache is the result computed afresh ---------------------------


def _copy(tmp_path: Path, name: str) -> Path:
    shutil.copytree(FIXTURES / name, tmp_path / name)
    return tmp_path / name


def _plate_in_cm(tmp_path: Path) -> Path:
    """The tool changer with its plate declared in cm (a unit mix-up: the plate comes out
    ten times too large, and the balls 13.6 times smaller than it)."""
    scene = _copy(tmp_path, "tool-changer") / "tool.kcheck.yaml"
    text = scene.read_text()
    old = "{mesh: plate.stl, material: aluminium,"
    assert old in text
    scene.write_text(text.replace(old, old + " units: cm,"))
    return scene


def _repaired(tmp_path: Path) -> Path:
    """A 100 mm cube with one face missing, read with `repair: true` (a warning)."""
    import trimesh

    mesh = trimesh.creation.box(extents=(100, 100, 100))
    keep = [i for i, n in enumerate(mesh.face_normals) if not np.allclose(n, [1, 0, 0])]
    trimesh.Trimesh(mesh.vertices, mesh.faces[keep], process=False).export(tmp_path / "open.stl")
    scene = tmp_path / "open.kcheck.yaml"
    scene.write_text(
        "version: 1\nunits: mm\nbody: {mesh: open.stl, material: aluminium, repair: true}\n"
        "supports:\n"
        "  - {name: a, position: [-50, 0, 0], normal: [1, 0, 0]}\n"
        "  - {name: b, position: [50, -50, 0], normal: [0, 1, 0]}\n"
        "  - {name: c, position: [-50, -50, 0], normal: [0, 1, 0]}\n"
        "load: {magnitude: 1, angle: 225}\n"
    )
    return scene


@pytest.mark.parametrize(
    "make", [_plate_in_cm, _repaired], ids=["parts-units-transform", "repaired"]
)
def test_a_hit_is_the_computation_field_for_field(make, computed, tmp_path):
    """Bounds, each part's bounds, the mesh's warnings and notes come back from the cache
    exactly as computed: the sanity warnings judge by them (issue 25: the cache lost the
    boxes, and the tool changer with its plate in cm warned only on the first run)."""
    scene = load_scene(make(tmp_path))
    folder = tmp_path / "cache"
    fresh = body_mass_properties_cached(scene.body, scene.scale, None)
    cold = body_mass_properties_cached(scene.body, scene.scale, folder)
    warm = body_mass_properties_cached(scene.body, scene.scale, folder)
    assert len(computed) == 2  # the warm run read the entry
    _same(fresh, cold)
    _same(fresh, warm)
    assert warm.bounds is not None and len(warm.part_bounds) == len(scene.body.parts)
    if make is _repaired:
        assert [w.code for w in warm.warnings] == ["mesh-repaired"]
        assert warm.warnings[0].field == ("body", "mesh")


def _format_1_entry(mass) -> dict:
    """An entry as kcheck wrote it before the format was versioned (no bounds, no part
    bounds, no warnings), with a valid checksum."""
    from kcheck.gate.cache import _checksum

    payload = {
        "mass": mass.mass,
        "center_of_mass": mass.center_of_mass.tolist(),
        "inertia": mass.inertia.tolist(),
        "source": "mesh",
        "volume": mass.volume,
        "notes": list(mass.notes),
    }
    return {"checksum": _checksum(payload), "payload": payload}


def _without_part_bounds(entry: dict) -> dict:
    """Today's format with a field missing, and a checksum that matches what is left."""
    from kcheck.gate.cache import _checksum

    payload = {k: v for k, v in entry["payload"].items() if k != "part_bounds"}
    return {**entry, "payload": payload, "checksum": _checksum(payload)}


@pytest.mark.parametrize(
    "rewrite",
    [
        lambda entry, key, old: {"key": key, **old},  # format 1 under today's key
        lambda entry, key, old: {**entry, "format": 1},  # today's payload claimed format 1
        lambda entry, key, old: {k: v for k, v in entry.items() if k != "format"},
        lambda entry, key, old: _without_part_bounds(entry),
    ],
    ids=["format-1", "claims-format-1", "no-format", "field-missing"],
)
def test_an_entry_of_another_format_is_recomputed_never_half_read(rewrite, computed, tmp_path):
    scene = load_scene(_plate_in_cm(tmp_path))
    folder = tmp_path / "cache"
    reference = body_mass_properties_cached(scene.body, scene.scale, folder)
    key = body_key(scene.body, scene.scale)
    path = folder / "mass" / key[:2] / f"{key}.json"
    entry = json.loads(path.read_text())
    assert entry["format"] == FORMAT == 2
    path.write_text(json.dumps(rewrite(entry, key, _format_1_entry(reference))))
    assert MassCache(folder).get(key) is None
    again = body_mass_properties_cached(scene.body, scene.scale, folder)
    assert len(computed) == 2  # recomputed, not read
    _same(reference, again)
    assert json.loads(path.read_text())["format"] == FORMAT  # rewritten in today's format


def test_the_key_covers_units_transforms_field_mesh_bytes_and_version(
    computed, tmp_path, monkeypatch
):
    import kcheck.gate.cache as cache

    scene = load_scene(_copy(tmp_path, "tool-changer") / "tool.kcheck.yaml")
    body = scene.body
    key = body_key(body, scene.scale)
    plate, balls = body.parts

    def with_plate(**changes):
        return dataclasses.replace(body, parts=(dataclasses.replace(plate, **changes), balls))

    assert body_key(with_plate(scale=0.01, units="cm"), scene.scale) != key
    assert body_key(with_plate(rotation=None), scene.scale) != key
    assert body_key(with_plate(translation=(0.0, 0.0, 0.001)), scene.scale) != key
    assert body_key(with_plate(field=("body", "parts", 1)), scene.scale) != key
    assert body_key(body, scene.scale) == key  # and the same body, the same key
    with plate.mesh.open("ab") as fh:  # one byte more in the mesh file
        fh.write(b"\0")
    changed = body_key(body, scene.scale)
    assert changed != key
    monkeypatch.setattr(cache, "__version__", "99.0")
    monkeypatch.setattr(cache, "_CODE_FINGERPRINT", None)
    assert body_key(body, scene.scale) != changed


def test_cli_cold_warm_and_without_the_cache_give_one_verdict(cli, tmp_path):
    """The tool changer with its plate in cm: the same warning and, with --strict, the same
    exit code on the first run, the second and without the cache (it was 1, 0, 1)."""
    scene = _plate_in_cm(tmp_path)
    folder = tmp_path / "cache"
    runs = [("--cache-dir", str(folder)), ("--cache-dir", str(folder)), ("--no-cache",)]
    codes, warnings = [], []
    for extra in runs:
        code, out, _ = cli("check", "--format", "json", "--strict", *extra, str(scene))
        codes.append(code)
        warnings.append([w["message"] for w in json.loads(out)["scenes"][0]["warnings"]])
    assert list((folder / "mass").rglob("*.json"))  # the second run read an entry
    assert codes == [1, 1, 1]
    assert warnings[0] == warnings[1] == warnings[2]
    assert any("(balls.stl) is 13.6 times smaller" in w for w in warnings[0]), warnings[0]


def _former_plain(value: object) -> object:
    """``cache._plain`` as it was before its plain-leaf shortcut."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, (list, tuple)):
        return [_former_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _former_plain(v) for k, v in sorted(value.items())}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _former_plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return repr(value)


def test_plain_key_form_as_before() -> None:
    """The keys' plain form (``_plain``, plain leaves by exact type first) is the former one
    on every fixture's supports and body parts and on odd values: cached entries keep their
    keys."""
    from kcheck.gate.cache import _plain

    class Odd(float):
        pass

    values: list[object] = [
        1.5, -0.0, float("nan"), 3, True, None, "t", Odd(2.0), np.float64(1.0), np.int64(2),
        np.array([1.0, 2.0]), Path("a/b"), (1, [2.0, {"k": np.bool_(True)}]), {2: "x", 1: 1.0},
        object, complex(1, 2),
    ]  # fmt: skip
    for scene_file in sorted(FIXTURES.glob("*/*.kcheck.yaml")):
        scene = load_scene(scene_file)
        values.append(list(scene.supports))
        if scene.body is not None:
            values.append(list(scene.body.parts))
    for value in values:
        assert json.dumps(_plain(value), sort_keys=True) == json.dumps(
            _former_plain(value), sort_keys=True
        )


def test_cached_inertia_symmetry_as_allclose() -> None:
    """A cached entry's inertia is trusted when ``np.allclose(I, I.T, rtol=
    CACHED_SYMMETRY_RTOL, atol=0)`` holds (written out in ``_from_payload``): the same
    decision on inertias skewed by 0 to 100 times the tolerance, with zeros and signs."""
    from kcheck.gate.cache import _from_payload, _to_payload
    from kcheck.numerics.thresholds import CACHED_SYMMETRY_RTOL
    from kcheck.result import MassProperties

    rng = np.random.default_rng(29)
    base = _to_payload(MassProperties(1.0, np.zeros(3), np.eye(3), "mesh", 1e-3, (), None, (), ()))
    decided = set()
    for _ in range(3000):
        a = rng.normal(size=(3, 3))
        a = a + a.T
        a[rng.random((3, 3)) < 0.2] = 0.0
        skew = rng.normal(size=(3, 3)) * CACHED_SYMMETRY_RTOL * 10.0 ** rng.uniform(-2, 2)
        inertia = a * (1.0 + skew)
        want = bool(np.allclose(inertia, inertia.T, rtol=CACHED_SYMMETRY_RTOL, atol=0))
        got = _from_payload({**base, "inertia": inertia.tolist()}) is not None
        assert got == want
        decided.add(want)
    assert decided == {True, False}
