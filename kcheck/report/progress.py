"""The progress line on stderr: ``[5/13] parts/arm.kcheck.yaml … checking, plotting  12 s``.

Shown while scenes are checked when stderr is a terminal (``--progress auto``); it disappears
when the run ends, and steps aside (:meth:`ProgressLine.paused`) whenever the report prints a
scene, so the two never mix on a shared screen. It never goes to a pipe or a file.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rich.text import Text

__all__ = ["ProgressLine"]


class _Line:
    """The renderable: recomputed at each refresh so the elapsed time runs."""

    def __init__(self, total: int, doing: str) -> None:
        self.total = total
        self.doing = doing
        self.done = 0
        self.current: str | None = None
        self.started = time.perf_counter()

    def __rich__(self) -> Text:
        from rich.text import Text

        text = Text()
        if self.current is None:
            return text
        text.append(f"[{min(self.done + 1, self.total)}/{self.total}] ", style="bold")
        text.append(self.current or "")
        text.append(f" … {self.doing}", style="dim")
        text.append(f"  {time.perf_counter() - self.started:.0f} s", style="dim")
        return text


class ProgressLine:
    """A transient one-line progress display on stderr (a no-op when not wanted)."""

    def __init__(
        self,
        mode: str,
        total: int,
        doing: str = "checking",
        gone: Callable[[], None] | None = None,
    ) -> None:
        """``gone``: called once when stderr cannot be written any more (its reader went
        away); the line then stops and the run goes on without it."""
        tty = bool(getattr(sys.stderr, "isatty", None) and sys.stderr.isatty())
        self.enabled = total > 0 and (mode == "always" or (mode == "auto" and tty))
        self.line = _Line(total, doing)
        self.live: Any = None
        self.gone = gone

    def _live(self, method: str) -> None:
        """Call the display's ``method``; a stderr that fails ends the display, not the run
        (a progress line is never worth an exit code)."""
        if self.live is None:
            return
        try:
            getattr(self.live, method)()
        except OSError:
            self.live = None
            if self.gone is not None:
                self.gone()

    def __enter__(self) -> ProgressLine:
        if self.enabled:
            from rich.live import Live

            from kcheck.report.text import make_console

            console = make_console("auto", stderr=True)
            if not console.is_terminal:
                console = make_console("always", stderr=True)
            self.live = Live(
                self.line,
                console=console,
                transient=True,
                redirect_stdout=False,
                redirect_stderr=False,
                # No refresh thread: the batch forks workers, and a fork while a thread runs
                # may deadlock the child (Python 3.12 warns); the batch calls tick() instead.
                auto_refresh=False,
            )
            self._live("start")
        return self

    def __exit__(self, *exc: object) -> None:
        self._live("stop")
        self.live = None

    def tick(self) -> None:
        """Redraw the line (its clock runs): called by the batch while it waits."""
        self._live("refresh")

    def next(self, path: Path | str | None) -> None:
        """The scene now being checked (None: the last one is done)."""
        if self.line.current is not None:
            self.line.done += 1
        self.line.current = None if path is None else str(path)
        self._live("refresh")

    @contextmanager
    def paused(self) -> Iterator[None]:
        """Take the line off the screen while the report prints, then put it back."""
        if self.live is None:
            yield
            return
        self._live("stop")
        try:
            yield
        finally:
            self._live("start")
