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

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["PLOT_FORMATS", "figure", "formats", "save", "slug", "ANGLE_NOTE"]

#: Formats a picture can be written in (``--plot-format``).
PLOT_FORMATS = ("png", "svg")
#: Resolution of PNG pictures (dots per inch).
PNG_DPI = 110
#: The angle convention, stated in every picture that shows force angles.
ANGLE_NOTE = "angles ccw from 0° = {zero}, about {normal}"

_formats: ContextVar[tuple[str, ...]] = ContextVar("kcheck_plot_formats", default=("png",))
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
        if ext == "svg":
            # Text as text (small, searchable); no date, so files do not change needlessly.
            import matplotlib

            with matplotlib.rc_context({"svg.fonttype": "none"}):
                fig.savefig(path, metadata={"Date": None})
        else:
            fig.savefig(path, dpi=PNG_DPI)
        written.append(path)
    return tuple(written)
