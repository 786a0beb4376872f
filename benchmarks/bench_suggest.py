"""Timings of ``kcheck suggest``'s search: ``python benchmarks/bench_suggest.py``.

Prints, for the three-groove fixture (100 N) and the 3-2-1 block (at 20 N, where a safe
placement exists), the wall time (``time.perf_counter``, median of repeats after a warm-up) of
the whole search — first pass over the candidate points, four local rounds, SLSQP refinement of
the 40 best, limiting friction of the best five — against the number of candidate points and of
directions per point, with one and two processes, and the best margin found. The three-groove
reference is exact: the optimum lies on the axis of symmetry, at the bottom face's centre
(the best direction there from a 10^5-point grid refined with SLSQP). The block's reference is
the best of a large run (20 000 points, 2000 directions). Also: the least-force bisection.
``--paired``: the search without and with its continuous refinement, time and margin.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from bench_analytical_3d import median_time  # the benchmarks' one timer

from kcheck.analysis.candidates import SurfaceSampler
from kcheck.analysis.cases import problem_for
from kcheck.analysis.suggest import (
    caps_at,
    least_force,
    point_caps,
    search,
    with_load,
)
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.deepest import most_robust_direction
from kcheck.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    """Print the tables."""
    tg = load_scene(ROOT / "fixtures/three-groove/coupling.kcheck.yaml")
    tg_mass = body_mass_properties(tg.body, tg.scale)
    caps = point_caps(problem_for(tg, tg_mass))
    at_axis = caps_at(caps, np.array([[0.0, 0.0, 6.5e-3]]))[0]
    tg_ref = float(np.degrees(most_robust_direction(caps.a, at_axis, 100_000)[1]))

    block = load_scene(ROOT / "fixtures/block-321/block.kcheck.yaml")
    block_mass = body_mass_properties(block.body, block.scale)
    block20 = with_load(block, block.load.point, block.load.direction, 20.0)
    big = search(block20, block_mass, SurfaceSampler(block20, 0), 20_000, directions=2000)
    block_ref = float(np.degrees(big.best[0].margin))
    print(f"references: three-groove {tg_ref:.4f}°, block-321 at 20 N {block_ref:.4f}°")
    print(
        f"{'scene':<14} {'points':>7} {'dirs':>5} {'jobs':>4} {'median':>9} "
        f"{'best':>9} {'error':>8}"
    )
    rows = [
        (tg, tg_mass, tg_ref, "three-groove"),
        (block20, block_mass, block_ref, "block-321"),
    ]
    for scene, mass, ref, name in rows:
        for points, directions, jobs, repeats in (
            (500, 200, 1, 5),
            (2000, 200, 1, 3),
            (2000, 500, 1, 3),
            (2000, 500, 2, 3),
            (2000, 2000, 1, 3),
            (8000, 500, 1, 2),
            (8000, 500, 2, 2),
        ):

            def run(scene=scene, mass=mass, points=points, directions=directions, jobs=jobs):
                sampler = SurfaceSampler(scene, 0)
                return search(scene, mass, sampler, points, directions=directions, jobs=jobs)

            t = median_time(run, repeats)
            found = run()
            best = float(np.degrees(found.best[0].margin))  # type: ignore[attr-defined]
            print(
                f"{name:<14} {points:>7} {directions:>5} {jobs:>4} {1e3 * t:>7.0f} ms "
                f"{best:>8.4f}° {ref - best:>7.4f}°"
            )
    block10 = with_load(block, block.load.point, block.load.direction, 10.0)
    found = search(block10, block_mass, SurfaceSampler(block10, 0), 2000, directions=500)
    pts = found.points[np.argsort(-found.margins)[:200]]
    t = median_time(lambda: least_force(block10, block_mass, pts, start=10.0), 3)
    least = least_force(block10, block_mass, pts, start=10.0)
    print(f"least force of block-321 from 10 N (200 points, 500 dirs): {least:.3g} N, {t:.2f} s")


def paired() -> None:
    """Old against new: the sampled search alone (``polish=0``, as before the continuous
    refinement) and with the three best points refined by Nelder–Mead (``polish=3``, the
    default), on the same points: median wall time and best margin (2000 points, 500
    directions, seed 0)."""
    print(f"{'scene':<18} {'search':<22} {'median':>9} {'best':>9}")
    for name, path, magnitude in (
        ("three-groove", "fixtures/three-groove/coupling.kcheck.yaml", None),
        ("block-321 (50 N)", "fixtures/block-321/block.kcheck.yaml", None),
        ("block-321 (20 N)", "fixtures/block-321/block.kcheck.yaml", 20.0),
        ("planar-block", "fixtures/planar-block/block.kcheck.yaml", None),
    ):
        scene = load_scene(ROOT / path)
        mass = body_mass_properties(scene.body, scene.scale)
        if magnitude is not None:
            scene = with_load(scene, scene.load.point, scene.load.direction, magnitude)
        for label, polish in (("sampled (old)", 0), ("sampled + Nelder-Mead", 3)):

            def run(scene=scene, mass=mass, polish=polish):
                return search(scene, mass, SurfaceSampler(scene, 0), 2000, polish=polish)

            t = median_time(run, 3)
            best = float(np.degrees(run().best[0].margin))
            print(f"{name:<18} {label:<22} {t:>7.2f} s {best:>8.4f}°")


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--paired"]:
        paired()
    else:
        main()
