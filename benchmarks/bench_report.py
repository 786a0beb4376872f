"""What a report costs: checks alone against checks with pictures (PNG, SVG, both), and the
text and HTML reports, over the bundled fixtures.

Run: ``python benchmarks/bench_report.py [--repeat N] [FIXTURE ...]`` (default: every fixture
folder). Prints a markdown table of CPU seconds per scene and the totals (results in
docs/performance.md). Everything runs in one process, as ``kcheck check`` does: matplotlib's
import (about a second) is paid once, before the timings, and reported on its own.
"""

from __future__ import annotations

import argparse
import io
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from kcheck.gate.runner import Settings, check_scene
from kcheck.plugin import load_checks
from kcheck.report import ReportOptions, make_reporter

ROOT = Path(__file__).resolve().parents[1]


def timed(fn: Callable[[], object], repeat: int) -> tuple[float, object]:
    """Median CPU time (s) of this process running ``fn`` over ``repeat`` runs, and its last
    value. CPU time, not wall time: the machine is shared, and waiting for a core is not a
    cost of kcheck (everything here runs in one thread)."""
    times, value = [], None
    for _ in range(repeat):
        start = time.process_time()
        value = fn()
        times.append(time.process_time() - start)
    return statistics.median(times), value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("fixtures", nargs="*", help="fixture folders (default: all)")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    folders = [ROOT / "fixtures" / f for f in args.fixtures] or sorted(
        p for p in (ROOT / "fixtures").iterdir() if p.is_dir()
    )
    files = [next(folder.glob("*.kcheck.yaml")) for folder in folders]
    checks = load_checks()

    start = time.process_time()
    import matplotlib.figure  # noqa: F401 - paid once per run, reported apart

    print(f"matplotlib import: {time.process_time() - start:.2f} s CPU (once per run)\n")
    modes: dict[str, tuple[str, ...] | None] = {
        "checks only": None,
        "+ PNG": ("png",),
        "+ SVG": ("svg",),
        "+ PNG and SVG": ("png", "svg"),
    }
    totals = dict.fromkeys(modes, 0.0)
    results = []
    print("| scene | pictures | " + " | ".join(modes) + " |")
    print("| --- | ---: | " + " | ".join("---:" for _ in modes) + " |")
    with tempfile.TemporaryDirectory() as tmp:
        for path in files:
            row = []
            count = 0
            for name, formats in modes.items():
                settings = Settings(
                    plots=None if formats is None else Path(tmp) / name.replace(" ", ""),
                    plot_formats=formats or ("png",),
                )
                seconds, result = timed(
                    lambda p=path, s=settings: check_scene(p, checks, settings=s), args.repeat
                )
                totals[name] += seconds
                row.append(f"{seconds:.2f} s")
                if formats == ("png",):
                    count = len(result.plots)  # type: ignore[attr-defined]
                if formats == ("png", "svg"):
                    results.append(result)  # the HTML report inlines the SVG pictures
            print(f"| {path.parent.name} | {count} | " + " | ".join(row) + " |")
        print("| **all** | | " + " | ".join(f"**{t:.1f} s**" for t in totals.values()) + " |")

        print()
        for fmt in ("text", "json", "html"):
            stream = io.StringIO()

            def write(fmt: str = fmt, stream: io.StringIO = stream) -> None:
                stream.seek(0)
                stream.truncate()
                reporter = make_reporter(fmt, stream, ReportOptions(color="never", to_file=True))
                reporter.start(len(results))
                for r in results:
                    reporter.scene(r)
                reporter.finish(results, 1.0)

            seconds, _ = timed(write, args.repeat)
            size = len(stream.getvalue().encode())
            n = len(results)
            print(f"{fmt} report of {n} scenes: {seconds * 1e3:.0f} ms, {size / 1e3:.0f} kB")


if __name__ == "__main__":
    main()
