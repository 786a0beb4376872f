"""GitLab Code Quality: the JSON list GitLab's merge-request widget reads
(``artifacts: reports: codequality``), one entry per issue.

Each entry has ``description``, ``check_name`` (the rule, :mod:`kcheck.report.issues`),
``fingerprint`` (the SARIF one: unique in the report, the same across runs and machines),
``severity`` (``major`` for whatever fails the run, ``minor`` otherwise; ``blocker`` for bad
input, a budget breach or a crash) and ``location`` (the path relative to the repository
root, and the line: 1 when the issue has none).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from kcheck.report.issues import CollectingReporter, clean_text
from kcheck.report.sarif import _relative, fingerprint, issue_key, source_root
from kcheck.result import SceneResult

__all__ = ["GitlabReporter"]


class GitlabReporter(CollectingReporter):
    """Collects issues as scenes finish; writes the Code Quality report at the end."""

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the report."""
        root: Path = source_root()
        entries = []
        seen: dict[str, int] = {}
        for issue in self.issues:
            path = _relative(issue.path, root) or issue.path
            key = issue_key(issue, root)
            seen[key] = seen.get(key, 0) + 1
            if issue.kind == "error":
                severity = "blocker"
            elif issue.level == "error" or issue.counts:
                severity = "major"
            else:
                severity = "minor"
            entries.append(
                {
                    "description": clean_text(issue.text),
                    "check_name": issue.rule,
                    "fingerprint": fingerprint(key, seen[key]),
                    "severity": severity,
                    "location": {"path": clean_text(path), "lines": {"begin": issue.line or 1}},
                }
            )
        self.stream.write(json.dumps(entries, indent=2) + "\n")
