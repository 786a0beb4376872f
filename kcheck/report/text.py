"""The terminal report (rich): one line per passing scene, the reasons for every failure, a
short summary at the end.

Verbosity: ``-q`` (-1) only scenes that did not pass and the summary; default (0) one line
per passing scene and, for a scene that did not pass, each check's verdict with its reasons
and hints; ``-v`` (1) every scene in full: sweep plane, mass properties, notes, every check
with its tables. What is said comes from :mod:`kcheck.report.views`; this module only lays
it out. On a terminal prose wraps at the width but numbers never break; anywhere else
(pipes, files, CI logs) nothing wraps, so every line stays whole for grep.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from typing import Any, TextIO

from rich.cells import cell_len, chop_cells
from rich.console import Console
from rich.padding import Padding
from rich.table import Table
from rich.text import Text

from kcheck.report import ReportOptions, tables, views
from kcheck.report.safe import SafeStream
from kcheck.report.safe import stdout as safe_stdout
from kcheck.result import CheckResult, Finding, SceneResult, Status

__all__ = ["TextReporter", "make_console", "render_scene", "render_summary", "render_mass"]

STYLE = {
    "pass": "bold green",
    "marginal": "bold dark_orange",
    "warn": "bold yellow",
    "fail": "bold red",
    "error": "bold magenta",
    "n/a": "dim",
    "not checked": "yellow",
}
OUTCOME_STYLE = {o: "green" for o in views.GOOD_OUTCOMES} | {"swept": "cyan"}
# Width of a console that never wraps (pipes, files): lines stay whole.
UNWRAPPED = 100_000


class _Console(Console):
    """Rich's console, but a reader that goes away is the caller's to handle: rich's own
    answer (:meth:`Console.on_broken_pipe`) ends the process with exit code 1 whatever the
    verdict; here it is the :class:`BrokenPipeError` every other report meets (the command
    line then sends the rest to the null device and exits with the verdict's code)."""

    def on_broken_pipe(self) -> None:
        """Write nothing more, and raise the error being handled again."""
        self.quiet = True
        raise  # noqa: PLE0704 -- called from rich's `except BrokenPipeError:`


def make_console(color: str = "auto", file: TextIO | None = None, stderr: bool = False) -> Console:
    """A console honouring ``--color``: ``auto`` follows the TTY and FORCE_COLOR, and a
    non-empty NO_COLOR turns off every ANSI style, not only colours (plain logs in CI).

    The stream is wrapped in :class:`SafeStream` (no character can crash the report). When
    it is not a terminal, lines wrap at an exported ``COLUMNS`` (a pipe to a pager, a CI log
    of a fixed width) and nothing wraps without it (every line whole for grep).
    """
    kwargs: dict[str, Any] = {"markup": False, "highlight": False, "emoji": False}
    if color == "always":
        kwargs["force_terminal"] = True
    elif color == "never" or os.environ.get("NO_COLOR"):
        kwargs["no_color"] = True
        kwargs["color_system"] = None
    if file is None:
        import sys

        stream = SafeStream(lambda: sys.stderr) if stderr else safe_stdout()
    else:
        stream = file if isinstance(file, SafeStream) else SafeStream(file)
    console = _Console(file=stream, **kwargs)  # type: ignore[arg-type]
    if not console.is_terminal:
        columns = _columns()
        if columns is None:
            console = _Console(file=stream, width=UNWRAPPED, soft_wrap=True, **kwargs)  # type: ignore[arg-type]
        else:
            # Rich pads wrapped cells to the width: lines in a pipe end without the padding.
            trimmed = _Trimmed(lambda: stream.stream)
            console = _Console(file=trimmed, width=columns, **kwargs)  # type: ignore[arg-type]
    return console


class _Trimmed(SafeStream):
    """A safe stream whose lines end without trailing blanks (rich pads a wrapped grid's
    cells to the full width; a pipe or a file should not carry them)."""

    _END = re.compile(r"[ \t]+(?=\n)")

    def write(self, text: str) -> int:
        """Write ``text`` with the blanks before each line end taken off."""
        super().write(self._END.sub("", text))
        return len(text)


def _columns() -> int | None:
    """The width an exported ``COLUMNS`` asks for (at least 40), or None without one."""
    text = os.environ.get("COLUMNS", "").strip()
    if not text.isdigit() or int(text) <= 0:
        return None
    return max(int(text), 40)


def _indented(console: Console, text: Text, indent: int) -> None:
    """Print ``text`` with every wrapped line indented (no indent padding when unwrapped)."""
    console.print(Padding(text, (0, 0, 0, indent), expand=False))


#: Blanks a line never breaks at: between a number and its unit (``0.0866 N``, ``4.2 GPa``,
#: ``28.8 %``) and in a relation with a number (``μ = 0.122``, ``N = -0.0866``).
_GLUED = re.compile(
    r"(?<=\d) (?=[A-Za-zµμ°%Ω][\w·/^²³µμ°%]{0,7}(?!\w))|(?<=[=≤≥<>≈~]) (?=[-−+]?\d)"
    r"|(?<=\w) (?=[=≤≥≈] [-−+]?\d)"
)


def wrap_offsets(text: str, width: int) -> list[int]:
    """Offsets at which to break ``text`` into lines of at most ``width`` cells: at blanks,
    never at a glued one (:data:`_GLUED`); a word wider than ``width`` is cut."""
    glued = {m.start() for m in _GLUED.finditer(text)}
    # Tokens: runs of characters up to and including a breakable blank.
    tokens: list[tuple[int, int]] = []
    start = 0
    for i, ch in enumerate(text):
        if ch == " " and i not in glued and (i + 1 < len(text) and text[i + 1] != " "):
            tokens.append((start, i + 1))
            start = i + 1
    tokens.append((start, len(text)))
    breaks: list[int] = []
    line = 0
    for a, b in tokens:
        size = cell_len(text[a:b].rstrip(" "))
        if line and line + size > width:
            breaks.append(a)
            line = 0
        while size > width:  # a word wider than the line: cut it
            cut = a + len(chop_cells(text[a:b], width)[0])
            breaks.append(cut)
            a, size = cut, cell_len(text[cut:b].rstrip(" "))
        line += cell_len(text[a:b])
    return breaks


def _wrapped(right: Text, width: int) -> list[Text]:
    """``right`` in lines of at most ``width`` cells (:func:`wrap_offsets`), blanks at the
    breaks taken off."""
    lines = right.divide(wrap_offsets(right.plain, max(width, 10))) if right.plain else [right]
    for line in lines:
        line.rstrip()
    return list(lines)


def _hanging(console: Console, indent: int, left: Text, right: Text) -> None:
    """``left`` then ``right``; on a terminal, lines of ``right`` that wrap start under it,
    never between a number and its unit."""
    if console.width >= UNWRAPPED:
        console.print(Text(" " * indent).append_text(left).append_text(right))
        return
    left = Text(" " * indent).append_text(left)
    pad = " " * left.cell_len
    for i, line in enumerate(_wrapped(right, console.width - left.cell_len)):
        console.print((left.copy() if i == 0 else Text(pad)).append_text(line), soft_wrap=True)


def _word(word: str) -> Text:
    return Text(f"{word:<5}", style=STYLE.get(word, "bold"))


def _padded(word: str, width: int) -> str:
    """A verdict in capitals, padded to ``width`` and followed by at least one blank."""
    return f"{word.upper():<{width}}" if len(word) < width else f"{word.upper()} "


def render_mass(
    console: Console, mass: Any, indent: str = "  ", units: str | None = None, notes: bool = True
) -> None:
    """Mass properties as an engineer reads them from a CAD package, in the scene's units."""
    for line in tables.mass_lines(mass, units):
        console.print(f"{indent}{line}")
    for note in mass.notes if notes else ():
        console.print(f"{indent}note: {note}", style="yellow")


def _print_table(console: Console, view: tables.Table, indent: int) -> None:
    """A table, indented, without trailing blanks. When it is wider than the terminal, each
    row becomes one line of ``header value`` pairs instead, so no number is ever cut."""
    _indented(console, Text(view.title, style="dim"), indent)
    table = _table(view)
    width = console.width - indent
    if console.measure(table).maximum > width:
        for row, outcome in zip(view.rows, view.styles, strict=True):
            pairs = Text(row[0], style="bold")
            pairs.append(f"  {row[1]}", style=OUTCOME_STYLE.get(str(outcome), "red"))
            for header, cell in zip(view.headers[2:], row[2:], strict=True):
                pairs.append(f"  {header} {cell}".replace("\n", ", "))
            _hanging(console, indent, Text(), pairs)
        return
    options = console.options.update(width=width)
    for line in console.render_lines(table, options, pad=False, new_lines=False):
        # No style is "" in rich's types (None and a null Style add no span either).
        text = Text.assemble(" " * indent, *((seg.text, seg.style or "") for seg in line))
        text.rstrip()
        console.print(text)


def _table(view: tables.Table) -> Table:
    table = Table(show_header=True, header_style="bold", box=None, pad_edge=False, padding=(0, 1))
    for header, numeric in zip(view.headers, view.numeric, strict=True):
        table.add_column(header, justify="right" if numeric else "left", no_wrap=True)
    for row, outcome in zip(view.rows, view.styles, strict=True):
        cells: list[Any] = list(row)
        cells[1] = Text(cells[1], style=OUTCOME_STYLE.get(str(outcome), "red"))
        table.add_row(*cells)
    return table


def _reason(console: Console, word: str, text: str, line: int | None, hint: str | None) -> None:
    """One reason (``✗ why  (line n)``) and what to change (``→ hint``), hanging at 8."""
    body = Text(text)
    if line is not None:
        body.append(f"  (line {line})", style="dim")
    _hanging(console, 8, Text("✗ ", style=STYLE.get(word, "bold")), body)
    if hint:
        _hanging(console, 8, Text("→ ", style="cyan"), Text(hint, style="cyan"))


def _check_line(console: Console, scene: SceneResult, check: CheckResult) -> None:
    """The verdict of one check, then why (findings and hints) and where checks disagree."""
    word = views.verdict(check)
    line = Text(check.id, style="bold")
    line.append(f"  {views.message(check)}")
    for limit in views.limitations(check):
        line.append(f" ({limit})", style="yellow")
    _hanging(console, 2, _word(word).append(" "), line)
    plane = views.check_sweep_text(scene, check)
    if plane is not None:
        _hanging(console, 8, Text(), Text(plane, style="dim"))
    if word in ("marginal", "fail", "warn", "error") and check.findings:
        for reason in views.reasons(check):
            _reason(console, word, reason.text, reason.line, reason.hint)
    for f in check.suppressed:
        _suppressed(console, 8, f)
    for other in views.disagreements(scene, check):
        _hanging(console, 8, Text("but ", style="bold yellow"), Text(other))


def _suppressed(console: Console, indent: int, finding: Finding, check: str = "") -> None:
    """A suppressed failure, with why it does not count."""
    where = f"  (line {finding.line})" if finding.line is not None else ""
    what = f"{check}: " if check else ""
    _hanging(
        console,
        indent,
        Text("suppressed ", style="dim"),
        Text(f"{what}{finding.message}{where} — {finding.suppressed}", style="dim"),
    )


def _errors(console: Console, scene: SceneResult) -> None:
    """Every input error of the file, once, compiler style: ``path:line:col: field: message``."""
    errors = scene.errors or ()
    if not errors and scene.error:
        _hanging(console, 2, Text(), Text(scene.error, style="magenta"))
        return
    for e in errors:
        where, message = views.error_line(scene.path, e)
        _hanging(console, 2, Text(f"{where}: ", style="bold"), Text(message))
        if e.hint:
            _hanging(console, 4, Text("→ ", style="cyan"), Text(e.hint, style="cyan"))


def render_scene(
    console: Console, scene: SceneResult, verbosity: int = 0, pictures: bool = True
) -> bool | None:
    """One scene: its verdict line; unless it passed (or with -v) the details. Returns
    whether the block ended with a blank line (details do; a one-line scene does not), or
    None when nothing was printed (-q and a passing scene). ``pictures``: whether to list the
    scene's picture files (not when they were only drawn for an HTML page)."""
    word = views.scene_verdict(scene)
    if verbosity < 0 and word == "pass":
        return None
    head = Text(f"{scene.name or scene.path}", style="bold")
    if scene.name:
        head.append(f"  {scene.path}", style="dim")
    headline = views.headline(scene)
    if headline and (word == "pass" or verbosity > 0):
        head.append(f"  {headline}")
    _hanging(console, 0, Text(_padded(word, 7), style=STYLE.get(word, "bold")), head)
    verbose = verbosity > 0
    if word == "pass" and not verbose:
        for check in scene.checks:
            for f in check.suppressed:
                _suppressed(console, 2, f, check.id)
        return False
    if scene.error or scene.errors:
        _errors(console, scene)
        console.print()
        return True
    sweep = views.sweep_text(scene)
    if sweep and (verbose or not views.default_sweep(scene)):
        _hanging(console, 2, Text(), Text(sweep, style="dim"))
    friction = views.friction_text(scene) if verbose else None
    if friction:
        _hanging(console, 2, Text(), Text(friction, style="dim"))
    if verbose and scene.mass_properties is not None:
        render_mass(console, scene.mass_properties, units=scene.units, notes=False)
    for note in scene.notes:
        _hanging(console, 2, Text("note: ", style="yellow"), Text(note))
    if scene.warnings:
        n = len(scene.warnings)
        what = Text("scene", style="bold").append(
            f"  {n} warning{'s' if n > 1 else ''} about the scene itself (not a check's)"
        )
        _hanging(console, 2, _word("warn").append(" "), what)
    for warning in scene.warnings:
        _reason(console, "warn", warning.message, warning.line, warning.hint)
    # A check not checked for want of input always shows, with what to supply; one that
    # does not apply only with -v.
    skipped = [c for c in scene.checks if c.status is Status.SKIPPED and not c.not_checked]
    for check in scene.checks:
        if check in skipped and not verbose:
            continue
        _check_line(console, scene, check)
        if verbose:
            for view in (
                tables.case_table(check, scene.units, scene.kind),
                tables.forces_table(check),
            ):
                if view is not None:
                    _print_table(console, view, 4)
    if skipped and not verbose:
        console.print(f"  {len(skipped)} n/a: {', '.join(c.id for c in skipped)}", style="dim")
    if verbose and pictures:
        for plot in scene.plots:
            console.print(f"  picture: {plot}", style="cyan")
    console.print()
    return True


def render_summary(
    console: Console,
    scenes: Sequence[SceneResult],
    elapsed_s: float,
    plots: int = 0,
    blank: bool = True,
) -> None:
    """pytest-style short summary (one line per failure), then the run's counts and time;
    ``blank``: whether a blank line precedes it already."""
    lines = views.short_summary(scenes)
    if lines:
        if not blank:
            console.print()
        console.print("short summary", style="bold")
        for word, where, text in lines:
            line = Text(where, style="bold")
            line.append(f"  {text}")
            _hanging(console, 0, Text(_padded(word, 6), style=STYLE.get(word, "bold")), line)
    if plots:
        console.print(f"{plots} picture file{'s' if plots > 1 else ''} written", style="cyan")
    n = views.counts(scenes)
    worst = next((k for k in ("error", "fail", "warn", "marginal") if n[k]), "pass")
    console.print(views.run_line(scenes, elapsed_s), style=STYLE[worst])


class TextReporter:
    """The terminal report: each scene as it finishes, then the summary."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        import sys

        color = "never" if options.to_file else options.color
        self.console = make_console(color, file=None if stream is sys.stdout else stream)
        self.options = options
        self.verbosity = options.verbosity
        self.blank = True

    def start(self, total: int) -> None:
        """State the angle convention once, before the first scene."""
        if self.verbosity >= 0 and total:
            _indented(self.console, Text(views.ANGLE_CONVENTION, style="dim"), 0)
            self.console.print()

    def scene(self, result: SceneResult) -> None:
        """Print one scene."""
        blank = render_scene(self.console, result, self.verbosity, self.options.pictures_kept)
        self.blank = self.blank if blank is None else blank

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Print the short summary and the counts."""
        # Pictures drawn only to be inlined in an HTML page are not "written" anywhere.
        plots = sum(len(r.plots) for r in results) if self.options.pictures_kept else 0
        render_summary(self.console, results, elapsed_s, plots, self.blank)
