"""Scene results as a flat list of located issues: what every CI format (concise, GitHub
annotations, SARIF, Markdown) reports, one line or record each.

An issue is a check's failure (one per finding), a marginal result (its one finding, level
``warning``: it fails the run only with ``fail_on = "warning"``), a check that crashed, an
input error of the scene, a scene past its time or memory budget, or a sanity warning of the
scene. Its ``rule``
is stable across runs (SARIF ``ruleId``, annotation title): ``<check>/<finding code>``
(``analytical-2d/jams``), the check id for a finding without a code (or whose code is the
check id), ``<check>/crashed``, ``input-error``, ``budget-exceeded/time``,
``budget-exceeded/memory``, ``worker-died``, ``internal-error``, ``scene-warning/<code>``
(:data:`KCHECK_RULES` describes kcheck's own).
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Literal, TextIO

from kcheck.records import dataclass
from kcheck.result import CheckResult, Finding, SceneResult, Status

if TYPE_CHECKING:
    from kcheck.report import ReportOptions

__all__ = [
    "Issue",
    "issues",
    "counts_toward_exit",
    "clean_text",
    "summary_line",
    "LineReporter",
    "CollectingReporter",
]

INPUT_ERROR = "input-error"

#: kcheck's own rules (not a check's): id -> (short description, full description). A scene
#: error whose finding carries one of these ids as its code is reported under it.
KCHECK_RULES: dict[str, tuple[str, str]] = {
    INPUT_ERROR: (
        "The scene file is not valid input.",
        "The scene file, or a mesh or path it names, cannot be used: the message gives the "
        "file, the field and the line. The scene's checks did not run; the run exits 2.",
    ),
    "budget-exceeded/time": (
        "Checking the scene ran past its time budget.",
        "The scene's worker ran past the time budget of one scene (--timeout, configuration "
        "`timeout`) and was stopped; the batch went on without it and the run exits 2. The "
        "scene itself may be valid: raise the budget if it is meant to take this long.",
    ),
    "budget-exceeded/memory": (
        "Checking the scene ran out of its memory budget.",
        "The scene's worker ran out of the memory budget of one scene (--memory-limit, "
        "configuration `memory_limit`); the batch went on without it and the run exits 2. The "
        "scene itself may be valid: raise the budget if it is meant to be this large.",
    ),
    "worker-died": (
        "The worker process checking the scene ended.",
        "The worker process checking the scene ended without a result (killed by a signal, "
        "most often past its memory budget); the batch went on and the run exits 2.",
    ),
    "internal-error": (
        "kcheck failed while checking the scene (a bug).",
        "kcheck raised an unexpected exception while reading or checking the scene: a bug, "
        "please report it with the scene. The run exits 2.",
    ),
    "scene-warning": (
        "A sanity warning about the scene.",
        "A sanity warning about the scene (a units slip, a reversed normal, an implausible "
        'mass): shown, and failing the run only with --strict (fail_on = "warning").',
    ),
}

Level = Literal["error", "warning"]


@dataclass(frozen=True)
class Issue:
    """One located thing to report. ``kind``: ``failure`` (a check failed), ``marginal`` (a
    check passed within its marginal band), ``error`` (bad input or a crashed check) or
    ``warning`` (a scene's sanity warning); ``level`` is the severity (``warning`` for a
    marginal result); ``counts`` says whether it fails the run (with the run's ``fail_on``)."""

    path: str
    line: int | None
    column: int | None
    level: Level
    kind: Literal["failure", "marginal", "error", "warning"]
    rule: str
    check: str | None
    message: str
    hint: str | None = None
    field: str | None = None
    counts: bool = True
    #: Why a suppressed failure does not count (it then never counts); None otherwise.
    suppressed: str | None = None

    @property
    def subject(self) -> str:
        """The message on one line, for bad input led by its field."""
        text = " ".join(self.message.splitlines())
        if self.kind == "error" and self.field:
            text = f"field `{self.field}`: {text}"
        return text

    @property
    def text(self) -> str:
        """:attr:`subject` with the hint, for one-line formats."""
        return self.subject if not self.hint else f"{self.subject} (hint: {self.hint})"

    @property
    def location(self) -> str:
        """``path:line:column`` as far as known."""
        out = self.path
        if self.line is not None:
            out += f":{self.line}"
            if self.column is not None:
                out += f":{self.column}"
        return out


def counts_toward_exit(level: Level, fail_on: str) -> bool:
    """Whether an issue of ``level`` fails a run with ``fail_on`` (``error``/``warning``)."""
    return level == "error" or fail_on == "warning"


def _field(finding: Finding) -> str | None:
    from kcheck.errors import format_path

    return None if finding.field is None else format_path(finding.field)


def _failure(
    path: str, check: CheckResult, f: Finding, counts: bool, suppressed: str | None = None
) -> Issue:
    """A failing finding of a check as an issue (a suppressed one never counts)."""
    return Issue(
        path,
        f.line,
        f.column,
        level=check.severity,
        kind="failure",
        rule=f"{check.id}/{f.code}" if f.code and f.code != check.id else check.id,
        check=check.id,
        message=f.message,
        hint=f.hint,
        field=_field(f),
        counts=counts,
        suppressed=suppressed,
    )


def issues(scene: SceneResult, fail_on: str = "error", suppressed: bool = False) -> Iterator[Issue]:
    """Every issue of one scene, in report order (input errors, checks, scene warnings);
    with ``suppressed``, each check's suppressed failures too (after its others)."""
    path = scene.path
    if scene.status is Status.ERROR and not scene.checks:
        for e in scene.errors or (Finding(scene.error or "input error"),):
            yield Issue(
                path,
                e.line,
                e.column,
                level="error",
                kind="error",
                rule=e.code if e.code in KCHECK_RULES else INPUT_ERROR,
                check=None,
                message=e.message,
                hint=e.hint,
                field=_field(e),
            )
    for check in scene.checks:
        if check.status is Status.ERROR:
            yield Issue(
                path,
                None,
                None,
                level="error",
                kind="error",
                rule=f"{check.id}/crashed",
                check=check.id,
                message=check.message,
            )
        elif check.status is Status.FAIL:
            counts = counts_toward_exit(check.severity, fail_on)
            for f in check.findings or (Finding(check.message),):
                yield _failure(path, check, f, counts)
        elif check.status is Status.MARGINAL:
            counts = counts_toward_exit("warning", fail_on)
            for f in check.findings or (Finding(check.message),):
                yield replace(_failure(path, check, f, counts), level="warning", kind="marginal")
        if suppressed:
            for f in check.suppressed:
                yield _failure(path, check, f, False, f.suppressed)
    for w in scene.warnings:
        yield Issue(
            path,
            w.line,
            w.column,
            level="warning",
            kind="warning",
            rule=f"scene-warning/{w.code}" if w.code else "scene-warning",
            check=None,
            message=w.message,
            hint=w.hint,
            field=_field(w),
            counts=counts_toward_exit("warning", fail_on),
        )


_INVALID_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff\ud800-\udfff]")


