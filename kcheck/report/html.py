"""The HTML report: one self-contained page an engineer brings to a design review.

Summary first (the run's verdict, each scene's verdict with a link to its section, every
failure with its reason), then per scene the mass properties and each check's verdict,
explanation, tables and pictures. Pictures are inlined as SVG; the page loads nothing (its
Content-Security-Policy forbids every request), so it opens offline and archives as one file.
What is said comes from :mod:`kcheck.report.views`, like the text report.
"""

from __future__ import annotations

import datetime
import io
import shutil
import tempfile
from collections.abc import Callable, Sequence
from html import escape
from importlib import resources
from pathlib import Path
from typing import TextIO

from kcheck import __version__
from kcheck.report import ReportOptions, tables, views
from kcheck.report.inline_svg import InlineSvg
from kcheck.report.safe import printable
from kcheck.result import CheckResult, SceneResult, Status

__all__ = ["HtmlReporter", "render_page", "write_page"]

#: Nothing may be fetched: no scripts, fonts, images or styles from anywhere.
CSP = "default-src 'none'; style-src 'unsafe-inline'; img-src data:"


def _e(text: object) -> str:
    """Text made safe for HTML and for UTF-8 (a lone surrogate is escaped, never raised)."""
    return escape(printable(str(text), "utf-8"))


def _badge(word: str) -> str:
    css = "na" if word in ("n/a", "not checked") else word
    return f'<span class="badge {css}">{_e(word)}</span>'


def _svg(path: Path) -> str | None:
    """The ``<svg>`` element of a picture file, ready to inline (None if unreadable)."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    start = text.find("<svg")
    return None if start < 0 else text[start:]


def _anchor(index: int) -> str:
    return f"scene-{index + 1}"


def _path(path: str) -> str:
    """A path that breaks only after a slash (never at a hyphen inside a folder name)."""
    parts = _e(path).split("/")
    pieces = [f"{p}/" for p in parts[:-1]] + [parts[-1]]
    return "".join(f'<span class="nobr">{p}</span>' for p in pieces if p)


class TableStyles:
    """One class per distinct table layout (its headers) on a page, and the page's rules for
    it: numeric columns aligned right, and on a narrow screen each cell labelled with its
    column's header (the rows become cards). Written once per layout in the page's head, not
    once per cell: a label in every cell was 2 % of the fixtures' page."""

    def __init__(self) -> None:
        self.layouts: dict[tuple[tuple[str, bool], ...], str] = {}

    def __call__(self, view: tables.Table) -> str:
        """The class of ``view``'s layout."""
        layout = tuple(zip(view.headers, view.numeric, strict=True))
        return self.layouts.setdefault(layout, f"t{len(self.layouts)}")

    def css(self) -> str:
        """The rules of every layout seen."""
        wide, narrow = [], []
        for layout, name in self.layouts.items():
            for k, (header, numeric) in enumerate(layout, 1):
                if numeric:
                    wide.append(f"table.{name} td:nth-child({k}){{text-align:right}}")
                label = header.replace("\\", "\\\\").replace('"', '\\"')
                narrow.append(f'table.{name} td:nth-child({k})::before{{content:"{label}"}}')
        return "".join(wide) + "@media (max-width:700px){" + "".join(narrow) + "}"


def _table(view: tables.Table, styles: TableStyles) -> str:
    head = "".join(
        f'<th class="{"num" if n else ""}">{_e(h)}</th>'
        for h, n in zip(view.headers, view.numeric, strict=True)
    )
    rows = []
    for row, outcome in zip(view.rows, view.styles, strict=True):
        cells = []
        for k, cell in enumerate(row):
            css = ""
            if k == 1 and view.headers[1] == "outcome":
                good = str(outcome) in views.GOOD_OUTCOMES
                css = ' class="outcome-ok"' if good else ' class="outcome-bad"'
            cells.append(f"<td{css}>{_e(cell).replace(chr(10), '<br>')}</td>")
        rows.append(f"<tr>{''.join(cells)}</tr>")
    return (
        f'<div class="table-title">{_e(view.title)}</div>'
        f'<table class="data cards {styles(view)}"><thead><tr>{head}</tr></thead>'
        f"<tbody>{''.join(rows)}</tbody></table>"
    )


