"""The JSON report (format version in :data:`kcheck.result.JSON_FORMAT_VERSION`)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TextIO

from kcheck import __version__
from kcheck.report import ReportOptions
from kcheck.result import SceneResult, run_json

__all__ = ["JsonReporter"]


class JsonReporter:
    """One JSON document with every scene, written when the run is done."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options

    def start(self, total: int) -> None:
        """Nothing to write before the end."""

    def scene(self, result: SceneResult) -> None:
        """Nothing to write before the end."""

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the whole document."""
        self.stream.write(json.dumps(run_json(results, __version__), indent=2) + "\n")
