"""The picture of ``kcheck suggest``: the margin over the candidate points, the best
candidate's force and the design's. matplotlib comes in through :mod:`kcheck.pictures.plotting`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from kcheck.analysis.suggest import Search
from kcheck.pictures import colours as palette
from kcheck.pictures.plotting import figure, formats, save
from kcheck.scene import Scene

__all__ = ["plot_suggestion"]

# Margins at or below this (deg) mean "no direction is safe at this point": drawn grey.
NONE_DEG = -179.99


def plot_suggestion(
    scene: Scene,
    found: Search,
    design: tuple[np.ndarray, np.ndarray] | None,
    path: Path,
) -> tuple[Path, ...]:
    """Write ``path`` (PNG or SVG, by its suffix): the candidate points coloured by their best
    margin in 3D, from above and from the front, with the best candidate's force and the
    design's."""
    from matplotlib.colors import TwoSlopeNorm

    fig = figure(figsize=(17.5, 5.6))
    units, s = scene.units, scene.scale
    pts = found.points / s
    margins = np.degrees(found.margins)
    some = margins > NONE_DEG
    span = float(np.ptp(pts, axis=0).max()) or 1.0
    top = max(float(margins.max()), 1.0)
    low = min(float(np.percentile(margins[some], 5)) if np.any(some) else -1.0, -1.0)
    style = {"cmap": palette.MARGIN_MAP, "norm": TwoSlopeNorm(0.0, max(low, -3 * top), top)}
    order = np.argsort(margins)  # the best drawn last, on top
    grey, live = order[~some[order]], order[some[order]]
    arrows = []
    if found.best:
        arrows.append((found.best[0].point / s, found.best[0].direction, palette.CANDIDATE, "best"))
    if design is not None:
        arrows.append((design[0] / s, design[1], palette.DESIGN, "design"))

    ax3 = fig.add_subplot(1, 3, 1, projection="3d")
    ax3.scatter(*pts[grey].T, s=4, color=palette.NO_VALUE)
    dots = ax3.scatter(*pts[live].T, s=6, c=margins[live], **style)
    for p, d, c, label in arrows:
        ax3.quiver(*(p - 0.3 * span * d), *(0.3 * span * d), color=c, lw=2, label=label)
        ax3.scatter(*p, color=c, marker="*", s=120)
    # Cosmetic: a flat cloud of points still gets a thousandth of its span as depth.
    ax3.set_box_aspect(np.maximum(np.ptp(pts, axis=0), 1e-3 * span))
    ax3.set_xlabel(f"x ({units})")
    ax3.set_ylabel(f"y ({units})")
    ax3.set_title(f"candidate points, z up ({units})", fontsize=10)
    for k, (i, j, title) in enumerate(((0, 1, "from +z"), (0, 2, "from -y"))):
        ax = fig.add_subplot(1, 3, 2 + k)
        _view(ax, pts, margins, grey, live, style, arrows, (i, j), span)
        ax.set_title(f"seen {title} (the best drawn on top)", fontsize=10)
        ax.set_xlabel(f"{'xyz'[i]} ({units})")
        ax.set_ylabel(f"{'xyz'[j]} ({units})")
    fig.colorbar(dots, ax=fig.axes, label="best margin at the point (°); grey: none", shrink=0.8)
    best_text = (
        f"best margin {np.degrees(found.best[0].margin):.2f}°" if found.best else "no candidate"
    )
    fig.suptitle(
        f"{scene.name}: where to put the closing force — {len(pts)} points, {best_text}",
        fontsize=11,
    )
    with formats((path.suffix.lstrip(".").lower(),)):
        return save(fig, path.parent, path.stem)


def _view(
    ax: Any,
    pts: np.ndarray,
    margins: np.ndarray,
    grey: np.ndarray,
    live: np.ndarray,
    style: dict[str, Any],
    arrows: list[tuple[np.ndarray, np.ndarray, str, str]],
    axes: tuple[int, int],
    span: float,
) -> None:
    """One orthographic view of the candidate points and the forces."""
    i, j = axes
    ax.scatter(pts[grey, i], pts[grey, j], s=4, color=palette.NO_VALUE)
    ax.scatter(pts[live, i], pts[live, j], s=8, c=margins[live], **style)
    for p, d, c, label in arrows:
        tail = p - 0.3 * span * d
        ax.annotate(
            "",
            (p[i], p[j]),
            (tail[i], tail[j]),
            arrowprops={"arrowstyle": "-|>", "color": c, "lw": 2, "mutation_scale": 18},
        )
        ax.plot(p[i], p[j], "*", color=c, ms=12, label=label)
    ax.set_aspect("equal", adjustable="datalim")
    if arrows:
        ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
