"""SVG pictures made light for inlining in one HTML page (the fixtures' page: 4.7 MB to < 2 MB).

matplotlib writes every element's whole style inline (``style="fill: none; stroke: ..."``),
coordinates to a micro-point, a wrapper group per artist, random 11-character ids and an
RDF block per picture. On one page the same few dozen styles repeat thousands of times, so
:class:`InlineSvg` gives each distinct style one short class, written once in the page's
``<style>`` (:meth:`InlineSvg.css`), rounds coordinates to 0.1 pt (0.13 px at the page's
widest, below what a screen shows), drops empty wrapper groups and the metadata, and renames
ids to short page-unique names (several pictures on one page never pick up each other's clip
paths or markers). What a picture shows, and every text in it, is unchanged.
"""

from __future__ import annotations

import re

__all__ = ["InlineSvg"]

_METADATA = re.compile(r"<metadata>.*?</metadata>", re.S)
_DEFS_STYLE = re.compile(r"<defs>\s*<style[^>]*>[^<]*</style>\s*</defs>")
_TAG = re.compile(r"<(/?)g(\s[^>]*)?>")
_ID = re.compile(r'\bid="([^"]+)"')
_STYLE = re.compile(r'<(\w+)([^<>]*?) style="([^"]*)"')
_COORDS = re.compile(r'(?<=\s)(points|x|y|width|height)="([^"]*)"')
_PATH = re.compile(r'(?<=\s)d="([^"]*)"')
_PATH_TOKEN = re.compile(r"[MLQCZz]|-?\d+(?:\.\d+)?")
#: Numbers each command of a path takes (matplotlib writes only these, all absolute).
_ARITY = {"M": 2, "L": 2, "Q": 4, "C": 6}
_NUMBER = re.compile(r"-?\d+\.\d+")
_ZERO_ROTATION = re.compile(r' transform="rotate\(-?0 [^)"]*\)"')
_SPACE_AROUND_COMMAND = re.compile(r" ?([MLHVCSQTAZmlhvcsqtaz]) ?")

_SHORT_DEF = re.compile(
    r'<path id="([\w-]+)" d="m(-?[\d.]+) ?(-?[\d.]+)([a-z\d .-]*)"( class="\w+")?/>'
)
_USE = re.compile(r'<use href="#([\w-]+)" x="(-?[\d.]+)" y="(-?[\d.]+)"( class="\w+")?/>')
#: A stretch of sibling leaf elements (no group opens or closes inside it): drawing order
#: between them matters only where they overlap.
_LEAF_RUN = re.compile(r"(?:<(?:path|use|rect)\b[^<>]*/>){2,}")
#: A mark drawn by reference (a tick, a cross) this short is cheaper written out in one path
#: per run of references (``M x y v3.5`` per tick, 15 bytes, against 45 for a ``<use>``).
SHORT_MARK = 16

_CLIPPED = re.compile(r'<(?:path|use|rect)\b[^<>]*?( clip-path="url\(#([\w-]+)\)")[^<>]*/>')
_PNG = re.compile(r"data:image/png;base64,([A-Za-z0-9+/=]+)")

#: Distance (in 0.1 pt) a dropped point of a polyline may lie from the line drawn: 0.15 pt,
#: 0.2 px on the page's widest pictures, below a screen's pixel.
TOLERANCE = 1.5
#: The style matplotlib puts in every SVG (a universal rule), written once per page instead.
SVG_BASE_CSS = "svg *{stroke-linejoin:round;stroke-linecap:butt}"


def _round(match: re.Match[str]) -> str:
    text = f"{float(match.group(0)):.1f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def _coordinates(match: re.Match[str]) -> str:
    name, value = match.group(1), match.group(2)
    return f'{name}="{_NUMBER.sub(_round, value)}"'


def _tenths(value: int) -> str:
    """A length in tenths of a point, written short (``-.3``, ``12``, ``4.5``)."""
    sign = "-" if value < 0 else ""
    whole, tenth = divmod(abs(value), 10)
    if not tenth:
        return f"{sign}{whole}"
    return f"{sign}{whole or ''}.{tenth}"


def _numbers(values: list[int]) -> str:
    out = ""
    for v in values:
        text = _tenths(v)
        # A minus sign separates a number from the one before; else a space.
        out += text if not out or text[0] == "-" else f" {text}"
    return out


