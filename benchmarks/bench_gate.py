"""kcheck as a CI gate: start-up time and batches, as a user runs it (a fresh process each).

Run: ``python benchmarks/bench_gate.py [--sizes 10,100,1000] [--kinds planar,spatial]
[--jobs 1,2] [--repeat 7] [--skip-batches] [--skip-startup]``.
Prints markdown tables (results in docs/performance.md):

1. start-up, paired in the same run with ``python -c "import numpy"`` and ``python -c pass``
   (alternating, medians): ``kcheck check`` on one planar scene with explicit mass properties,
   and on one with a small mesh (cold and warm mass-property cache), ``--format json``;
2. batches of N generated scenes, ``--format json --output``: planar scenes each with its own
   small box mesh, and spatial three-groove scenes each with its own (slightly scaled) copy of
   the fixture's top plate (four bodies, 8 k faces); cold and warm cache, 1 and 2 jobs.
   ``spatial`` scenes are the fixture without its ``tolerances:`` entry (the workload issue 8
   set its target on, before the tolerances check existed); ``spatial-tolerances`` keep it,
   so the ``tolerances`` check's Monte Carlo (10^4 samples per scene) runs too.

kcheck runs without ``PYTHONDONTWRITEBYTECODE`` (dropped from the environment if set), so its
own modules load from their ``.pyc`` files as in any installed copy; the warm-up run writes
them.

Wall time and CPU time (user + system of kcheck and its workers) are measured with
``os.wait4``; the peak resident memory is the largest of kcheck's processes. The machine's
load average is printed with the tables: on a shared machine the numbers are upper bounds.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "fixtures"
KCHECK = [sys.executable, "-m", "kcheck"]
#: kcheck's environment: as a user's, with bytecode caches (an environment that forbids
#: writing them would make every run compile kcheck's ~70 modules: +150-200 ms).
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}

PLANAR = """\
version: 1
name: planar block {i}
units: mm
body:
  {body}
supports:
  - {{name: y1, position: [{a}, 0, 0], normal: [0, 1, 0]}}
  - {{name: y2, position: [80, 0, 0], normal: [0, 1, 0]}}
  - {{name: x1, position: [0, 30, 0], normal: [1, 0, 0]}}
friction: 0.1
load:
  magnitude: 1
  angle: {angle}
"""


def adopt_orphans() -> bool:
    """Make this process the reaper of its descendants' orphans (Linux): kcheck's last worker
    ends by itself after the run, not waited for (kcheck.gate.pool), so its CPU is counted
    only by whoever reaps it. False where that cannot be had."""
    global _ADOPTING
    if _ADOPTING is None:
        try:
            import ctypes

            pr_set_child_subreaper = 36
            _ADOPTING = ctypes.CDLL(None, use_errno=True).prctl(pr_set_child_subreaper, 1) == 0
        except (OSError, AttributeError):
            _ADOPTING = False
    return _ADOPTING


_ADOPTING: bool | None = None


def children() -> set[int]:
    """This process's children (Linux ``/proc``; empty elsewhere)."""
    try:
        text = Path(f"/proc/self/task/{os.getpid()}/children").read_text()
    except OSError:
        return set()
    return {int(pid) for pid in text.split()}


def reap_orphans(before: set[int], usage: resource.struct_rusage) -> tuple[float, int]:
    """CPU s and peak RSS (KiB) of a finished process (``usage``, from ``os.wait4``) with the
    orphans it left that this process adopted (:func:`adopt_orphans`; ``before``: this
    process's children before it started), each waited for as it ends."""
    cpu, rss = usage.ru_utime + usage.ru_stime, usage.ru_maxrss
    for pid in children() - before:
        _, _, left = os.wait4(pid, 0)
        cpu, rss = cpu + left.ru_utime + left.ru_stime, max(rss, left.ru_maxrss)
    return cpu, rss


def run(cmd: list[str], env: dict[str, str] | None = None) -> tuple[float, float, float, int]:
    """Wall s (until the process ends), CPU s (user + sys of the process and every
    descendant, those it left to end by themselves included), peak RSS MiB, exit code."""
    adopt_orphans()
    before = children()
    start = time.perf_counter()
    proc = subprocess.Popen(
        cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env or dict(ENV)
    )
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    # wait4 reports the process with its waited-for descendants (kcheck's workers): CPU
    # summed, ru_maxrss the largest single process. Descendants it did not wait for are this
    # process's children now (orphans adopted): their CPU is added as they end.
    cpu, rss = reap_orphans(before, usage)
    return wall, cpu, rss / 1024, proc.returncode