def _reasons(check: CheckResult) -> str:
    word = views.verdict(check)
    if word not in ("marginal", "fail", "warn", "error") or not check.findings:
        return ""
    items = []
    for r in views.reasons(check):
        where = "" if r.line is None else f' <span class="where">line {r.line}</span>'
        hint = "" if not r.hint else f'<span class="hint">{_e(r.hint)}</span>'
        items.append(f"<li>{_e(r.text)}{where}{hint}</li>")
    return f'<ul class="reasons">{"".join(items)}</ul>'


def _check(
    scene: SceneResult,
    check: CheckResult,
    pictures: list[tuple[str, str]],
    styles: TableStyles,
) -> str:
    word = views.verdict(check)
    css = "na" if word in ("n/a", "not checked") else word
    if check.status is Status.SKIPPED:
        return (
            f'<article class="check na"><h3>{_badge(word)} {_e(check.id)}'
            f' <span class="muted small">{_e(views.message(check))}</span></h3></article>'
        )
    parts = [f'<article class="check {css}" id="{_e(scene.path)}::{_e(check.id)}">']
    parts.append(f"<h3>{_badge(word)} {_e(check.id)}</h3>")
    limits = "".join(f' <span class="limit">({_e(x)})</span>' for x in views.limitations(check))
    parts.append(f'<p class="message">{_e(check.message)}{limits}</p>')
    plane = views.check_sweep_text(scene, check)
    if plane is not None:
        parts.append(f'<p class="small muted">{_e(plane)}</p>')
    parts.append(_reasons(check))
    for other in views.disagreements(scene, check):
        parts.append(f'<p class="disagree"><b>but</b> {_e(other)}</p>')
    rendered = "".join(_table(t, styles) for t in _tables_of(scene, check))
    if rendered:
        parts.append(f'<div class="tables">{rendered}</div>')
    for name, svg in pictures:
        parts.append(f"<figure>{svg}<figcaption>{_e(name)}</figcaption></figure>")
    parts.append("</article>")
    return "".join(parts)


def _mass(scene: SceneResult) -> str:
    if scene.mass_properties is None:
        return ""
    view = tables.mass_view(scene.mass_properties, scene.units)
    rows = [f"<dt>{_e(label)}</dt><dd>{_e(value)}</dd>" for label, value in view.facts]
    if view.inertia is not None:
        cells = "".join(
            "<tr>" + "".join(f'<td class="num">{_e(c)}</td>' for c in row) + "</tr>"
            for row in view.inertia
        )
        rows.append(
            f"<dt>inertia about the centre of mass ({_e(view.inertia_unit)})</dt>"
            f'<dd><table class="data">{cells}</table></dd>'
        )
    rows += [f"<dt>{_e(label)}</dt><dd>{_e(value)}</dd>" for label, value in view.principal]
    return f'<dl class="mass">{"".join(rows)}</dl>'


def _tables_of(scene: SceneResult, check: CheckResult) -> list[tables.Table]:
    shown = [tables.case_table(check, scene.units, scene.kind), tables.forces_table(check)]
    return [t for t in shown if t is not None]


