"""Support names placed beside their own supports, inside the frame, apart from each other
(issue 22: labels under the wrong ball, or clipped at the edge).

A name is anchored at its support's point and set a few points beside it: across the support's
arrow, on the side away from the other supports; where that would leave the frame or cover a
text already there (another name, a pole's, an angle), the next side is tried. Supports that
coincide in the view (the three contacts of a ball in a trihedral socket) share one label.
Every label carries the gid ``support-label:NAME[,NAME...]`` so that a test can find it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.pictures import colours as palette

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.text import Annotation

__all__ = ["label_supports", "GID_PREFIX", "OFFSET_POINTS"]

GID_PREFIX = "support-label:"
#: Gap between a support's point and its name (points).
OFFSET_POINTS = 6.0
#: Supports closer than this share of the view's size share a label.
SAME_PLACE = 0.035
LABEL_BOX = {"boxstyle": "square,pad=0.12", "fc": palette.PAPER, "ec": "none", "alpha": 0.8}


def _unit(v: np.ndarray) -> np.ndarray | None:
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-9 else None


def _groups(points: np.ndarray, distance: float) -> list[list[int]]:
    """Indices of supports drawn at (nearly) the same place, greedily by the first."""
    groups: list[list[int]] = []
    for j, p in enumerate(points):
        for group in groups:
            if np.linalg.norm(points[group[0]] - p) <= distance:
                group.append(j)
                break
        else:
            groups.append([j])
    return groups


def _sides(arrow: np.ndarray | None, radial: np.ndarray | None) -> list[np.ndarray]:
    """Directions to try, best first: across the arrow on the side away from the other
    supports, the other side, straight away from them, then the rest of the compass."""
    out: list[np.ndarray] = []
    if arrow is not None:
        across = np.array([-arrow[1], arrow[0]])
        if radial is not None and across @ radial < 0:
            across = -across
        out += [across, -across]
    if radial is not None:
        out.append(radial)
    angles = np.radians(np.arange(0, 360, 45) + 90)
    out += [np.array([np.cos(a), np.sin(a)]) for a in angles]
    return out


def _alignment(u: np.ndarray) -> dict[str, Any]:
    return {
        "ha": "left" if u[0] > 0.38 else "right" if u[0] < -0.38 else "center",
        "va": "bottom" if u[1] > 0.38 else "top" if u[1] < -0.38 else "center",
    }


def label_supports(
    ax: Axes,
    points: np.ndarray,
    arrows: np.ndarray,
    names: Sequence[str],
    size: float,
    **style: Any,
) -> list[Annotation]:
    """Name each support (or group of coinciding ones) beside its point; ``points`` (m, 2) in
    data units, ``arrows`` (m, 2) the direction from each point to its arrow's tail as drawn
    (zero where the arrow points at the viewer), ``size`` the drawing's size in data units.
    Call after the axes' limits and aspect are set; returns the labels."""
    ax.apply_aspect()
    renderer = _renderer(ax.figure)
    frame = ax.get_window_extent(renderer)
    # Directions in display space (the view's aspect may not be equal).
    scale = np.abs(np.diag(ax.transData.get_matrix())[:2])
    # Names keep off the texts already in the panel (poles, angles, the load's name) and off
    # each other.
    placed: list[Any] = [
        t.get_window_extent(renderer) for t in ax.texts if t.get_text() and t.get_visible()
    ]
    labels: list[Annotation] = []
    centre = points.mean(axis=0)
    for group in _groups(points, SAME_PLACE * size):
        anchor = points[group].mean(axis=0)
        arrow = _unit(arrows[group].mean(axis=0) * scale)
        radial = _unit((anchor - centre) * scale)
        text = ", ".join(names[j] for j in group)
        sides = _sides(arrow, radial)
        # The first side inside the frame and clear of the names placed, else the first
        # inside it, else the first.
        fits: list[tuple[bool, bool, int]] = []
        for k, u in enumerate(sides):
            box = _draw(ax, text, anchor, u, style).get_window_extent(renderer)
            ax.texts[-1].remove()
            inside = (
                box.x0 >= frame.x0 and box.x1 <= frame.x1 and box.y0 >= frame.y0
                and box.y1 <= frame.y1
            )  # fmt: skip
            clear = not any(box.overlaps(other) for other in placed)
            fits.append((not inside, not clear, k))
            if inside and clear:
                break
        best = sides[min(fits)[2]]
        label = _draw(ax, text, anchor, best, style)
        label.set_gid(GID_PREFIX + ",".join(names[j] for j in group))
        placed.append(label.get_window_extent(renderer))
        labels.append(label)
    return labels


def _renderer(fig: Any) -> Any:
    """The figure's Agg renderer (a figure made without pyplot has a canvas that cannot
    measure text until it is given the Agg one, which it keeps: it writes every format)."""
    if not hasattr(fig.canvas, "get_renderer"):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
    return fig.canvas.get_renderer()


def _draw(ax: Axes, text: str, anchor: np.ndarray, u: np.ndarray, style: dict[str, Any]) -> Any:
    return ax.annotate(
        text, tuple(anchor), xytext=tuple(OFFSET_POINTS * u), textcoords="offset points",
        bbox=LABEL_BOX, zorder=7, annotation_clip=False, **_alignment(u), **style,
    )  # fmt: skip


#: gid of the text a picture writes where it has nothing to show.
EMPTY_GID = "empty-note"


def say_why_empty(ax: Axes, text: str) -> Any:
    """Write in the middle of ``ax`` why it shows nothing (issue 22: an empty picture says
    why, in the picture); the text carries the gid :data:`EMPTY_GID`."""
    return ax.text(
        0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", fontsize=9,
        color=palette.INK, wrap=True, zorder=20, gid=EMPTY_GID,
        bbox={"boxstyle": "round,pad=0.4", "fc": palette.PAPER, "ec": palette.MUTED},
    )  # fmt: skip
