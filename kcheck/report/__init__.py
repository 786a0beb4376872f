"""Reports: every output format is a :class:`Reporter` fed scene results as they finish.

Formats are looked up by name and imported only when asked for (``rich`` only for the text
report), so a JSON run never loads the terminal machinery. A reporter writes to the stream it
was given; the CLI decides where that is (stdout, ``--output``, ``--output-format``).
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from dataclasses import field
from typing import TYPE_CHECKING, Protocol, TextIO

from kcheck.records import dataclass

if TYPE_CHECKING:
    from rich.console import Console

    from kcheck.result import MassProperties, SceneResult

__all__ = [
    "FORMATS",
    "ReportOptions",
    "Reporter",
    "make_reporter",
    "make_console",
    "render_mass",
]

#: Output formats: name -> "module:class" of its reporter.
FORMATS: dict[str, str] = {
    "text": "kcheck.report.text:TextReporter",
    "json": "kcheck.report.json:JsonReporter",
    "concise": "kcheck.report.concise:ConciseReporter",
    "github": "kcheck.report.github:GithubReporter",
    "markdown": "kcheck.report.markdown:MarkdownReporter",
    "junit": "kcheck.report.junit:JunitReporter",
    "sarif": "kcheck.report.sarif:SarifReporter",
    "gitlab": "kcheck.report.gitlab:GitlabReporter",
    "html": "kcheck.report.html:HtmlReporter",
}


@dataclass(frozen=True)
class ReportOptions:
    """What every reporter may honour: colour (``auto``/``always``/``never``, text only),
    verbosity (-1 quiet, 0 default, 1 verbose), whether the stream is a file, the lowest
    severity that fails the run (``fail_on``: ``error`` or ``warning``), the summary of
    every installed check by id (rule descriptions in SARIF), and whether the pictures the
    results name are kept (``pictures_kept``: false when they were drawn into a temporary
    folder only to be inlined in an HTML page)."""

    color: str = "auto"
    verbosity: int = 0
    to_file: bool = False
    fail_on: str = "error"
    checks: Mapping[str, str] = field(default_factory=dict)
    pictures_kept: bool = True


class Reporter(Protocol):
    """Receives a run's results in order: ``start``, one ``scene`` per file, ``finish``."""

    def start(self, total: int) -> None:
        """The run is about to check ``total`` scene files."""

    def scene(self, result: SceneResult) -> None:
        """One scene is done (results arrive in the order of the files)."""

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Every scene is done; ``elapsed_s`` is the wall time of the whole run.

        ``results`` are every scene's result without its bulky parts (cases, details and
        mass properties are dropped by the command line, so a batch of thousands is not all
        held); verdicts, messages and findings are all there. A reporter needing more keeps
        it from ``scene``."""


def make_reporter(name: str, stream: TextIO, options: ReportOptions) -> Reporter:
    """The reporter of a format, writing to ``stream``."""
    module, _, cls = FORMATS[name].partition(":")
    return getattr(importlib.import_module(module), cls)(stream, options)


def make_console(color: str = "auto", file: TextIO | None = None, stderr: bool = False) -> Console:
    """A rich console honouring ``--color`` and NO_COLOR (see :mod:`kcheck.report.text`)."""
    from kcheck.report.text import make_console as make

    return make(color, file=file, stderr=stderr)


def render_mass(
    console: Console, mass: MassProperties, indent: str = "  ", units: str | None = None
) -> None:
    """Mass properties as an engineer reads them, lengths in ``units`` (default m)
    (:func:`kcheck.report.text.render_mass`)."""
    from kcheck.report.text import render_mass as render

    render(console, mass, indent, units)
