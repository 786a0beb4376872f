"""SARIF 2.1.0 for code scanning (GitHub ``upload-sarif``, GitLab, Azure DevOps).

Each result is located at the scene file and the line of the offending support or field
(``Finding.line``). File URIs are relative to ``%SRCROOT%`` (``uriBaseId``), the repository
holding the working directory (else the working directory), whose absolute URI is given once
in ``originalUriBaseIds``; a file outside it is an absolute ``file:`` URI.

``ruleId`` is stable across runs (``analytical-2d/jams``, ``input-error``,
``budget-exceeded/time``; :mod:`kcheck.report.issues`), every rule has a short and a full
description and, when kcheck's distribution names its documentation (``Project-URL:
Documentation``), a ``helpUri`` into it. ``level`` follows the severity and whether the
issue fails the run: a warning that fails it (``--strict``, ``fail_on = "warning"``) is an
``error``. ``partialFingerprints`` hash the path relative to ``%SRCROOT%``, the rule and the
field, not the line (an alert survives edits above it) nor the machine; results sharing all
three are told apart by their order (``…/2``), so every fingerprint of a log is unique. Bad
input and crashed checks are results too, and also make ``invocations[0].executionSuccessful``
false with a ``toolExecutionNotifications`` entry each (the run's exit code is then 2).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Sequence
from pathlib import Path, PurePath
from typing import Any
from urllib.parse import quote

from kcheck import __version__
from kcheck.report.issues import KCHECK_RULES, CollectingReporter, Issue, clean_text, issues
from kcheck.result import SceneResult, is_external

__all__ = ["SarifReporter", "SCHEMA_URI", "SRCROOT", "artifact_uri", "source_root", "docs_url"]

SCHEMA_URI = "https://json.schemastore.org/sarif-2.1.0.json"
SRCROOT = "%SRCROOT%"
#: Where each rule is documented, relative to the documentation's root.
CHECKS_PAGE = "checks.md"
CI_PAGE = "ci.md"


def _quote(path: str) -> str:
    # A file name that is not UTF-8 reaches Python as lone surrogates: back to its bytes.
    return quote(path, errors="surrogateescape")


def artifact_uri(path: str) -> str:
    """A relative path as a relative URI reference; an absolute one as a ``file:`` URI."""
    pure = PurePath(path)
    uri = _quote(pure.as_posix())
    return "file://" + uri if pure.is_absolute() else uri


def source_root(start: Path | None = None) -> Path:
    """``%SRCROOT%``: the repository holding ``start`` (default: the working directory; the
    first folder upwards with a ``.git``), else ``start`` itself."""
    here = Path(os.path.abspath(start or Path.cwd()))
    for folder in (here, *here.parents):
        if (folder / ".git").exists():
            return folder
    return here


def docs_url() -> str | None:
    """kcheck's documentation folder as its distribution names it (``Project-URL:
    Documentation, …``), ending in ``/``; None when it names none."""
    import importlib.metadata

    try:
        urls = importlib.metadata.metadata("kcheck").get_all("Project-URL") or []
    except importlib.metadata.PackageNotFoundError:
        return None
    for entry in urls:
        label, _, url = str(entry).partition(",")
        if label.strip().lower() == "documentation" and url.strip():
            return url.strip().rstrip("/") + "/"
    return None


def _relative(path: str, root: Path) -> str | None:
    """``path`` relative to ``root`` as a POSIX path, or None when it lies outside."""
    absolute = Path(os.path.abspath(path))
    try:
        return absolute.relative_to(root).as_posix()
    except ValueError:
        return None


def _rule(rule: str, summaries: dict[str, str], docs: str | None) -> dict[str, Any]:
    """A rule's descriptor: short and full description, help, and a link into the docs."""
    check, _, code = rule.partition("/")
    if rule in KCHECK_RULES or check in KCHECK_RULES:
        short, full = KCHECK_RULES.get(rule) or KCHECK_RULES[check]
        page, anchor = CI_PAGE, "rules"
    else:
        summary = summaries.get(check, f"kcheck check {check}")
        short = f"{summary} — {code}." if code else f"{summary}."
        if code == "crashed":
            short = f"{summary} — the check crashed (a bug: please report it)."
            full = f"The check `{check}` raised an exception: a bug in the check; the run exits 2."
        elif code == "marginal":
            short = f"{summary} — marginal: passes, but closer to failing than its minimum margin."
            full = (
                f"The check `{check}` ({summary}) passed, but its margin is below the minimum "
                "margin its options ask for (a marginal result, level warning: it fails the run "
                f"only with --strict). Described in {CHECKS_PAGE}, section `marginal-results`."
            )
        else:
            full = (
                f"The check `{check}` ({summary}) failed"
                + (f" with a finding of kind `{code}`" if code else "")
                + f"; the message says why and where. Described in {CHECKS_PAGE}, "
                f"section `{check}`."
            )
        page, anchor = CHECKS_PAGE, check
    descriptor: dict[str, Any] = {
        "id": rule,
        "shortDescription": {"text": clean_text(short)},
        "fullDescription": {"text": clean_text(full)},
        "help": {"text": clean_text(f"{full} (kcheck's docs/{page}, section `{anchor}`)")},
    }
    if docs is not None:
        descriptor["helpUri"] = f"{docs}{page}#{anchor}"
    return descriptor


