"""``kcheck check``: check scene files and report, with CI-gate exit codes."""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from kcheck.cli.common import ExitCode, fail
from kcheck.cli.config import add_gate_options

if TYPE_CHECKING:
    from kcheck.report import Reporter
    from kcheck.result import SceneResult

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``check`` command."""
    from kcheck.report import FORMATS

    check = sub.add_parser(
        "check",
        help="check scene files (default: every *.kcheck.yaml in .)",
        description="Check scene files and report; exit 0 when every check passed, 1 when a "
        "check failed, 2 on bad input or usage (other scenes are still checked).",
    )
    check.add_argument(
        "paths",
        nargs="*",
        type=Path,
        help="scene files and folders (searched recursively for *.kcheck.yaml); a mesh file "
        "checks the scenes that use it (default: configuration `paths`, else .)",
    )
    check.add_argument(
        "--format",
        choices=tuple(FORMATS),
        help="report format on standard output or --output: text (for people), json, "
        "concise (path:line: check: message), github (workflow annotations), markdown "
        "(pull-request comment), junit, sarif (default: text)",
    )
    check.add_argument("--output", "-o", type=Path, help="write the report to this file")
    check.add_argument(
        "--plots",
        type=Path,
        metavar="DIR",
        help="write pictures (PNG and SVG) into DIR (needs the `plot` extra)",
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
    add_gate_options(check)
    check.set_defaults(handler=run)


def _slim(result: SceneResult) -> SceneResult:
    """A result without its bulky parts, kept for the end of a batch (Reporter.finish)."""
    checks = tuple(dataclasses.replace(c, cases=(), details={}) for c in result.checks)
    return dataclasses.replace(result, mass_properties=None, checks=checks)


class _Tee:
    """Feeds several reporters; a report file that cannot be written is remembered, the
    others go on (standard output's broken pipe ends the run as usual)."""

    def __init__(self, reporters: Sequence[tuple[str, Reporter, TextIO]]) -> None:
        self.reporters = list(reporters)
        self.failures: list[str] = []

    def _each(self, method: str, *args: Any) -> None:
        from kcheck.paths import describe_os_error

        for entry in list(self.reporters):
            label, reporter, stream = entry
            try:
                getattr(reporter, method)(*args)
                if method == "finish":
                    stream.flush()
            except BrokenPipeError:
                if stream is sys.stdout:
                    raise
                self.failures.append(f"cannot write {label}: the reader went away")
                self.reporters.remove(entry)
            except OSError as exc:
                self.failures.append(f"cannot write {label}: {describe_os_error(exc)}")
                self.reporters.remove(entry)

    def start(self, total: int) -> None:
        self._each("start", total)

    def scene(self, result: SceneResult) -> None:
        self._each("scene", result)

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        self._each("finish", results, elapsed_s)


def _open(path: Path) -> TextIO:
    path.parent.mkdir(parents=True, exist_ok=True)
    # A scene's path or text may hold lone surrogates (a file name that is not UTF-8).
    return path.open("w", encoding="utf-8", errors="backslashreplace")


def run(args: argparse.Namespace) -> int:
    """Check every scene, stream the report, choose the exit code."""
    from kcheck.cli.config import cache_folder, effective_config, output_targets, plan_checks
    from kcheck.paths import check_output_dir, check_output_file
    from kcheck.plugin import load_checks
    from kcheck.report import FORMATS, ReportOptions, make_reporter
    from kcheck.result import Status
    from kcheck.runner import Settings, discover, run_batch

    config = effective_config(args)
    checks = load_checks()
    plan = plan_checks(config, checks)
    if config["format"] not in FORMATS:
        return fail(f"unknown format `{config['format']}`; known: {', '.join(FORMATS)}")
    # Every output is checked before any scene runs.
    if args.output is not None:
        check_output_file(args.output, "--output")
    targets = output_targets(config)
    _refuse_shared_outputs([("--output", args.output)] if args.output is not None else [], targets)
    if args.plots is not None:
        check_output_dir(args.plots, "--plots")

    paths = [Path(p) for p in config["paths"]] or [Path(".")]
    files, missing = discover(paths)
    if args.changed_only or args.since:
        from kcheck.vcs import changed_scenes

        files = changed_scenes(files, args.since or "HEAD")
    jobs = config["jobs"] or _cores()
    settings = Settings(
        allow_outside=config["allow_outside_paths"],
        plots=args.plots,
        severities=plan.severities,
        check_options=plan.options,
        selected=plan.selected,
        cache_dir=cache_folder(config),
        jobs=jobs,
        timeout_s=config["timeout"],
        memory_bytes=int(config["memory_limit"] * 2**20),
        max_file_bytes=int(config["max_file_size"] * 2**20),
        max_mesh_bytes=int(config["max_mesh_size"] * 2**20),
    )
    options = ReportOptions(
        color=args.color,
        to_file=args.output is not None,
        fail_on=config["fail_on"],
        checks={lc.spec.name: lc.check.summary for lc in checks},
    )
    streams: list[tuple[str, Reporter, TextIO]] = []
    try:
        main_stream = sys.stdout if args.output is None else _open(args.output)
        label = "the report" if args.output is None else f"the report {args.output}"
        streams.append((label, make_reporter(config["format"], main_stream, options), main_stream))
        for name, path in targets:
            stream = _open(path)
            file_options = dataclasses.replace(options, to_file=True)
            streams.append(
                (f"the {name} report {path}", make_reporter(name, stream, file_options), stream)
            )
    except OSError as exc:
        from kcheck.paths import describe_os_error

        for _, _, stream in streams:
            if stream is not sys.stdout:
                stream.close()
        return fail(f"cannot open a report file: {describe_os_error(exc)} ({exc.filename})")
    tee = _Tee(streams)
    results: list[SceneResult] = []
    try:
        started = time.perf_counter()
        tee.start(len(files) + len(missing))
        for result in missing:
            results.append(result)
            tee.scene(result)
        for result in run_batch(files, checks, settings):
            tee.scene(result)
            results.append(_slim(result))
        tee.finish(results, time.perf_counter() - started)
    finally:
        for _, _, stream in streams:
            if stream is not sys.stdout:
                try:
                    stream.close()
                except OSError as exc:
                    tee.failures.append(f"cannot write {stream.name}: {exc.strerror}")
    for r in results:
        if r.status is Status.ERROR and r.error:
            print(f"kcheck: error: {r.error}", file=sys.stderr)
    for message in tee.failures:
        print(f"kcheck: error: {message}", file=sys.stderr)
    states = {r.status for r in results}
    if Status.ERROR in states or tee.failures:
        return ExitCode.USAGE_OR_INPUT
    if Status.FAIL in states or (config["fail_on"] == "warning" and Status.WARN in states):
        return ExitCode.CHECKS_FAILED
    return ExitCode.OK


def _refuse_shared_outputs(
    output: list[tuple[str, Path]], targets: Sequence[tuple[str, Path]]
) -> None:
    """UsageError if two reports would go to one file (each would overwrite the other)."""
    import os
    import stat

    from kcheck.errors import UsageError

    seen: dict[str, str] = {}
    for label, path in [*output, *((f"--output-format {n}:", p) for n, p in targets)]:
        label = f"{label}{path}" if label.endswith(":") else f"{label} {path}"
        try:
            if stat.S_ISCHR(path.stat().st_mode):
                continue  # /dev/null, /dev/stdout: writing twice is harmless
        except (OSError, ValueError):
            pass
        key = os.path.realpath(path)
        if key in seen:
            raise UsageError(
                f"{label}: the same file as {seen[key]}; give each report its own file"
            )
        seen[key] = label


def _cores() -> int:
    from kcheck.config import cpu_count

    return cpu_count()
