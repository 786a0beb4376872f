"""Micro-benchmark of ``statics.equilibria``: a spatial scene's twelve contact-wrench cones.

``python benchmarks/bench_equilibria.py``: CPU per scene of ``equilibria`` for every case of
the spatial fixtures with a load and ``--count`` generated spatial scenes (both pyramids,
twelve cones a three-ball scene), warm, in this process.

``python benchmarks/bench_equilibria.py --paired --baseline c5f8237 [--rounds 5]``: this tree
against a baseline commit, rounds alternating baseline / new, each a fresh process with its
tree first on ``PYTHONPATH`` (``git archive`` extraction); prints medians and new / baseline.

``python benchmarks/bench_equilibria.py --dump FILE``: every cone's rows ``(kind, a, c)``
pickled, to compare two trees' answers bit for bit.
"""

from __future__ import annotations

import os
from pathlib import Path

from paired import FIXTURES, ROOT, SCENE_SETS, paired_rounds, print_ratios, run_worker

WORKER = (
    r"""
import json, pickle, sys, time
from pathlib import Path
import numpy as np
import kcheck
from kcheck.analysis.jamming_cases import jam_statics
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.statics import equilibria
from kcheck.scene import load_scene
"""
    + SCENE_SETS
    + r"""
out, dump = {}, {}
for name, paths in sets.items():
    scenes = [load_scene(p) for p in paths]
    scenes = [s for s in scenes if s.load is not None and s.load.direction is not None]
    statics = [jam_statics(s, body_mass_properties(s.body, s.scale))[0] for s in scenes]
    calls = [
        (st, np.flatnonzero(np.arange(len(st.names)) != r), pyramid)
        for st in statics
        for r in range(len(st.names))
        for pyramid in ("circumscribed", "inscribed")
    ]
    results = [equilibria(st, keep, pyramid=p) for st, keep, p in calls]  # warm-up
    dump[name] = [(e.kind, e.a, e.c) for e in results]
    best = []
    for _ in range(REPEAT):
        start = time.process_time()
        for st, keep, p in calls:
            equilibria(st, keep, pyramid=p)
        best.append((time.process_time() - start) / len(statics))
    out[name] = min(best)
if DUMP:
    with open(DUMP, "wb") as f:
        pickle.dump(dump, f)
print(json.dumps(out))
"""
)


def time_equilibria(
    tree: Path, folder: Path, count: int, repeat: int, dump: str
) -> dict[str, float]:
    """One fresh process timing ``equilibria`` with ``tree`` first on the path."""
    folder.mkdir(parents=True, exist_ok=True)
    constants = {"FIXTURES": FIXTURES, "COUNT": count, "REPEAT": repeat, "DUMP": dump}
    return run_worker(tree, folder, WORKER, constants, dict(os.environ))


def paired(baseline: str, count: int, rounds: int, repeat: int) -> None:
    """``equilibria`` of this tree against ``baseline``, alternating fresh processes."""
    samples = paired_rounds(
        baseline,
        rounds,
        lambda label, tree, tmp: time_equilibria(tree, tmp / label, count, repeat, ""),
    )
    print_ratios(samples, "scenes", "`equilibria` a scene", baseline)


if __name__ == "__main__":
    import argparse
    import tempfile

    parser = argparse.ArgumentParser()
    parser.add_argument("--paired", action="store_true")
    parser.add_argument("--baseline", default="main")
    parser.add_argument("--count", type=int, default=30)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--dump", default="")
    args = parser.parse_args()
    if args.paired:
        paired(args.baseline, args.count, args.rounds, args.repeat)
    else:
        with tempfile.TemporaryDirectory() as tmp:
            dump = str(Path(args.dump).resolve()) if args.dump else ""
            got = time_equilibria(ROOT, Path(tmp), args.count, args.repeat, dump)
        for key, value in got.items():
            print(f"{key}: {value * 1e3:.2f} ms a scene")
