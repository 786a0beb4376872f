"""Same input, same answer (issue 25): a verdict never depends on what ran before, on the
cache, or on how many workers ran it.

Every fixture, the tests' scene variants (unit mix-ups among them: the tool changer's plate or
balls in cm, its coordinates slipped to m, a planar block and a lone-I_zz block declared in m,
three-groove in cm, Kelvin in inches, a repaired mesh, the tests' planar scene and its
coordinates slipped to m) and 200 generated scenes (150 rewrites of the fixtures and 50
designs of today's format from the fuzzer, :mod:`tests.fuzz`) run as one batch of ``kcheck
check --format json`` in four runs that take it the five ways:

==============================  =======================================================
cold cache, ``-j 2``            ``--cache-dir A`` (empty), two workers
warm cache                      ``--cache-dir A`` again, one worker per core (the default)
``--no-cache``, ``-j 2``        ``--no-cache``, two workers
``-j 1``                        ``--cache-dir A`` (warm), one worker
==============================  =======================================================

The four JSON documents must be identical apart from the run-time fields (``runtime_s``):
every verdict, number, warning, note and word. The cache once changed verdicts: it kept no
bounding boxes, so a second run judged a part in the wrong unit by an inertia box and said
nothing (``tests/kcheck/test_cache.py`` has the cache's own tests).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FIXTURES, PLANAR_SCENE

pytestmark = pytest.mark.slow

GENERATED_REWRITES = 150
GENERATED_DESIGNS = 50
SEED = 25


def _variant(root: Path, name: str, fixture: str, edits: list[tuple[str, str]]) -> None:
    folder = root / "variants" / name
    shutil.copytree(FIXTURES / fixture, folder)
    scene = next(folder.glob("*.kcheck.yaml"))
    text = scene.read_text()
    for old, new in edits:
        assert old in text, (name, old)
        text = text.replace(old, new)
    scene.write_text(text)


def _repaired(root: Path) -> None:
    import numpy as np
    import trimesh

    folder = root / "variants" / "repaired-mesh"
    folder.mkdir(parents=True)
    box = trimesh.creation.box(extents=(100, 60, 20))
    keep = [i for i, n in enumerate(box.face_normals) if not np.allclose(n, [1, 0, 0])]
    trimesh.Trimesh(box.vertices, box.faces[keep], process=False).export(folder / "open.stl")
    (folder / "open.kcheck.yaml").write_text(
        "version: 1\nunits: mm\nbody: {mesh: open.stl, material: aluminium, repair: true}\n"
        "supports:\n"
        "  - {name: y1, position: [-30, -30, 0], normal: [0, 1, 0]}\n"
        "  - {name: y2, position: [30, -30, 0], normal: [0, 1, 0]}\n"
        "  - {name: x1, position: [-50, 0, 0], normal: [1, 0, 0]}\n"
        "friction: 0.1\nload: {magnitude: 1, angle: 225}\n"
    )


def corpus(root: Path) -> dict[str, int]:
    """Lay the scenes out under ``root``; how many of each kind."""
    from tests.fuzz.model import materialize
    from tests.fuzz.mutate import valid_case
    from tests.fuzz.v2 import v2_case

    shutil.copytree(FIXTURES, root / "fixtures", ignore=shutil.ignore_patterns("*.py"))
    plate = "{mesh: plate.stl, material: aluminium,"
    balls = "{mesh: balls.stl, material: steel}"
    variants = {
        "tool-changer-plate-in-cm": ("tool-changer", [(plate, plate + " units: cm,")]),
        "tool-changer-balls-in-cm": ("tool-changer", [(balls, balls[:-1] + ", units: cm}")]),
        # docs/from-cad-to-scene.md §8: the meshes in mm, every coordinate slipped to m
        "tool-changer-units-slip": (
            "tool-changer",
            [
                ("units: mm", "units: m"),
                (plate, plate + " units: mm,"),
                (balls, balls[:-1] + ", units: mm}"),
            ],
        ),
        "planar-block-in-m": ("planar-block", [("units: mm", "units: m")]),
        "thesis-block-4-2-in-m": ("thesis-block-4-2", [("units: mm", "units: m")]),
        "three-groove-in-cm": ("three-groove", [("units: mm", "units: cm")]),
        "kelvin-in-in": ("kelvin", [("units: mm", "units: in")]),
    }
    for name, (fixture, edits) in variants.items():
        _variant(root, name, fixture, edits)
    _repaired(root)
    for name, units in (("planar-scene", "mm"), ("planar-scene-in-m", "m")):
        folder = root / "variants" / name
        folder.mkdir(parents=True)
        text = PLANAR_SCENE.replace("units: mm", f"units: {units}")
        (folder / "planar.kcheck.yaml").write_text(text.lstrip())
    for i in range(GENERATED_REWRITES):
        case = valid_case(SEED, i)
        materialize(case, root / "generated" / case.ident)
    for i in range(GENERATED_DESIGNS):
        case = v2_case(SEED, i)
        materialize(case, root / "generated" / case.ident)
    return {
        "fixtures": len(list(FIXTURES.glob("*/*.kcheck.yaml"))),
        "variants": len(variants) + 3,
        "generated": GENERATED_REWRITES + GENERATED_DESIGNS,
    }


MODES: dict[str, tuple[str, ...]] = {
    "cold cache, -j 2": ("--cache-dir", "{cache}", "-j", "2"),
    "warm cache": ("--cache-dir", "{cache}"),
    "--no-cache, -j 2": ("--no-cache", "-j", "2"),
    "-j 1": ("--cache-dir", "{cache}", "-j", "1"),
}
COLD = "cold cache, -j 2"


def _strip(value: Any) -> Any:
    """The document without its run-time fields."""
    if isinstance(value, dict):
        return {k: _strip(v) for k, v in value.items() if k != "runtime_s"}
    if isinstance(value, list):
        return [_strip(v) for v in value]
    return value


def _differences(a: Any, b: Any, where: str = "$") -> list[str]:
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{where}: keys {sorted(a.keys() ^ b.keys())}"] if a.keys() != b.keys() else []
        for k in a.keys() & b.keys():
            out += _differences(a[k], b[k], f"{where}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        out = [f"{where}: {len(a)} items, {len(b)}"] if len(a) != len(b) else []
        for i, (x, y) in enumerate(zip(a, b, strict=False)):
            out += _differences(x, y, f"{where}[{i}]")
        return out
    if a != b or type(a) is not type(b):
        return [f"{where}: {a!r} / {b!r}"]
    return []


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """The four runs. The one-worker run reads the cache the cold run filled, beside the
    others: the test costs about three runs' time on two cores."""
    root = tmp_path_factory.mktemp("same-answer")
    counts = corpus(root / "scenes")
    cache = root / "cache"
    env = {k: v for k, v in os.environ.items() if k != "KCHECK_CACHE_DIR"}

    def start(mode: str) -> subprocess.Popen:
        argv = [a.replace("{cache}", str(cache)) for a in MODES[mode]]
        return subprocess.Popen(
            [sys.executable, "-m", "kcheck", "check", "--format", "json", "--isolated"]
            + ["--color", "never", *argv, "scenes"],
            cwd=root,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )

    out: dict[str, Any] = {"counts": counts, "cache": cache, "docs": {}, "codes": {}}

    def finish(mode: str, proc: subprocess.Popen) -> None:
        stdout, stderr = proc.communicate(timeout=900)
        assert "Traceback" not in stderr, stderr[-3000:]
        out["docs"][mode] = json.loads(stdout)
        out["codes"][mode] = proc.returncode

    finish(COLD, start(COLD))
    out["entries after the cold run"] = len(list(cache.rglob("*.json")))
    one_worker = start("-j 1")
    for mode in ("warm cache", "--no-cache, -j 2"):
        finish(mode, start(mode))
    finish("-j 1", one_worker)
    return out


