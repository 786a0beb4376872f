"""The paired benchmarks' shared set-up: this tree against a baseline commit, in the same run.

The baseline commit is extracted (``git archive``) into a temporary folder; each round runs a
fresh process per tree, the tree (and its ``plugins``) first on ``PYTHONPATH``, with a worker
script whose constants (``ROOT``, ``TESTS``, ``FIXTURES``, ``TMP``, ``EXPECT``, …) are written
in a header before it. The worker prints one JSON object of numbers on its last line; the
rounds' numbers are gathered per tree and compared as medians (new / baseline).

Used by ``bench_speed.py``, ``bench_equilibria.py``, ``bench_jamming.py`` and
``bench_second_answer.py`` (imported as ``paired``: ``benchmarks/`` is the script's folder).
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The spatial fixtures with a load.
FIXTURES = [
    "three-groove/coupling.kcheck.yaml",
    *(f"three-groove-beta-{b}/coupling.kcheck.yaml" for b in (15, 25, 35, 45, 55, 65)),
    "block-321/block.kcheck.yaml",
    "kelvin/coupling.kcheck.yaml",
    "tool-changer/tool.kcheck.yaml",
]

#: A worker's opening lines for the two scene sets: the spatial fixtures with a load and
#: ``COUNT`` generated spatial scenes (``tests/spatial_scenes.py``), as ``sets``, after
#: checking that ``kcheck`` comes from the tree measured. Needs ``kcheck`` imported.
SCENE_SETS = r"""
sys.path.append(TESTS)  # after kcheck: tests/kcheck would shadow it as a namespace package
from spatial_scenes import write_spatial_scenes
assert kcheck.__file__.startswith(EXPECT), kcheck.__file__
sets = {"fixtures": [Path(ROOT) / "fixtures" / f for f in FIXTURES]}
sets["generated"] = write_spatial_scenes(Path(TMP), range(COUNT))
"""

Samples = dict[str, dict[str, list[float]]]


def extract(baseline: str, folder: Path) -> Path:
    """``baseline``'s tree extracted with ``git archive`` into ``folder``/baseline."""
    base = folder / "baseline"
    base.mkdir()
    archive = subprocess.run(
        ["git", "archive", baseline], cwd=ROOT, capture_output=True, check=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(base)], input=archive, check=True)
    return base


def tree_env(tree: Path, env: dict[str, str] | None = None) -> dict[str, str]:
    """``env`` (default: this process's) with ``tree`` and its plugins alone on PYTHONPATH."""
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = os.pathsep.join([str(tree), str(tree / "plugins")])
    return env


def run_worker(
    tree: Path, folder: Path, worker: str, constants: dict[str, object], env: dict[str, str]
) -> dict[str, float]:
    """One fresh process running ``worker`` in ``folder`` with ``tree`` first on the path,
    after a header defining ``ROOT``, ``TESTS``, ``EXPECT`` (``tree``'s ``kcheck``), ``TMP``
    (``folder``) and ``constants``; its last line of output, parsed as JSON."""
    values = {
        "ROOT": str(ROOT),
        "TESTS": str(ROOT / "tests"),
        "EXPECT": str(tree / "kcheck"),
        "TMP": str(folder),
        **constants,
    }
    header = "".join(f"{name} = {value!r}\n" for name, value in values.items())
    run = subprocess.run(
        [sys.executable, "-c", header + worker],
        capture_output=True,
        text=True,
        env=tree_env(tree, env),
        cwd=folder,
    )
    if run.returncode:
        raise SystemExit(run.stderr)
    return json.loads(run.stdout.strip().splitlines()[-1])


def paired_rounds(
    baseline: str, rounds: int, measure: Callable[[str, Path, Path], dict[str, float]]
) -> Samples:
    """``rounds`` rounds alternating baseline / new: ``measure(label, tree, tmp)`` (a fresh
    process, say) for ``baseline`` extracted and for this tree, in a temporary folder ``tmp``;
    the numbers gathered per label and key. Prints the load average before and after."""
    import tempfile

    print(f"load average before: {os.getloadavg()}")
    samples: Samples = {"baseline": {}, "new": {}}
    with tempfile.TemporaryDirectory() as name:
        tmp = Path(name)
        base = extract(baseline, tmp)
        for _ in range(rounds):
            for label, tree in (("baseline", base), ("new", ROOT)):
                for key, value in measure(label, tree, tmp).items():
                    samples[label].setdefault(key, []).append(value)
    print(f"load average after: {os.getloadavg()}")
    return samples


def medians(samples: Samples) -> Iterator[tuple[str, float, float]]:
    """Each key's median baseline and new numbers, in the new side's order."""
    for key in samples["new"]:
        old, new = samples["baseline"][key], samples["new"][key]
        yield key, statistics.median(old), statistics.median(new)


def print_ratios(samples: Samples, first: str, what: str, baseline: str, digits: int = 2) -> None:
    """A Markdown table of ``samples``' medians in ms: key, baseline, new, new / baseline."""
    print(f"| {first} | {what}, baseline ({baseline}) | new | new / baseline |")
    print("| --- | --- | --- | --- |")
    for key, old, new in medians(samples):
        print(
            f"| {key} | {old * 1e3:.{digits}f} ms | {new * 1e3:.{digits}f} ms | {new / old:.2f} |"
        )
