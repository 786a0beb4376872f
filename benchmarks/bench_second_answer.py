"""Paired micro-benchmark of the second answer's search alone (issue 24, `jamming`'s "held or
moves"): :func:`kcheck.analysis.held_alternatives.held_alternatives` on the held cases the
`jamming` check hands it, this tree against a baseline commit in the same run.

The held cases come from the recorded reference (``tests/golden/second_answer_reference.json``:
the cases `jamming` found held at the commit it names), so the benchmark times the search
only, on the same cases for both trees, whatever else changed in `jamming`. Rounds alternate
baseline / new, each a fresh process importing its tree (``git archive`` extraction,
:mod:`paired`); CPU time (``time.process_time``) per generated spatial scene (every scene
counts, held cases or not, like the check's cost) and per held case.

Run: ``python benchmarks/bench_second_answer.py [--baseline c5f8237] [--count 100]
[--rounds 3] [--set spatial]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

from paired import paired_rounds, print_ratios, run_worker

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
    folder = Path(tempfile.mkdtemp(dir=tmp))
    constants = {"COUNT": count, "SET": which}
    return run_worker(tree, folder, WORKER, constants, dict(os.environ))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--baseline", default="c5f8237")
    parser.add_argument("--count", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--set", default="spatial", choices=["spatial", "random-3d", "random-2d"])
    args = parser.parse_args()
    held = 0

    def measure(label: str, tree: Path, tmp: Path) -> dict[str, float]:
        nonlocal held
        got = run(tree, tmp, args.count, args.set)
        held = int(got.pop("held"))
        return got

    samples = paired_rounds(args.baseline, args.rounds, measure)
    print(f"{args.set}: {args.count} scenes, {held} held cases")
    print_ratios(samples, "per", "search", args.baseline)


if __name__ == "__main__":
    main()
