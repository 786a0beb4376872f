"""Paired micro-benchmark of the second answer's search alone (issue 24, `jamming`'s "held or
moves"): :func:`kcheck.analysis.held_alternatives.held_alternatives` on the held cases the
`jamming` check hands it, this tree against a baseline commit in the same run.

The held cases come from the recorded reference (``tests/golden/second_answer_reference.json``:
the cases `jamming` found held at the commit it names), so the benchmark times the search
only, on the same cases for both trees, whatever else changed in `jamming`. Rounds alternate
baseline / new, each a fresh process importing its tree (``git archive`` extraction, as in
:mod:`bench_speed`); CPU time (``time.process_time``) per generated spatial scene (every scene
counts, held cases or not, like the check's cost) and per held case.

Run: ``python benchmarks/bench_second_answer.py [--baseline c5f8237] [--count 100]
[--rounds 3] [--set spatial]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

WORKER = r"""
import json, sys, time
from pathlib import Path
import numpy as np
import kcheck
assert kcheck.__file__.startswith(EXPECT), kcheck.__file__
sys.path.append(ROOT)
from tests.record_second_answer_reference import OUT, scene_sets
from kcheck.analysis.held_alternatives import held_alternatives
from kcheck.body.mass import body_mass_properties
from kcheck.scene import load_scene

reference = json.loads(OUT.read_text())
counts = {"spatial": 0, "random-3d": 0, "random-2d": 0}
counts[SET] = COUNT
paths = scene_sets(Path(TMP), counts["spatial"], counts["random-3d"], counts["random-2d"])[SET]
recorded = reference["cases"][SET]
work = []
for path in paths:
    if path.name in recorded:
        scene = load_scene(path)
        mass = body_mass_properties(scene.body, scene.scale)
        work.append((scene, mass, [(r, np.asarray(k)) for r, k, _ in recorded[path.name]]))
held = sum(len(c) for _, _, c in work)
[held_alternatives(*w) for w in work[:3]]  # warm-up
start = time.process_time()
[held_alternatives(*w) for w in work]
spent = time.process_time() - start
print(json.dumps({"scene": spent / len(paths), "held case": spent / held, "held": held}))
"""


def run(tree: Path, tmp: Path, count: int, which: str) -> dict[str, float]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(tree), str(tree / "plugins")])
    folder = Path(tempfile.mkdtemp(dir=tmp))
    header = (
        f"ROOT = {str(ROOT)!r}\nTMP = {str(folder)!r}\nCOUNT = {count}\nSET = {which!r}\n"
        f"EXPECT = {str(tree / 'kcheck')!r}\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", header + WORKER], capture_output=True, text=True, env=env, cwd=folder
    )
    if out.returncode:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--baseline", default="c5f8237")
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--set", default="spatial", choices=["spatial", "random-3d", "random-2d"])
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    samples: dict[str, dict[str, list[float]]] = {"baseline": {}, "new": {}}
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "baseline"
        base.mkdir()
        archive = subprocess.run(
            ["git", "archive", args.baseline], cwd=ROOT, capture_output=True, check=True
        ).stdout
        subprocess.run(["tar", "-x", "-C", str(base)], input=archive, check=True)
        held = 0
        for _ in range(args.rounds):
            for label, tree in (("baseline", base), ("new", ROOT)):
                got = run(tree, Path(tmp), args.count, args.set)
                held = int(got.pop("held"))
                for key, value in got.items():
                    samples[label].setdefault(key, []).append(value)
    print(f"load average after: {os.getloadavg()}")
    print(f"{args.set}: {args.count} scenes, {held} held cases")
    print(f"| per | search, baseline ({args.baseline}) | new | new / baseline |")
    print("| --- | --- | --- | --- |")
    for key in samples["new"]:
        old = statistics.median(samples["baseline"][key])
        new = statistics.median(samples["new"][key])
        print(f"| {key} | {old * 1e3:.2f} ms | {new * 1e3:.2f} ms | {new / old:.2f} |")


if __name__ == "__main__":
    main()
