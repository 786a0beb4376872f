"""Record the reference of the second answer's search (issue 24, lane unique2): the held cases
the `jamming` check hands to :func:`kcheck.analysis.held_alternatives.held_alternatives` on
generated scenes and the fixtures, with what the search answered, into
``tests/golden/second_answer_reference.json``. Recorded once, before the search was made
faster, at the commit named in the file; ``tests/kcheck/test_second_answer_reference.py``
recomputes the search on the same cases and compares.

Scenes: the speed work's generated spatial scenes (:mod:`spatial_scenes`, ``0 .. spatial-1``),
the `reseat` agreement's random spatial and planar scenes (:mod:`tests.plugins.reseat_scenes`,
seed 26, one dimension at a time) and the fixtures with a body.

Run: ``python tests/record_second_answer_reference.py [--spatial 300] [--random 100]
[--planar 100]``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT))

OUT = HERE / "golden" / "second_answer_reference.json"


def random_scenes(folder: Path, count: int, dim: int, seed: int = 26) -> list[Path]:
    """``count`` seated random scenes of dimension ``dim`` (tests.plugins.reseat_scenes)."""
    from tests.plugins.reseat_scenes import random_scene

    rng = np.random.default_rng(seed)
    paths: list[Path] = []
    index = 0
    while len(paths) < count:
        index += 1
        path = random_scene(rng, folder, index, dim)
        if path is not None:
            paths.append(path)
    return paths


def scene_sets(folder: Path, spatial: int, random: int, planar: int) -> dict[str, list[Path]]:
    """The scene files of each set, written into ``folder``."""
    from spatial_scenes import write_spatial_scenes

    (folder / "random3").mkdir()
    (folder / "random2").mkdir()
    fixtures = sorted((ROOT / "fixtures").glob("*/*.kcheck.yaml"))
    return {
        "spatial": write_spatial_scenes(folder / "spatial", range(spatial)),
        "random-3d": random_scenes(folder / "random3", random, 3),
        "random-2d": random_scenes(folder / "random2", planar, 2),
        "fixtures": fixtures,
    }


def held_cases(path: Path) -> list[tuple[int, list[int], list[str] | None]]:
    """The held cases `jamming` passes to the search on one scene, ``(retracted, kept,
    answer)``; empty without a body."""
    import kcheck_checks.jamming as jamming
    from kcheck_checks.jamming import Jamming, JammingOptions

    from kcheck.body.mass import body_mass_properties
    from kcheck.plugin import Inputs
    from kcheck.scene import load_scene

    try:
        scene = load_scene(path)
    except Exception:  # noqa: BLE001 - a fixture that is not a plain scene file
        return []
    if scene.body is None or scene.load is None and not np.any(scene.gravity):
        return []
    mass = body_mass_properties(scene.body, scene.scale)
    seen: list[tuple[int, list[int], list[str] | None]] = []
    search = jamming.held_alternatives

    def record(scene, mass, cases):  # type: ignore[no-untyped-def]
        found = search(scene, mass, cases)
        seen.extend((int(r), [int(j) for j in kept], found[r]) for r, kept in cases)
        return found

    jamming.held_alternatives = record
    try:
        Jamming().run(Inputs(scene, mass, JammingOptions()))
    finally:
        jamming.held_alternatives = search
    return seen


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--spatial", type=int, default=300)
    parser.add_argument("--random", type=int, default=100)
    parser.add_argument("--planar", type=int, default=100)
    args = parser.parse_args()
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=HERE
    ).stdout.strip()
    out: dict[str, dict[str, list]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, paths in scene_sets(Path(tmp), args.spatial, args.random, args.planar).items():
            out[name] = {}
            for path in paths:
                cases = held_cases(path)
                if cases:
                    key = str(path.relative_to(ROOT)) if name == "fixtures" else path.name
                    out[name][key] = [list(c) for c in cases]
    counts = {
        "spatial": args.spatial,
        "random-3d": args.random,
        "random-2d": args.planar,
    }
    # One scene a line: diffs stay readable.
    sets = ",\n".join(
        f"  {json.dumps(name)}: {{\n"
        + ",\n".join(f"   {json.dumps(k)}: {json.dumps(v)}" for k, v in sorted(scenes.items()))
        + "\n  }"
        for name, scenes in out.items()
    )
    text = f'{{"commit": "{commit}", "counts": {json.dumps(counts)},\n "cases": {{\n{sets}\n }}\n}}'
    json.loads(text)
    OUT.write_text(text + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
