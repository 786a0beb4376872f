"""``analyse`` (the six retraction cases of a spatial scene: outcome, forces, friction
intervals, safe ranges) one scene at a time against ``analyse_many`` on chunks of scenes (the
cases' algebra of a chunk in one batch of numpy calls), paired in one run.

Run: ``python benchmarks/bench_analyse_batch.py [--count 300] [--chunk 100] [--repeat 3]``.

Scenes: the generated spatial scenes of ``tests/spatial_scenes.py``; loading and mass
properties are not timed. Printed: the median over repeats of the CPU time per scene
(``time.process_time``) of each, interleaved, and their ratio. The results are the same
bits (asserted here, and in ``tests/kcheck/test_batch.py``).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from spatial_scenes import write_spatial_scenes  # noqa: E402

from kcheck.analysis import analyse, analyse_many  # noqa: E402
from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.scene import load_scene  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=300)
    parser.add_argument("--chunk", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as tmp:
        scenes = [load_scene(p) for p in write_spatial_scenes(Path(tmp), range(args.count))]
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    pairs = list(zip(scenes, masses, strict=True))
    chunks = [pairs[i : i + args.chunk] for i in range(0, len(pairs), args.chunk)]

    def one() -> list:
        return [analyse(s, m) for s, m in pairs]

    def batched() -> list:
        return [a for c in chunks for a in analyse_many([s for s, _ in c], [m for _, m in c])]

    assert [a.results for a in one()] == [a.results for a in batched()]
    times: dict[str, list[float]] = {"one": [], "batched": []}
    for _ in range(args.repeat):
        for name, fn in (("one", one), ("batched", batched)):
            start = time.process_time()
            fn()
            times[name].append((time.process_time() - start) / len(pairs))
    a, b = (statistics.median(times[k]) for k in ("one", "batched"))
    print(f"load average after: {os.getloadavg()}")
    print(f"| scenes | `analyse`, one at a time | `analyse_many`, chunks of {args.chunk} | ratio |")
    print("| --- | --- | --- | --- |")
    print(
        f"| generated spatial ({len(pairs)}) | {a * 1e3:.2f} ms | {b * 1e3:.2f} ms | {b / a:.2f} |"
    )


if __name__ == "__main__":
    main()
