"""kcheck against the peer method (Patti & Vogels 2019, :mod:`peer_patti_vogels`): the limiting
coefficient of friction of all six retraction cases of a spatial scene, paired in one run.

Run: ``python benchmarks/bench_peer.py [--count 1000] [--repeat 5]``.

kcheck's side is what the analytical checks run for it: the nondimensional problem
(``problem_for``), the six cases (``analyse_cases``: free twists, both friction systems) and the
exact friction intervals of every case at the design direction (``friction_intervals_many``),
whose ``limiting`` is the limiting coefficient. It computes more than the peer (every interval
of μ, both sliding senses, Painlevé intervals), but the peer's quantity must not cost more.
The peer gets the same scene as arrays (points, normals, the external wrench); building them is
not timed. Scenes: the spatial fixtures with a design direction and the generated spatial
scenes of ``tests/spatial_scenes.py``; loading and mass properties are not timed.

kcheck is timed two ways: one scene at a time (``analyse_cases``, ``friction_intervals_many``),
and the scenes of a chunk in one batch (``--chunk`` scenes: ``analyse_cases_many``,
``friction_intervals_batch``, as a worker given a chunk of scenes can run them; the values are
the same bits, ``tests/kcheck/test_batch.py``).

Printed: per scene set, the median over repeats of the time per scene of each, interleaved
(kcheck, kcheck batched, peer, kcheck, ...) so load changes hit all alike, their ratios to
the peer's, and how many cases agree (where kcheck's limiting coefficient is the jamming
onset the peer computes; elsewhere kcheck's limit is contact loss, which the peer does not
model) with the largest relative difference.
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
sys.path.insert(0, str(ROOT / "benchmarks"))

import peer_patti_vogels as peer  # noqa: E402
from spatial_scenes import write_spatial_scenes  # noqa: E402

from kcheck.analysis.cases import problem_for  # noqa: E402
from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.mechanics.dynamics import analyse_cases, analyse_cases_many  # noqa: E402
from kcheck.mechanics.friction import (  # noqa: E402
    friction_intervals_batch,
    friction_intervals_many,
)
from kcheck.scene import load_scene  # noqa: E402

FIXTURES = [
    "three-groove/coupling.kcheck.yaml",
    *(f"three-groove-beta-{b}/coupling.kcheck.yaml" for b in (15, 25, 35, 45, 55, 65)),
    "block-321/block.kcheck.yaml",
    "kelvin/coupling.kcheck.yaml",
    "tool-changer/tool.kcheck.yaml",
]


def kcheck_limits(scene, mass) -> list[float | None]:
    """kcheck's limiting coefficient of every case at the design direction."""
    problem = problem_for(scene, mass)
    cases = analyse_cases(problem)
    intervals = friction_intervals_many(problem, cases, scene.load.direction)
    return [None if i is None else i.limiting for i in intervals]


def kcheck_limits_batch(chunk: list) -> list[list[float | None]]:
    """:func:`kcheck_limits` of a chunk of ``(scene, mass)`` pairs, in one batch."""
    problems = [problem_for(s, m) for s, m in chunk]
    cases = analyse_cases_many(problems)
    found = friction_intervals_batch(problems, cases, [s.load.direction for s, _ in chunk])
    return [[None if i is None else i.limiting for i in each] for each in found]


def peer_inputs(scene, mass) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points, normals and the external wrench (load, weight, preloads; about the origin)."""
    points = np.array([s.position for s in scene.supports])
    normals = np.array([s.normal for s in scene.supports])
    com = np.asarray(mass.center_of_mass, float)
    forces = [(com, mass.mass * scene.gravity)]
    load = scene.load
    torque = np.zeros(3)
    if load is not None and load.magnitude > 0:
        point = com if load.point is None else load.point
        forces.append((point, load.magnitude * load.direction))
        torque = torque + load.torque
    forces += [(p.point, p.force) for p in scene.preloads]
    f = sum(force for _, force in forces)
    m = sum(np.cross(point, force) for point, force in forces) + torque
    return points, normals, np.concatenate([f, m])


def timed(fn, args_list) -> float:
    """Seconds per call of ``fn(*args)`` over the list."""
    start = time.process_time()
    for args in args_list:
        fn(*args)
    return (time.process_time() - start) / len(args_list)


def compare(name: str, scenes: list, repeat: int, chunk: int) -> None:
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    ours = list(zip(scenes, masses, strict=True))
    chunks = [(ours[i : i + chunk],) for i in range(0, len(ours), chunk)]
    theirs = [peer_inputs(s, m) for s, m in ours]
    batched = [v for (c,) in chunks for v in kcheck_limits_batch(c)]
    agree = total = 0
    worst = 0.0
    for (s, m), args, together in zip(ours, theirs, batched, strict=True):
        mine, other = kcheck_limits(s, m), peer.limiting_friction(*args)
        assert mine == together  # the batch gives the same values
        for a, b in zip(mine, other, strict=True):
            if a is None or not np.isfinite(a) or not np.isfinite(b):
                continue
            total += 1
            rel = abs(a - b) / b
            if rel < 1e-6:
                agree += 1
                worst = max(worst, rel)
    t_ours, t_batch, t_peer = [], [], []
    for _ in range(repeat):
        t_ours.append(timed(kcheck_limits, ours))
        t_batch.append(timed(kcheck_limits_batch, chunks) * len(chunks) / len(ours))
        t_peer.append(timed(peer.limiting_friction, theirs))
    a, c, b = (statistics.median(t) for t in (t_ours, t_batch, t_peer))
    print(
        f"| {name} ({len(scenes)}) | {a * 1e3:.3f} ms | {c * 1e3:.3f} ms | {b * 1e3:.3f} ms | "
        f"{a / b:.2f} | {c / b:.2f} | "
        f"{agree} of {total} finite kcheck limits, largest rel. difference {worst:.1e} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--chunk", type=int, default=100)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    print(
        f"| scenes | kcheck (6 cases) | kcheck, chunks of {args.chunk} batched | peer (6 cases) "
        "| kcheck / peer | batched / peer | agreement |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- |")
    fixtures = [load_scene(ROOT / "fixtures" / f) for f in FIXTURES]
    with_direction = [s for s in fixtures if s.load and s.load.direction is not None]
    compare("fixtures", with_direction, 50, args.chunk)
    with tempfile.TemporaryDirectory() as tmp:
        paths = write_spatial_scenes(Path(tmp), range(args.count))
        compare("generated spatial", [load_scene(p) for p in paths], args.repeat, args.chunk)
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
