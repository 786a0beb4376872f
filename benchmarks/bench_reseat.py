"""Cost of the `reseat` check: ``python benchmarks/bench_reseat.py`` (needs the `sim` extra).

One retraction case, 1 s simulated (0.5 s retract + 0.5 s return, plus the 0.1 s settle), at
the default time step 1e-4 s, CPU time (``time.process_time``, median of 5 after a warm-up)
of :func:`kcheck.analysis.reseat.simulate`, paired with the `analytical-2d` check's whole run
on the same scene (every case at the instant of retraction). Then the whole `reseat` check
(every case, at the time step and at half of it). Also one case at 1 s simulated with MuJoCo's
noslip pass on (10 iterations), and one first-motion run, the check's own and the agreement
test's (first_motion_settings: 50 ms phase, 0.5 ms contacts, 0.05 ms step, noslip, no
return) paired with the agreement run it replaced (2 ms contacts, no noslip, with the
return). Scenes: the Appendix A block (planar, 3 supports) and the Maxwell three-vee
(spatial, 6 supports). Run from the project's root.

``python benchmarks/bench_reseat.py back-off``: the cost of moving a backing-off support at
every step (``retraction_time_ms``; Python sets its position before each step of the back-off)
against the jump, paired and interleaved: one case at the defaults with the longest back-off a
0.5 s phase allows (250 ms), and one first-motion run (first_motion_settings, 0.05 ms step)
with a 200 ms back-off.
"""

from __future__ import annotations

import dataclasses
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from kcheck_checks.analytical_2d import Analytical2D  # noqa: E402
from kcheck_checks.analytical_3d import Analytical3D  # noqa: E402
from kcheck_checks.reseat import Reseat, ReseatOptions, settings_of  # noqa: E402

from kcheck.analysis.reseat import first_motion_settings, simulate  # noqa: E402
from kcheck.body.mass import body_mass_properties  # noqa: E402
from kcheck.plugin import Inputs  # noqa: E402
from kcheck.scene import load_scene  # noqa: E402

SCENES = (
    ("thesis-appendix-a", "block.kcheck.yaml", Analytical2D),
    ("maxwell-three-vee", "coupling.kcheck.yaml", Analytical3D),
)


def cpu_time(work: Callable[[], object], repeats: int) -> float:
    """Median CPU seconds of ``work`` after one warm-up call."""
    work()
    times = []
    for _ in range(repeats):
        start = time.process_time()
        work()
        times.append(time.process_time() - start)
    return statistics.median(times)


def main() -> None:
    """Print the table rows (docs/performance.md)."""
    settings = settings_of(ReseatOptions())
    noslip = dataclasses.replace(settings, noslip_iterations=10)
    first = first_motion_settings(settings)  # the check's own first-motion run
    before = dataclasses.replace(settings, duration=0.05)  # the agreement test's run before
    for folder, name, analytical in SCENES:
        scene = load_scene(ROOT / "fixtures" / folder / name)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        mu = scene.friction_range("kinetic")[1]
        one = cpu_time(lambda s=scene, m=mass, f=mu: simulate(s, m, 0, f, settings), 5)
        base = cpu_time(lambda s=scene, m=mass, a=analytical: a().run(Inputs(s, m, a.options())), 5)
        whole = cpu_time(lambda s=scene, m=mass: Reseat().run(Inputs(s, m, ReseatOptions())), 1)
        slip = cpu_time(lambda s=scene, m=mass, f=mu: simulate(s, m, 0, f, noslip), 5)
        fm = cpu_time(lambda s=scene, m=mass, f=mu: simulate(s, m, 0, f, first, returns=False), 5)
        old = cpu_time(lambda s=scene, m=mass, f=mu: simulate(s, m, 0, f, before), 5)
        k = len(scene.supports)
        print(
            f"| {folder} | {k} | {1e3 * one:.0f} ms | {1e3 * slip:.0f} ms | "
            f"{1e3 * fm:.1f} ms (before: {1e3 * old:.1f} ms) | "
            f"{1e3 * base:.1f} ms ({analytical.id}, all {k} cases) | {whole:.2f} s |"
        )


def paired(
    one: Callable[[], object], other: Callable[[], object], repeats: int
) -> tuple[float, float]:
    """Median CPU seconds of ``one`` and ``other``, interleaved, after one warm-up of each."""
    one(), other()
    a, b = [], []
    for _ in range(repeats):
        for work, times in ((one, a), (other, b)):
            start = time.process_time()
            work()
            times.append(time.process_time() - start)
    return statistics.median(a), statistics.median(b)


def back_off() -> None:
    """Print the back-off rows (docs/performance.md): jump, back-off, ratio."""
    settings = settings_of(ReseatOptions())
    runs = (
        ("1 s simulated, 250 ms back-off", settings, 0.25, True),
        ("first motion, 200 ms back-off", first_motion_settings(settings), 0.2, False),
    )
    for folder, name, _ in SCENES:
        scene = load_scene(ROOT / "fixtures" / folder / name)
        assert scene.body is not None
        mass = body_mass_properties(scene.body, scene.scale)
        mu = scene.friction_range("kinetic")[1]
        for what, jump, seconds, returns in runs:
            slow = dataclasses.replace(jump, retraction_time=seconds)
            if not returns:  # the first-motion run's window opens when the back-off ends
                slow = first_motion_settings(
                    dataclasses.replace(settings, retraction_time=seconds, duration=2 * seconds)
                )
                jump = dataclasses.replace(slow, retraction_time=0.0)
            a, b = paired(
                lambda s=scene, m=mass, f=mu, j=jump, r=returns: simulate(s, m, 0, f, j, returns=r),
                lambda s=scene, m=mass, f=mu, w=slow, r=returns: simulate(s, m, 0, f, w, returns=r),
                5,
            )
            print(f"| {folder} | {what} | {1e3 * a:.0f} ms | {1e3 * b:.0f} ms | {b / a:.2f} |")


if __name__ == "__main__":
    back_off() if sys.argv[1:] == ["back-off"] else main()
