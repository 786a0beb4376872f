"""Benchmark of ``kcheck study``: throughput and memory of a Monte Carlo study of a spatial
fixture (the Maxwell three-vee, `analytical-3d` only), and Dask's scaling from 1 to 2 workers.

Run: ``python benchmarks/bench_study.py [--variants N] [--jobs J] [--dask N]``. The issue asks
for 100,000 variants in at most 10 minutes with memory flat (< 500 MB) while the table grows;
run with ``--variants 100000`` for the real figure; fewer variants give a rate to extrapolate
from (say so when quoting it). Memory is the proportional set size (PSS) of the kcheck
process and its worker processes together, sampled every 0.2 s from /proc (Linux), and
reported at each quarter of the run, so a table growing in memory would show. Prints the
machine's load average: the machine is shared, the numbers are upper bounds.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "fixtures" / "maxwell-three-vee" / "coupling.kcheck.yaml"

STUDY = """\
version: 1
scene: {scene}
design: {{type: monte-carlo, samples: {n}, seed: 1}}
parameters:
  - {{name: half_angle, path: couplings.*.groove.half_angle, range: [35, 55], unit: deg}}
  - {{name: mu, path: friction, distribution: {{type: truncated-normal, mean: 0.15, sd: 0.05,
     min: 0.02, max: 0.4}}}}
  - {{name: load_x, path: load.point.0, distribution: {{type: normal, mean: 0, sd: 3}}, unit: mm}}
checks: [analytical-3d]
chunk: {chunk}
"""


def _pss_kb(pid: int) -> int:
    """Proportional set size of a process, kB: pages shared by forked workers count once
    over all of them (RSS would count them in every worker)."""
    try:
        with open(f"/proc/{pid}/smaps_rollup") as f:
            for line in f:
                if line.startswith("Pss:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def _tree(pid: int) -> list[int]:
    """A process and its descendants (from /proc)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            children.setdefault(int(fields[1]), []).append(int(entry))
        except (OSError, IndexError, ValueError):
            continue
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo += children.get(p, [])
    return out


def _cpu_s(pid: int) -> float:
    """User and system CPU seconds of one process so far (0 when it is gone)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return 0.0


def _tree_rss_mb(pid: int) -> float:
    """Memory of a process and its descendants, MB: the sum of their PSS (from /proc)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            children.setdefault(int(fields[1]), []).append(int(entry))
        except (OSError, IndexError, ValueError):
            continue
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        total += _pss_kb(p)
        todo += children.get(p, [])
    return total / 1024


