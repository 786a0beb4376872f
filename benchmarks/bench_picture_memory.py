"""Peak resident memory of a worker drawing pictures, with and without recycling:
``python benchmarks/bench_picture_memory.py [--scenes N] [--jobs J] [--fixtures GLOB]
[--baseline-scenes M]``.

N scenes (copies of the fixtures, in turn: 2D and 3D, meshes and explicit mass properties)
are checked with ``--plots`` and ``--html`` in one ``kcheck check`` run, twice, paired in the
same invocation: with workers recycled past ``kcheck.gate.pool.RECYCLE_RSS_BYTES`` (the fix)
and with that threshold set to None (before it). Each run is a fresh process; its workers'
peak resident memory is ``ru_maxrss`` of its waited-for children (the largest worker's peak),
the parent's its own ``ru_maxrss``. The two runs' JSON reports must agree (apart from run
times): recycling changes no answer. Run it at low priority (``nice``) on a shared machine.

``--fixtures planar-block`` copies only the fixtures whose folder matches the glob (cheap
planar scenes make 1000 scenes affordable on a shared machine); ``--baseline-scenes M`` runs
the never-recycled baseline on the first M scenes only (0: none), its growth per scene being
what the long recycled run is bounded against; the JSON answers are then compared on those M.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Run in a fresh interpreter: patch the threshold (argv[1]: MiB, or "none"), check, and
#: print the peaks (KiB on Linux) as JSON on stderr's last line.
RUNNER = """
import json, resource, sys
from kcheck.gate import pool
pool.RECYCLE_RSS_BYTES = None if sys.argv[1] == "none" else int(sys.argv[1]) * 2**20
from kcheck.cli import main
code = main(sys.argv[2:])
getattr(pool, "reap_exited", lambda: None)()  # the last workers, not waited for by main
children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
parent = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"code": int(code), "worker_kib": children, "parent_kib": parent}),
      file=sys.stderr)
"""


def make_scenes(folder: Path, n: int, pattern: str = "*") -> None:
    """``n`` scene folders, copies of the fixtures (folders matching ``pattern``) in turn."""
    fixtures = sorted(p.parent for p in (ROOT / "fixtures").glob(f"{pattern}/*.kcheck.yaml"))
    if not fixtures:
        raise SystemExit(f"no fixture folder matches {pattern!r}")
    for i in range(n):
        shutil.copytree(
            fixtures[i % len(fixtures)], folder / f"{i:04d}-{fixtures[i % len(fixtures)].name}"
        )


def run(scenes: Path, work: Path, threshold: str, jobs: int) -> dict[str, float]:
    """One ``kcheck check`` of ``scenes`` with pictures; its peaks (MiB), time and report."""
    report = work / f"report-{threshold}.json"
    args = [
        "check", str(scenes), "--plots", str(work / f"plots-{threshold}"),
        "--html", str(work / f"page-{threshold}.html"), "--format", "json",
        "--output", str(report), "--jobs", str(jobs), "--cache-dir", str(work / "cache"), "-q",
    ]  # fmt: skip
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-c", RUNNER, threshold, *args], capture_output=True, text=True
    )
    wall = time.perf_counter() - start
    try:
        peaks = json.loads(proc.stderr.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        raise SystemExit(f"kcheck failed: {proc.stderr[-2000:]}") from None
    return {
        "worker": peaks["worker_kib"] / 1024,
        "parent": peaks["parent_kib"] / 1024,
        "wall": wall,
        "code": peaks["code"],
        "report": str(report),
    }


#: What differs between two runs by design: run times, and the picture files' folder.
VARYING = {"runtime_s", "elapsed_s", "plots"}


def first_difference(a: object, b: object, where: str = "$") -> str | None:
    """Where two JSON values first differ (None: equal)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            found = first_difference(a.get(key), b.get(key), f"{where}.{key}")
            if found:
                return found
        return None
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            found = first_difference(x, y, f"{where}[{i}]")
            if found:
                return found
        return None
    return None if a == b else f"{where}: {str(a)[:200]} / {str(b)[:200]}"


def answers(path: str) -> object:
    """A JSON report without what differs by design (:data:`VARYING`)."""

    def strip(value: object) -> object:
        if isinstance(value, dict):
            return {k: strip(v) for k, v in value.items() if k not in VARYING}
        if isinstance(value, list):
            return [strip(v) for v in value]
        return value

    return strip(json.loads(Path(path).read_text(encoding="utf-8")))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=200, help="number of scenes (default 200)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    parser.add_argument("--fixtures", default="*", help="glob of fixture folders (default *)")
    parser.add_argument(
        "--baseline-scenes",
        type=int,
        default=None,
        help="scenes of the never-recycled baseline (default: as many; 0: no baseline)",
    )
    args = parser.parse_args()
    from kcheck.gate.pool import RECYCLE_RSS_BYTES

    fixed = str(RECYCLE_RSS_BYTES // 2**20)
    print(
        f"{datetime.date.today()}; {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores; Python {platform.python_version()}; load average "
        f"{os.getloadavg()[0]:.2f}; {args.scenes} scenes, --jobs {args.jobs}, "
        f"--plots and --html; fixtures {args.fixtures}; recycling threshold {fixed} MiB"
    )
    base_n = args.scenes if args.baseline_scenes is None else args.baseline_scenes
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        scenes = work / "scenes"
        scenes.mkdir()
        make_scenes(scenes, args.scenes, args.fixtures)
        # The mass-property cache warmed once, so both runs do the same work.
        subprocess.run(
            [sys.executable, "-m", "kcheck", "check", str(scenes), "-q", "--cache-dir",
             str(work / "cache"), "--jobs", str(args.jobs)],
            capture_output=True,
        )  # fmt: skip
        rows = [("recycled (the fix)", args.scenes, run(scenes, work, fixed, args.jobs))]
        difference = None
        if base_n:
            few = scenes
            if base_n != args.scenes:
                few = work / "baseline-scenes"
                few.mkdir()
                make_scenes(few, base_n, args.fixtures)
            rows.append(("never recycled (before)", base_n, run(few, work, "none", args.jobs)))
            if base_n == args.scenes:
                difference = first_difference(
                    answers(str(rows[0][2]["report"])), answers(str(rows[1][2]["report"]))
                )
    print("| workers | scenes | peak RSS of a worker | parent's peak RSS | wall | exit |")
    print("| --- | ---: | --- | --- | --- | --- |")
    for name, n, r in rows:
        print(
            f"| {name} | {n} | {r['worker']:.0f} MiB | {r['parent']:.0f} MiB | {r['wall']:.0f} s "
            f"| {r['code']} |"
        )
    if len(rows) == 1 or base_n != args.scenes:
        print("same JSON answers in both runs: not compared (different scene counts)")
        return
    print(f"same JSON answers in both runs: {difference is None}")
    if difference is not None:
        raise SystemExit(f"the answers differ at {difference}")


if __name__ == "__main__":
    main()
