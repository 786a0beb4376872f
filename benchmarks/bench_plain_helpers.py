"""Lane mendcert's paired check that folding the written-out plain-float helpers into one each
costs (almost) nothing: this tree against a baseline commit, in the same run.

Run: ``python benchmarks/bench_plain_helpers.py [--baseline 0170cbc] [--rounds 5]``.

Rounds alternate baseline / new, each a fresh process (``benchmarks/paired.py``) timing, in
CPU time per call (``time.process_time``) over many calls:

* ``Frame.for_points`` of 6 points (its plain-float path; the norm now ``norm3``);
* ``row_norms`` of one 3-vector (its plain-float path, now ``norm3``);
* ``statics._planar_generator_rows`` of 4 planar supports (8 rows rounded, now by
  ``numerics.arrays.round3_like_numpy``) and ``cones.planar_cone_holds`` of them;
* ``scene.validate.plain_value_problems`` of a scene-sized tree (one branch per kind now).

Printed: a Markdown table of the medians over rounds (µs per call) and new / baseline.
"""

from __future__ import annotations

import argparse
import os
import statistics
from pathlib import Path

from paired import paired_rounds, run_worker

WORKER = r"""
import json, time
import numpy as np
import kcheck
assert kcheck.__file__.startswith(EXPECT), kcheck.__file__
from kcheck.mechanics.cones import planar_cone_holds
from kcheck.mechanics.kinematics import Frame, row_norms
from kcheck.mechanics.statics import _planar_generator_rows
from kcheck.scene.validate import Problems, plain_value_problems

rng = np.random.default_rng(1)
points = [rng.normal(size=(6, 3)) for _ in range(200)]
vectors = [rng.normal(size=3) for _ in range(200)]
planar = []
for _ in range(200):
    angles = rng.uniform(0, 2 * np.pi, 4)
    p = rng.uniform(-1, 1, (4, 2)).tolist()
    n = np.column_stack([np.cos(angles), np.sin(angles)]).tolist()
    planar.append((p, n, rng.uniform(0.05, 0.5, 4).tolist()))
tree = {
    "supports": [
        {"name": f"s{i}", "point": [1.5, -2.0, 0.25], "normal": [0.0, 0.6, 0.8], "mu": 0.2}
        for i in range(12)
    ],
    "body": {"mesh": "part.stl", "material": "steel", "density": 7850.0},
    "load": {"force": [0.0, 0.0, -9.81], "point": [0.0, 0.0, 0.1]},
    "checks": {"jamming": {"min_margin_deg": 5.0}, "maxwell": {"min_cos": 0.7}},
}


def per_call(fn, items, reps):
    start = time.process_time()
    for _ in range(reps):
        for x in items:
            fn(x)
    return (time.process_time() - start) / (reps * len(items))


def planar_case(case):
    rows = _planar_generator_rows(*case)
    if rows is not None:
        planar_cone_holds(rows, (0.1, 0.2, -1.0), -1e-9, 1e-12)


out = {
    "Frame.for_points (6 points)": per_call(lambda p: Frame.for_points(p, 3, 1.0), points, 50),
    "row_norms (one 3-vector)": per_call(row_norms, vectors, 200),
    "planar generator rows + cone test (4 supports)": per_call(planar_case, planar, 20),
    "plain_value_problems (scene tree)": per_call(
        lambda t: plain_value_problems(t, Problems(TMP, {})), [tree] * 20, 50
    ),
}
print(json.dumps(out))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="0170cbc")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()

    def measure(label: str, tree: Path, tmp: Path) -> dict[str, float]:
        return run_worker(tree, tmp, WORKER, {}, dict(os.environ))

    samples = paired_rounds(args.baseline, args.rounds, measure)
    print(f"| call | baseline ({args.baseline}) | new | new / baseline |")
    print("| --- | --- | --- | --- |")
    for key, new in samples["new"].items():
        old = statistics.median(samples["baseline"][key])
        now = statistics.median(new)
        print(f"| {key} | {old * 1e6:.2f} µs | {now * 1e6:.2f} µs | {now / old:.2f} |")


if __name__ == "__main__":
    main()
