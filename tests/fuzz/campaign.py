"""A fuzz campaign: many inputs of every kind, run as mixed batches, with a report.

    python -m tests.fuzz.campaign --seed 1 --inputs 10000 --report fuzz-report.json
    python -m tests.fuzz.campaign --only mutation-1-4711 --keep /tmp/case   # one input again
    python -m tests.fuzz.campaign --seed 1 --valid-batch 1000   # 1000 valid scenes, one batch
    python -m tests.fuzz.campaign --seed 1 --inputs 10000 --batch 15   # one batch again

Every input is generated from ``(seed, kind, index)`` alone: the identifier printed with a
problem (``kind-seed-index``) regenerates it with ``--only``. One kcheck worker (``-j 1``)
per batch, batches one after another: the campaign uses one core.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import resource
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from tests.fuzz.attacks import yaml_case
from tests.fuzz.baseline import baseline
from tests.fuzz.cli_cases import cli_case
from tests.fuzz.fs import fs_case
from tests.fuzz.harness import INPUT_TIME_LIMIT_S, Harness, Problem
from tests.fuzz.meshes import mesh_case
from tests.fuzz.model import Case
from tests.fuzz.mutate import extreme_case, fixture_copy, mutation_case, valid_case
from tests.fuzz.scenes import fixtures
from tests.fuzz.v2 import v2_case, v2_mutation_case

__all__ = ["GENERATORS", "SHARES", "plan", "run_campaign", "main"]

GENERATORS: dict[str, Callable[[int, int], Case]] = {
    "mutation": mutation_case,
    "extreme": extreme_case,
    "yaml": yaml_case,
    "fs": fs_case,
    "mesh": mesh_case,
    "cli": cli_case,
    "valid": valid_case,
    "v2": v2_case,
    "v2mutation": v2_mutation_case,
}
#: Share of each kind in a campaign of N inputs (``v2`` and ``v2mutation``: generated
#: designs of today's format, valid and mutated, since issue 25).
SHARES = {
    "mutation": 0.32,
    "extreme": 0.16,
    "yaml": 0.10,
    "fs": 0.07,
    "mesh": 0.08,
    "cli": 0.10,
    "v2": 0.07,
    "v2mutation": 0.10,
}
#: Extra reports written by some batches (all read back), cycling.
EXTRA_REPORTS: tuple[dict[str, str], ...] = (
    {},
    {"r.sarif": "sarif", "r.xml": "junit"},
    {"r.md": "markdown", "r.txt": "github", "r.c": "concise"},
    {"r.text": "text", "r.html": "html"},
    {},
    {"r.sarif": "sarif"},
    {"r.junit": "junit"},
    {".plots": "plots", "r.html": "html"},  # pictures of whatever the batch holds
)


def plan(seed: int, total: int, shares: dict[str, float] = SHARES) -> dict[str, int]:
    """How many inputs of each kind (at least one of each)."""
    return {kind: max(1, round(total * share)) for kind, share in shares.items()}


def cases(seed: int, counts: dict[str, int]) -> list[Case]:
    return [GENERATORS[kind](seed, i) for kind, n in counts.items() for i in range(n)]


@dataclass(frozen=True)
class Ref:
    """An input by its numbers, generated again when its batch runs (10,000 inputs held at
    once would take 800 MB). Kind ``fixture``: copy number ``serial`` of fixture ``index``."""

    kind: str
    index: int
    unprivileged: bool = False
    serial: int = 0

    def make(self, seed: int) -> Case:
        if self.kind == "fixture":
            return fixture_copy(fixtures()[self.index].name, self.serial, seed)
        return GENERATORS[self.kind](seed, self.index)


def survey(seed: int, counts: dict[str, int]) -> tuple[list[Ref], list[Ref]]:
    """Scene inputs and command-line inputs of a plan, each generated once and dropped."""
    scenes: list[Ref] = []
    cli: list[Ref] = []
    for kind, n in counts.items():
        for i in range(n):
            case = GENERATORS[kind](seed, i)
            (scenes if case.argv is None else cli).append(Ref(kind, i, case.unprivileged))
    return scenes, cli


def batches(seed: int, scene_refs: Sequence[Ref], size: int) -> Iterator[list[Ref]]:
    """Mixed batches: inputs of every kind in a seeded order, each batch opened by a valid
    fixture (whose time absorbs start-up) and with more fixtures mixed in (whose verdicts must
    survive whatever their neighbours do); inputs needing an unprivileged run by themselves."""
    rng = random.Random(f"{seed}:batches")
    order = list(scene_refs)
    rng.shuffle(order)
    count = len(fixtures())
    counter = 0
    for unprivileged in (False, True):
        group = [r for r in order if r.unprivileged == unprivileged]
        for start in range(0, len(group), size):
            chunk = group[start : start + size]
            batch: list[Ref] = []
            for i, ref in enumerate(chunk):
                if i % 20 == 0:
                    counter += 1
                    batch.append(Ref("fixture", counter % count, serial=counter))
                batch.append(ref)
            yield batch


def run_campaign(
    harness: Harness,
    seed: int,
    counts: dict[str, int],
    *,
    batch_size: int = 100,
    log: Callable[[str], None] = print,
    reports: Sequence[dict[str, str]] = EXTRA_REPORTS,
    only_batch: int | None = None,
) -> None:
    """Run every input of a plan (or only its scene batch number ``only_batch``, with the
    reports it wrote); problems and statistics end up in ``harness``."""
    scene_refs, cli = survey(seed, counts)
    started = time.monotonic()
    for n, refs in enumerate(batches(seed, scene_refs, batch_size)):
        if only_batch is not None and n != only_batch:
            continue
        extra = reports[n % len(reports)]
        batch = [ref.make(seed) for ref in refs]
        found = harness.run_batch(batch, outputs=extra)
        log(
            f"batch {n}: {len(batch)} scenes, {len(found)} problem(s), "
            f"{time.monotonic() - started:.0f} s"
        )
        for p in found:
            log(f"  {p.klass}: {p.case}: {p.detail[:300]}")
    for i, ref in enumerate(cli if only_batch is None else ()):
        for p in harness.run_cli(ref.make(seed)):
            log(f"  {p.klass}: {p.case}: {p.detail[:300]}")
        if i % 100 == 99:
            log(f"cli: {i + 1} of {len(cli)}, {time.monotonic() - started:.0f} s")


def summary(harness: Harness, seconds: float, seed: int) -> dict:
    """The campaign's numbers, for the report file."""
    s = harness.stats
    by_class = Counter(p.klass for p in harness.problems)
    return {
        "seed": seed,
        "seconds": round(seconds, 1),
        "processes": s.processes,
        "inputs": dict(s.inputs),
        "accepted": dict(s.accepted),
        "rejected": dict(s.rejected),
        "rejections naming the file": dict(s.named_file),
        "rejections with a line": dict(s.with_line),
        "rejections with a field": dict(s.with_field),
        "errors at real fields": dict(s.real_fields),
        "peak memory of one kcheck run, MB": round(s.peak_mb, 1),
        "peak memory run": s.peak_what,
        "peak memory of the fuzzer itself, MB": round(
            resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1
        ),
        "time limit per input, s": harness.time_limit_s,
        "slowest input, s": round(s.slowest_s, 3),
        "slowest input": s.slowest_what,
        "problems by class": dict(by_class),
        "problems": [p.__dict__ for p in harness.problems],
    }


