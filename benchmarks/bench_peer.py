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

Printed: per scene set, the median over repeats of the time per scene of each, interleaved
(kcheck, peer, kcheck, ...) so load changes hit both alike, their ratio, and how many cases
agree (where kcheck's limiting coefficient is the jamming onset the peer computes; elsewhere
kcheck's limit is contact loss, which the peer does not model) with the largest relative
difference.
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
from kcheck.mechanics.dynamics import analyse_cases  # noqa: E402
from kcheck.mechanics.friction import friction_intervals_many  # noqa: E402
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


def compare(name: str, scenes: list, repeat: int) -> None:
    masses = [body_mass_properties(s.body, s.scale) for s in scenes]
    ours = list(zip(scenes, masses, strict=True))
    theirs = [peer_inputs(s, m) for s, m in ours]
    agree = total = 0
    worst = 0.0
    for (s, m), args in zip(ours, theirs, strict=True):
        mine, other = kcheck_limits(s, m), peer.limiting_friction(*args)
        for a, b in zip(mine, other, strict=True):
            if a is None or not np.isfinite(a) or not np.isfinite(b):
                continue
            total += 1
            rel = abs(a - b) / b
            if rel < 1e-6:
                agree += 1
                worst = max(worst, rel)
    t_ours, t_peer = [], []
    for _ in range(repeat):
        t_ours.append(timed(kcheck_limits, ours))
        t_peer.append(timed(peer.limiting_friction, theirs))
    a, b = statistics.median(t_ours), statistics.median(t_peer)
    print(
        f"| {name} ({len(scenes)}) | {a * 1e3:.3f} ms | {b * 1e3:.3f} ms | {a / b:.2f} | "
        f"{agree} of {total} finite kcheck limits, largest rel. difference {worst:.1e} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    print("| scenes | kcheck (6 cases) | peer (6 cases) | kcheck / peer | agreement |")
    print("| --- | --- | --- | --- | --- |")
    fixtures = [load_scene(ROOT / "fixtures" / f) for f in FIXTURES]
    compare("fixtures", [s for s in fixtures if s.load and s.load.direction is not None], 50)
    with tempfile.TemporaryDirectory() as tmp:
        paths = write_spatial_scenes(Path(tmp), range(args.count))
        compare("generated spatial", [load_scene(p) for p in paths], args.repeat)
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