class SarifReporter(CollectingReporter):
    """Collects issues as scenes finish; writes the SARIF log at the end."""

    #: ``%SRCROOT%`` (:func:`source_root`), found when the log is written.
    root: Path = Path("/")

    def _location(self, issue: Issue) -> dict[str, Any]:
        relative = _relative(issue.path, self.root)
        artifact: dict[str, Any] = (
            {"uri": artifact_uri(issue.path)}
            if relative is None
            else {"uri": _quote(relative), "uriBaseId": SRCROOT}
        )
        physical: dict[str, Any] = {"artifactLocation": artifact}
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

    def _key(self, issue: Issue) -> str:
        """What identifies an issue across runs and machines: its path relative to
        ``%SRCROOT%`` (else as given), rule, and field (else message)."""
        return issue_key(issue, self.root)

    def scene(self, result: SceneResult) -> None:
        """Keep the scene's issues, suppressed failures included (SARIF ``suppressions``)."""
        self.issues.extend(issues(result, self.options.fail_on, suppressed=True))

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the log."""
        self.root = source_root()
        rule_ids = sorted({i.rule for i in self.issues})
        index = {r: n for n, r in enumerate(rule_ids)}
        summaries = dict(self.options.checks)
        docs = docs_url()
        rules = [_rule(r, summaries, docs) for r in rule_ids]
        sarif_results = []
        notifications = []
        seen: dict[str, int] = {}
        for issue in self.issues:
            message = {"text": clean_text(f"{issue.text}")}
            key = self._key(issue)
            seen[key] = seen.get(key, 0) + 1
            entry: dict[str, Any] = {
                "ruleId": issue.rule,
                "ruleIndex": index[issue.rule],
                "level": "error" if issue.level == "error" or issue.counts else "warning",
                "message": message,
                "locations": [self._location(issue)],
                "partialFingerprints": {"kcheckFinding/v2": fingerprint(key, seen[key])},
            }
            if issue.suppressed is not None:
                entry["suppressions"] = [
                    {
                        "kind": "external" if is_external(issue.suppressed) else "inSource",
                        "justification": clean_text(issue.suppressed),
                    }
                ]
            sarif_results.append(entry)
            if issue.kind == "error":
                notifications.append(
                    {"level": "error", "message": message, "locations": [self._location(issue)]}
                )
        invocation: dict[str, Any] = {"executionSuccessful": not notifications}
        if notifications:
            invocation["toolExecutionNotifications"] = notifications
        driver: dict[str, Any] = {
            "name": "kcheck",
            "version": __version__,
            "semanticVersion": __version__,
            "rules": rules,
        }
        if docs is not None:
            driver["informationUri"] = docs
        log = {
            "$schema": SCHEMA_URI,
            "version": "2.1.0",
            "runs": [
                {
                    "tool": {"driver": driver},
                    "originalUriBaseIds": {
                        SRCROOT: {"uri": artifact_uri(self.root.as_posix()).rstrip("/") + "/"}
                    },
                    "invocations": [invocation],
                    "columnKind": "unicodeCodePoints",
                    "results": sarif_results,
                }
            ],
        }
        self.stream.write(json.dumps(log, indent=2) + "\n")


def issue_key(issue: Issue, root: Path) -> str:
    """What identifies an issue across runs and machines: its path relative to ``root``
    (else as given), rule, and field (else message)."""
    path = _relative(issue.path, root) or issue.path
    what = issue.field if issue.field else issue.message
    return f"{path}\0{issue.rule}\0{what}"


def fingerprint(key: str, occurrence: int = 1) -> str:
    """The partial fingerprint of an issue's key (:meth:`SarifReporter._key`) and its
    occurrence among the log's issues of the same key (1 for the first)."""
    digest = hashlib.sha256(key.encode("utf-8", "replace")).hexdigest()
    return digest if occurrence == 1 else f"{digest}/{occurrence}"
