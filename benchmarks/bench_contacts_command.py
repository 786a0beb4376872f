"""Timing of the whole ``kcheck contacts base.stl body.stl --units mm`` command (imports,
reading the files, finding, merged-parts finding, the scene) on ``bench_contacts.py``'s
assembly written as binary STL (491,520 faces per part):
``python benchmarks/bench_contacts_command.py [--baseline REF] [--rounds N]``.

Paired, interleaved in the same run, against the kcheck of git revision REF (default
``56e5ffb``, before the third round of issue 29's speed work; ``6d98969`` is before binary
STLs were read without trimesh, ``03dc445`` before the merged-parts finding was split once),
exported to a temporary folder and run with the same Python. Wall time is the child's
(``time.perf_counter`` around it), CPU time its user + system time (``resource``); all must
write the same scene and the same report. Beside kcheck as it is (the two STL files read at
once, in two threads), the same kcheck with them read one after the other
(``kcheck.cli.contacts.READ_IN_THREADS`` off). Medians of N rounds (default 5), the load
average before and after.
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from bench_contacts import assembly  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


#: The command with the two files read one after the other (kcheck.cli.contacts's switch).
SERIAL = (
    "import sys; import kcheck.cli.contacts as c; c.READ_IN_THREADS = False; "
    "from kcheck.cli import main; sys.exit(main(sys.argv[1:]))"
)


def run(src: Path, folder: Path, serial: bool = False) -> tuple[float, float, str, str]:
    """Wall and CPU time of one command run with kcheck from ``src`` (with ``serial``, the
    two files read one after the other), its scene and report."""
    command = ["contacts", "base.stl", "body.stl", "--units", "mm"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, *(["-c", SERIAL] if serial else ["-m", "kcheck"]), *command],
        cwd=folder,
        env={**os.environ, "PYTHONPATH": str(src)},
        capture_output=True,
        text=True,
        check=True,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return wall, cpu, done.stdout, done.stderr


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("ref", nargs="?", help="the baseline revision (as --baseline)")
    parser.add_argument("--baseline", default="56e5ffb", help="git revision to pair against")
    parser.add_argument("--rounds", type=int, default=5, help="paired rounds (default 5)")
    args = parser.parse_args()
    ref = args.ref or args.baseline
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        folder, old = Path(tmp) / "parts", Path(tmp) / "old"
        folder.mkdir()
        old.mkdir()
        base, body = assembly()
        base.export(folder / "base.stl")
        body.export(folder / "body.stl")
        archive = subprocess.run(
            ["git", "archive", ref, "kcheck"], cwd=ROOT, capture_output=True, check=True
        ).stdout
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive, check=True)
        times: dict = {"now": [], "serial": [], "before": []}
        out = {}
        for _ in range(args.rounds):
            for name, src, serial in (
                ("now", ROOT, False),
                ("serial", ROOT, True),
                ("before", old, False),
            ):
                wall, cpu, scene, report = run(src, folder, serial)
                times[name].append((wall, cpu))
                out[name] = (scene, report)
    same = all(out[name] == out["before"] for name in ("now", "serial"))
    print(f"491,520 faces per part; the same scene and report as {ref}: {same}")
    for name, what in (
        ("now", "kcheck contacts"),
        ("serial", "kcheck contacts, the two files read one after the other"),
        ("before", f"kcheck contacts at {ref}"),
    ):
        wall = statistics.median(t[0] for t in times[name])
        cpu = statistics.median(t[1] for t in times[name])
        print(f"{what}: {wall:.2f} s wall, {cpu:.2f} s CPU (medians of {args.rounds})")
    for name in ("now", "serial"):
        cpu = [b[1] / n[1] for n, b in zip(times[name], times["before"], strict=True)]
        wall = [b[0] / n[0] for n, b in zip(times[name], times["before"], strict=True)]
        print(
            f"paired ratio {ref} / {name}: CPU {statistics.median(cpu):.2f}x, "
            f"wall {statistics.median(wall):.2f}x (medians over rounds)"
        )
    print(
        f"load average before {load_before:.1f}, after {os.getloadavg()[0]:.1f} "
        f"on {os.cpu_count()} cores"
    )


if __name__ == "__main__":
    main()
