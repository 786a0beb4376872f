"""``kcheck check``: check scene files and report, with CI-gate exit codes."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import gc
import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from kcheck.cli.common import (
    ExitCode,
    close_replacing,
    discard_gone,
    discard_stdout,
    fail,
    open_replacing,
)
from kcheck.cli.config import add_gate_options
from kcheck.cli.executors import add_sample_options

if TYPE_CHECKING:
    from kcheck.gate.paths import Excluder
    from kcheck.report import Reporter
    from kcheck.result import SceneResult

__all__ = ["add_parser", "run"]

EPILOG = """\
exit codes:
  0  every check passed (some may be marginal, or checks of severity warning may have
     failed; see --strict)
  1  a check failed
  2  bad input or usage; every other scene is still checked

examples:
  kcheck check parts/                  one line per scene, reasons for failures
  kcheck check parts/ -v               every table, mass properties, sweep plane
  kcheck check parts/ --html review.html --plots plots/
  kcheck check --format github --output-format sarif:kcheck.sarif    in CI
"""

#: The format whose page inlines SVG pictures: asking for it makes the run draw them.
PAGE_FORMAT = "html"


def add_parser(sub: Any) -> None:
    """Register the ``check`` command."""
    from kcheck.report import FORMATS

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
        type=Path,
        help="scene files and folders (searched recursively for *.kcheck.yaml); a mesh file "
        "checks the scenes that use it (default: configuration paths, else .)",
    )
    check.add_argument(
        "--format",
        choices=tuple(FORMATS),
        help="report format on standard output or --output: text (for people), json, "
        "concise (path:line: check: message), github (workflow annotations), markdown "
        "(pull-request comment), junit, sarif, gitlab (GitLab Code Quality), html (one "
        "self-contained page) "
        "(default: text)",
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
    check.add_argument(
        "--exit-zero",
        action="store_true",
        help="exit 0 even when checks failed (bad input or usage still exit 2)",
    )
    check.add_argument(
        "--statistics",
        action="store_true",
        help="after the report, the number of issues per rule, most frequent first (on "
        "standard error)",
    )
    check.add_argument(
        "--baseline",
        type=Path,
        metavar="FILE",
        help="accept the failures recorded in FILE (written by --write-baseline); only new "
        "failures fail the run",
    )
    check.add_argument(
        "--write-baseline",
        type=Path,
        metavar="FILE",
        help="record the run's failures in FILE (exit 0 unless bad input)",
    )
    check.add_argument(
        "--stdin-filename",
        type=Path,
        metavar="PATH",
        help="with the path - (a scene on standard input): take the scene to be at PATH "
        "(meshes relative to its folder; per-path ignores and the baseline match it); "
        "default: the working directory, the scene reported as -",
    )
    add_gate_options(check)
    add_sample_options(check)
    _add_report_options(check)
    check.set_defaults(handler=run)


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
        "its tables and pictures inline as SVG; needs the plot extra for pictures); the same "
        "as --output-format html:FILE",
    )
    group.add_argument(
        "--plot-format",
        default="png",
        metavar="FORMATS",
        help="picture formats for --plots, comma-separated from png, svg (default: png)",
    )


def _slim(result: SceneResult) -> SceneResult:
    """A result without its bulky parts, kept for the end of a batch (Reporter.finish)."""
    checks = tuple(dataclasses.replace(c, cases=(), details={}) for c in result.checks)
    return dataclasses.replace(result, mass_properties=None, checks=checks)


class _Tee:
    """Feeds several reporters; a report file that cannot be written is remembered (and
    kept out of the end: nothing is written half), the others go on. When the reader of
    standard output goes away, its reports stop and the run goes on to its exit code."""

    def __init__(self, reporters: Sequence[tuple[str, Reporter, TextIO]]) -> None:
        self.reporters = list(reporters)
        self.failures: list[str] = []
        self.broken: list[TextIO] = []

    def _each(self, method: str, *args: Any) -> None:
        from kcheck.errors import describe_os_error

        for entry in list(self.reporters):
            label, reporter, stream = entry
            try:
                getattr(reporter, method)(*args)
                if method == "finish":
                    stream.flush()
            except BrokenPipeError:
                self.reporters.remove(entry)
                if stream is sys.stdout:  # the run goes on to its verdict (docs/ci.md)
                    discard_stdout()
                    continue
                self.broken.append(stream)
                self.failures.append(f"cannot write {label}: the reader went away")
            except OSError as exc:
                self.failures.append(f"cannot write {label}: {describe_os_error(exc)}")
                self.reporters.remove(entry)
                self.broken.append(stream)

    def start(self, total: int) -> None:
        self._each("start", total)

    def scene(self, result: SceneResult) -> None:
        self._each("scene", result)

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        self._each("finish", results, elapsed_s)


@contextlib.contextmanager
def _reader_may_go() -> Iterator[None]:
    """Run a step that writes to stdout or stderr; if a reader went away, the rest of the
    step's text is lost with it and the streams whose reader went away write to the null
    device from now on."""
    try:
        yield
    except BrokenPipeError:
        discard_gone()


def _plot_formats(text: str) -> tuple[str, ...] | None:
    from kcheck.pictures import PLOT_FORMATS

    names = tuple(dict.fromkeys(n.strip().lower() for n in text.split(",") if n.strip()))
    return names if names and all(n in PLOT_FORMATS for n in names) else None


@contextlib.contextmanager
def _pictures(
    plots: Path | None, plot_formats: tuple[str, ...], page: bool
) -> Iterator[tuple[Path | None, tuple[str, ...]]]:
    """Where pictures go and in which formats: an HTML page inlines SVG, so with a page the
    pictures include SVG, in a temporary folder when --plots is not given."""
    if not page:
        yield plots, plot_formats
    elif plots is not None:
        yield plots, tuple(dict.fromkeys((*plot_formats, "svg")))
    else:
        import tempfile  # only for an HTML page without --plots (shutil, random: ~10 ms)

        with tempfile.TemporaryDirectory(prefix="kcheck-html-") as tmp:
            yield Path(tmp), ("svg",)


def run(args: argparse.Namespace) -> int:
    """Check every scene, stream the reports, choose the exit code."""
    temporary: list[Path] = []  # the scene read from standard input, removed at the end
    collecting = gc.isenabled()
    frozen = gc.get_freeze_count()
    gc.disable()  # until the scenes run: see _started
    try:
        return _check(args, temporary, collecting)
    finally:
        if not frozen:  # a caller's own frozen objects (kcheck called as a library) stay
            gc.unfreeze()
        if collecting:
            gc.enable()
        for path in temporary:
            path.unlink(missing_ok=True)


def _started(collecting: bool) -> None:
    """Start-up is over: the garbage collector runs again, past what start-up made.

    While kcheck imports numpy, its modules and the checks (about 41,000 objects, nearly all
    kept for the whole run) the collector would run some 45 times and find almost nothing
    (about 5 ms of every start, issue 24). The objects made so far are then frozen
    (:func:`gc.freeze`, Python's recipe for a process that forks workers), so that no later
    collection, here or in a worker, walks them again.
    """
    if not gc.get_freeze_count():
        gc.freeze()  # undone when the command ends (run), for callers of kcheck in-process
    if collecting:
        gc.enable()


def _check(args: argparse.Namespace, temporary: list[Path], collecting: bool) -> int:
    from kcheck.cli.config import cache_folder, effective_config, output_targets, plan_checks
    from kcheck.cli.executors import sample_map
    from kcheck.gate.paths import check_output_dir, check_output_file
    from kcheck.gate.runner import Settings, discover, run_batch
    from kcheck.plugin import load_checks
    from kcheck.report import ReportOptions, make_reporter
    from kcheck.result import Status

    config = effective_config(args)
    sampled = args.sample_jobs or args.dask_local or args.scheduler
    if sampled is not None and args.jobs is not None:
        return fail(
            "-j runs scenes in worker processes; with --sample-jobs, --dask-local or "
            "--scheduler the samples run there and the scenes in this process: give one"
        )
    checks = load_checks()
    plan = plan_checks(config, checks)
    plot_formats = _plot_formats(args.plot_format)
    if plot_formats is None:
        return fail(f"--plot-format: expected png, svg or png,svg; got {args.plot_format!r}")
    # Every output is checked before any scene runs.
    if args.output is not None:
        check_output_file(args.output, "--output")
    targets = output_targets(config)
    if args.html is not None:
        check_output_file(args.html, "--html")
        targets.append((PAGE_FORMAT, args.html))
    _refuse_shared_outputs([("--output", args.output)] if args.output is not None else [], targets)
    if args.plots is not None:
        check_output_dir(args.plots, "--plots")
    page = PAGE_FORMAT in {config["format"], *(name for name, _ in targets)}

    paths = [Path(p) for p in config["paths"]] or [Path(".")]
    exclude = _excluder(config)
    accept, baseline = _acceptance(args, config)
    stdin: tuple[Path, str] | None = None
    if any(str(p) == "-" for p in args.paths or ()):
        if len(args.paths) != 1:
            return fail("`-` (a scene on standard input) cannot be given with other paths")
        stdin = _stdin_scene(args.stdin_filename)
        temporary.append(stdin[0])
        files = [stdin[0]]
        missing: list[SceneResult] = []
    else:
        if args.stdin_filename is not None:
            return fail("--stdin-filename: only with `-` (a scene on standard input)")
        files, missing = discover(paths, exclude)
    if stdin is not None:
        pass  # the one scene, whatever --changed-only or the hook would say
    elif args.pre_commit:
        files, missing = _hook_files(files, missing, args.paths, exclude, _inputs(args))
    elif args.changed_only or args.since:
        from kcheck.gate.vcs import changed_scenes

        files = changed_scenes(
            files, args.since or "HEAD", since=args.since is not None, inputs=_inputs(args)
        )
    options = ReportOptions(
        color=args.color,
        verbosity=1 if args.verbose else -1 if args.quiet else 0,
        to_file=args.output is not None,
        fail_on=config["fail_on"],
        checks={lc.spec.name: lc.check.summary for lc in checks},
        pictures_kept=args.plots is not None,
    )
    streams: list[tuple[str, Reporter, TextIO]] = []
    opened: list[TextIO] = []  # every report file, to put in place or drop at the end

    def open_file(path: Path) -> TextIO:
        opened.append(open_replacing(path))
        return opened[-1]

    # `FORMAT:-` writes that report to standard output, in the place of the main report
    # (which then goes only to --output, if given).
    to_stdout = [name for name, path in targets if str(path) == "-"]
    try:
        if args.output is not None or not to_stdout:
            main_stream = sys.stdout if args.output is None else open_file(args.output)
            label = "the report" if args.output is None else f"the report {args.output}"
            reporter = make_reporter(config["format"], main_stream, options)
            streams.append((label, reporter, main_stream))
        for name, path in targets:
            if str(path) == "-":
                streams.append((f"the {name} report", make_reporter(name, sys.stdout, options),
                                sys.stdout))  # fmt: skip
                continue
            stream = open_file(path)
            file_options = dataclasses.replace(options, to_file=True)
            streams.append(
                (f"the {name} report {path}", make_reporter(name, stream, file_options), stream)
            )
    except BaseException as exc:  # an interrupt too: no report file is left behind
        for stream in opened:
            close_replacing(stream, keep=False)
        if not isinstance(exc, OSError):
            raise
        from kcheck.errors import describe_os_error

        return fail(f"cannot open a report file: {describe_os_error(exc)} ({exc.filename})")
    tee = _Tee(streams)
    finished = False  # an interrupt (or any error) keeps every report file as it was
    try:
        with (
            _pictures(args.plots, plot_formats, page) as (plots, formats),
            sample_map(args, config["timeout"], int(config["memory_limit"] * 2**20)) as samples,
        ):
            settings = Settings(
                allow_outside=config["allow_outside_paths"],
                plots=plots,
                plot_formats=formats,
                severities=plan.severities,
                check_options=plan.options,
                selected=plan.selected,
                named=plan.named,
                cache_dir=cache_folder(config),
                # Samples on an executor: the scenes in this process, in turn (a Dask
                # client does not survive a fork, and the samples hold the cores).
                jobs=0 if samples is not None else config["jobs"] or _cores(),
                timeout_s=config["timeout"],
                memory_bytes=int(config["memory_limit"] * 2**20),
                max_file_bytes=int(config["max_file_size"] * 2**20),
                max_mesh_bytes=int(config["max_mesh_size"] * 2**20),
                sample_map=samples,
            )
            doing = "checking" + (", plotting" if plots is not None else "")
            # The progress line's, once it is shown; first, while the first scenes run in
            # workers, what this process will need for their results.
            ticks: list[Callable[[], None]] = [_Once(_warm_up)]
            _started(collecting)
            batch = run_batch(files, checks, settings, tick=lambda: _each(ticks))
            batch = (accept(r, stdin) for r in batch)
            results, elapsed = _run(tee, files, missing, batch, args, doing, ticks)
        finished = True
    finally:
        from kcheck.errors import describe_os_error

        for label, _, stream in streams:
            if stream in opened:
                try:
                    close_replacing(stream, keep=finished and stream not in tee.broken)
                except OSError as exc:
                    tee.failures.append(f"cannot write {label}: {describe_os_error(exc)}")
    # The verdict decides the exit code even when a reader of stdout or stderr went away
    # (docs/ci.md): what is left for it goes to the null device.
    if to_stdout or not (config["format"] == "text" and args.output is None):
        with _reader_may_go():
            _errors_to_stderr(results)
        with _reader_may_go():
            _summary_to_terminal(results, elapsed, args.output, bool(to_stdout))
    with _reader_may_go():
        for message in tee.failures:
            print(f"kcheck: error: {message}", file=sys.stderr)
    if args.statistics:
        with _reader_may_go():
            _statistics(results, config["fail_on"])
    if baseline is not None:
        with _reader_may_go():
            _stale_baseline(baseline, results, args.baseline)
    states = {r.status for r in results}
    if args.write_baseline is not None:
        from kcheck.gate.suppress import write_baseline
        from kcheck.report.sarif import source_root

        try:
            count = write_baseline(args.write_baseline, results, source_root())
        except OSError as exc:
            from kcheck.errors import describe_os_error

            return fail(f"--write-baseline {args.write_baseline}: {describe_os_error(exc)}")
        with _reader_may_go():
            print(f"kcheck: {count} failures recorded in {args.write_baseline}", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT if Status.ERROR in states else ExitCode.OK
    if Status.ERROR in states or tee.failures:
        return ExitCode.USAGE_OR_INPUT
    if Status.FAIL in states or (
        config["fail_on"] == "warning" and {Status.WARN, Status.MARGINAL} & states
    ):
        return ExitCode.OK if args.exit_zero else ExitCode.CHECKS_FAILED
    return ExitCode.OK


def _acceptance(
    args: argparse.Namespace, config: Any
) -> tuple[Callable[[SceneResult, tuple[Path, str] | None], SceneResult], Any]:
    """What accepts failures (inline suppressions, per-path ignores, the baseline): a
    function from a scene's result to its result with accepted failures set aside, and the
    baseline with its root (None without ``--baseline``), to find its stale entries after."""
    baseline = None
    root = None  # the repository root, for the baseline's keys
    if args.baseline is not None and args.write_baseline is None:
        from kcheck.gate.suppress import Baseline
        from kcheck.report.sarif import source_root  # only then (its imports cost)

        root = source_root()
        try:
            baseline = Baseline.read(args.baseline)
        except ValueError as exc:
            from kcheck.errors import UsageError

            raise UsageError(f"--baseline {args.baseline}: {exc}") from exc
    ignores = None  # none configured: the same answers as an empty table's
    if config["per_path_ignores"]:
        from kcheck.gate.suppress import PathIgnores

        ignores = PathIgnores(config["per_path_ignores"], config.root)

    def accept(result: SceneResult, stdin: tuple[Path, str] | None) -> SceneResult:
        from kcheck.gate.suppress import SuppressionError, apply, inline_suppressions
        from kcheck.result import Finding, Status

        source = Path(result.path)
        if stdin is not None and result.path == str(stdin[0]):
            result = _renamed(result, str(stdin[0]), stdin[1])
        if not result.checks:
            return result
        try:
            text = source.read_text(encoding="utf-8", errors="replace")
        except OSError:
            text = ""
        try:
            inline = inline_suppressions(text)
        except SuppressionError as exc:
            message = str(exc)
            finding = Finding(message, line=exc.line, column=exc.column)
            return dataclasses.replace(
                result, status=Status.ERROR, checks=(), error=message, errors=(finding,)
            )
        return apply(result, inline, ignores, baseline, root)

    return accept, None if baseline is None or root is None else (baseline, root)


def _stale_baseline(baseline: Any, results: Sequence[SceneResult], source: Path) -> None:
    """Warn once about baseline entries no failure matched: a fixed failure left in the file
    would accept a new one of the same rule and field later."""
    entries, root = baseline
    stale = entries.stale(results, root)
    if not stale:
        return
    shown = "; ".join(f"{path} {rule} ({field})" for path, rule, field in stale[:5])
    more = f"; and {len(stale) - 5} more" if len(stale) > 5 else ""
    print(
        f"kcheck: warning: {len(stale)} baseline "
        f"{'entry matches' if len(stale) == 1 else 'entries match'} no failure any more "
        f"(fixed?): {shown}{more}; rewrite {source} with --write-baseline to drop "
        f"{'it' if len(stale) == 1 else 'them'}",
        file=sys.stderr,
    )


def _stdin_scene(name: Path | None) -> tuple[Path, str]:
    """The scene on standard input, written to a temporary file beside where it is taken
    to be (``--stdin-filename``, else the working directory), and its name in reports."""
    import tempfile

    from kcheck.errors import UsageError, describe_os_error

    folder = name.parent if name is not None else Path(".")
    data = sys.stdin.buffer.read()
    try:
        fd, temporary = tempfile.mkstemp(prefix=".kcheck-stdin-", suffix=".kcheck.yaml", dir=folder)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
    except OSError as exc:
        raise UsageError(
            f"cannot hold the scene from standard input in {folder}: {describe_os_error(exc)}"
        ) from exc
    return Path(os.path.relpath(temporary)), str(name) if name is not None else "-"


def _renamed(result: SceneResult, temporary: str, shown: str) -> SceneResult:
    """A result of the standard input's scene under the name it is shown by."""

    def fix(text: str | None) -> str | None:
        return None if text is None else text.replace(temporary, shown)

    errors = tuple(dataclasses.replace(e, message=fix(e.message) or "") for e in result.errors)
    return dataclasses.replace(result, path=shown, error=fix(result.error), errors=errors)


def _statistics(results: Sequence[SceneResult], fail_on: str) -> None:
    """``COUNT  RULE`` per rule, most frequent first, on stderr (ruff's --statistics)."""
    from collections import Counter

    from kcheck.report.issues import issues

    counts = Counter(i.rule for r in results for i in issues(r, fail_on))
    for rule, count in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])):
        print(f"{count:>5}  {rule}", file=sys.stderr)


