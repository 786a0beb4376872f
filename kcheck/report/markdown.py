"""A pull-request comment in Markdown (GitHub, GitLab): the verdict, a summary table and one
line per failure with its location. Also right for ``$GITHUB_STEP_SUMMARY``.

Long batches stay readable and under comment size limits: with more than
:data:`MAX_TABLE_ROWS` scenes only those that did not pass get a row, and at most
:data:`MAX_ISSUE_LINES` failure lines are listed.
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, TextIO

from kcheck.fmt import format_number, format_percent, format_share
from kcheck.report.issues import CollectingReporter, Issue, clean_text, summary_line
from kcheck.report.views import (
    GOOD_OUTCOMES,
    headline,
    margin_figure,
    margin_text,
    skipped_counts,
    verdict,
)
from kcheck.result import SceneResult, Status

if TYPE_CHECKING:
    from kcheck.report import ReportOptions

__all__ = ["MarkdownReporter", "escape"]

MAX_TABLE_ROWS = 50
MAX_ISSUE_LINES = 200

MARK = {
    Status.PASS: "✅ pass",
    Status.MARGINAL: "🔶 marginal",
    Status.WARN: "⚠️ warn",
    Status.FAIL: "❌ fail",
    Status.ERROR: "🛑 error",
    Status.SKIPPED: "n/a",
}
_SPECIAL = re.compile(r"([\\`*_\[\]<>|#])")


def escape(text: str) -> str:
    """Plain text safe in a table cell or list item (no markup, no line breaks)."""
    return _SPECIAL.sub(r"\\\1", clean_text(text).replace("\r", " ").replace("\n", " "))


def _code(text: str) -> str:
    text = clean_text(text).replace("\n", " ")
    fence = "``" if "`" in text else "`"
    return f"{fence} {text} {fence}" if fence == "``" else f"`{text}`"


def _checks_cell(scene: SceneResult) -> str:
    if not scene.checks:
        return escape(scene.error or "")
    parts = []
    for c in scene.checks:
        if c.status is not Status.SKIPPED:
            # A failed check of severity warning warns: ⚠️, as the text says "warn".
            parts.append(f"{escape(c.id)} {MARK[Status(verdict(c))].split(' ')[0]}")
    parts += [escape(p) for p in skipped_counts(scene.checks)]
    return ", ".join(parts)


def _issue_line(issue: Issue) -> str:
    who = f"**{escape(issue.check)}**" if issue.check else f"**{escape(issue.rule)}**"
    level = " (marginal)" if issue.kind == "marginal" else ""
    level = level or ("" if issue.level == "error" else " (warning)")
    line = f"- {_code(issue.location)} {who}{level}: {escape(issue.subject)}"
    if issue.hint:
        line += f" — _{escape(issue.hint)}_"
    return line


def _not_checked(scene: SceneResult, indent: str = "") -> list[str]:
    """One list item per check not checked for want of input, with its reason (what to
    supply): ``- **hertz** not checked: material of v1's ball unknown ...``."""
    return [
        f"{indent}- **{escape(c.id)}** {escape(c.message)}" for c in scene.checks if c.not_checked
    ]


