"""Timings of the spatial analysis: ``python benchmarks/bench_analytical_3d.py``.

Prints the median wall time (``time.perf_counter``) of repeated runs of: all six retracted
cases (outcome, forces, friction intervals); the exact safe region (area by Stokes' theorem,
per-case areas, most robust direction, design margin); and the safe share of the sphere, exact
against the Fibonacci lattice at 10^3 .. 10^6 directions: value, error estimate, actual error
(against the exact area) and time. The exact area's own error is shown as the spread of the
area over random rotations of the same caps (pure rounding) next to its estimate.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np
from kcheck_checks.analytical_3d import Analytical3D, Analytical3DOptions, direction_caps

from kcheck.analysis import analyse
from kcheck.body.mass import body_mass_properties
from kcheck.mechanics.caps import region, signed_distance
from kcheck.mechanics.deepest import deepest_point
from kcheck.mechanics.sphere import safe_fraction
from kcheck.plugin import Inputs
from kcheck.scene import load_scene

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


def case_regions(a: np.ndarray, c: np.ndarray, owner: np.ndarray) -> list[object]:
    """The safe region of each case alone."""
    return [region(a[owner == i], c[owner == i]) for i in np.unique(owner)]


def rotation(rng: np.random.Generator) -> np.ndarray:
    """A random rotation matrix."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


def main() -> None:
    """Print the tables."""
    import os

    print(f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'scene':<38} {'what':<48} {'median':>10}")
    for relative in SCENES:
        scene = load_scene(ROOT / "fixtures" / relative)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        analysis = analyse(scene, mass)
        _, a, c, owner, _ = direction_caps(analysis.problem, analysis)
        reg = region(a, c)
        design = analysis.design
        inputs = Inputs(scene, mass, Analytical3DOptions())
        rows = [
            ("whole check (analytical-3d run)", partial(Analytical3D().run, inputs), 30),
            ("6 cases: outcome, forces, friction intervals", partial(analyse, scene, mass), 30),
            (f"exact safe region, {len(a)} caps (area, boundary)", partial(region, a, c), 50),
            ("exact per-case areas (6 regions)", partial(case_regions, a, c, owner), 30),
            ("most robust direction (exact)", partial(deepest_point, reg), 50),
            ("design margin (exact signed distance)", partial(signed_distance, reg, design), 50),
            ("lattice share, 10^4 directions", partial(safe_fraction, a, c, 10_000), 10),
            ("lattice share, 10^5 directions", partial(safe_fraction, a, c, 100_000), 5),
        ]
        for what, fn, repeats in rows:
            t = median_time(fn, repeats)  # type: ignore[arg-type]
            print(f"{scene.name[:38]:<38} {what:<48} {1e3 * t:>7.2f} ms")
    print()
    for relative in SCENES:
        scene = load_scene(ROOT / "fixtures" / relative)
        assert scene.body is not None
        analysis = analyse(scene, body_mass_properties(scene.body, scene.scale))
        _, a, c, _, _ = direction_caps(analysis.problem, analysis)
        exact = region(a, c).fraction
        rng = np.random.default_rng(0)
        spread = max(abs(region(a, c @ rotation(rng).T).fraction - exact) for _ in range(20))
        t_exact = median_time(partial(region, a, c), 50)
        result = Analytical3D().run(
            Inputs(scene, body_mass_properties(scene.body, scene.scale), Analytical3DOptions())
        )
        estimate = result.details["safe_solid_angle_fraction_error"]
        print(f"safe share of {scene.name}: exact {exact:.15f}")
        print(f"{'method':>16} {'share':>18} {'estimate':>10} {'actual err':>11} {'time':>10}")
        print(
            f"{'exact':>16} {exact:>18.15f} {estimate:>10.1e} {spread:>11.1e} "
            f"{1e3 * t_exact:>7.2f} ms"
        )
        for n in (1_000, 10_000, 100_000, 1_000_000):
            lattice = safe_fraction(a, c, n)
            t = median_time(partial(safe_fraction, a, c, n), 5 if n < 10**6 else 2)
            err = abs(lattice.fraction - exact)
            row = f"{lattice.fraction:>18.6f} {lattice.error:>10.1e} {err:>11.1e}"
            print(f"{f'lattice {n:.0e}':>16} {row} {1e3 * t:>7.2f} ms")
        print()


if __name__ == "__main__":
    main()
