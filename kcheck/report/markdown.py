"""A pull-request comment in Markdown (GitHub, GitLab): the verdict, a summary table and one
line per failure with its location. Also right for ``$GITHUB_STEP_SUMMARY``.

Long batches stay readable and under comment size limits: with more than
:data:`MAX_TABLE_ROWS` scenes only those that did not pass get a row, and at most
:data:`MAX_ISSUE_LINES` failure lines are listed.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Sequence

from kcheck.report.issues import CollectingReporter, Issue, clean_text, summary_line
from kcheck.report.views import verdict
from kcheck.result import SceneResult, Status

__all__ = ["MarkdownReporter", "escape"]

MAX_TABLE_ROWS = 50
MAX_ISSUE_LINES = 200

MARK = {
    Status.PASS: "✅ pass",
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
    skipped = sum(1 for c in scene.checks if c.status is Status.SKIPPED)
    if skipped:
        parts.append(f"{skipped} n/a")
    return ", ".join(parts)


def _issue_line(issue: Issue) -> str:
    who = f"**{escape(issue.check)}**" if issue.check else f"**{escape(issue.rule)}**"
    level = "" if issue.level == "error" else " (warning)"
    line = f"- {_code(issue.location)} {who}{level}: {escape(issue.subject)}"
    if issue.hint:
        line += f" — _{escape(issue.hint)}_"
    return line


class MarkdownReporter(CollectingReporter):
    """Collects the issues as scenes finish; writes the comment at the end."""

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the comment."""
        counts = Counter(r.status for r in results)
        failing = counts[Status.FAIL] + counts[Status.ERROR]
        if self.options.fail_on == "warning":
            failing += counts[Status.WARN]
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
        if self.issues:
            out += ["### Failures, errors and warnings", ""]
            out += [_issue_line(i) for i in self.issues[:MAX_ISSUE_LINES]]
            if len(self.issues) > MAX_ISSUE_LINES:
                out.append(f"- … and {len(self.issues) - MAX_ISSUE_LINES} more")
            out.append("")
        self.stream.write("\n".join(out))
