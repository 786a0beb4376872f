"""``kcheck check``: check scene files and report, with CI-gate exit codes."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from kcheck.cli.common import ExitCode, fail

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``check`` command."""
    check = sub.add_parser(
        "check",
        help="check scene files (default: every *.kcheck.yaml in .)",
        description="Check scene files and report; exit 0 when every check passed, 1 when a "
        "check failed, 2 on bad input or usage (other scenes are still checked).",
    )
    check.add_argument(
        "paths",
        nargs="*",
        default=["."],
        type=Path,
        help="scene files and folders (searched recursively for *.kcheck.yaml)",
    )
    check.add_argument(
        "--format",
        choices=("text", "json"),
        default="text",
        help="report format (default: text)",
    )
    check.add_argument("--output", "-o", type=Path, help="write the report to this file")
    check.add_argument(
        "--plots",
        type=Path,
        metavar="DIR",
        help="write pictures (PNG and SVG) into DIR (needs the `plot` extra)",
    )
    check.add_argument(
        "--select", metavar="IDS", help="comma-separated check ids to run (default: all installed)"
    )
    check.add_argument(
        "--color",
        choices=("auto", "always", "never"),
        default="auto",
        help="colour in the text report (default: auto, which follows the terminal, "
        "NO_COLOR and FORCE_COLOR)",
    )
    check.add_argument(
        "--allow-outside-paths",
        action="store_true",
        help="let scenes use meshes outside their own folder",
    )
    check.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Check every scene, stream the report, choose the exit code."""
    from kcheck.plugin import load_checks
    from kcheck.report import ReportOptions, make_reporter
    from kcheck.result import Status
    from kcheck.runner import Settings, discover, run_batch

    checks = load_checks()
    if args.select:
        wanted = [s.strip() for s in args.select.split(",") if s.strip()]
        known = {lc.spec.name for lc in checks}
        unknown = [w for w in wanted if w not in known]
        if unknown:
            return fail(
                f"unknown check(s) {', '.join(unknown)}; installed: {', '.join(sorted(known))}"
            )
        checks = [lc for lc in checks if lc.spec.name in wanted]
    files, missing = discover(args.paths)
    if args.plots is not None:
        args.plots.mkdir(parents=True, exist_ok=True)
    settings = Settings(allow_outside=args.allow_outside_paths, plots=args.plots)

    stream = sys.stdout
    if args.output is not None:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        stream = args.output.open("w", encoding="utf-8")
    try:
        options = ReportOptions(color=args.color, to_file=args.output is not None)
        reporter = make_reporter(args.format, stream, options)
        started = time.perf_counter()
        reporter.start(len(files) + len(missing))
        results = list(missing)
        for result in missing:
            reporter.scene(result)
        for result in run_batch(files, checks, settings):
            results.append(result)
            reporter.scene(result)
        reporter.finish(results, time.perf_counter() - started)
    finally:
        if stream is not sys.stdout:
            stream.close()
    for r in results:
        if r.status is Status.ERROR and r.error:
            print(f"kcheck: error: {r.error}", file=sys.stderr)
    states = {r.status for r in results}
    if Status.ERROR in states:
        return ExitCode.USAGE_OR_INPUT
    return ExitCode.CHECKS_FAILED if Status.FAIL in states else ExitCode.OK
