"""The JSON report (format version in :data:`kcheck.result.JSON_FORMAT_VERSION`).

Written as scenes finish, nothing held: the document opens at the start, each scene is one
line of compact JSON inside the ``scenes`` array (C encoder; ``indent`` would force the pure
Python one), and the array closes at the end. The layout is ordinary JSON; a scene per line
also makes a batch easy to grep.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TextIO

from kcheck import __version__
from kcheck.report import ReportOptions
from kcheck.result import JSON_FORMAT_VERSION, SceneResult

__all__ = ["JsonReporter"]

_ENCODER = json.JSONEncoder(separators=(", ", ": "))


class JsonReporter:
    """One JSON document with every scene, streamed."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options
        self.count = 0

    def start(self, total: int) -> None:
        """The document's head."""
        head = _ENCODER.encode(
            {"kcheck_version": __version__, "format_version": JSON_FORMAT_VERSION}
        )
        self.stream.write(head[:-1] + ', "scenes": [')

    def scene(self, result: SceneResult) -> None:
        """One scene, on its own line."""
        self.stream.write(("\n" if self.count == 0 else ",\n") + _ENCODER.encode(result.to_json()))
        self.count += 1

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Close the document."""
        self.stream.write("\n]}\n" if self.count else "]}\n")
