"""The concise report: one ``path:line: check: message`` line per issue, for logs and editors
(the form compilers, ruff and mypy use, so editors jump to the line)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import TextIO

from kcheck.report import ReportOptions
from kcheck.report.issues import clean_text, issues, summary_line
from kcheck.result import SceneResult

__all__ = ["ConciseReporter"]


class ConciseReporter:
    """Each scene's issues as soon as it is done; a summary line at the end."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options

    def start(self, total: int) -> None:
        """Nothing before the first scene."""

    def scene(self, result: SceneResult) -> None:
        """One line per issue: ``path:line: check: message``; warnings say so."""
        for issue in issues(result, self.options.fail_on):
            what = issue.rule if issue.check is None else issue.check
            if issue.level == "warning":
                what += " (warning)"
            self.stream.write(clean_text(f"{issue.location}: {what}: {issue.text}") + "\n")

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """The counts."""
        counts = Counter(r.status for r in results)
        self.stream.write(summary_line(counts, len(results)) + "\n")
