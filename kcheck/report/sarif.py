"""SARIF 2.1.0 for code scanning (GitHub ``upload-sarif``, GitLab, Azure DevOps).

Each result is located at the scene file and the line of the offending support or field
(``Finding.line``); its ``ruleId`` is stable across runs (``analytical-2d/jams``,
``input-error``; :mod:`kcheck.report.issues`), and ``partialFingerprints`` hash the file,
rule and field, not the line, so an alert survives edits above it. Bad input and crashed
checks are results too, and also make ``invocations[0].executionSuccessful`` false with a
``toolExecutionNotifications`` entry each (the run's exit code is then 2).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from pathlib import PurePath
from typing import Any
from urllib.parse import quote

from kcheck import __version__
from kcheck.report.issues import INPUT_ERROR, CollectingReporter, Issue, clean_text
from kcheck.result import SceneResult

__all__ = ["SarifReporter", "SCHEMA_URI", "artifact_uri"]

SCHEMA_URI = "https://json.schemastore.org/sarif-2.1.0.json"


def artifact_uri(path: str) -> str:
    """A relative path as a relative URI reference; an absolute one as a ``file:`` URI."""
    pure = PurePath(path)
    # A file name that is not UTF-8 reaches Python as lone surrogates: back to its bytes.
    uri = quote(pure.as_posix(), errors="surrogateescape")
    return "file://" + uri if pure.is_absolute() else uri


def _rule_text(rule: str, summaries: dict[str, str]) -> str:
    if rule == INPUT_ERROR:
        return "The scene file is not valid input (file, field and line in the message)."
    if rule.startswith("scene-warning"):
        return "A sanity warning about the scene (units, normals, masses)."
    check, _, code = rule.partition("/")
    summary = summaries.get(check, f"kcheck check {check}")
    if code == "crashed":
        return f"{summary} — the check crashed (a bug: please report it)."
    return f"{summary} — {code}." if code else summary


def _location(issue: Issue) -> dict[str, Any]:
    physical: dict[str, Any] = {"artifactLocation": {"uri": artifact_uri(issue.path)}}
    if issue.line is not None:
        region: dict[str, Any] = {"startLine": issue.line}
        if issue.column is not None:
            region["startColumn"] = issue.column
        physical["region"] = region
    location: dict[str, Any] = {"physicalLocation": physical}
    if issue.field:
        location["logicalLocations"] = [
            {"fullyQualifiedName": clean_text(issue.field), "kind": "member"}
        ]
    return location


def _fingerprint(issue: Issue) -> str:
    what = issue.field if issue.field else issue.message
    return hashlib.sha256(
        f"{issue.path}\0{issue.rule}\0{what}".encode("utf-8", "replace")
    ).hexdigest()


class SarifReporter(CollectingReporter):
    """Collects issues as scenes finish; writes the SARIF log at the end."""

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the log."""
        rule_ids = sorted({i.rule for i in self.issues})
        index = {r: n for n, r in enumerate(rule_ids)}
        summaries = dict(self.options.checks)
        rules = [
            {"id": r, "shortDescription": {"text": clean_text(_rule_text(r, summaries))}}
            for r in rule_ids
        ]
        sarif_results = []
        notifications = []
        for issue in self.issues:
            message = {"text": clean_text(f"{issue.text}")}
            sarif_results.append(
                {
                    "ruleId": issue.rule,
                    "ruleIndex": index[issue.rule],
                    "level": issue.level,
                    "message": message,
                    "locations": [_location(issue)],
                    "partialFingerprints": {"kcheckFinding/v1": _fingerprint(issue)},
                }
            )
            if issue.kind == "error":
                notifications.append(
                    {"level": "error", "message": message, "locations": [_location(issue)]}
                )
        invocation: dict[str, Any] = {"executionSuccessful": not notifications}
        if notifications:
            invocation["toolExecutionNotifications"] = notifications
        log = {
            "$schema": SCHEMA_URI,
            "version": "2.1.0",
            "runs": [
                {
                    "tool": {
                        "driver": {
                            "name": "kcheck",
                            "version": __version__,
                            "semanticVersion": __version__,
                            "rules": rules,
                        }
                    },
                    "invocations": [invocation],
                    "columnKind": "unicodeCodePoints",
                    "results": sarif_results,
                }
            ],
        }
        self.stream.write(json.dumps(log, indent=2) + "\n")
