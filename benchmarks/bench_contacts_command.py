"""Timing of the whole ``kcheck contacts base.stl body.stl --units mm`` command (imports,
reading the files, finding, merged-parts finding, the scene) on ``bench_contacts.py``'s
assembly written as binary STL: ``python benchmarks/bench_contacts_command.py [REF]``.

Paired, interleaved in the same run, against the kcheck of git revision REF (default
``6d98969``, before binary STLs were read without trimesh; ``03dc445`` is before the
merged-parts finding was split once and STL vertices merged by kcheck), exported to a
temporary folder and run with the same Python. CPU time is the child's user + system time
(``resource``); both must write the same scene.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from bench_contacts import assembly  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def run(src: Path, folder: Path) -> tuple[float, float, str]:
    """Wall and CPU time of one command run with kcheck from ``src``, and its scene."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "kcheck", "contacts", "base.stl", "body.stl", "--units", "mm"],
        cwd=folder,
        env={**os.environ, "PYTHONPATH": str(src)},
        capture_output=True,
        text=True,
        check=True,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return wall, cpu, done.stdout


def main() -> None:
    ref = sys.argv[1] if len(sys.argv) > 1 else "6d98969"
    with tempfile.TemporaryDirectory() as tmp:
        folder, old = Path(tmp) / "parts", Path(tmp) / "old"
        folder.mkdir()
        old.mkdir()
        base, body = assembly()
        base.export(folder / "base.stl")
        body.export(folder / "body.stl")
        archive = subprocess.run(
            ["git", "archive", ref, "kcheck"], cwd=ROOT, capture_output=True, check=True
        ).stdout
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive, check=True)
        times: dict = {"now": [], "before": []}
        scenes = {}
        for _ in range(3):
            for name, src in (("now", ROOT), ("before", old)):
                wall, cpu, scenes[name] = run(src, folder)
                times[name].append((wall, cpu))
    print(f"491,520 faces per part; the same scene as {ref}: {scenes['now'] == scenes['before']}")
    for name, what in (("now", "kcheck contacts"), ("before", f"kcheck contacts at {ref}")):
        wall = statistics.median(t[0] for t in times[name])
        cpu = statistics.median(t[1] for t in times[name])
        print(f"{what}: {wall:.2f} s wall, {cpu:.2f} s CPU (medians of 3)")
    print(f"load average after: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
