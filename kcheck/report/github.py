"""GitHub Actions workflow commands: an ``::error``/``::warning`` annotation per issue, shown
on the pull request's changed files, then a plain summary line.

Escaping follows actions/toolkit (``packages/core/src/command.ts``): in the message ``%``,
CR and LF are percent-encoded; in properties also ``:`` and ``,``. GitHub shows at most 10
errors and 10 warnings per step, so CI should print a full report too (``docs/ci.md``).
"""

from __future__ import annotations

from kcheck.report.issues import Issue, LineReporter, clean_text

__all__ = ["GithubReporter", "escape_data", "escape_property", "annotation"]


def escape_data(text: str) -> str:
    """A command's message (after ``::``)."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    """A command property's value (``file=``, ``title=``)."""
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def annotation(issue: Issue) -> str:
    """One workflow command line. A warning that fails the run (``fail_on = warning``) is
    an ``::error`` so the annotation matches the exit code."""
    command = "error" if issue.level == "error" or issue.counts else "warning"
    props = [f"file={escape_property(issue.path)}"]
    if issue.line is not None:
        props.append(f"line={issue.line}")
        if issue.column is not None:
            props.append(f"col={issue.column}")
    props.append(f"title={escape_property(f'kcheck ({issue.rule})')}")
    text = f"{issue.location}: {issue.text}"
    return clean_text(f"::{command} {','.join(props)}::{escape_data(text)}")


class GithubReporter(LineReporter):
    """Annotations as each scene finishes; the counts at the end, as a plain line."""

    def line(self, issue: Issue) -> str:
        """One workflow command."""
        return annotation(issue)

    def summary(self, text: str) -> str:
        """Not an annotation."""
        return f"kcheck: {text}"
