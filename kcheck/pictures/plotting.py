"""Shared plumbing for pictures: matplotlib (the `plot` extra) is imported only here, lazily.

Pictures are written as PNG by default; ``--plot-format`` (and the HTML report, which inlines
SVG) ask for other formats through :func:`formats`, which the runner sets around each check's
``plot`` call. Figures come from a small pool (:func:`figure`) and are cleared and reused:
building a new figure and canvas for every picture costs more than drawing a simple one.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck.pictures import PLOT_FORMATS
from kcheck.pictures.colours import OUTCOME_COLOURS, VERDICT_COLOURS, outcome_colour
from kcheck.records import dataclass
from kcheck.result import CheckResult, Finding, Status

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "PLOT_FORMATS",
    "OUTCOME_COLOURS",
    "VERDICT_COLOURS",
    "SceneVerdict",
    "figure",
    "formats",
    "scene_verdict",
    "current_scene",
    "current_formats",
    "save",
    "slug",
    "outcome_colour",
    "sweep_note",
]

#: Resolution of PNG pictures (dots per inch).
PNG_DPI = 110
#: In an SVG, a collection with more vertices than this (a shaded sphere map, contour fills, a
#: meshed body) is embedded as an image at SVG_RASTER_DPI, the rest staying vector: such
#: collections made SVGs of 300-500 kB, and the fixtures' HTML report 12.6 MB.
SVG_RASTER_VERTICES = 400
#: ... but a hatched collection (a sphere map's "does not close" bands) stays vector up to this
#: many vertices: in SVG its hatch is one small pattern, and its outline, simplified to the
#: page's 0.1 pt grid, weighs less than the hatch drawn into an image.
SVG_HATCH_VERTICES = 20_000
#: ... and so does a filled contour (a sphere map's margin shades) up to this many: smooth
#: level curves simplify well; a noisy field (jamming's least holding friction) does not.
SVG_CONTOUR_VERTICES = 1_000
SVG_RASTER_DPI = 80
#: Colours of an image embedded in an SVG (a palette PNG: a fifth of matplotlib's RGBA).
SVG_IMAGE_COLOURS = 64
#: The fonts an SVG's text asks for (the font pictures are drawn in, then common fallbacks).
SVG_FAMILIES = "'DejaVu Sans', Verdana, Arial, sans-serif"
SVG_FONTS = f"font-family: {SVG_FAMILIES}"
_formats: ContextVar[tuple[str, ...]] = ContextVar("kcheck_plot_formats", default=("png",))
_scene: ContextVar[SceneVerdict | None] = ContextVar("kcheck_scene_verdict", default=None)


@dataclass(frozen=True)
class SceneVerdict:
    """The scene a picture belongs to, as the runner found it: its verdict word, every check's
    result and the scene's warnings (pictures' titles say the scene's verdict when worse)."""

    word: str
    checks: tuple[CheckResult, ...]
    warnings: tuple[Finding, ...] = ()


@contextmanager
def scene_verdict(
    status: Status | str, checks: Sequence[CheckResult], warnings: Sequence[Finding] = ()
) -> Iterator[None]:
    """Within the block, pictures know their scene's verdict (:func:`current_scene`)."""
    word = Status(status).value
    token = _scene.set(SceneVerdict(word, tuple(checks), tuple(warnings)))
    try:
        yield
    finally:
        _scene.reset(token)


def current_scene() -> SceneVerdict | None:
    """The scene verdict set by :func:`scene_verdict` (None outside one: a picture drawn on
    its own, e.g. by a library caller)."""
    return _scene.get()


_pool: dict[tuple[float, float], Figure] = {}


@contextmanager
def formats(names: Sequence[str]) -> Iterator[None]:
    """Write pictures in ``names`` (each in :data:`PLOT_FORMATS`) within the block."""
    unknown = [n for n in names if n not in PLOT_FORMATS]
    if unknown or not names:
        raise ValueError(f"picture formats must be among {', '.join(PLOT_FORMATS)}")
    token = _formats.set(tuple(dict.fromkeys(names)))
    try:
        yield
    finally:
        _formats.reset(token)


def current_formats() -> tuple[str, ...]:
    """The picture formats requested for the pictures being drawn now."""
    return _formats.get()


def sweep_note(normal: object, zero: object) -> str:
    """The angle convention of a sweep plane, for a caption."""
    from kcheck.fmt import describe_sweep

    return f"angles: {describe_sweep(normal, zero)}"  # type: ignore[arg-type]


def slug(text: str) -> str:
    """File-name-safe form of a scene or check name."""
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower() or "scene"


def figure(figsize: tuple[float, float] = (8.0, 6.0), **kwargs: Any) -> Figure:
    """A cleared matplotlib figure on the non-interactive Agg canvas (no display needed).

    Figures of one size are reused (cleared) from a pool; a figure is only valid until the
    next call for the same size, so draw and :func:`save` one picture at a time.
    """
    from matplotlib.figure import Figure

    layout = kwargs.pop("layout", "constrained")
    key = (float(figsize[0]), float(figsize[1]))
    fig = _pool.get(key)
    if fig is None or kwargs:
        fig = Figure(figsize=figsize, layout=layout, **kwargs)
        if not kwargs:
            _pool[key] = fig
    else:
        fig.clear()
        fig.set_layout_engine(layout)
    return fig