def medians(samples: list[tuple[float, float, float, int]]) -> tuple[float, float, float]:
    return (
        statistics.median(s[0] for s in samples),
        statistics.median(s[1] for s in samples),
        max(s[2] for s in samples),
    )


def explicit_scene(tmp: Path) -> Path:
    """A planar scene with explicit mass properties (no mesh)."""
    scene = tmp / "explicit.kcheck.yaml"
    body = "mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001"
    scene.write_text(PLANAR.format(i=0, a=20, angle=225, body=body))
    return scene


def startup(tmp: Path, repeat: int) -> None:
    explicit = explicit_scene(tmp)
    mesh_dir = tmp / "mesh"
    shutil.copytree(FIXTURES / "planar-block", mesh_dir)
    mesh_scene = mesh_dir / "block.kcheck.yaml"
    cache = tmp / "startup-cache"
    env = {**ENV, "KCHECK_CACHE_DIR": str(cache)}
    cases = {
        "python -c pass": [sys.executable, "-c", "pass"],
        'python -c "import numpy"': [sys.executable, "-c", "import numpy"],
        "kcheck check (explicit mass, planar)": [
            *KCHECK,
            "check",
            str(explicit),
            "--format",
            "json",
        ],
        "kcheck check (small mesh, cold cache)": [
            *KCHECK,
            "check",
            str(mesh_scene),
            "--format",
            "json",
            "--no-cache",
        ],  # fmt: skip
        "kcheck check (small mesh, warm cache)": [
            *KCHECK,
            "check",
            str(mesh_scene),
            "--format",
            "json",
        ],  # fmt: skip
        "kcheck check --jobs 1 (explicit mass)": [
            *KCHECK,
            "check",
            str(explicit),
            "--format",
            "json",
            "--jobs",
            "1",
        ],  # fmt: skip
    }
    run(cases["kcheck check (small mesh, warm cache)"], env)  # fills the cache
    samples: dict[str, list[tuple[float, float, float, int]]] = {k: [] for k in cases}
    for _ in range(repeat):  # interleaved, so load changes hit every case alike
        for name, cmd in cases.items():
            samples[name].append(run(cmd, env))
    numpy_wall = medians(samples['python -c "import numpy"'])[0]
    print("| what | wall (median) | CPU | × `import numpy` (wall) | peak RSS |")
    print("| --- | --- | --- | --- | --- |")
    for name, s in samples.items():
        wall, cpu, rss = medians(s)
        print(f"| {name} | {wall:.3f} s | {cpu:.3f} s | {wall / numpy_wall:.2f} | {rss:.0f} MiB |")


def import_breakdown(tmp: Path, repeat: int) -> None:
    """Where a one-scene JSON run's start-up goes: ``python -X importtime``, the self time of
    every imported module summed by distribution (the standard library as one), median over
    runs."""
    import re

    scene = explicit_scene(tmp)
    line = re.compile(r"import time:\s+(\d+) \|\s+(\d+) \| (\s*)(\S+)")
    totals: dict[str, list[float]] = {}
    walls = []
    for _ in range(repeat):
        start = time.perf_counter()
        proc = subprocess.run(
            [sys.executable, "-X", "importtime", "-m", "kcheck", "check", str(scene),
             "--format", "json", "--jobs", "1"],
            capture_output=True, text=True, env=ENV,
        )  # fmt: skip
        walls.append(time.perf_counter() - start)
        groups: dict[str, float] = {}
        for m in line.finditer(proc.stderr):
            top = m.group(4).split(".")[0].lstrip("_")
            if top in sys.stdlib_module_names or m.group(4) in sys.builtin_module_names:
                top = "(standard library)"
            elif top in ("kcheck", "kcheck_checks"):
                top = f"{top} ({m.group(4).split('.')[1] if '.' in m.group(4) else ''})"
                top = top.replace(" ()", "")
            groups[top] = groups.get(top, 0.0) + int(m.group(1)) / 1e6
        for name, value in groups.items():
            totals.setdefault(name, []).append(value)
    print("| imports of (self time, summed) | median |")
    print("| --- | --- |")
    ranked = sorted(totals.items(), key=lambda kv: -statistics.median(kv[1]))
    for name, values in ranked[:16]:
        print(f"| {name} | {statistics.median(values) * 1e3:.1f} ms |")
    rest = sum(statistics.median(v) for _, v in ranked[16:])
    print(f"| (others) | {rest * 1e3:.1f} ms |")
    print(f"| (whole run, wall, -X importtime) | {statistics.median(walls) * 1e3:.0f} ms |")


