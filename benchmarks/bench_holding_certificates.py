"""The equilibrium questions of ``analyse`` (``friction_may_hold``, ``jams`` against lift-off):
each one's conic programme (clarabel) against the checked certificates of
:mod:`kcheck.mechanics.holding_certificates` in batches, paired in one run.

Run: ``python benchmarks/bench_holding_certificates.py [--count 300] [--repeat 3]``.

The questions are those ``analyse_many`` asks of ``--count`` generated spatial scenes
(``tests/spatial_scenes.py``), gathered once. Printed: per batch size, the median over repeats
of the CPU time per question (``time.process_time``) of the programmes (one by one, as one
scene asks them) and of the certificates (batches of that many), how many the certificates
decide, and that every decided answer is the programme's (asserted).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from spatial_scenes import write_spatial_scenes  # noqa: E402

from kcheck.analysis import analyse_many  # noqa: E402
from kcheck.analysis import cases as cases_module  # noqa: E402
from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.mechanics.holding_certificates import holding_certified  # noqa: E402
from kcheck.mechanics.statics import _solve_conic_anew  # noqa: E402
from kcheck.scene import load_scene  # noqa: E402


def questions(count: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The (columns, wrench, coefficients) of every equilibrium question of the scenes."""
    with tempfile.TemporaryDirectory() as tmp:
        scenes = [load_scene(p) for p in write_spatial_scenes(Path(tmp), range(count))]
    masses = [body_mass_properties(s.body, s.scale) for s in scenes if s.body is not None]
    found: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def gather(*args: list[np.ndarray]) -> list[bool | None]:
        found.extend(zip(*args, strict=True))
        return [None] * len(args[0])

    cases_module.holding_certified = gather  # type: ignore[assignment]
    cases_module.HOLDING_CERTIFICATE_BATCH = 0  # type: ignore[misc]
    analyse_many(scenes, masses)
    return found


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=300)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    asked = questions(args.count)
    columns, wrenches, mus = (list(x) for x in zip(*asked, strict=True))
    answers = [_solve_conic_anew(c, w, m, None) is not None for c, w, m in asked]

    def programmes() -> None:
        for c, w, m in asked:
            _solve_conic_anew(c, w, m, None)

    rows = []
    for size in (6, 12, 18, 24, 100, 600):
        decided = 0
        for i in range(0, len(asked), size):
            got = holding_certified(
                columns[i : i + size], wrenches[i : i + size], mus[i : i + size]
            )
            for g, a in zip(got, answers[i : i + size], strict=True):
                assert g is None or g == a
                decided += g is not None

        def batches(size: int = size) -> None:
            for i in range(0, len(asked), size):
                holding_certified(columns[i : i + size], wrenches[i : i + size], mus[i : i + size])

        times: dict[str, list[float]] = {"programmes": [], "certificates": []}
        for _ in range(args.repeat):
            for name, fn in (("programmes", programmes), ("certificates", batches)):
                start = time.process_time()
                fn()
                times[name].append((time.process_time() - start) / len(asked) * 1e6)
        a, b = (statistics.median(times[k]) for k in ("programmes", "certificates"))
        rows.append((size, a, b, decided))
    print(f"load average after: {os.getloadavg()}")
    print(f"{len(asked)} questions of {args.count} generated spatial scenes, {sum(answers)} hold")
    print("| batch | programmes, one by one | certificates | ratio | decided |")
    print("| --- | --- | --- | --- | --- |")
    for size, a, b, decided in rows:
        print(f"| {size} | {a:.0f} µs | {b:.0f} µs | {b / a:.2f} | {decided} of {len(asked)} |")


if __name__ == "__main__":
    main()
