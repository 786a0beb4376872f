"""Shared plumbing for pictures: matplotlib (the `plot` extra) is imported only here, lazily."""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["figure", "save", "slug"]


def slug(text: str) -> str:
    """File-name-safe form of a scene or check name."""
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower() or "scene"


def figure(**kwargs: Any) -> Figure:
    """A new matplotlib figure on the non-interactive Agg canvas (no display needed)."""
    from matplotlib.figure import Figure

    kwargs.setdefault("layout", "constrained")
    return Figure(**kwargs)


def save(fig: Figure, directory: Path, stem: str) -> tuple[Path, Path]:
    """Write a figure as PNG (150 dpi) and SVG; return both paths."""
    directory.mkdir(parents=True, exist_ok=True)
    png, svg = directory / f"{stem}.png", directory / f"{stem}.svg"
    fig.savefig(png, dpi=150)
    fig.savefig(svg)
    return png, svg
