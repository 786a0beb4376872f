"""Where the start-up of ``kcheck check`` goes (issue 24): CPU self time of every module a run
imports, grouped by package; the time spent creating dataclasses; the run after its imports;
the worker process. One planar scene with explicit mass properties, ``--format json``.

Run: ``python benchmarks/startup_parts.py [--repeat 5]`` (each repeat a fresh process; the
table gives the minimum and the median over them). ``python -X importtime`` misses modules
imported through :func:`importlib.import_module` (the checks, found through entry points, and
the command's module), so this times every module's ``exec_module`` with an import hook
(CPU, ``time.process_time``; a module's own time, without the modules it imports). The hook
adds a little to every import: read the numbers as shares, the paired ratio is
``bench_startup.py``'s.
"""

from __future__ import annotations

import argparse
import ast
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_gate import ENV, explicit_scene

PROBE = r"""
import dataclasses, importlib.abc, os, resource, sys, time

T = time.process_time
stack, own = [], {}


class Timed(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        for finder in sys.meta_path:
            if finder is self or not hasattr(finder, "find_spec"):
                continue
            spec = finder.find_spec(name, path, target)
            if spec is None:
                continue
            loader = spec.loader
            if loader is not None and hasattr(loader, "exec_module"):
                run = loader.exec_module

                def timed(module, run=run, name=name):
                    start = T()
                    stack.append(0.0)
                    try:
                        run(module)
                    finally:
                        spent = T() - start
                        own[name] = spent - stack.pop()
                        if stack:
                            stack[-1] += spent

                try:
                    loader.exec_module = timed
                except (AttributeError, TypeError):
                    pass
            return spec
        return None


sys.meta_path.insert(0, Timed())
made = [0.0, 0, 0]  # CPU s, classes, depth (kcheck.records' decorator calls the standard one)
process_class = dataclasses._process_class


def counted(*args, **kwargs):
    start = T()
    made[2] += 1
    try:
        return process_class(*args, **kwargs)
    finally:
        made[2] -= 1
        if not made[2]:
            made[0] += T() - start
            made[1] += 1


dataclasses._process_class = counted
try:  # kcheck's own decorator (kcheck.records, from issue 24's fourth round): timed whole
    import kcheck.records as records
except ImportError:
    pass
else:
    decorate = records.dataclass

    def timed_decorator(cls=None, /, **options):
        def wrap(cls):
            start = T()
            made[2] += 1
            try:
                return decorate(cls, **options)
            finally:
                made[2] -= 1
                made[0] += T() - start
                made[1] += 1

        return wrap if cls is None else wrap(cls)

    records.dataclass = timed_decorator
start = T()
import numpy  # noqa: E402

numpy_s = T() - start
with_numpy = set(sys.modules)
from kcheck.cli import main  # noqa: E402

stdout, sys.stdout = sys.stdout, open(os.devnull, "w")
start = T()
main(["check", sys.argv[1], "--format", "json"])
main_s = T() - start
sys.stdout = stdout
# The last worker ends by itself, not waited for (kcheck.gate.pool): reaped here, so that its
# CPU is in RUSAGE_CHILDREN (a kcheck that waits for it has none left).
reap = getattr(sys.modules.get("kcheck.gate.pool"), "reap_exited", None)
if reap is not None:
    reap(wait=True)
child = resource.getrusage(resource.RUSAGE_CHILDREN)
after = {m: s for m, s in own.items() if m not in with_numpy}
print(repr({
    "numpy": numpy_s, "main": main_s, "imports": sum(after.values()),
    "dataclasses": made[0], "dataclass count": made[1],
    "worker": child.ru_utime + child.ru_stime, "modules": after,
}))
"""

GROUPS = (
    "kcheck_checks",
    "kcheck.cli",
    "kcheck.gate",
    "kcheck.scene",
    "kcheck.analysis",
    "kcheck.mechanics",
    "kcheck.report",
    "kcheck.plugin",
    "kcheck.numerics",
    "kcheck.body",
    "yaml",
)


def group(module: str) -> str:
    for name in GROUPS:
        if module == name or module.startswith(name + "."):
            return name
    if module.split(".")[0] == "kcheck":
        return "kcheck (result, fmt, errors)"
    return "Python's and other modules numpy does not import"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--modules", type=int, default=0, help="also list the N costliest")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as name:
        scene = explicit_scene(Path(name))
        runs = []
        for _ in range(args.repeat + 1):  # the first writes the bytecode caches
            out = subprocess.run(
                [sys.executable, "-c", PROBE, str(scene)],
                capture_output=True,
                text=True,
                env=ENV,
                cwd=name,
                check=True,
            ).stdout
            runs.append(ast.literal_eval(out.strip().splitlines()[-1]))
        runs = runs[1:]
    rows: dict[str, list[float]] = {}
    counts: dict[str, int] = {}
    for run in runs:
        sums: dict[str, float] = {}
        for module, spent in run["modules"].items():
            sums[group(module)] = sums.get(group(module), 0.0) + spent
            counts[group(module)] = counts.get(group(module), 0)
        for key, spent in sums.items():
            rows.setdefault(key, []).append(spent)
    for module in runs[0]["modules"]:
        counts[group(module)] += 1

    def cell(values: list[float]) -> str:
        return f"{min(values) * 1e3:.1f} | {statistics.median(values) * 1e3:.1f}"

    print(f"load average {os.getloadavg()[0]:.1f}; {len(runs)} runs; CPU ms")
    print("| part | min | median |")
    print("| --- | --- | --- |")
    print(f"| import numpy | {cell([r['numpy'] for r in runs])} |")
    print(f"| kcheck's imports after numpy | {cell([r['imports'] for r in runs])} |")
    count = runs[0]["dataclass count"]
    print(f"| of which creating {count} dataclasses | {cell([r['dataclasses'] for r in runs])} |")
    for key, values in sorted(rows.items(), key=lambda kv: -min(kv[1])):
        print(f"| {key} ({counts[key]} modules) | {cell(values)} |")
    print(f"| main(), imports included | {cell([r['main'] for r in runs])} |")
    print(f"| the worker process | {cell([r['worker'] for r in runs])} |")
    if args.modules:
        own = {m: [r["modules"].get(m, 0.0) for r in runs] for m in runs[0]["modules"]}
        print("\n| module (own time) | min | median |\n| --- | --- | --- |")
        for module, values in sorted(own.items(), key=lambda kv: -min(kv[1]))[: args.modules]:
            print(f"| {module} | {cell(values)} |")


if __name__ == "__main__":
    main()
