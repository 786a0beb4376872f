"""Time per scene of the mechanics checks, their Python/numpy call counts, and the peak memory
of the sphere lattice: ``python benchmarks/bench_mechanics.py [--memory]``.

For each fixture the mass properties are computed once; then each applicable check's ``run`` is
timed (median of repeated warm runs, ``time.perf_counter``) and profiled once with cProfile
(function calls in total and calls into numpy). ``--memory`` runs the sphere lattice at 10^6
and 5·10^6 directions in fresh processes and prints their peak resident memory (ru_maxrss).
"""

from __future__ import annotations

import cProfile
import pstats
import subprocess
import sys
from pathlib import Path

from bench_analytical_3d import median_time

ROOT = Path(__file__).resolve().parents[1]
SCENES = (
    "planar-block/block.kcheck.yaml",
    "thesis-potato/potato.kcheck.yaml",
    "three-groove/coupling.kcheck.yaml",
    "block-321/block.kcheck.yaml",
)


def calls(fn) -> tuple[int, int]:
    """Function calls of one run: in total, and into numpy."""
    profile = cProfile.Profile()
    profile.runcall(fn)
    stats = pstats.Stats(profile)
    total = numpy = 0
    for (filename, _, _), (_, ncalls, *_rest) in stats.stats.items():  # type: ignore[attr-defined]
        total += ncalls
        if "numpy" in filename:
            numpy += ncalls
    return total, numpy


def check_table() -> None:
    """Per scene and check: median time, calls, numpy calls."""
    from kcheck.body.mass import body_mass_properties
    from kcheck.plugin import Inputs, load_checks
    from kcheck.scene import load_scene

    checks = [
        lc.check
        for lc in load_checks()
        if lc.spec.name in ("maxwell", "analytical-2d", "analytical-3d", "graphical-2d")
    ]
    print(f"{'scene':<34} {'check':<14} {'median':>9} {'calls':>8} {'numpy':>8}")
    for relative in SCENES:
        path = ROOT / "fixtures" / relative
        if not path.exists():
            continue
        scene = load_scene(path)
        mass = body_mass_properties(scene.body, scene.scale) if scene.body else None
        for check in checks:
            if check.skip_reason(scene) is not None:
                continue
            options = check.options.model_validate(scene.check_options.get(check.id, {}))
            inputs = Inputs(scene, mass if check.needs_mass_for(scene) else None, options)
            t = median_time(lambda c=check, i=inputs: c.run(i), 20)
            total, numpy = calls(lambda c=check, i=inputs: c.run(i))
            print(f"{scene.name[:34]:<34} {check.id:<14} {1e3 * t:>6.2f} ms {total:>8} {numpy:>8}")


MEMORY_CHILD = """
import resource, sys
import numpy as np
from kcheck.mechanics.sphere import safe_fraction
c = np.random.default_rng(1).normal(size=(36, 3))
a = 0.3 * np.linalg.norm(c, axis=1)
n = int(sys.argv[1])
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
f = safe_fraction(a, c, n)
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(f"{n} {before / 1024:.0f} {after / 1024:.0f}")
"""


def memory_table() -> None:
    """Peak RSS (MiB) of the sphere lattice at 10^6 and 5e6 directions, fresh processes."""
    print(f"{'directions':>10} {'RSS before':>11} {'peak RSS':>9}")
    for n in (10**6, 5 * 10**6):
        out = subprocess.run(
            [sys.executable, "-c", MEMORY_CHILD, str(n)],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.split()
        print(f"{out[0]:>10} {out[1]:>7} MiB {out[2]:>5} MiB")


if __name__ == "__main__":
    import os

    print(f"load average {os.getloadavg()[0]:.2f}")
    check_table()
    if "--memory" in sys.argv:
        memory_table()