def clean_text(text: str) -> str:
    """Text any format can carry: control characters and unpaired surrogates replaced by
    U+FFFD (a scene's support name may hold anything YAML allows)."""
    return _INVALID_XML.sub("\ufffd", text)


def summary_line(counts: Mapping[Status, int], total: int, elapsed_s: float | None = None) -> str:
    """``4 scenes: 2 passed, 1 with warnings, 1 failed, 0 with errors (1.2 s)``; marginal
    scenes are counted when there are any."""
    marginal = counts.get(Status.MARGINAL, 0)
    text = (
        f"{total} scene{'s' if total != 1 else ''}: {counts.get(Status.PASS, 0)} passed, "
        + (f"{marginal} marginal, " if marginal else "")
        + f"{counts.get(Status.WARN, 0)} with warnings, {counts.get(Status.FAIL, 0)} failed, "
        f"{counts.get(Status.ERROR, 0)} with errors"
    )
    if elapsed_s is not None:
        text += f" ({elapsed_s:.1f} s)"
    return text


class LineReporter:
    """Base of the formats that write one line per issue as each scene finishes and a
    summary line at the end; subclasses give :meth:`line` and :meth:`summary`."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options

    def line(self, issue: Issue) -> str:
        """One issue's line."""
        raise NotImplementedError

    def summary(self, text: str) -> str:
        """The last line, from :func:`summary_line`."""
        return text

    def start(self, total: int) -> None:
        """Nothing before the first scene."""

    def scene(self, result: SceneResult) -> None:
        """One line per issue."""
        for issue in issues(result, self.options.fail_on):
            self.stream.write(clean_text(self.line(issue)) + "\n")

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """The counts."""
        counts = Counter(r.status for r in results)
        self.stream.write(self.summary(summary_line(counts, len(results))) + "\n")


class CollectingReporter:
    """Base of the formats written whole at the end: keeps every scene's issues (a few
    small records each) in :attr:`issues`; subclasses write in ``finish``."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options
        self.issues: list[Issue] = []

    def start(self, total: int) -> None:
        """Nothing before the end."""

    def scene(self, result: SceneResult) -> None:
        """Keep the scene's issues."""
        self.issues.extend(issues(result, self.options.fail_on))