def test_the_corpus_has_every_fixture_variant_and_200_generated_scenes(runs):
    counts = runs["counts"]
    assert counts["generated"] >= 200
    doc = runs["docs"][COLD]
    assert len(doc["scenes"]) == sum(counts.values())
    by_path = {Path(s["path"]).parent.name: s for s in doc["scenes"]}
    # the unit mix-ups do what they are there for
    codes = {w["code"] for w in by_path["tool-changer-plate-in-cm"]["warnings"]}
    assert "part-size-outlier" in codes
    # every coordinate slipped to m: the supports 30 m off the body are an input error that
    # names the unit the numbers fit (kcheck.analysis.placement)
    slipped = by_path["tool-changer-units-slip"]
    assert slipped["status"] == "error"
    assert "units: mm" in slipped["error"] and "from the body's surface" in slipped["error"]
    assert [w["code"] for w in by_path["repaired-mesh"]["warnings"]] == ["mesh-repaired"]
    # verdicts of every kind occur
    assert {"pass", "fail", "warn"} <= {s["status"] for s in doc["scenes"]}


def test_the_warm_runs_read_the_cache(runs):
    assert runs["entries after the cold run"] > 10
    assert len(list(runs["cache"].rglob("*.json"))) == runs["entries after the cold run"]


@pytest.mark.parametrize("mode", [m for m in MODES if m != COLD])
def test_every_way_gives_the_same_json(runs, mode):
    reference = _strip(runs["docs"][COLD])
    other = _strip(runs["docs"][mode])
    differences = _differences(reference, other)
    if differences:
        scenes = reference["scenes"]
        first = differences[0]
        index = int(first.split("[", 2)[1].split("]")[0]) if first.startswith("$.scenes[") else 0
        where = scenes[index]["path"] if index < len(scenes) else "?"
        pytest.fail(
            f"{mode}: {len(differences)} differences, first in {where}:\n"
            + "\n".join(differences[:20])
        )
    assert runs["codes"][mode] == runs["codes"][COLD]