def _children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(n: int, executor: list[str], chunk: int, folder: Path) -> tuple[float, list[float], float]:
    """Wall time of one study, the tree's memory at each quarter of the variants, and the
    CPU seconds of kcheck and every worker it waited for (independent of the machine's
    load, unlike the wall time)."""
    cpu = _children_cpu_s()
    study = folder / f"bench-{n}.kcheck-study.yaml"
    study.write_text(STUDY.format(scene=SCENE, n=n, chunk=chunk), encoding="utf-8")
    out = folder / f"bench-{n}-{'-'.join(executor) or 'serial'}.parquet"
    parts = out.with_name(out.name + ".parts")
    chunks = -(-n // chunk)
    start = time.perf_counter()
    proc = subprocess.Popen(
        [sys.executable, "-m", "kcheck", "study", str(study), "-o", str(out), *executor],
        stdout=subprocess.DEVNULL,
    )
    peaks = [0.0, 0.0, 0.0, 0.0]
    # CPU seconds of every process of the tree, the last sample of each: Dask's workers are
    # not waited for by kcheck, so RUSAGE_CHILDREN misses them.
    seen: dict[int, float] = {}
    reported = 0
    started = False  # the parts' folder appears at the start and goes once joined
    while proc.poll() is None:
        started = started or parts.exists()
        done = len(list(parts.glob("chunk-*"))) if parts.exists() else chunks if started else 0
        quarter = min(3, 4 * done // max(chunks, 1))
        peaks[quarter] = max(peaks[quarter], _tree_rss_mb(proc.pid))
        for p in _tree(proc.pid):
            seen[p] = max(seen.get(p, 0.0), _cpu_s(p))
        if quarter > reported:  # progress, so that a run cut short still says something
            reported = quarter
            print(
                f"  {done}/{chunks} chunks after {time.perf_counter() - start:.0f} s, CPU "
                f"{sum(seen.values()):.0f} s, memory {peaks[quarter - 1]:.0f} MB, load "
                f"{os.getloadavg()[0]:.1f}",
                flush=True,
            )
        time.sleep(0.2)
    assert proc.returncode == 0, proc.returncode
    wall = time.perf_counter() - start
    waited = _children_cpu_s() - cpu
    # the processes kcheck waited for are in `waited`; Dask's workers only in the samples
    return wall, peaks, max(waited, sum(seen.values()))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--variants", type=int, default=2000)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--chunk", type=int, default=64)
    ap.add_argument("--dask", type=int, default=0, help="variants for the Dask 1-vs-2 run")
    ap.add_argument("--rounds", type=int, default=1, help="alternations of the Dask run")
    ap.add_argument("--skip-local", action="store_true", help="only the Dask run")
    args = ap.parse_args()
    print(f"load average before: {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        if not args.skip_local:
            wall, peaks, cpu = run(args.variants, ["-j", str(args.jobs)], args.chunk, folder)
            rate = args.variants / wall
            print(
                f"{args.variants} variants, -j {args.jobs}: {wall:.1f} s, {rate:.1f} variants/s, "
                f"{1000 * wall / args.variants:.2f} ms per variant; 100,000 would take "
                f"{100_000 / rate / 60:.1f} min at this rate"
            )
            per = cpu / args.variants
            print(
                f"CPU time {cpu:.1f} s = {1000 * per:.1f} ms per variant (start-up included): on "
                f"{os.cpu_count()} idle cores 100,000 would take about "
                f"{100_000 * per / (os.cpu_count() or 1) / 60:.1f} min"
            )
            print(
                "memory (PSS) of kcheck and its workers by quarter of the run (MB): "
                + ", ".join(f"{p:.0f}" for p in peaks)
            )
        if args.dask:
            # paired: 1 and 2 workers alternate, `--rounds` times, so a change in the
            # machine's load falls on both
            walls: dict[int, list[float]] = {1: [], 2: []}
            cpus: dict[int, list[float]] = {1: [], 2: []}
            for _ in range(args.rounds):
                for workers in (1, 2):
                    w, _, c = run(args.dask, ["--dask-local", str(workers)], args.chunk, folder)
                    walls[workers].append(w)
                    cpus[workers].append(c)
                    print(
                        f"Dask LocalCluster, {workers} worker(s): {args.dask} variants in "
                        f"{w:.1f} s ({args.dask / w:.1f} variants/s), CPU {c:.1f} s "
                        f"({c / w:.2f} cores busy on average), load {os.getloadavg()[0]:.1f}"
                    )
            w1, w2 = (sum(walls[k]) for k in (1, 2))
            c1, c2 = (sum(cpus[k]) for k in (1, 2))
            print(f"throughput 2 workers / 1 worker (wall): {w1 / w2:.2f}x")
            # each round's pair (1 worker, then 2, back to back) shares the machine's load
            ratios = sorted(a / b for a, b in zip(walls[1], walls[2], strict=True))
            print(
                f"paired rounds, 1-worker wall / 2-worker wall: "
                f"{', '.join(f'{r:.2f}' for r in ratios)}; median {statistics.median(ratios):.2f}x"
            )
            print(
                f"CPU per variant 2 workers / 1 worker: {c2 / c1:.2f} (1.00: no Dask overhead "
                f"from the second worker); cores busy {c1 / w1:.2f} (1 worker), {c2 / w2:.2f} "
                f"(2 workers): on 2 idle cores the 2-worker throughput would be about "
                f"{2 * c1 / c2:.2f}x"
            )
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
