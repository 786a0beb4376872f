"""Benchmark of the `tolerances` check and of friction ranges.

Run: ``python benchmarks/bench_tolerances.py`` (medians of repeated warm runs). Prints the
tables recorded in docs/performance.md, with the machine's load average (the numbers are
only comparable on a quiet machine).

* the Monte Carlo core (:func:`kcheck.mechanics.tolerance.sample_margins`) on the three-groove
fixture
  and the planar block, 10^3 to 10^5 samples, and the whole check at 10^4;
* the analytical checks with ``friction: {min, max}`` against one coefficient.
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np
from kcheck_checks.analytical_2d import Analytical2D
from kcheck_checks.analytical_3d import Analytical3D
from kcheck_checks.tolerances import Tolerances, TolerancesOptions

from kcheck.analysis.cases import problem_for
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.tolerance import perturb, sample_margins
from kcheck.plugin import Inputs
from kcheck.scene import Scene, load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = {
    "three-groove": ROOT / "fixtures" / "three-groove" / "coupling.kcheck.yaml",
    "planar-block": ROOT / "fixtures" / "planar-block" / "block.kcheck.yaml",
}


def median_s(fn: Callable[[], object], repeat: int = 5) -> float:
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def with_friction(scene: Scene, text: str, tmp: Path) -> Scene:
    source = scene.path.read_text()
    line = next(ln for ln in source.splitlines() if ln.startswith("friction:"))
    path = tmp / scene.path.name
    path.write_text(source.replace(line, f"friction: {text}"))
    for mesh in scene.path.parent.glob("*.stl"):
        (tmp / mesh.name).write_bytes(mesh.read_bytes())
    return load_scene(path)


def monte_carlo() -> None:
    print("| scene | samples | sample_margins | per sample | whole check |")
    print("|---|---|---|---|---|")
    for name, path in SCENES.items():
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        problem = problem_for(scene, mass)
        design = scene.load.direction[: scene.dim]
        for count in (1_000, 10_000, 100_000):
            layouts = perturb(
                problem,
                position=0.05e-3,
                normal=np.radians(0.5),
                friction_low=problem.friction * 0.5,
                friction_high=problem.friction,
                count=count,
                rng=np.random.default_rng(0),
            )
            seconds = median_s(partial(sample_margins, problem, layouts, design), 3)
            whole = "–"
            if count == 10_000 and scene.tolerances is not None:
                inputs = Inputs(scene, mass, TolerancesOptions(samples=count))
                whole = f"{1e3 * median_s(partial(Tolerances().run, inputs), 3):.0f} ms"
            print(
                f"| {name} | {count:,} | {1e3 * seconds:.0f} ms | {1e6 * seconds / count:.1f} µs "
                f"| {whole} |"
            )


def ranges() -> None:
    import tempfile

    print("| scene | check | one coefficient | range {min, max} |")
    print("|---|---|---|---|")
    for name, path, check, text in (
        ("planar-block", SCENES["planar-block"], Analytical2D(), "{min: 0.05, max: 0.3}"),
        ("three-groove", SCENES["three-groove"], Analytical3D(), "{min: 0.05, max: 0.15}"),
    ):
        scene = load_scene(path)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        with tempfile.TemporaryDirectory() as tmp:
            ranged = with_friction(scene, text, Path(tmp))
            one = median_s(partial(check.run, Inputs(scene, mass, check.options())))
            many = median_s(partial(check.run, Inputs(ranged, mass, check.options())))
        print(f"| {name} | {check.id} | {1e3 * one:.1f} ms | {1e3 * many:.1f} ms |")


if __name__ == "__main__":
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores\n")
    monte_carlo()
    print()
    ranges()