def make_planar(folder: Path, n: int) -> None:
    import trimesh

    for i in range(n):
        d = folder / f"s{i:04d}"
        d.mkdir(parents=True)
        # each scene its own mesh: a 100 x 60 x (20 + i/1000) mm box
        box = trimesh.creation.box(extents=(100.0, 60.0, 20.0 + i / 1000))
        box.apply_translation((50.0, 30.0, 0.0))
        box.export(d / "block.stl")
        (d / "block.kcheck.yaml").write_text(
            PLANAR.format(
                i=i,
                a=20 + (i % 7),
                angle=225 + (i % 11),
                body="mesh: block.stl\n  material: aluminium",
            )
        )


def make_spatial(folder: Path, n: int, tolerances: bool = False) -> None:
    """Three-groove scenes; without the fixture's ``tolerances:`` unless ``tolerances``."""
    import trimesh

    source = FIXTURES / "three-groove"
    plate = trimesh.load_mesh(source / "top-plate.stl")
    text = (source / "coupling.kcheck.yaml").read_text()
    if not tolerances:
        text = "".join(
            line for line in text.splitlines(keepends=True) if not line.startswith("tolerances:")
        )
    for i in range(n):
        d = folder / f"s{i:04d}"
        d.mkdir(parents=True)
        copy = plate.copy()
        copy.apply_scale(1 + i * 1e-6)  # different content: a cold cache misses every one
        copy.export(d / "top-plate.stl")
        (d / "coupling.kcheck.yaml").write_text(
            text.replace("magnitude: 100", f"magnitude: {100 + i % 13}")
        )


def batches(tmp: Path, sizes: list[int], families: list[str], jobs_list: list[int]) -> None:
    print(
        "| scenes | kind | jobs | cache | wall | CPU | CPU per scene | peak RSS (largest process) |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for family in families:
        for n in sizes:
            folder = tmp / f"{family}-{n}"
            if family == "planar":
                make_planar(folder, n)
            else:
                make_spatial(folder, n, tolerances=family == "spatial-tolerances")
            for jobs in jobs_list:
                cache = tmp / f"cache-{family}-{n}-{jobs}"
                for state in ("cold", "warm"):
                    out = tmp / "out.json"
                    cmd = [
                        *KCHECK, "check", str(folder), "--format", "json", "--output", str(out),
                        "--jobs", str(jobs), "--cache-dir", str(cache),
                    ]  # fmt: skip
                    wall, cpu, rss, code = run(cmd)
                    print(
                        f"| {n} | {family} | {jobs} | {state} | {wall:.2f} s | {cpu:.2f} s | "
                        f"{cpu / n * 1e3:.1f} ms | {rss:.0f} MiB | (exit {code})",
                        flush=True,
                    )
            shutil.rmtree(folder)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="10,100,1000")
    parser.add_argument("--kinds", default="planar,spatial")  # also: spatial-tolerances
    parser.add_argument("--jobs", default="1,2")
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--skip-batches", action="store_true")
    parser.add_argument("--skip-startup", action="store_true")
    args = parser.parse_args()
    print(
        textwrap.dedent(f"""\
        machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()},
        {platform.platform()}; load average before: {os.getloadavg()}
        """)
    )
    with tempfile.TemporaryDirectory() as tmp:
        if not args.skip_startup:
            startup(Path(tmp), args.repeat)
            print()
            import_breakdown(Path(tmp), args.repeat)
            print()
        if not args.skip_batches:
            sizes = [int(s) for s in args.sizes.split(",")]
            jobs = [int(j) for j in args.jobs.split(",")]
            batches(Path(tmp), sizes, args.kinds.split(","), jobs)
    print(f"\nload average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
