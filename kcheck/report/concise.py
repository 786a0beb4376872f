"""The concise report: one ``path:line: check: message`` line per issue, for logs and editors
(the form compilers, ruff and mypy use, so editors jump to the line)."""

from __future__ import annotations

from kcheck.report.issues import Issue, LineReporter

__all__ = ["ConciseReporter"]


class ConciseReporter(LineReporter):
    """Each scene's issues as soon as it is done; a summary line at the end."""

    def line(self, issue: Issue) -> str:
        """``path:line: check: message``; warnings say so."""
        what = issue.rule if issue.check is None else issue.check
        if issue.kind == "marginal":
            what += " (marginal)"
        elif issue.level == "warning":
            what += " (warning)"
        return f"{issue.location}: {what}: {issue.text}"
