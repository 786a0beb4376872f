"""Scene loading: YAML parsing with libyaml's C parser against PyYAML's pure-Python one, and
a whole `load_scene` (validation, coupling expansion), in ms per file.

``python benchmarks/bench_scene_loading.py`` — medians of repeated runs after one warm-up.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

from bench_analytical_3d import median_time

from kcheck.scene import load_scene
from kcheck.scene.yamlio import HAVE_LIBYAML, read_yaml

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures"
SCENES = [
    FIXTURES / "planar-block" / "block.kcheck.yaml",
    FIXTURES / "three-groove" / "coupling.kcheck.yaml",
    FIXTURES / "tool-changer" / "tool.kcheck.yaml",
]


def median_ms(run: Callable[[], object], repeat: int = 200) -> float:
    """Median wall time of ``run`` in ms (``bench_analytical_3d.median_time``)."""
    return 1e3 * median_time(run, repeat)


def main() -> None:
    print(f"libyaml available: {HAVE_LIBYAML}; load average {os.getloadavg()[0]:.2f}")
    print("| scene | C parser | pure Python | load_scene (C) |")
    print("| --- | --- | --- | --- |")
    for path in SCENES:
        c = median_ms(lambda p=path: read_yaml(p, backend="c")) if HAVE_LIBYAML else float("nan")
        py = median_ms(lambda p=path: read_yaml(p, backend="python"))
        full = median_ms(lambda p=path: load_scene(p))
        name = path.relative_to(FIXTURES).as_posix()
        print(f"| {name} ({path.stat().st_size} B) | {c:.2f} ms | {py:.2f} ms | {full:.2f} ms |")


if __name__ == "__main__":
    main()
