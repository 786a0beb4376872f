"""Profile of a worker's cold chunk (issue 24, the cold-cache row): N spatial scenes
(:func:`bench_gate.make_spatial`, each with its own plate mesh) through the gate's own
per-chunk function :func:`kcheck.gate.runner.check_files` with an empty cache folder, after
the imports and one scene are warm (as in a worker past its first scene).

Run: ``python benchmarks/profile_cold_chunk.py [N] [cold|warm|noprof]`` (default 100, cold):
prints the chunk's CPU time per scene and cProfile's tables (cumulative and own time); ``warm``
fills the cache first, ``noprof`` times without the profiler.
"""

from __future__ import annotations

import cProfile
import pstats
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_gate import make_spatial  # noqa: E402

from kcheck.gate.runner import Settings, check_files  # noqa: E402
from kcheck.plugin import load_checks  # noqa: E402


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    mode = sys.argv[2] if len(sys.argv) > 2 else "cold"
    tmp = Path(tempfile.mkdtemp())
    make_spatial(tmp / "scenes", n + 2)
    files = sorted((tmp / "scenes").glob("*/coupling.kcheck.yaml"))
    checks = load_checks()
    check_files(files[:2], checks, Settings(cache_dir=tmp / "warm-up"))  # imports warm
    settings = Settings(cache_dir=tmp / "cache")
    if mode == "warm":
        check_files(files[2:], checks, settings)
    profile = cProfile.Profile()
    start = time.process_time()
    if mode == "noprof":
        check_files(files[2:], checks, settings)
    else:
        profile.enable()
        check_files(files[2:], checks, settings)
        profile.disable()
    cpu = time.process_time() - start
    print(f"{mode}: {n} scenes, {cpu:.2f} s CPU, {cpu / n * 1e3:.1f} ms a scene", flush=True)
    if mode != "noprof":
        stats = pstats.Stats(profile)
        stats.sort_stats("cumulative").print_stats(45)
        stats.sort_stats("tottime").print_stats(30)


if __name__ == "__main__":
    main()
