"""``kcheck check``: check scene files and report, with CI-gate exit codes."""

from __future__ import annotations

import argparse
import contextlib
import sys
import tempfile
import time
from collections.abc import Iterator
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
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
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
        help="write pictures into DIR, PNG unless --plot-format says otherwise "
        "(needs the plot extra: pip install 'kcheck[plot]')",
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
    _add_report_options(check)
    check.set_defaults(handler=run)


EPILOG = """\
exit codes:
  0  every check passed (checks of severity warning may have failed)
  1  a check failed
  2  bad input or usage; every other scene is still checked

examples:
  kcheck check parts/                  one line per scene, reasons for failures
  kcheck check parts/ -v               every table, mass properties, sweep plane
  kcheck check parts/ --html review.html --plots plots/
"""


def _add_report_options(check: Any) -> None:
    """How much the text report says, progress, pictures' format, the HTML page."""
    group = check.add_argument_group("report")
    amount = group.add_mutually_exclusive_group()
    amount.add_argument(
        "-v",
        "--verbose",
        action="store_true",
        help="every scene in full: sweep plane, mass properties, notes, every check with its "
        "tables, pictures written",
    )
    amount.add_argument(
        "-q",
        "--quiet",
        action="store_true",
        help="only scenes that did not pass, and the summary",
    )
    group.add_argument(
        "--progress",
        choices=("auto", "always", "never"),
        default="auto",
        help="progress line on stderr while scenes are checked (default: auto, shown when "
        "stderr is a terminal; it disappears when the run is done)",
    )
    group.add_argument(
        "--html",
        type=Path,
        metavar="FILE",
        help="also write one self-contained HTML page (summary first, then every scene with "
        "its tables and pictures inline as SVG; needs the plot extra for pictures)",
    )
    group.add_argument(
        "--plot-format",
        default="png",
        metavar="FORMATS",
        help="picture formats for --plots, comma-separated from png, svg (default: png)",
    )


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
    plot_formats = _plot_formats(args.plot_format)
    if plot_formats is None:
        return fail(f"--plot-format: expected png, svg or png,svg; got {args.plot_format!r}")
    html = None
    if args.html is not None:
        try:  # before the run: a page that cannot be written is a usage error, not a traceback
            args.html.parent.mkdir(parents=True, exist_ok=True)
            html = args.html.open("w", encoding="utf-8")
        except OSError as exc:
            return fail(f"--html {args.html}: cannot write the page ({_reason(exc)})")
    files, missing = discover(args.paths)
    if args.plots is not None:
        args.plots.mkdir(parents=True, exist_ok=True)
    with _pictures_for_html(args, plot_formats) as (plots, plot_formats):
        settings = Settings(
            allow_outside=args.allow_outside_paths, plots=plots, plot_formats=plot_formats
        )
        stream = sys.stdout
        if args.output is not None:
            args.output.parent.mkdir(parents=True, exist_ok=True)
            stream = args.output.open("w", encoding="utf-8")
        verbosity = 1 if args.verbose else -1 if args.quiet else 0
        try:
            options = ReportOptions(
                color=args.color, verbosity=verbosity, to_file=args.output is not None
            )
            target = "the report" if args.output is None else str(args.output)
            reporters = [_Target(target, make_reporter(args.format, stream, options))]
            if html is not None:
                reporters.append(_Target(str(args.html), make_reporter("html", html, options)))
            batch = run_batch(files, checks, settings)
            results, elapsed = _run(reporters, files, missing, batch, args)
            if html is not None:
                with _Target(str(args.html), None).writing():
                    html.close()  # a full disk shows here, as an error of the page
        except _WriteError as exc:
            return fail(f"cannot write {exc.target}: {_reason(exc.error)}")
        finally:
            if stream is not sys.stdout:
                stream.close()
            if html is not None and not html.closed:
                with contextlib.suppress(OSError):
                    html.close()
    text_on_stdout = args.format == "text" and args.output is None
    if not text_on_stdout:
        _errors_to_stderr(results)
        _summary_to_terminal(results, elapsed, args.output)
    states = {r.status for r in results}
    if Status.ERROR in states:
        return ExitCode.USAGE_OR_INPUT
    return ExitCode.CHECKS_FAILED if Status.FAIL in states else ExitCode.OK


