"""JUnit XML: one test suite per scene file, one test case per scene × check (GitLab and
Jenkins test reports, Azure Pipelines).

A check that failed is a ``<failure>`` (its ``type`` the rule, its text every finding with
its line); a check that crashed, or a scene whose input is bad, is an ``<error>`` (bad input
as one test case named ``input``); a check that does not apply is ``<skipped>``. A failed
check of severity ``warning`` is a failure only when warnings fail the run (``--strict``);
otherwise the test case passes and carries the warning in ``<system-out>``.
"""

from __future__ import annotations

import socket
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from datetime import datetime, timezone
from typing import TextIO

from kcheck.report import ReportOptions
from kcheck.report.issues import INPUT_ERROR, clean_text, issues
from kcheck.result import SceneResult, Status

__all__ = ["JunitReporter"]


def _text(issue_lines: list[str]) -> str:
    return clean_text("\n".join(issue_lines))


class JunitReporter:
    """Builds a suite per scene as it finishes; writes the document at the end."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options
        self.suites: list[ET.Element] = []
        self.stamp = datetime.now(timezone.utc).replace(microsecond=0).isoformat()

    def start(self, total: int) -> None:
        """Nothing before the end."""

    def scene(self, result: SceneResult) -> None:
        """One test suite for the scene."""
        suite = ET.Element("testsuite", name=clean_text(result.path), timestamp=self.stamp)
        classname = clean_text(result.path)
        found = list(issues(result, self.options.fail_on))
        tally = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}

        def case(name: str, time_s: float) -> ET.Element:
            tally["tests"] += 1
            return ET.SubElement(
                suite, "testcase", name=name, classname=classname, file=classname,
                time=f"{time_s:.6f}",
            )  # fmt: skip

        if result.status is Status.ERROR and not result.checks:
            tc = case("input", result.runtime_s)
            lines = [f"{i.location}: {i.text}" for i in found]
            first = found[0] if found else None
            if first is not None and first.line is not None:
                tc.set("line", str(first.line))
            kind = first.rule if first is not None else INPUT_ERROR  # or a budget's rule
            err = ET.SubElement(
                tc, "error", message=clean_text(result.error or "input error"), type=kind
            )
            err.text = _text(lines)
            tally["errors"] += 1
        for check in result.checks:
            tc = case(check.id, check.runtime_s)
            mine = [i for i in found if i.check == check.id]
            lines = [f"{i.location}: {i.text}" for i in mine]
            lines_at = [i.line for i in mine if i.line is not None]
            if lines_at:
                tc.set("line", str(lines_at[0]))
            if check.status is Status.SKIPPED:
                ET.SubElement(tc, "skipped", message=clean_text(check.message))
                tally["skipped"] += 1
            elif check.status is Status.ERROR:
                el = ET.SubElement(tc, "error", message=clean_text(check.message), type="crashed")
                el.text = _text(lines)
                tally["errors"] += 1
            elif check.status in (Status.FAIL, Status.MARGINAL) and any(i.counts for i in mine):
                el = ET.SubElement(
                    tc, "failure", message=clean_text(check.message), type=mine[0].rule
                )
                el.text = _text(lines)
                tally["failures"] += 1
            elif check.status is Status.FAIL:  # a warning that does not fail the run
                out = ET.SubElement(tc, "system-out")
                out.text = _text([f"warning: {check.message}", *lines])
            elif check.status is Status.MARGINAL:  # marginal, not failing the run
                out = ET.SubElement(tc, "system-out")
                out.text = _text([f"marginal: {check.message}", *lines])
        warnings = [i for i in found if i.kind == "warning"]
        if warnings:
            out = ET.SubElement(suite, "system-out")
            out.text = _text([f"warning: {i.location}: {i.text}" for i in warnings])
        for key, value in tally.items():
            suite.set(key, str(value))
        suite.set("time", f"{result.runtime_s:.6f}")
        self.suites.append(suite)

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the document."""
        root = ET.Element("testsuites", name="kcheck", time=f"{elapsed_s:.6f}")
        for key in ("tests", "failures", "errors", "skipped"):
            root.set(key, str(sum(int(s.get(key, "0")) for s in self.suites)))
        for suite in self.suites:
            suite.set("hostname", clean_text(socket.gethostname()))
            root.append(suite)
        ET.indent(root)
        # ASCII with character references: right on any terminal and in any file encoding.
        body = ET.tostring(root, encoding="us-ascii", xml_declaration=False).decode("ascii")
        self.stream.write('<?xml version="1.0" encoding="utf-8"?>\n' + body + "\n")
