"""Cost of the `hertz` check: ``python benchmarks/bench_hertz.py``.

Median wall time (``time.perf_counter``, after a warm-up) of the check's ``run`` on a
three-vee coupling (six contacts, spring preloads, a disturbing load) and a Kelvin coupling,
and of the Hertz solve alone for many contacts at once (elliptical, B/A from 1 to 100).
The scenes are built as the tests build them (tests/couplings.py), so run from the project's
root.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench_analytical_3d import median_time  # noqa: E402 (the benchmarks' one timer)
from kcheck_checks.hertz import Hertz  # noqa: E402
from kcheck_checks.hertz_materials import HertzOptions  # noqa: E402

from kcheck.mechanics.hertz import contact_modulus, hertz  # noqa: E402
from kcheck.plugin import Inputs  # noqa: E402
from kcheck.scene import Preload  # noqa: E402
from tests.couplings import coupling_scene, kelvin, three_vee, with_preloads  # noqa: E402


def main() -> None:
    """Print the table."""
    folder = Path(tempfile.mkdtemp())
    options = HertzOptions(disturbing_force=[5.0, 0.0, -20.0], error_point=[0.0, 0.0, 30.0])
    for name, contacts in (
        ("three-vee", three_vee(0.05, 6e-3, 45.0)),
        ("kelvin", kelvin(0.05, 6e-3, 35.0)),
    ):
        scene = coupling_scene(folder, contacts)
        centres = {s.geometry.coupling: s.geometry.ball_center for s in scene.supports}
        scene = with_preloads(
            scene, [Preload(n, c, np.array([0.0, 0.0, -100.0])) for n, c in centres.items()]
        )
        inputs = Inputs(scene, None, options)
        t = median_time(lambda inputs=inputs: Hertz().run(inputs), 200)
        print(f"hertz check, {name:<10} (6 contacts): {1e3 * t:6.2f} ms")
    modulus = contact_modulus(210e9, 0.3, 210e9, 0.3)
    for n in (6, 1000, 100_000):
        ratio = np.geomspace(1.0, 100.0, n)
        t = median_time(
            lambda n=n, ratio=ratio: hertz(np.full(n, 100.0), 50.0, 50.0 * ratio, modulus), 20
        )
        print(f"Hertz solve, {n:>7} elliptical contacts: {1e3 * t:8.2f} ms")


if __name__ == "__main__":
    main()