def _simplify(points: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Douglas-Peucker: the polyline's corners, every dropped point within
    :data:`TOLERANCE` of the kept segment beside it (on the 0.1 pt grid)."""
    if len(points) < 3:
        return points
    keep = [False] * len(points)
    keep[0] = keep[-1] = True
    stack = [(0, len(points) - 1)]
    while stack:
        first, last = stack.pop()
        (ax, ay), (bx, by) = points[first], points[last]
        dx, dy = bx - ax, by - ay
        length2 = dx * dx + dy * dy
        worst, where = -1.0, -1
        for k in range(first + 1, last):
            px, py = points[k][0] - ax, points[k][1] - ay
            t = 0.0 if length2 == 0 else min(1.0, max(0.0, (px * dx + py * dy) / length2))
            ex, ey = px - t * dx, py - t * dy
            distance2 = ex * ex + ey * ey
            if distance2 > worst:
                worst, where = distance2, k
        if worst > TOLERANCE * TOLERANCE:
            keep[where] = True
            stack += [(first, where), (where, last)]
    return [p for p, kept in zip(points, keep, strict=True) if kept]


def _commands(d: str) -> list[tuple[str, list[int]]] | None:
    """Path data as absolute commands on the 0.1 pt grid (None for data this does not know)."""
    tokens = _PATH_TOKEN.findall(d)
    if "".join(tokens) != "".join(d.split()):
        return None
    commands: list[tuple[str, list[int]]] = []
    i = 0
    while i < len(tokens):
        command = tokens[i].upper()
        i += 1
        n = 0 if command == "Z" else _ARITY.get(command)
        if n is None or i + n > len(tokens):
            return None
        try:
            commands.append((command, [round(float(t) * 10) for t in tokens[i : i + n]]))
        except ValueError:
            return None
        i += n
    return commands


def _relative(d: str) -> str | None:
    """Path data in relative commands on a 0.1 pt grid: each point is rounded on its own and
    the steps taken between rounded points, so no error adds up along a path; runs of line
    segments lose the points within 0.15 pt of the simplified line (:func:`_simplify`).
    None for data this does not know (then the path is only rounded)."""
    commands = _commands(d)
    if commands is None:
        return None
    out: list[str] = []
    x = y = x0 = y0 = 0
    last = ""

    def emit(letter: str, steps: list[int]) -> None:
        nonlocal last
        if letter == "l" and steps[1] == 0 and steps[0]:
            letter, steps = "h", steps[:1]
        elif letter == "l" and steps[0] == 0 and steps[1]:
            letter, steps = "v", steps[1:]
        out.append(("" if last == letter and letter != "m" else letter) + _numbers(steps))
        last = letter

    i = 0
    while i < len(commands):
        command, points = commands[i]
        if command == "L":
            run = [(x, y)]
            while i < len(commands) and commands[i][0] == "L":
                run.append((commands[i][1][0], commands[i][1][1]))
                i += 1
            for px, py in _simplify(run)[1:]:
                emit("l", [px - x, py - y])
                x, y = px, py
            continue
        i += 1
        if command == "Z":
            out.append("z")
            last = "z"
            x, y = x0, y0
            continue
        emit(command.lower(), [p - (x if k % 2 == 0 else y) for k, p in enumerate(points)])
        if command == "M":
            x0, y0 = points
        x, y = points[-2], points[-1]
    text = ""
    for part in out:
        text += part if not text or part[0] in "-mlhvqcz" else f" {part}"
    return text


def _path(match: re.Match[str]) -> str:
    d = match.group(1)
    short = _relative(d)
    if short is None:
        short = _SPACE_AROUND_COMMAND.sub(r"\1", " ".join(_NUMBER.sub(_round, d).split()))
    return f'd="{short}"'


def _ungroup(svg: str) -> str:
    """Drop ``<g>`` wrappers that carry no attribute (and their closing tags)."""
    kept: list[bool] = []

    def tag(match: re.Match[str]) -> str:
        if match.group(1):
            return match.group(0) if kept.pop() else ""
        attributes = (match.group(2) or "").strip()
        kept.append(bool(attributes))
        return match.group(0) if attributes else ""

    return _TAG.sub(tag, svg)


def _clip_groups(svg: str) -> str:
    """Neighbouring elements clipped by the same path, as one clipped group (the same pixels:
    a group is clipped as each of its members would be)."""
    out: list[str] = []
    end = 0
    run: list[re.Match[str]] = []

    def close() -> None:
        if len(run) == 1:
            out.append(run[0].group(0))
        elif run:
            members = "".join(m.group(0).replace(m.group(1), "", 1) for m in run)
            out.append(f"<g{run[0].group(1)}>{members}</g>")
        run.clear()

    for match in _CLIPPED.finditer(svg):
        if run and (match.start() != end or match.group(2) != run[0].group(2)):
            close()
        if not run:
            out.append(svg[end : match.start()])
        run.append(match)
        end = match.end()
    close()
    out.append(svg[end:])
    return "".join(out)


def _merge_marks(svg: str) -> str:
    """The ``<use>`` of one short relative mark (axis ticks) among sibling leaf elements, as
    one path drawn where the last of them was: the same strokes at the same places, above the
    grid lines they alternated with (which they touch only at an end point), in the style the
    mark's own class gives (only references that add no other class are merged)."""
    marks = {
        m.group(1): (
            round(float(m.group(2)) * 10),
            round(float(m.group(3)) * 10),
            m.group(4),
            m.group(5) or "",
        )
        for m in _SHORT_DEF.finditer(svg)
        if len(m.group(2)) + len(m.group(3)) + len(m.group(4)) + 2 <= SHORT_MARK
    }
    if not marks:
        return svg

    def run(match: re.Match[str]) -> str:
        text = match.group(0)
        by_mark: dict[str, list[re.Match[str]]] = {}
        for use in _USE.finditer(text):
            mark = marks.get(use.group(1))
            if mark is not None and (use.group(4) or mark[3]) == mark[3]:
                by_mark.setdefault(use.group(1), []).append(use)
        merged = {key: uses for key, uses in by_mark.items() if len(uses) > 1}
        if not merged:
            return text
        out, end = [], 0
        last = {uses[-1].start(): key for key, uses in merged.items()}
        for use in sorted((u for uses in merged.values() for u in uses), key=lambda u: u.start()):
            out.append(text[end : use.start()])
            end = use.end()
            key = last.get(use.start())
            if key is not None:
                dx, dy, rest, css = marks[key]
                d = "".join(
                    f"M{_tenths(round(float(u.group(2)) * 10) + dx)} "
                    f"{_tenths(round(float(u.group(3)) * 10) + dy)}{rest}"
                    for u in merged[key]
                )
                out.append(f'<path d="{d}"{css}/>')
        out.append(text[end:])
        return "".join(out)

    return _LEAF_RUN.sub(run, svg)


def _webp(match: re.Match[str]) -> str:
    """An embedded PNG as lossless WebP when that is smaller (the same pixels; every browser
    since 2020 shows WebP, the page is read only in a browser)."""
    import base64
    import io

    from PIL import Image

    raw = base64.b64decode(match.group(1))
    try:
        with Image.open(io.BytesIO(raw)) as picture:
            out = io.BytesIO()
            picture.convert("RGBA").save(out, "WEBP", lossless=True, quality=100, method=4)
    except (OSError, ValueError, KeyError):  # Pillow built without WebP: the PNG stays
        return match.group(0)
    if len(out.getvalue()) >= len(raw):
        return match.group(0)
    return "data:image/webp;base64," + base64.b64encode(out.getvalue()).decode("ascii")


class InlineSvg:
    """Lightens the SVG pictures of one page; remembers the page's styles and ids."""

    def __init__(self) -> None:
        self.classes: dict[str, str] = {}
        self._ids = 0

    def __call__(self, svg: str) -> str:
        """The ``<svg>`` element ``svg`` (from ``<svg`` on), light and with page-unique ids."""
        svg = _METADATA.sub("", svg)
        svg = _DEFS_STYLE.sub("", svg)
        svg = _ungroup(svg)
        svg = _ZERO_ROTATION.sub("", svg)
        # The root's own size and viewBox are left alone; coordinates inside are rounded.
        head_end = svg.find(">") + 1
        svg = svg[:head_end] + _COORDS.sub(_coordinates, svg[head_end:])
        svg = _PATH.sub(_path, svg)
        svg = self._rename_ids(svg)
        svg = _STYLE.sub(self._classify, svg)
        svg = _clip_groups(svg)
        svg = _PNG.sub(_webp, svg)
        svg = svg.replace("xlink:href=", "href=")
        svg = _merge_marks(svg)
        return svg.replace(' xmlns:xlink="http://www.w3.org/1999/xlink"', "", 1)

    def _rename_ids(self, svg: str) -> str:
        names: dict[str, str] = {}
        for old in dict.fromkeys(_ID.findall(svg)):
            names[old] = f"i{self._ids:x}"
            self._ids += 1
        if not names:
            return svg

        def swap(match: re.Match[str]) -> str:
            new = names.get(match.group(2))
            return match.group(0) if new is None else f"{match.group(1)}{new}"

        return re.sub(r'(id="|#)([^"\)\s]+)', swap, svg)

    def _classify(self, match: re.Match[str]) -> str:
        element, attributes, style = match.groups()
        if " class=" in attributes:
            return match.group(0)
        style = ";".join(part.strip().replace(": ", ":") for part in style.split(";") if part)
        name = self.classes.setdefault(style, f"s{len(self.classes):x}")
        return f'<{element}{attributes} class="{name}"'

    def css(self) -> str:
        """The rules of every style met so far (for the page's ``<style>``)."""
        rules = "".join(f".{name}{{{style}}}" for style, name in self.classes.items())
        return SVG_BASE_CSS + rules
