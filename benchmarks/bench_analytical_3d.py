"""Timings of the spatial analysis: ``python benchmarks/bench_analytical_3d.py``.

Prints the median wall time (``time.perf_counter``) of repeated runs of: all six retracted
cases with exact sweep-plane ranges and limiting friction on one scene; the sphere map (safe
fraction, most robust direction) at 10^4 and 10^5 directions; and the safe-fraction error
estimate against run time as the number of directions grows.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

from kcheck_checks.analytical_3d import direction_caps

from kcheck.analysis import analyse
from kcheck.mass import body_mass_properties
from kcheck.scene import load_scene
from kcheck.sphere import most_robust_direction as most_robust
from kcheck.sphere import safe_fraction

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("three-groove/coupling.kcheck.yaml", "block-321/block.kcheck.yaml")


def median_time(fn: Callable[[], object], repeats: int) -> float:
    """Median wall time (s) of ``repeats`` calls after one warm-up call."""
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    """Print the tables."""
    print(f"{'scene':<38} {'what':<44} {'median':>10}")
    for relative in SCENES:
        scene = load_scene(ROOT / "fixtures" / relative)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        analysis = analyse(scene, mass)
        _, a, c, _, _ = direction_caps(analysis.problem, analysis)
        rows = [
            ("6 cases: outcome, forces, ranges, mu limit", partial(analyse, scene, mass), 50),
            ("safe fraction, 10^4 directions", partial(safe_fraction, a, c, 10_000), 30),
            ("safe fraction, 10^5 directions", partial(safe_fraction, a, c, 100_000), 10),
            ("most robust direction, 10^4 + refine", partial(most_robust, a, c, 10_000), 20),
            ("most robust direction, 10^5 + refine", partial(most_robust, a, c, 100_000), 10),
        ]
        for what, fn, repeats in rows:
            t = median_time(fn, repeats)
            print(f"{scene.name:<38} {what:<44} {1e3 * t:>7.2f} ms")
    print()
    scene = load_scene(ROOT / "fixtures" / SCENES[0])
    assert scene.body is not None
    analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
    _, a, c, _, _ = direction_caps(analysis.problem, analysis)
    reference = safe_fraction(a, c, 4_000_000).fraction
    print(f"safe fraction of {scene.name} (reference: 4e6 directions = {reference:.6f})")
    print(f"{'directions':>10} {'fraction':>10} {'estimate':>10} {'actual err':>11} {'time':>10}")
    for n in (1_000, 10_000, 100_000, 1_000_000):
        result = safe_fraction(a, c, n)
        t = median_time(partial(safe_fraction, a, c, n), 5 if n < 10**6 else 2)
        err = abs(result.fraction - reference)
        row = f"{result.fraction:>10.6f} {result.error:>10.2e} {err:>11.2e}"
        print(f"{n:>10} {row} {1e3 * t:>7.2f} ms")


if __name__ == "__main__":
    main()
