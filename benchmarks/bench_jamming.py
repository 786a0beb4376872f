"""Benchmark of the jamming check: cost per scene, and the conic solver against pyramid LPs.

Run: ``python benchmarks/bench_jamming.py`` (medians of repeated runs, warm). Prints the tables
recorded in docs/performance.md.

``python benchmarks/bench_jamming.py --paired [--baseline main] [--count 30] [--rounds 3]``:
the jamming check of this tree against a baseline commit in the same run (issue 24), rounds
alternating baseline / new, each a fresh process (:mod:`paired`'s ``git archive``
extraction), CPU per scene on the spatial fixtures with a load and ``--count`` generated
spatial scenes; prints medians and new / baseline, for the whole check and for its parts
(the sphere map, the least holding μ, the sweep-plane arcs; CPU inside the same runs). Both
trees run with one BLAS thread, as ``kcheck`` pins it.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from kcheck_checks.jamming import Jamming, JammingOptions
from paired import FIXTURES, ROOT, SCENE_SETS, paired_rounds, print_ratios, run_worker
from scipy.optimize import linprog

from kcheck.analysis.jamming_cases import analyse_jamming, case_arcs, jam_map, jam_statics
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.least_friction import (
    least_friction,
)
from kcheck.mechanics.statics import (
    edge_wrenches,
    equilibrium_forces,
    friction_edges,
    holds_exactly,
)
from kcheck.plugin import Inputs
from kcheck.scene import load_scene

SCENES = {
    "planar-block": ROOT / "fixtures" / "planar-block" / "block.kcheck.yaml",
    "three-groove": ROOT / "fixtures" / "three-groove" / "coupling.kcheck.yaml",
    "block-321": ROOT / "fixtures" / "block-321" / "block.kcheck.yaml",
}


def median_ms(fn, repeat: int = 7) -> float:
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return 1e3 * statistics.median(times)


def check_cost() -> None:
    print("| scene | pyramid sides | whole check | plane band error | sphere band error |")
    print("|---|---|---|---|---|")
    for name, path in SCENES.items():
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        sides = (8,) if scene.kind == "planar" else (4, 6, 8, 12, 16)
        for m in sides:
            inputs = Inputs(scene, mass, JammingOptions(pyramid_edges=m))
            ms = median_ms(lambda inputs=inputs: Jamming().run(inputs), 5)
            statics, swept, design = jam_statics(scene, mass)
            analysis = analyse_jamming(statics, swept, design, m)
            e1, e2 = scene.sweep.e1[: scene.dim], scene.sweep.e2[: scene.dim]
            plane = max(np.degrees(case_arcs(c, e1, e2).error) for c in analysis.cases)
            sphere = "–" if scene.kind == "planar" else f"{jam_map(analysis, 20000).error_deg:.2f}°"
            label = "exact" if scene.kind == "planar" else str(m)
            print(f"| {name} | {label} | {ms:.1f} ms | {plane:.2g}° | {sphere} |")


def lp_holds(generators: np.ndarray, wrench: np.ndarray) -> bool:
    """Feasibility of ``G^T lambda = -W, lambda >= 0`` with scipy HiGHS."""
    res = linprog(
        np.zeros(len(generators)),
        A_eq=generators.T,
        b_eq=-wrench,
        bounds=[(0, None)] * len(generators),
        method="highs",
    )
    return res.status == 0


def solver_comparison() -> None:
    scene = load_scene(SCENES["three-groove"])
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    statics, _, _ = jam_statics(scene, mass)
    keep = np.arange(1, 6)
    rng = np.random.default_rng(1)
    dirs = rng.normal(size=(40, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    rough = np.ones(6)

    def exact(d: np.ndarray, mu: float) -> bool:
        return holds_exactly(statics, keep, statics.wrench(d), mu * rough)

    reference = [least_friction(lambda mu, d=d: exact(d, mu), 0.3, rtol=1e-9) for d in dirs]
    print("| method | least friction: largest relative error | time per feasibility solve |")
    print("|---|---|---|")
    w = statics.wrench(dirs[0])
    t_exact = median_ms(lambda: equilibrium_forces(statics, keep, w), 21)
    found = [least_friction(lambda mu, d=d: exact(d, mu), 0.3, rtol=1e-6) for d in dirs]
    err = max(abs(f - r) / r for f, r in zip(found, reference, strict=True) if r)
    print(
        f"| clarabel, exact second-order cones | {err:.1e} (bisection to 1e-6) | {t_exact:.2f} ms |"
    )
    for m in (8, 16, 32):
        for pyramid in ("inscribed", "circumscribed"):

            def poly(d: np.ndarray, mu: float, m: int = m, pyramid: str = pyramid) -> bool:
                forces = friction_edges(statics.normals[keep], mu * rough[keep], m, pyramid)
                g = edge_wrenches(statics.points[keep], forces)
                return lp_holds(g, statics.wrench(d))

            g = edge_wrenches(
                statics.points[keep], friction_edges(statics.normals[keep], 0.3 * rough[keep], m)
            )
            t_lp = median_ms(lambda g=g: lp_holds(g, w), 21)
            got = [least_friction(lambda mu, d=d: poly(d, mu), 0.3, rtol=1e-6) for d in dirs]
            err = max(abs(f - r) / r for f, r in zip(got, reference, strict=True) if r)
            print(f"| HiGHS LP, {pyramid} {m}-sided pyramids | {err:.1e} | {t_lp:.2f} ms |")


def import_times() -> None:
    for module in ("clarabel", "scipy.optimize", "scipy.spatial"):
        code = (
            f"import time; t = time.perf_counter(); import {module}; print(time.perf_counter() - t)"
        )
        runs = [
            float(
                subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout
            )
            for _ in range(5)
        ]
        print(f"| import {module} | {1e3 * statistics.median(runs):.0f} ms |")


PAIRED_WORKER = (
    r"""
