"""Issue 24's paired benchmark: this tree against a baseline commit, in the same run.

Run: ``python benchmarks/bench_speed.py [--baseline f0391ad] [--count 50] [--rounds 5]
[--what analyse,analyse_many]``.

The baseline commit is extracted (``git archive``) into a temporary folder and imported from
there (its ``kcheck`` and ``plugins`` first on ``sys.path``); this tree likewise from
its own folder. Rounds alternate baseline / new, each a fresh process measuring, per scene and in
CPU time (``time.process_time``, less disturbed than wall time by other jobs on a shared
machine), with mass properties computed beforehand and not timed:

* ``analyse``: the six retraction cases (outcome, forces, friction intervals, safe ranges);
* ``analyse_many``: the same for the whole set of scenes in one batch;
* ``limiting friction``: the problem, the six cases and their friction intervals (what
  ``benchmarks/bench_peer.py`` pairs with Patti & Vogels' method);
* ``analytical-3d`` and ``jamming``: each check's ``run``;

on the spatial fixtures with a load and on ``--count`` generated spatial scenes
(``tests/spatial_scenes.py``). Printed: medians over rounds of the mean time per scene, and
new / baseline.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from paired import FIXTURES, SCENE_SETS, medians, paired_rounds, run_worker

WORKER = (
    r"""
import json, sys, time
from pathlib import Path
import kcheck
from kcheck.analysis import analyse, analyse_many
from kcheck.analysis.cases import problem_for
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.dynamics import analyse_cases
from kcheck.mechanics.friction import friction_intervals_many
from kcheck.plugin import Inputs
from kcheck.scene import load_scene
from kcheck_checks.analytical_3d import Analytical3D
from kcheck_checks.jamming import Jamming
"""
    + SCENE_SETS
    + r"""
out = {}
for name, paths in sets.items():
    scenes = [load_scene(p) for p in paths]
    scenes = [s for s in scenes if s.load is not None and s.load.direction is not None]
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    def limiting(s, m):
        p = problem_for(s, m)
        return friction_intervals_many(p, analyse_cases(p), s.load.direction)
    checks = {}
    for check in (Analytical3D(), Jamming()):
        checks[check.id] = (check, [
            Inputs(s, m, check.options(**s.check_options.get(check.id, {})))
            for s, m in zip(scenes, masses)
        ])
    def run_check(name):
        check, inputs = checks[name]
        return [check.run(i) for i in inputs]
    runs = {
        "analyse": lambda: [analyse(s, m) for s, m in zip(scenes, masses)],
        "analyse_many": lambda: analyse_many(scenes, masses),
        "limiting friction": lambda: [limiting(s, m) for s, m in zip(scenes, masses)],
        "analytical-3d": lambda: run_check("analytical-3d"),
        "jamming": lambda: run_check("jamming"),
    }
    for what, fn in runs.items():
        if WHAT and what not in WHAT:
            continue
        fn()  # warm-up (lazy imports, caches)
        start = time.process_time()
        fn()
        out[f"{name}|{what}"] = (time.process_time() - start) / len(scenes)
print(json.dumps(out))
"""
)


def measure(tree: Path, count: int, tmp: Path, what: list[str]) -> dict[str, float]:
    """One fresh process: mean CPU seconds per scene of each measurement."""
    tmp.mkdir(exist_ok=True)
    constants = {"FIXTURES": FIXTURES, "COUNT": count, "WHAT": what}
    return run_worker(tree, tmp, WORKER, constants, dict(os.environ))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--baseline", default="f0391ad")
    parser.add_argument("--count", type=int, default=50)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument(
        "--what",
        default="",
        help="comma-separated subset of: analyse, analyse_many, limiting friction, "
        "analytical-3d, jamming (default: all)",
    )
    args = parser.parse_args()
    what = [w.strip() for w in args.what.split(",") if w.strip()]
    samples = paired_rounds(
        args.baseline,
        args.rounds,
        lambda label, tree, tmp: measure(tree, args.count, tmp / label, what),
    )
    print(f"| scenes | what | baseline ({args.baseline}) | new | new / baseline |")
    print("| --- | --- | --- | --- | --- |")
    for key, old, new in medians(samples):
        scenes, part = key.split("|")
        print(f"| {scenes} | {part} | {old * 1e3:.2f} ms | {new * 1e3:.2f} ms | {new / old:.2f} |")


if __name__ == "__main__":
    main()