def save(fig: Figure, directory: Path, stem: str) -> tuple[Path, ...]:
    """Write a figure in each requested format; return the paths."""
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for ext in _formats.get():
        path = directory / f"{stem}.{ext}"
        with _quiet_drawing():
            if ext == "svg":
                # Text as text (small, searchable); no date, so files do not change needlessly.
                import matplotlib

                heavy = _rasterize_heavy(fig)
                try:
                    with matplotlib.rc_context({"svg.fonttype": "none"}):
                        fig.savefig(path, metadata={"Date": None}, dpi=SVG_RASTER_DPI)
                finally:
                    for artist in heavy:
                        artist.set_rasterized(False)
                _lighten_svg(path)
            else:
                fig.savefig(path, dpi=PNG_DPI)
        written.append(path)
    return tuple(written)


_PATH_DATA = re.compile(r'\b(d|points)="([^"]*)"')
_DECIMALS = re.compile(r"(-?\d+\.\d{2})\d+")
_REFERENCE = re.compile(r"(?:url\(#|href=\"#)([^\"\)]+)")
_GROUP_ID = re.compile(r'<g id="([^"]+)">')
_BETWEEN_TAGS = re.compile(r">[ \t]*\n\s*<")
_FONTS = re.compile(r"font-family: [^;\"]*")
# matplotlib before 3.10 writes the CSS shorthand: `font: 10px 'DejaVu Sans', ...`.
_FONT_SHORTHAND = re.compile(r"(font: [^;\"]*?\d+(?:\.\d+)?px) [^;\"]*")
_PNG = re.compile(r"data:image/png;base64,\s*([A-Za-z0-9+/=\s]+)")


def _lighten_svg(path: Path) -> None:
    """Make a written SVG lighter without changing what it shows: path coordinates to 0.01 pt
    (matplotlib writes 1e-6 pt), one short font list (matplotlib repeats its eleven fallbacks
    on every text), no group ids nothing refers to, no indentation (line breaks between tags),
    and each embedded image as a 64-colour optimised PNG when that is smaller. Text (every
    number a reader sees) is left as written."""
    import base64
    import io

    from PIL import Image

    text = path.read_text(encoding="utf-8")

    def coordinates(match: re.Match[str]) -> str:
        data = _DECIMALS.sub(r"\1", match.group(2))
        return f'{match.group(1)}="{" ".join(data.split())}"'

    def image(match: re.Match[str]) -> str:
        raw = base64.b64decode(match.group(1))
        with Image.open(io.BytesIO(raw)) as picture:
            method = Image.Quantize.FASTOCTREE if picture.mode == "RGBA" else None
            small = picture.quantize(colors=SVG_IMAGE_COLOURS, method=method)
            out = io.BytesIO()
            small.save(out, "PNG", optimize=True)
        best = min(raw, out.getvalue(), key=len)
        return "data:image/png;base64," + base64.b64encode(best).decode("ascii")

    text = _FONTS.sub(SVG_FONTS, _PATH_DATA.sub(coordinates, text))
    text = _FONT_SHORTHAND.sub(lambda m: f"{m.group(1)} {SVG_FAMILIES}", text)
    # Group ids nothing refers to (matplotlib names every artist), and indentation.
    used = set(_REFERENCE.findall(text))
    text = _GROUP_ID.sub(lambda m: m.group(0) if m.group(1) in used else "<g>", text)
    text = _BETWEEN_TAGS.sub("><", text)
    path.write_text(_PNG.sub(image, text), encoding="utf-8")


def _count(vertices: Any) -> int:
    return len(vertices)


def _rasterize_heavy(fig: Figure) -> list[Any]:
    """Mark the figure's heavy collections and patches (shaded maps, contour fills, meshes,
    outlines of a meshed body: hundreds of vertices each) to be drawn as embedded images in
    an SVG; titles, labels, lines and markers stay vector (text stays text). Returns the
    artists marked, to unmark after saving."""
    marked: list[Any] = []
    for ax in fig.axes:
        for artist in ax.collections:
            if artist.get_rasterized():
                continue
            # A 3D collection's paths are projected only when drawn: a meshed body is heavy.
            solid = type(artist).__name__ in ("Poly3DCollection", "QuadMesh")
            vertices = sum(_count(path.vertices) for path in artist.get_paths())
            # A filled contour keeps its hatches in `hatches` (one per level), not get_hatch().
            hatched = bool(artist.get_hatch() or any(getattr(artist, "hatches", None) or ()))
            contour = type(artist).__name__ in ("QuadContourSet", "TriContourSet")
            limit = SVG_HATCH_VERTICES if hatched else SVG_CONTOUR_VERTICES if contour else 0
            if not solid and vertices <= limit:
                continue
            if solid or vertices > SVG_RASTER_VERTICES:
                artist.set_rasterized(True)
                marked.append(artist)
        for patch in ax.patches:
            vertices = _count(patch.get_path().vertices)
            if patch.get_hatch() and vertices <= SVG_HATCH_VERTICES:
                continue
            heavy = vertices > SVG_RASTER_VERTICES
            if heavy and not patch.get_rasterized():
                patch.set_rasterized(True)
                marked.append(patch)
    return marked


@contextmanager
def _quiet_drawing() -> Iterator[None]:
    """Drawing without matplotlib's notes on stderr (issue 13: nothing but kcheck's own lines
    there): a name in a script the font lacks is drawn as boxes, and a figure crowded by very
    long names is saved without its layout; either way the picture is written. Every
    UserWarning while saving is matplotlib's note, silenced by its kind, not by its wording
    ("Glyph ... missing from font", "constrained_layout not applied"), which is
    matplotlib's to change."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        yield
