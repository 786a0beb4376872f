"""Benchmark of the `pose-error` check.

Run: ``python benchmarks/bench_pose_error.py`` (medians of repeated warm runs). Prints the table
recorded in docs/performance.md, with the machine's load average (the numbers are only
comparable on a quiet machine).

* the whole check's ``run`` on fixtures/kelvin with six error sources plus load and mass
  (36 drawn numbers per sample), 10^3 to 10^5 samples, independent and Sobol draws;
* paired: the skinny product (10^5 x 6) @ (6 x 3) by numpy's matmul (a threaded BLAS call)
  against einsum, which the check uses.

The check on the sample executors (in process, local workers, Dask) is measured, paired with
`tolerances`, by ``python benchmarks/bench_tolerances.py executors``.
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from kcheck_checks.pose_error import PoseError, PoseErrorOptions

from kcheck.body.mass import body_mass_properties
from kcheck.plugin import Inputs
from kcheck.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
KELVIN = ROOT / "fixtures" / "kelvin" / "coupling.kcheck.yaml"
OPTIONS = {
    "point": [0.0, 0.0, 50.0],
    "ball_radius_um": 1.0,
    "ball_position_um": 2.0,
    "seat_position_um": 2.0,
    "seat_angle_urad": 50.0,
    "groups": [{"name": "mill", "couplings": ["socket", "vee"], "position_um": 5.0}],
    "load_percent": 5.0,
    "mass_percent": 2.0,
    "ball_material": "52100",
    "seat_material": "52100",
}


def median_s(fn: Callable[[], object], repeat: int = 3) -> float:
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    scene = load_scene(KELVIN)
    assert scene.body is not None
    mass = body_mass_properties(scene.body, scene.scale)
    print("| samples | random | sobol |")
    print("|---|---|---|")
    for count in (1_000, 10_000, 100_000):
        row = []
        for sampler in ("random", "sobol"):
            opts = PoseErrorOptions.model_validate(OPTIONS | {"samples": count, "sampler": sampler})
            row.append(median_s(lambda o=opts: PoseError().run(Inputs(scene, mass, o))))
        print(f"| {count} | {1e3 * row[0]:.0f} ms | {1e3 * row[1]:.0f} ms |")
    a = np.random.default_rng(0).standard_normal((100_000, 6))
    b = np.random.default_rng(1).standard_normal((6, 3))
    matmul = median_s(lambda: a @ b, 5)
    einsum = median_s(lambda: np.einsum("sk,ak->sa", a, b.T), 5)
    print(f"| (1e5 x 6) @ (6 x 3) | matmul {1e3 * matmul:.1f} ms | einsum {1e3 * einsum:.1f} ms |")


if __name__ == "__main__":
    main()
