"""Reports: every output format is a :class:`Reporter` fed scene results as they finish.

Formats are looked up by name and imported only when asked for (``rich`` only for the text
report), so a JSON run never loads the terminal machinery. A reporter writes to the stream it
was given; the CLI decides where that is (stdout, ``--output``, ``--output-format``).
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, TextIO

if TYPE_CHECKING:
    from rich.console import Console

    from kcheck.mass import MassProperties
    from kcheck.result import SceneResult

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
    "html": "kcheck.report.html:HtmlReporter",
}


@dataclass(frozen=True)
class ReportOptions:
    """What every reporter may honour: colour (``auto``/``always``/``never``, text only),
    verbosity (-1 quiet, 0 default, 1 verbose) and whether the stream is a file."""

    color: str = "auto"
    verbosity: int = 0
    to_file: bool = False


class Reporter(Protocol):
    """Receives a run's results in order: ``start``, one ``scene`` per file, ``finish``."""

    def start(self, total: int) -> None:
        """The run is about to check ``total`` scene files."""

    def scene(self, result: SceneResult) -> None:
        """One scene is done (results arrive in the order of the files)."""

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Every scene is done; ``elapsed_s`` is the wall time of the whole run."""


def make_reporter(name: str, stream: TextIO, options: ReportOptions) -> Reporter:
    """The reporter of a format, writing to ``stream``."""
    module, _, cls = FORMATS[name].partition(":")
    return getattr(importlib.import_module(module), cls)(stream, options)  # type: ignore[no-any-return]


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