def _excluder(config: Any) -> Excluder:
    from kcheck.gate.paths import Excluder

    patterns = (*config["exclude"], *config["extend_exclude"])
    return Excluder(patterns, config.root, gitignore=config["respect_gitignore"])


def _inputs(args: argparse.Namespace) -> list[Path]:
    """Files besides scenes, meshes and configuration whose change changes every verdict."""
    return [args.baseline] if args.baseline is not None and args.write_baseline is None else []


def _hook_files(
    everything: list[Path],
    missing: list[SceneResult],
    given: Sequence[Path],
    exclude: Excluder,
    inputs: Sequence[Path] = (),
) -> tuple[list[Path], list[SceneResult]]:
    """The pre-commit hook's scenes: those a change against HEAD affects (among the
    configured paths), and those of the files pre-commit passed (``--all-files``, ``--files``)
    unless excluded (as ruff's ``--force-exclude``: the full run would not check them)."""
    from kcheck.gate.runner import discover
    from kcheck.gate.vcs import changed_scenes

    # `pre-commit run --from-ref A --to-ref B` (CI) says so in the environment: then the
    # change is the branch's, against the merge-base, as for --since.
    from_ref = os.environ.get("PRE_COMMIT_FROM_REF")
    affected = set(
        changed_scenes(everything, from_ref or "HEAD", since=bool(from_ref), inputs=inputs)
    )
    given = [p for p in given if not exclude.forced(p)]
    named, named_missing = discover(given, exclude) if given else ([], [])
    wanted = affected | set(named)
    files = [f for f in everything if f in wanted]
    files += [f for f in named if f not in set(everything)]
    seen = {m.path for m in missing}
    return files, missing + [m for m in named_missing if m.path not in seen]


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