def _scene(index: int, scene: SceneResult, svgs: dict[str, str], styles: TableStyles) -> str:
    word = views.scene_verdict(scene)
    parts = [f'<section class="scene {word}" id="{_anchor(index)}">']
    parts.append(
        f'<div class="scene-head">{_badge(word)}<h2>{_e(scene.name or scene.path)}</h2></div>'
    )
    facts = [f'<span class="mono">{_e(scene.path)}</span>']
    facts += [_e(x) for x in (scene.kind, scene.units and f"units {scene.units}") if x]
    headline = views.headline(scene)
    if headline:
        facts.append(_e(headline))
    parts.append(f'<div class="facts">{" · ".join(facts)}</div>')
    if scene.errors or scene.error:
        errors = scene.errors or ()
        items = [
            f"<li><b>{_e(where)}</b>: {_e(message)}</li>"
            for where, message in (views.error_line(scene.path, e) for e in errors)
        ] or [f"<li>{_e(scene.error)}</li>"]
        parts.append(f'<ul class="errors">{"".join(items)}</ul></section>')
        return "".join(parts)
    sweep = views.sweep_text(scene)
    if sweep:
        parts.append(f'<p class="small muted">{_e(sweep)}</p>')
    parts.append(_mass(scene))
    for note in scene.notes:
        parts.append(f'<p class="small">note: {_e(note)}</p>')
    for w in scene.warnings:
        where = "" if w.line is None else f" (line {w.line})"
        hint = "" if not w.hint else f'<span class="hint">{_e(w.hint)}</span>'
        parts.append(f'<p class="disagree">warning: {_e(w.message)}{_e(where)}{hint}</p>')
    used: set[str] = set()
    for check in scene.checks:
        mine = [(n, s) for n, s in svgs.items() if n not in used and f"-{check.id}" in n]
        used.update(n for n, _ in mine)
        parts.append(_check(scene, check, mine, styles))
    for name, svg in svgs.items():
        if name not in used:
            parts.append(f"<figure>{svg}<figcaption>{_e(name)}</figcaption></figure>")
    parts.append("</section>")
    return "".join(parts)


def _summary(scenes: Sequence[SceneResult]) -> str:
    rows = []
    for i, scene in enumerate(scenes):
        word = views.scene_verdict(scene)
        if word == "pass":
            what = views.headline(scene)
        else:
            lines = views.short_summary([scene])
            what = "; ".join(text for _, _, text in lines[:3])
            if len(lines) > 3:
                what += f" (and {len(lines) - 3} more)"
        path = f'<div class="where">{_path(scene.path)}</div>' if scene.name else ""
        rows.append(
            f"<tr><td>{_badge(word)}</td>"
            f'<td><a href="#{_anchor(i)}">{_e(scene.name or scene.path)}</a>{path}</td>'
            f"<td>{_e(what)}</td></tr>"
        )
    return f'<table class="summary"><tbody>{"".join(rows)}</tbody></table>'


def _failures(scenes: Sequence[SceneResult]) -> str:
    items = []
    for i, scene in enumerate(scenes):
        for word, where, text in views.short_summary([scene]):
            items.append(
                f'<li>{_badge(word)} <a href="#{_anchor(i)}">{_e(where)}</a> {_e(text)}</li>'
            )
    if not items:
        return ""
    return f'<h2>Failures</h2><ul class="failures">{"".join(items)}</ul>'


def render_page(
    scenes: Sequence[SceneResult], elapsed_s: float, pictures: Sequence[dict[str, str]]
) -> str:
    """The whole page; ``pictures[i]`` maps picture file names of scene ``i`` to SVG."""
    page = io.StringIO()
    write_page(page, scenes, elapsed_s, pictures)
    return page.getvalue()


def write_page(
    stream: TextIO,
    scenes: Sequence[SceneResult],
    elapsed_s: float,
    pictures: Sequence[dict[str, str]],
) -> None:
    """Write the page to ``stream`` a scene at a time: a page of a hundred scenes with
    pictures is some 70 MB, and joined whole it was held four times over (issue 13)."""
    # The head holds the pictures' styles: a first pass finds them, holding no picture.
    inline = InlineSvg()
    for found in pictures:
        for svg in found.values():
            inline(svg)

    # ... and the tables' layouts.
    styles = TableStyles()
    for scene in scenes:
        for check in scene.checks:
            for view in _tables_of(scene, check):
                styles(view)

    def sections(out: TextIO) -> None:
        for i, s in enumerate(scenes):
            svgs = {name: inline(svg) for name, svg in pictures[i].items()}
            out.write(_scene(i, s, svgs, styles))

    _write_page(stream, scenes, elapsed_s, sections, inline.css() + styles.css())