def _regenerate(ident: str) -> Case:
    kind, seed, index = ident.rsplit("-", 2)
    return GENERATORS[kind](int(seed), int(index))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests.fuzz.campaign", description=__doc__)
    parser.add_argument("--seed", type=int, default=None, help="default: from the clock")
    parser.add_argument("--inputs", type=int, default=10_000)
    parser.add_argument("--kinds", default=",".join(SHARES), help="comma-separated kinds")
    parser.add_argument("--batch-size", type=int, default=100)
    parser.add_argument("--report", type=Path, help="write the numbers and problems as JSON")
    parser.add_argument(
        "--time-limit",
        type=float,
        default=INPUT_TIME_LIMIT_S,
        metavar="S",
        help=f"longest time one input may take, s (default {INPUT_TIME_LIMIT_S:g}; more on a "
        "loaded machine)",
    )
    parser.add_argument("--only", help="run one input again: kind-seed-index")
    parser.add_argument("--valid-batch", type=int, metavar="N", help="N valid scenes, one batch")
    parser.add_argument(
        "--batch", type=int, metavar="N", help="run scene batch N of the plan again (from 0)"
    )
    parser.add_argument("--keep", type=Path, help="lay inputs out here and keep them")
    parser.add_argument(
        "--no-extra-reports",
        action="store_true",
        help="only the JSON report (for a kcheck without the newer formats)",
    )
    parser.add_argument(
        "--kcheck-path",
        type=Path,
        help="run the kcheck found in this source tree (e.g. an older commit's `git archive`)",
    )
    args = parser.parse_args(argv)
    seed = args.seed if args.seed is not None else int(time.time()) % 100_000
    print(f"fuzz campaign, seed {seed} (reproduce with --seed {seed})", flush=True)
    root = args.keep or Path(tempfile.mkdtemp(prefix="kcheck-fuzz-"))
    root.mkdir(parents=True, exist_ok=True)
    os.chmod(root, 0o755)
    harness = Harness(root, baseline(), keep=args.keep is not None, time_limit_s=args.time_limit)
    if args.kcheck_path:
        src = args.kcheck_path.resolve()
        harness.pythonpath = f"{src}{os.pathsep}{src / 'plugins'}"
    started = time.monotonic()

    def log(text: str) -> None:
        print(text, flush=True)

    if args.only:
        case = _regenerate(args.only)
        print(f"{case.ident}: {case.what[:500]}")
        found: list[Problem] = (
            harness.run_cli(case) if case.argv is not None else harness.run_batch([case])
        )
        for p in found:
            print(f"  {p.klass}: {p.detail}")
        print("files kept in", root if args.keep else "(none; give --keep DIR)")
        return 1 if found else 0
    if args.valid_batch:
        batch = [valid_case(seed, i) for i in range(args.valid_batch)]
        found = harness.run_batch(batch)
        log(f"{len(batch)} valid scenes in one batch: {len(found)} problem(s)")
        for p in found:
            log(f"  {p.klass}: {p.case}: {p.detail[:300]}")
    else:
        kinds = {k: v for k, v in SHARES.items() if k in args.kinds.split(",")}
        total = sum(kinds.values())
        counts = plan(seed, args.inputs, {k: v / total for k, v in kinds.items()})
        log(f"inputs per kind: {counts}")
        reports = ({},) if args.no_extra_reports else EXTRA_REPORTS
        run_campaign(
            harness,
            seed,
            counts,
            batch_size=args.batch_size,
            log=log,
            reports=reports,
            only_batch=args.batch,
        )
    result = summary(harness, time.monotonic() - started, seed)
    if args.report:
        args.report.write_text(json.dumps(result, indent=1, ensure_ascii=False) + "\n")
    brief = {k: v for k, v in result.items() if k != "problems"}
    print(json.dumps(brief, indent=1, ensure_ascii=False))
    return 1 if harness.problems else 0


if __name__ == "__main__":
    sys.exit(main())