def _each(calls: Sequence[Callable[[], None]]) -> None:
    for call in calls:
        call()


class _Once:
    """A call made the first time only."""

    def __init__(self, call: Callable[[], None]) -> None:
        self.call: Callable[[], None] | None = call

    def __call__(self) -> None:
        call, self.call = self.call, None
        if call is not None:
            call()


def _warm_up() -> None:
    """What this process does with the scenes' results, prepared while the first scenes run
    in workers (the pool's first wait, on another core) instead of after them (issue 24: a
    one-scene run's wall time). Changes nothing: the classes' ``__init__`` written at their
    first instance anyway (:mod:`kcheck.records`), in this process for the slimmed results;
    the module that accepts failures, imported before only when the configuration has
    per-path ignores or a baseline is given."""
    import kcheck.gate.suppress  # noqa: F401 - what accepts failures (_acceptance)
    from kcheck.result import CheckResult, SceneResult

    for cls in (SceneResult, CheckResult):
        cls.__init__  # noqa: B018 - reading it writes it (kcheck.records)


def _cores() -> int:
    from kcheck.gate.config import cpu_count

    return cpu_count()


def _run(
    tee: _Tee,
    files: list[Path],
    missing: list[SceneResult],
    batch: Iterator[SceneResult],
    args: argparse.Namespace,
    doing: str,
    ticks: list[Callable[[], None]],
) -> tuple[list[SceneResult], float]:
    """Feed every reporter each result as it arrives, with a progress line on stderr;
    return the (slimmed) results and the wall time."""
    from kcheck.report.progress import ProgressLine

    started = time.perf_counter()
    tee.start(len(files) + len(missing))
    results: list[SceneResult] = []
    for result in missing:
        results.append(result)
        tee.scene(result)
    with ProgressLine(args.progress, len(files), doing, gone=discard_gone) as progress:
        ticks.append(progress.tick)
        progress.next(files[0] if files else None)
        for k, result in enumerate(batch):
            with progress.paused():
                tee.scene(result)
            results.append(_slim(result))
            progress.next(files[k + 1] if k + 1 < len(files) else None)
    elapsed = time.perf_counter() - started
    tee.finish(results, elapsed)
    return results, elapsed


def _errors_to_stderr(results: list[SceneResult]) -> None:
    """Input errors on stderr, once each, when stdout is not the text report (which shows
    them in the scene's block)."""
    if not any(r.error for r in results):
        return  # the usual case: no report helpers to import (issue 24: start-up)
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


def _summary_to_terminal(
    results: list[SceneResult], elapsed: float, output: Path | None, stdout_taken: bool = False
) -> None:
    """With --output the report is in a file; the terminal still gets the run's last line
    (on stderr when a `FORMAT:-` report holds standard output)."""
    if output is None:
        return
    from kcheck.report import views
    from kcheck.report.safe import printable

    stream = sys.stderr if stdout_taken else sys.stdout
    line = f"{views.run_line(results, elapsed)}; report written to {output}"
    print(printable(line, getattr(stream, "encoding", None) or "utf-8"), file=stream)