def _write_page(
    stream: TextIO,
    scenes: Sequence[SceneResult],
    elapsed_s: float,
    sections: Callable[[TextIO], None],
    picture_css: str = "",
) -> None:
    """Head, summary, the scenes' sections (written by ``sections``), footer;
    ``picture_css``: the pictures' styles (:meth:`InlineSvg.css`)."""
    n = views.counts(scenes)
    worst = next((k for k in ("error", "fail", "warn", "marginal") if n[k]), "pass")
    style = resources.files("kcheck.report").joinpath("report.css").read_text(encoding="utf-8")
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    stream.write(
        "<!DOCTYPE html>\n"
        '<html lang="en"><head><meta charset="utf-8">'
        f'<meta http-equiv="Content-Security-Policy" content="{CSP}">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>kcheck report: {_e(views.run_line(scenes, elapsed_s))}</title>"
        f"<style>{style}{picture_css}</style></head><body>"
    )
    head = [
        "<main>",
        "<h1>kcheck report</h1>",
        f'<div class="muted small">kcheck {_e(__version__)} · {_e(when)}</div>',
        f'<div class="banner {worst}"><span class="word">{worst.upper()}</span>'
        f'<span class="line">{_e(views.run_line(scenes, elapsed_s))}</span></div>',
        f'<p class="convention">{_e(views.ANGLE_CONVENTION)}</p>',
        "<h2>Scenes</h2>",
        _summary(scenes),
        _failures(scenes),
    ]
    stream.write("".join(head))
    sections(stream)
    stream.write(
        "<footer>Written by kcheck. Lengths in each scene's units, forces in N, "
        "accelerations in m/s², angles in degrees.</footer></main></body></html>\n"
    )


class HtmlReporter:
    """Writes each scene's section, its SVG pictures inlined, to a temporary file as the scene
    arrives, and the page when the run is done: the summary comes first, and the pictures of
    a batch (about 0.7 MB a scene) are never all in memory at once."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        self.stream = stream
        self.options = options
        # Whole results: the ones Reporter.finish gets are slimmed (no cases, no tables).
        self.scenes: list[SceneResult] = []
        self._spool: TextIO | None = None
        self._inline = InlineSvg()
        self._styles = TableStyles()

    def start(self, total: int) -> None:
        """Nothing to write before the end (the summary comes first)."""

    def _sections(self) -> TextIO:
        if self._spool is None:
            # Beside the report when it is a file (its disk has room for the page), else in
            # the temporary folder.
            name = getattr(self.stream, "name", None)
            folder = Path(name).parent if isinstance(name, str) else None
            self._spool = tempfile.TemporaryFile(  # noqa: SIM115 (closed in finish)
                "w+",
                encoding="utf-8",
                errors="backslashreplace",
                dir=folder if folder is not None and folder.is_dir() else None,
            )
        return self._spool

    def scene(self, result: SceneResult) -> None:
        """Write the scene's section now, its SVG pictures read while their folder exists."""
        index = len(self.scenes)
        self.scenes.append(result)
        found: dict[str, str] = {}
        for plot in result.plots:
            path = Path(plot)
            if path.suffix == ".svg":
                svg = _svg(path)
                if svg is not None:
                    found[path.name] = self._inline(svg)
        self._sections().write(_scene(index, result, found, self._styles))

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Write the whole page: head and summary, then the sections as written."""
        spool = self._spool
        try:

            def sections(out: TextIO) -> None:
                if spool is not None:
                    spool.seek(0)
                    shutil.copyfileobj(spool, out, 1 << 20)

            css = self._inline.css() + self._styles.css()
            _write_page(self.stream, self.scenes, elapsed_s, sections, css)
        finally:
            if spool is not None:
                spool.close()
                self._spool = None