class _WriteError(Exception):
    """Writing one output (the report, the page) failed with an OS error."""

    def __init__(self, target: str, error: OSError) -> None:
        super().__init__(target)
        self.target, self.error = target, error


class _Target:
    """A reporter and the name of what it writes, for error messages."""

    def __init__(self, name: str, reporter: Any) -> None:
        self.name, self.reporter = name, reporter

    @contextlib.contextmanager
    def writing(self) -> Iterator[None]:
        try:
            yield
        except OSError as exc:
            raise _WriteError(self.name, exc) from exc

    def start(self, total: int) -> None:
        with self.writing():
            self.reporter.start(total)

    def scene(self, result: Any) -> None:
        with self.writing():
            self.reporter.scene(result)

    def finish(self, results: Any, elapsed_s: float) -> None:
        with self.writing():
            self.reporter.finish(results, elapsed_s)


def _reason(exc: OSError) -> str:
    """An OS error in words (a parent that is a file gets its own)."""
    if isinstance(exc, (FileExistsError, NotADirectoryError)):
        return "a folder on the path is a file"
    return exc.strerror or str(exc)


def _plot_formats(text: str) -> tuple[str, ...] | None:
    from kcheck.plotting import PLOT_FORMATS

    names = tuple(dict.fromkeys(n.strip().lower() for n in text.split(",") if n.strip()))
    return names if names and all(n in PLOT_FORMATS for n in names) else None


@contextlib.contextmanager
def _pictures_for_html(
    args: argparse.Namespace, plot_formats: tuple[str, ...]
) -> Iterator[tuple[Path | None, tuple[str, ...]]]:
    """Where pictures go and in which formats: the HTML page inlines SVG, so with --html the
    pictures include SVG, in a temporary folder when --plots is not given."""
    if args.html is None:
        yield args.plots, plot_formats
        return
    formats = tuple(dict.fromkeys((*plot_formats, "svg")))
    if args.plots is not None:
        yield args.plots, formats
        return
    with tempfile.TemporaryDirectory(prefix="kcheck-html-") as tmp:
        yield Path(tmp), ("svg",)


def _run(
    reporters: list[Any],
    files: list[Path],
    missing: list[Any],
    batch: Iterator[Any],
    args: argparse.Namespace,
) -> tuple[list[Any], float]:
    """Feed every reporter each result as it arrives, with a progress line on stderr;
    return the results and the wall time."""
    from kcheck.report.progress import ProgressLine

    total = len(files) + len(missing)
    started = time.perf_counter()
    for reporter in reporters:
        reporter.start(total)
    results = list(missing)
    for result in missing:
        for reporter in reporters:
            reporter.scene(result)
    doing = "checking" + (", plotting" if args.plots is not None or args.html else "")
    with ProgressLine(args.progress, len(files), doing) as progress:
        progress.next(files[0] if files else None)
        for k, result in enumerate(batch):
            results.append(result)
            with progress.paused():
                for reporter in reporters:
                    reporter.scene(result)
            progress.next(files[k + 1] if k + 1 < len(files) else None)
    elapsed = time.perf_counter() - started
    for reporter in reporters:
        reporter.finish(results, elapsed)
    return results, elapsed


def _errors_to_stderr(results: list[Any]) -> None:
    """Input errors on stderr, once each, when stdout is not the text report (which shows
    them in the scene's block)."""
    from kcheck.report import views
    from kcheck.report.safe import printable

    encoding = getattr(sys.stderr, "encoding", None) or "utf-8"
    for r in results:
        if not r.error:
            continue
        for e in r.errors or ():
            where, message = views.error_line(r.path, e)
            print(printable(f"kcheck: error: {where}: {message}", encoding), file=sys.stderr)
        if not r.errors:
            print(printable(f"kcheck: error: {r.error}", encoding), file=sys.stderr)


def _summary_to_terminal(results: list[Any], elapsed: float, output: Path | None) -> None:
    """With --output the report is in a file; the terminal still gets the run's last line."""
    if output is None:
        return
    from kcheck.report import views
    from kcheck.report.safe import printable

    line = f"{views.run_line(results, elapsed)}; report written to {output}"
    print(printable(line, getattr(sys.stdout, "encoding", None) or "utf-8"))