import json, sys, time
from pathlib import Path
import kcheck
from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs
from kcheck.scene import load_scene
from kcheck_checks.jamming import Jamming
"""
    + SCENE_SETS
    + r"""
out = {}
check = Jamming()
# The parts of issue 24's jamming targets, timed inside the same runs (CPU): the sphere map,
# the least holding mu of every case, the sweep-plane arcs.
import kcheck_checks.jamming as plugin
parts = {"sphere map": "jam_map", "least holding mu": "least_holding_friction",
         "sweep-plane arcs": "case_arcs"}
spent = dict.fromkeys(parts, 0.0)
def timed(label, function):
    def run(*args, **kwargs):
        start = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            spent[label] += time.process_time() - start
    return run
for label, attribute in parts.items():
    setattr(plugin, attribute, timed(label, getattr(plugin, attribute)))
for name, paths in sets.items():
    scenes = [load_scene(p) for p in paths]
    scenes = [s for s in scenes if s.load is not None and s.load.direction is not None]
    inputs = [
        Inputs(s, body_mass_properties(s.body, s.scale),
               check.options(**s.check_options.get(check.id, {})))
        for s in scenes
    ]
    [check.run(i) for i in inputs]  # warm-up (lazy imports, caches)
    spent.update(dict.fromkeys(parts, 0.0))
    start = time.process_time()
    [check.run(i) for i in inputs]
    out[name] = (time.process_time() - start) / len(inputs)
    for label in parts:
        out[f"{name}: {label}"] = spent[label] / len(inputs)
print(json.dumps(out))
"""
)


#: The thread counts kcheck.cli pins (its BLAS_THREAD_VARIABLES; not imported: the cli's
#: imports are not this benchmark's to measure).
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def paired(baseline: str, count: int, rounds: int) -> None:
    """The jamming check of this tree against ``baseline``, alternating fresh processes."""
    import os

    def measure(label: str, tree: Path, tmp: Path) -> dict[str, float]:
        # One BLAS thread, as `kcheck` pins it (kcheck.cli.pin_blas_threads): a second
        # OpenBLAS thread spinning after the lattice's matrix-vector products added about
        # 5 ms of CPU a generated scene that no kcheck run pays.
        env = dict(os.environ)
        for name in BLAS_THREADS:
            env.setdefault(name, "1")
        folder = tmp / label
        folder.mkdir(exist_ok=True)
        constants = {"FIXTURES": FIXTURES, "COUNT": count}
        return run_worker(tree, folder, PAIRED_WORKER, constants, env)

    samples = paired_rounds(baseline, rounds, measure)
    print_ratios(samples, "scenes", "jamming", baseline, digits=1)


if __name__ == "__main__":
    import argparse
    import os

    parser = argparse.ArgumentParser()
    parser.add_argument("--paired", action="store_true")
    parser.add_argument("--baseline", default="main")
    parser.add_argument("--count", type=int, default=30)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    if args.paired:
        paired(args.baseline, args.count, args.rounds)
        raise SystemExit
    print(f"load average {os.getloadavg()[0]:.2f}")
    check_cost()
    print()
    solver_comparison()
    print()
    import_times()