def _numbers(scene: SceneResult) -> list[str]:
    """The numbers a reviewer needs for a scene that did not pass, one list item per check
    that failed or warned: its design margin, the smallest safe share, the stress
    utilisation, and per case that does not close its outcome and limiting μ (the way out
    is in the failure lines' hints)."""
    out = _not_checked(scene)
    for check in scene.checks:
        word = verdict(check)
        if word not in ("fail", "warn", "marginal"):
            continue
        figures = []
        margin = margin_text(check)
        if margin is not None:
            figures.append(f"design {margin}")
        share = check.details.get("safe_solid_angle_fraction")
        if isinstance(share, (int, float)):
            figures.append(f"{format_share(float(share))} of directions safe")
        if check.safe_ranges_deg is not None and not check.safe_ranges_deg and margin is None:
            figures.append("no safe direction")
        worst = check.details.get("max_utilisation")
        if isinstance(worst, (int, float)):
            figures.append(f"peak contact stress {format_percent(float(worst))} of allowed")
        band = check.details.get("margin")
        if word == "marginal" and isinstance(band, Mapping):
            figures.append(margin_figure(band))
        mark = MARK[Status(word)].split(" ")[0]
        head = f"- **{escape(check.id)}** {mark} {word}"
        out.append(head + (f": {escape('; '.join(figures))}" if figures else ""))
        for case in check.cases:
            if case.outcome in GOOD_OUTCOMES:
                continue
            line = f"  - retract {escape(case.retracted)}: {escape(case.outcome.replace('_', ' '))}"
            mu = case.limiting_friction
            if mu is not None and math.isfinite(mu):
                line += f", closes for μ ≤ {format_number(mu, 3)}"
            pulls = {k: v for k, v in (case.normal_forces or {}).items() if v < 0}
            if pulls:
                line += ", " + ", ".join(
                    f"{escape(k)} N = {format_number(v, 3)} N" for k, v in pulls.items()
                )
            if case.cos_maxwell is not None:
                line += f", cos θ = {case.cos_maxwell:.3f}"
            out.append(line)
    return out


class MarkdownReporter(CollectingReporter):
    """Collects the issues as scenes finish, and the numbers of every scene that did not pass
    (a headline for those that did); writes the comment at the end."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        super().__init__(stream, options)
        self.numbers: list[tuple[str, list[str]]] = []  # scenes that did not pass
        self.passing: list[str] = []
        self.total = 0

    def start(self, total: int) -> None:
        """Note how many scenes come: a long batch lists only the scenes that did not pass."""
        self.total = total

    def scene(self, result: SceneResult) -> None:
        """Keep the scene's issues and its numbers (the result's cases are not kept)."""
        super().scene(result)
        name = _code(result.path) + (f" {escape(result.name)}" if result.name else "")
        if result.status is Status.PASS:
            if self.total <= MAX_TABLE_ROWS:  # as the table: a long batch lists no passing scene
                said = headline(result)
                self.passing.append(f"- ✅ {name}" + (f" — {escape(said)}" if said else ""))
                self.passing += _not_checked(result, "  ")
        elif result.checks and len(self.numbers) < MAX_TABLE_ROWS:
            lines = _numbers(result)
            if lines:
                self.numbers.append((f"{MARK[result.status]} {name}", lines))

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the comment."""
        counts = Counter(r.status for r in results)
        failing = counts[Status.FAIL] + counts[Status.ERROR]
        if self.options.fail_on == "warning":
            failing += counts[Status.WARN] + counts[Status.MARGINAL]
        verdict = "❌ kcheck failed" if failing else "✅ kcheck passed"
        out = [f"## {verdict}", "", summary_line(counts, len(results), elapsed_s), ""]
        rows = [r for r in results if len(results) <= MAX_TABLE_ROWS or r.status is not Status.PASS]
        if rows:
            out += ["| scene | verdict | checks |", "| --- | --- | --- |"]
            for r in rows:
                name = _code(r.path) + (f" {escape(r.name)}" if r.name else "")
                out.append(f"| {name} | {MARK[r.status]} | {_checks_cell(r)} |")
            if len(rows) < len(results):
                out.append(f"\n{len(results) - len(rows)} passing scene(s) not listed.")
            out.append("")
        if self.numbers:
            out += ["### Numbers", ""]
            for head, lines in self.numbers:
                out += [f"{head}", "", *lines, ""]
        if self.passing:
            n = counts[Status.PASS]
            out += [
                f"<details><summary>{n} passing scene{'s' if n > 1 else ''}: key numbers</summary>",
                "",
                *self.passing,
                "",
                "</details>",
                "",
            ]
        if self.issues:
            out += ["### Failures, errors, warnings and marginal results", ""]
            out += [_issue_line(i) for i in self.issues[:MAX_ISSUE_LINES]]
            if len(self.issues) > MAX_ISSUE_LINES:
                out.append(f"- … and {len(self.issues) - MAX_ISSUE_LINES} more")
            out.append("")
        self.stream.write("\n".join(out))
