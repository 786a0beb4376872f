"""Start-up's critical path (issue 24): where a one-scene ``kcheck check`` spends the CPU that
its wall time waits for, on a machine with a core free for the worker.

A run is three parts in turn: kcheck's process up to the worker's fork (its imports, the
configuration, the checks found and loaded, the plan), the worker (the scene checked, its
result sent), and kcheck's process from the first result to the end of ``main`` (the report).
Work either process does while the other runs is off the path. The wall time of
``bench_startup.py`` is this sum plus the interpreter's start and exit and the waits (a
worker's teardown waited for, scheduling); under load it is mostly waiting, while these CPU
times hold, so this is the paired reading for a shared machine.

Run: ``python benchmarks/bench_startup_path.py --python BASE --python NEW [--repeat 15]``
(each a wrapper that runs the interpreter with its tree on ``PYTHONPATH``; see
docs/performance.md), interleaved, medians; fresh processes with bytecode caches, started from
a temporary folder without a ``pyproject.toml``. The probe runs ``kcheck.cli.main`` under
``python probe.py`` (not ``-m kcheck``) and times with ``time.process_time`` in each process.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_gate import ENV, explicit_scene

PROBE = r"""
import json, os, select, sys, time

T = time.process_time
marks = {}
read_end, write_end = os.pipe()
_fork = os.fork


def fork():
    marks["fork"] = T()
    pid = _fork()
    if pid == 0:  # the worker: its CPU when it is done (it closes its descriptors or exits)
        os.close(read_end)
        exit_, closerange = os._exit, os.closerange

        def report():
            if "sent" not in marks:
                marks["sent"] = True
                os.write(write_end, json.dumps(T()).encode())

        def exit_now(code):
            report()
            exit_(code)

        def close_all(*args):
            report()
            closerange(*args)

        os._exit, os.closerange = exit_now, close_all
    return pid


os.fork = fork
_select = select.select


def waited(*args):
    out = _select(*args)
    if out[0] and "result" not in marks:
        marks["result"] = T()
    return out


select.select = waited
import kcheck.cli

code = kcheck.cli.main(["check", sys.argv[1], "--format", "json"])
end = T()
os.close(write_end)
worker = json.loads(os.read(read_end, 100) or b"null")
print(json.dumps({
    "code": int(code), "before the fork": marks["fork"], "the worker": worker,
    "after the first result": end - marks["result"],
}), file=sys.stderr)
"""

PARTS = ("before the fork", "the worker", "after the first result")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--python", action="append")
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    pythons = args.python or [sys.executable]
    with tempfile.TemporaryDirectory() as name:
        tmp = Path(name)
        scene = explicit_scene(tmp)
        probe = tmp / "probe.py"
        probe.write_text(PROBE, encoding="utf-8")
        os.chdir(tmp)
        runs: dict[str, list[dict[str, float]]] = {p: [] for p in pythons}
        for k in range(args.repeat + 1):  # the first round writes bytecode caches
            for python in pythons:
                done = subprocess.run(
                    [python, str(probe), str(scene)],
                    capture_output=True,
                    text=True,
                    env=ENV,
                    check=True,
                )
                row = json.loads(done.stderr.strip().splitlines()[-1])
                assert row["code"] == 0 and row["the worker"] is not None, row
                if k:
                    runs[python].append(row)
    print(
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"load average {os.getloadavg()[0]:.1f}; {args.repeat} interleaved runs; CPU ms, medians"
    )
    print(f"| | {' | '.join(PARTS)} | critical path |")
    print(f"| --- |{' --- |' * (len(PARTS) + 1)}")
    for python, rows in runs.items():
        cells = [statistics.median(r[p] for r in rows) * 1e3 for p in PARTS]
        total = statistics.median(sum(r[p] for p in PARTS) for r in rows) * 1e3
        print(f"| {python} | {' | '.join(f'{c:.1f}' for c in cells)} | {total:.1f} |")


if __name__ == "__main__":
    main()
