"""Issue 24's batch targets, paired: ``kcheck check`` of N generated scenes with ``--jobs``,
this tree against a baseline commit in the same run.

Run: ``python benchmarks/bench_chunks.py [--baseline 56e5ffb] [--count 1000] [--jobs 2]
[--rounds 1] [--kinds spatial,planar]``.

The scenes are :mod:`bench_gate`'s (planar: a box mesh each; spatial: the three-groove fixture
with its own scaled copy of the top plate each, without ``tolerances:``). The baseline commit
is extracted (``git archive``) and put first on ``PYTHONPATH`` (its ``kcheck`` and
``plugins``), so ``python -m kcheck`` runs it with this environment's packages (run from a
temporary folder, which ``python -m`` puts first); the new side is this tree, put first on
``PYTHONPATH`` the same way.
Each side prints which ``kcheck`` it imports. Each round runs, per kind, baseline then
new: spatial cold (an empty cache) then warm (the same cache again), planar warm. Printed:
wall and CPU time (``os.wait4``, kcheck and its workers) of each, and new / baseline of the
medians.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_gate import ENV, KCHECK, make_planar, make_spatial, run  # noqa: E402
from paired import extract  # noqa: E402


def side_env(tree: Path) -> dict[str, str]:
    """kcheck's environment: ``tree`` (the baseline's export, or this tree) first on the path
    (an installed kcheck may be another checkout's: a helper's worktree shares the lead's
    environment)."""
    env = {k: v for k, v in ENV.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = os.pathsep.join([str(tree), str(tree / "plugins")])
    return env


def check(folder: Path, jobs: int, cache: Path, env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds of one ``kcheck check`` of a folder."""
    out = cache.parent / f"{cache.name}.json"
    cmd = [*KCHECK, "check", str(folder), "--format", "json", "--output", str(out),
           "--jobs", str(jobs), "--cache-dir", str(cache)]  # fmt: skip
    wall, cpu, _, code = run(cmd, env)
    if code not in (0, 1):
        raise SystemExit(f"kcheck exited {code}: {' '.join(cmd)}")
    return wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--baseline", default="56e5ffb")
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--kinds", default="spatial,planar")
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    samples: dict[tuple[str, str], dict[str, list[tuple[float, float]]]] = {}
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        os.chdir(tmp)  # not this tree: ``python -m`` puts the working folder first on the path
        base = extract(args.baseline, tmp)
        sides = {"baseline": side_env(base), "new": side_env(ROOT)}
        for kind in args.kinds.split(","):
            folder = tmp / kind
            (make_planar if kind == "planar" else make_spatial)(folder, args.count)
            # Both sides' bytecode written before timing (as in any installed copy).
            for label, env in sides.items():
                check(folder / "s0000", 1, tmp / "warmup-cache", env)
                where = subprocess.run(
                    [sys.executable, "-c", "import kcheck; print(kcheck.__file__)"],
                    env=env, capture_output=True, text=True, check=True,
                ).stdout.strip()  # fmt: skip
                print(f"{label}: {where}")
            for r in range(args.rounds):
                for label, env in sides.items():
                    cache = tmp / f"cache-{kind}-{label}-{r}"
                    states = ("cold", "warm") if kind == "spatial" else ("warm",)
                    if kind == "planar":  # no mesh cache worth the name: fill it first
                        check(folder, args.jobs, cache, env)
                    for state in states:
                        wall, cpu = check(folder, args.jobs, cache, env)
                        samples.setdefault((kind, state), {}).setdefault(label, []).append(
                            (wall, cpu)
                        )
                        print(
                            f"{kind} {state} {label}: {wall:.1f} s wall, {cpu:.1f} s CPU "
                            f"(load {os.getloadavg()[0]:.1f})"
                        )
    print(f"load average after: {os.getloadavg()}")
    print(
        f"| {args.count} scenes, -j {args.jobs} | baseline ({args.baseline}) wall / CPU "
        "| new wall / CPU | new / baseline (wall) | new / baseline (CPU) |"
    )
    print("| --- | --- | --- | --- | --- |")
    for (kind, state), by in samples.items():
        old = [statistics.median(x) for x in zip(*by["baseline"], strict=True)]
        new = [statistics.median(x) for x in zip(*by["new"], strict=True)]
        print(
            f"| {kind}, {state} | {old[0]:.1f} s / {old[1]:.1f} s | {new[0]:.1f} s / "
            f"{new[1]:.1f} s | {new[0] / old[0]:.2f} | {new[1] / old[1]:.2f} |"
        )


if __name__ == "__main__":
    main()
