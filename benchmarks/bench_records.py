"""kcheck.records' decorator (issue 24's start-up, and the review round "mendrec"): CPU a class
takes to create, and to make its first instance (where its ``__init__`` is compiled), for a
baseline tree against this one, paired: fresh processes, baseline and new interleaved; the
standard library's decorator alongside.

Run: ``python benchmarks/bench_records.py [--base REV] [--repeat 15]`` from the repository.
``--base`` (default ``main``) is extracted with ``git archive`` into a temporary folder; each
process imports ``kcheck.records`` from its tree alone (``PYTHONPATH``), creates 60 classes of
8 fields (frozen and not, half each, one with a default factory) and makes one instance of
each; the table gives medians over the processes in ms a class, and NEW / BASE.
"""

from __future__ import annotations

import argparse
import ast
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
from io import BytesIO
from pathlib import Path

PROBE = r"""
import dataclasses, sys, time
T = time.process_time
if sys.argv[1] == "std":
    decorate = dataclasses.dataclass
else:
    from kcheck.records import dataclass as decorate
body = '''
    'A record.'
    a: float
    b: float = 0.0
    c: tuple = ()
    d: str = ""
    e: int = 0
    f: float = 1.0
    g: tuple = dataclasses.field(default_factory=tuple)
    h: object = None
'''
classes, made, first = 60, 0.0, 0.0
for i in range(classes):
    scope = {"dataclasses": dataclasses, "decorate": decorate, "__name__": "__main__"}
    text = f"class C{i}:\n{body}"
    exec(text, scope)
    start = T()
    cls = decorate(scope[f"C{i}"], frozen=bool(i % 2))
    made += T() - start
    start = T()
    cls(1.0)
    first += T() - start
print(repr({"create": made / classes, "first instance": first / classes}))
"""


def tree_of(rev: str, into: Path) -> Path:
    data = subprocess.run(
        ["git", "archive", rev, "kcheck/records.py"], capture_output=True, check=True
    ).stdout
    with tarfile.open(fileobj=BytesIO(data)) as archive:
        archive.extractall(into, filter="data")
    (into / "kcheck" / "__init__.py").write_text("")  # the module alone, not the package
    return into


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--base", default="main")
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    here = Path(__file__).resolve().parent.parent
    with tempfile.TemporaryDirectory() as name:
        base = tree_of(args.base, Path(name) / "base")
        new = Path(name) / "new" / "kcheck"
        new.mkdir(parents=True)
        (new / "__init__.py").write_text("")
        (new / "records.py").write_text((here / "kcheck" / "records.py").read_text())
        trees = {"BASE": ("ours", base), "NEW": ("ours", new.parent), "standard": ("std", base)}
        seen: dict[str, list[dict[str, float]]] = {key: [] for key in trees}
        for _ in range(args.repeat):
            for key, (which, tree) in trees.items():
                env = {**os.environ, "PYTHONPATH": str(tree)}
                out = subprocess.run(
                    [sys.executable, "-c", PROBE, which],
                    capture_output=True,
                    text=True,
                    env=env,
                    cwd=name,
                    check=True,
                ).stdout
                seen[key].append(ast.literal_eval(out.strip().splitlines()[-1]))
    print(f"load average {os.getloadavg()[0]:.1f}; {args.repeat} runs; CPU ms a class, medians")
    print("| decorator | create | first instance | both |")
    print("| --- | --- | --- | --- |")
    med: dict[str, dict[str, float]] = {}
    for key, runs in seen.items():
        med[key] = {
            part: statistics.median(r[part] for r in runs) * 1e3
            for part in ("create", "first instance")
        }
        med[key]["both"] = med[key]["create"] + med[key]["first instance"]
        cells = " | ".join(f"{med[key][p]:.3f}" for p in ("create", "first instance", "both"))
        print(f"| {key} | {cells} |")
    ratios = " | ".join(
        f"{med['NEW'][p] / med['BASE'][p]:.2f}" for p in ("create", "first instance", "both")
    )
    print(f"| NEW / BASE | {ratios} |")


if __name__ == "__main__":
    main()
