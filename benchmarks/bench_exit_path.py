"""The command line's exit path (lane mendexit): a one-scene ``kcheck check`` to standard
output, to a report file (``-o``: written beside it and renamed since), and to a pipe whose
reader is gone; each interpreter given (a baseline's and the new one's), interleaved, medians.

Run: ``python benchmarks/bench_exit_path.py --python BASE --python NEW [--repeat 15]``
(each a wrapper that runs the interpreter with its tree on ``PYTHONPATH``; see
docs/performance.md). Wall and CPU (user + sys, ``os.wait4``) of fresh processes, started
from a temporary folder without a ``pyproject.toml``.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_gate import ENV, adopt_orphans, children, explicit_scene, reap_orphans


def timed(cmd: list[str], cwd: Path, stdout: int) -> tuple[float, float, int]:
    """Wall s, CPU s (user + sys, kcheck's last worker included: bench_gate.reap_orphans),
    exit code."""
    adopt_orphans()
    before = children()
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, env=ENV, stdout=stdout, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    return wall, reap_orphans(before, usage)[0], os.waitstatus_to_exitcode(status)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--python", action="append")
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    pythons = args.python or [sys.executable]
    with tempfile.TemporaryDirectory() as name:
        tmp = Path(name)
        scene = explicit_scene(tmp)
        check = ["-m", "kcheck", "check", str(scene), "--format", "json"]
        cases = {"stdout": [], "-o report.json": ["-o", str(tmp / "report.json")]}
        samples: dict[tuple[str, str], list[tuple[float, float, int]]] = {}
        for _ in range(args.repeat):
            for python in pythons:
                for case, extra in cases.items():
                    key = (case, python)
                    samples.setdefault(key, []).append(
                        timed([python, *check, *extra], tmp, subprocess.DEVNULL)
                    )
                read, write = os.pipe()
                os.close(read)
                try:
                    sample = timed([python, *check], tmp, write)
                finally:
                    os.close(write)
                samples.setdefault(("closed pipe", python), []).append(sample)
    load = os.getloadavg()[0]
    print(
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; ",
        end="",
    )
    print(f"load average {load:.1f}; {args.repeat} interleaved runs")
    print("| case | interpreter | wall (median) | CPU (median) | exit codes |")
    print("| --- | --- | --- | --- | --- |")
    for (case, python), runs in samples.items():
        wall = statistics.median(r[0] for r in runs)
        cpu = statistics.median(r[1] for r in runs)
        codes = sorted({r[2] for r in runs})
        print(f"| {case} | {python} | {wall:.3f} s | {cpu:.3f} s | {codes} |")


if __name__ == "__main__":
    main()
