"""The map of safe force (or gravity) directions of the spatial check.

An equal-area (Lambert azimuthal) map centred on the design direction — or on the most robust
one when the design is not safe — zoomed to the safe region, with every retracted support's
boundary and, hatched, the side where that support does not close. A small overview shows the
whole hemisphere and where the zoom lies. The verdict is in the title; the colour bar (margin
to the nearest boundary) appears only when some direction is safe.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis.cases import Analysis
from kcheck.fmt import format_angle, format_direction, format_share
from kcheck.mechanics.arcs import cap_margin_matrix
from kcheck.pictures import colours as palette
from kcheck.pictures.labels import say_why_empty
from kcheck.pictures.plotting import figure
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.pictures.titles import verdict_colour, verdict_title

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from kcheck_checks.analytical_3d import SphereMap

__all__ = ["sphere_figure", "lambert_inverse", "lambert_forward", "nice_step", "ring"]

EDGE = float(np.sqrt(2.0))  # disc radius of the hemisphere in the Lambert map
DEG = float(np.degrees(1.0))
AXES = {
    "+x": (1, 0, 0), "−x": (-1, 0, 0), "+y": (0, 1, 0),
    "−y": (0, -1, 0), "+z": (0, 0, 1), "−z": (0, 0, -1),
}  # fmt: skip


def _tangent_basis(centre: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors e1, e2 completing ``centre`` to a right-handed frame (e1 ~ world x or z)."""
    helper = np.array([0.0, 0.0, 1.0]) if abs(centre[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = helper - (helper @ centre) * centre
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(centre, e1)


def lambert_inverse(x: np.ndarray, y: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Directions (..., 3) of points of a Lambert azimuthal equal-area disc about ``centre``.

    The disc radius ``r = 2 sin(theta / 2)`` (theta from the centre) keeps areas; the
    hemisphere around the centre fills ``r <= sqrt(2)``.
    """
    e1, e2 = _tangent_basis(centre)
    r = np.hypot(x, y)
    theta = 2.0 * np.arcsin(np.clip(r / 2.0, 0.0, 1.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        ux, uy = np.where(r > 0, x / r, 1.0), np.where(r > 0, y / r, 0.0)
    s = np.sin(theta)[..., None]
    return np.cos(theta)[..., None] * centre + s * ux[..., None] * e1 + s * uy[..., None] * e2


def lambert_forward(d: np.ndarray, centre: np.ndarray) -> tuple[float, float]:
    """Disc coordinates of a direction in the Lambert map about ``centre``."""
    e1, e2 = _tangent_basis(centre)
    theta = float(np.arccos(np.clip(d @ centre, -1.0, 1.0)))
    psi = float(np.arctan2(d @ e2, d @ e1))
    r = 2.0 * np.sin(theta / 2.0)
    return r * np.cos(psi), r * np.sin(psi)


def ring(r: float, solid: bool) -> Any:
    """A circle about the map's centre at disc radius ``r``: solid for the hemisphere's rim,
    dotted for the angle rings inside it."""
    from matplotlib.patches import Circle

    return Circle(
        (0, 0), r, fill=False, color=palette.DARK if solid else palette.FAINT,
        linewidth=1.2 if solid else 0.5, linestyle="-" if solid else ":",
    )  # fmt: skip


def nice_step(span: float, count: int = 5) -> float:
    """A round step (1, 2 or 5 times a power of ten) giving about ``count`` steps in ``span``."""
    if not span > 0:
        return 1.0
    raw = span / count
    power = 10.0 ** np.floor(np.log10(raw))
    return float(next(m * power for m in (1, 2, 5, 10) if m * power >= 0.75 * raw))


def _margins(smap: SphereMap, dirs: np.ndarray, cases: np.ndarray) -> np.ndarray:
    """Per case, the margin (deg) of each direction (..., 3): shape (cases, ...)."""
    per_cap = cap_margin_matrix(smap.a, smap.c, dirs.reshape(-1, 3)) * DEG
    out = np.stack([per_cap[:, smap.owner == i].min(axis=1) for i in cases])
    return out.reshape(len(cases), *dirs.shape[:-1])


def _grid(lo: np.ndarray, hi: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.meshgrid(np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n))
    return x, y


def _beyond(smap: SphereMap, centre: np.ndarray) -> float:
    """The exact share of the sphere that is safe and more than 90° from ``centre`` (the
    hemisphere the map does not draw): the safe region cut by one more cap."""
    from kcheck.mechanics.caps import region

    return region(np.append(smap.a, 0.0), np.vstack([smap.c, -centre])).fraction


def _centre(smap: SphereMap) -> tuple[np.ndarray, str]:
    """The map's centre: the design direction, unless it is not safe and another one is."""
    if smap.design is not None and (
        smap.robust_margin <= 0 or (smap.design_margin is not None and smap.design_margin > 0)
    ):
        return np.asarray(smap.design, float), "design"
    return np.asarray(smap.robust, float), "most robust"


def _zoom(
    x: np.ndarray, y: np.ndarray, safe: np.ndarray, marks: list[tuple[float, float]]
) -> tuple[np.ndarray, np.ndarray]:
    """A square box around the safe region and the marked directions (the whole hemisphere
    when nothing is safe)."""
    if not np.any(safe):
        return np.array([-EDGE, -EDGE]) * 1.04, np.array([EDGE, EDGE]) * 1.04
    xs = np.concatenate([x[safe], [m[0] for m in marks]])
    ys = np.concatenate([y[safe], [m[1] for m in marks]])
    mid = np.array([xs.min() + xs.max(), ys.min() + ys.max()]) / 2
    half = max(xs.max() - xs.min(), ys.max() - ys.min()) / 2 * 1.35 + 0.02
    half = float(np.clip(half, 0.12, EDGE * 1.04))
    return mid - half, mid + half


def _rings(ax: Axes, lo: np.ndarray, hi: np.ndarray, about: str) -> None:
    """Circles of equal angle from the centre, at round angles, labelled."""
    from matplotlib.patches import Circle

    far = float(np.max(np.hypot(*np.meshgrid([lo[0], hi[0]], [lo[1], hi[1]]))))
    span = 2 * np.degrees(np.arcsin(min(far / 2, 1.0)))
    step = nice_step(min(span, 90.0), 4)
    # Cosmetic: + 1e-9 keeps the last ring that rounding of arange's end would drop.
    for angle in np.arange(step, min(span, 90.0) + 1e-9, step):
        r = 2 * np.sin(np.radians(angle) / 2)
        ax.add_patch(
            Circle((0, 0), r, fill=False, color=palette.MUTED, lw=0.6, ls=(0, (2, 3)), zorder=3)
        )
        at = np.array([np.cos(np.radians(58)), np.sin(np.radians(58))]) * r
        if np.all((at > lo) & (at < hi)):
            ax.text(at[0], at[1], f"{angle:g}°", fontsize=7, color=palette.MUTED, zorder=3)
    ax.plot(0, 0, "+", color=palette.MUTED, ms=9, zorder=3)
    ax.set_xlabel(
        f"dotted rings: angle from the {about} direction", fontsize=8, color=palette.MUTED
    )


def _axes_marks(
    ax: Axes, centre: np.ndarray, lo: np.ndarray, hi: np.ndarray, busy: Sequence[np.ndarray]
) -> None:
    """The coordinate axes' directions inside the view, except where a marker sits."""
    for label, vec in AXES.items():
        v = np.array(vec, float)
        # Cosmetic: an axis on the far hemisphere, or on its rim to rounding, is not labelled.
        if v @ centre < 1e-9 or any(float(v @ b) > np.cos(np.radians(1.0)) for b in busy):
            continue
        px, py = lambert_forward(v, centre)
        if lo[0] < px < hi[0] and lo[1] < py < hi[1]:
            ax.plot(px, py, "s", color=palette.DARK, ms=4, zorder=4)
            ax.text(px, py, f" {label}", fontsize=9, color=palette.DARK, va="bottom", zorder=4)


def _marks(ax: Axes, smap: SphereMap, centre: np.ndarray, what: str) -> list[Any]:
    """The design (star) and most robust (circle) directions; legend handles."""
    from matplotlib.lines import Line2D

    handles = []
    # direction, margin, marker, its matplotlib keyword arguments, name
    marks: tuple[tuple[np.ndarray | None, float | None, str, dict[str, Any], str], ...] = (
        (smap.robust, smap.robust_margin, "o",
         {"mfc": palette.PAPER, "mec": palette.INK, "mew": 1.6, "ms": 8}, "most robust"),
        (smap.design, smap.design_margin, "*",
         {"mfc": palette.DESIGN, "mec": palette.PAPER, "mew": 0.8, "ms": 14}, f"design {what}"),
    )  # fmt: skip
    for d, margin, marker, kw, name in marks:
        if d is None:
            continue
        label = f"{name} {format_direction(d, 2)}"
        if margin is not None:
            label += f"\nmargin {format_angle(margin * DEG)}"
        at = on_map(d, centre)
        # Always drawn, passing or failing: a direction on the other hemisphere sits on the
        # rim where it lies beyond, the angle from the centre beside it.
        ax.plot(*at, marker, zorder=8, clip_on=False, **kw)
        if d @ centre <= 0:
            away = format_angle(float(np.degrees(np.arccos(np.clip(d @ centre, -1, 1)))), 0)
            label += f"\n{away} from the centre: drawn on the rim"
            ax.annotate(
                f"{name.split()[0]} ({away} away)", at, xytext=(0, -14),
                textcoords="offset points", ha="center", va="top", fontsize=8, zorder=8,
                annotation_clip=False,
            )  # fmt: skip
        handles.append(Line2D([], [], marker=marker, ls="none", label=label, **kw))
    return handles


def on_map(d: np.ndarray, centre: np.ndarray) -> tuple[float, float]:
    """Where a direction is drawn on the hemisphere map about ``centre``: its Lambert
    position, or, on the other hemisphere, the point of the rim in its azimuth."""
    x, y = lambert_forward(d, centre)
    r = float(np.hypot(x, y))
    if d @ centre > 0 or r == 0:
        return x, y
    return x * EDGE / r, y * EDGE / r


def _case_boundaries(
    ax: Axes,
    x: np.ndarray,
    y: np.ndarray,
    m: np.ndarray,
    names: list[str],
    ids: np.ndarray,
    band: float,
) -> list[Any]:
    """Each case's boundary, hatched on the side where that case does not close, in the colour
    of its retracted support (``ids``: the supports' indices)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles: list[Line2D | Patch] = []
    for i, name in enumerate(names):
        mi = m[i]
        if not (np.nanmin(mi) < 0 < np.nanmax(mi)):
            continue
        colour = palette.support_colour(int(ids[i]))
        hatched = ax.contourf(
            x, y, mi, levels=[-band, 0.0], colors="none", hatches=["////"], zorder=4
        )
        hatched.set_edgecolor(colour)
        hatched.set_linewidth(0.0)
        ax.contour(x, y, mi, levels=[0.0], colors=[colour], linewidths=1.2, zorder=5)
        handles.append(
            Line2D([], [], color=colour, lw=1.2, label=f"{name} closes on the clear side")
        )
    if handles:
        handles.append(
            Patch(
                facecolor="none",
                edgecolor=palette.MUTED,
                hatch="////",
                label="hatched: does not close",
            )
        )
    return handles


def sphere_figure(scene: Scene, analysis: Analysis, smap: SphereMap, result: CheckResult) -> Any:
    """The safe-direction map (zoomed) beside an overview of the hemisphere."""
    from matplotlib.patches import Circle, Rectangle

    centre, about = _centre(smap)
    cases = np.unique(smap.owner)
    names = [analysis.results[i].retracted for i in cases]
    what = "force" if smap.swept == "load" else "gravity"

    # Overview of the hemisphere: where is anything safe?
    ox, oy = _grid(np.array([-EDGE, -EDGE]), np.array([EDGE, EDGE]), 161)
    inside = np.hypot(ox, oy) <= EDGE
    om = _margins(smap, lambert_inverse(ox, oy, centre), cases)
    overall = np.where(inside, om.min(axis=0), np.nan)
    safe = np.nan_to_num(overall, nan=-1.0) > 0
    marks = [
        on_map(np.asarray(d, float), centre) for d in (smap.design, smap.robust) if d is not None
    ]
    lo, hi = _zoom(ox, oy, safe, marks)

    fig = figure(figsize=(12.5, 7.2), layout=None)
    grid = fig.add_gridspec(
        2, 2, width_ratios=[2.4, 1.0], left=0.02, right=0.98, bottom=0.04, top=0.86,
        wspace=0.06, hspace=0.3,
    )  # fmt: skip
    ax = fig.add_subplot(grid[:, 0])
    over = fig.add_subplot(grid[0, 1])

    x, y = _grid(lo, hi, 181)
    dirs = lambert_inverse(x, y, centre)
    m = _margins(smap, dirs, cases)
    in_disc = np.hypot(x, y) <= EDGE
    m = np.where(in_disc, m, np.nan)
    total = m.min(axis=0)
    top = float(np.nanmax(total)) if np.any(total > 0) else 0.0
    # Cosmetic: the band from -1e9 (below every margin) to 0 fills where no direction is safe.
    ax.contourf(
        x,
        y,
        np.where(total > 0, np.nan, total),
        levels=[-1e9, 0.0],
        colors=[palette.NOTHING],
        zorder=1,
    )
    if top <= 0:
        say_why_empty(ax, f"no {what} direction is safe for every retraction:\nno green region")
    if top > 0:
        step = nice_step(top, 5)
        levels = np.arange(0.0, top + step, step)
        filled = ax.contourf(
            x, y, np.where(total > 0, total, np.nan), levels=levels, cmap=palette.SAFE_MAP, zorder=2
        )
        ax.contour(x, y, total, levels=[0.0], colors=palette.INK, linewidths=1.8, zorder=6)
        bar = fig.colorbar(
            filled, ax=over, orientation="horizontal", fraction=0.08, pad=0.25, aspect=25
        )
        bar.set_ticks(levels.tolist())
        bar.set_ticklabels([f"{v:g}°" for v in levels])
        bar.set_label("safe: margin to the nearest boundary", fontsize=8)
        bar.ax.tick_params(labelsize=7)
    span_deg = 2 * np.degrees(np.arcsin(min(float(hi[0] - lo[0]) / 4, 1.0)))
    handles = _case_boundaries(ax, x, y, m, names, cases, band=max(0.05 * span_deg, 0.3))
    ax.add_patch(Circle((0, 0), EDGE, fill=False, color=palette.DARK, lw=1.0, zorder=3))
    _rings(ax, lo, hi, about)
    busy = [np.asarray(d, float) for d in (smap.design, smap.robust) if d is not None]
    _axes_marks(ax, centre, lo, hi, busy)
    handles = _marks(ax, smap, centre, what) + handles
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])

    # Overview: the hemisphere, the safe region, the zoomed box.
    over.contourf(ox, oy, np.where(inside, safe.astype(float), np.nan), levels=[-0.5, 0.5, 1.5],
                  colors=[palette.NOTHING, palette.SAFE])  # fmt: skip
    for i in range(len(cases)):
        mi = np.where(inside, om[i], np.nan)
        if np.nanmin(mi) < 0 < np.nanmax(mi):
            over.contour(
                ox,
                oy,
                mi,
                levels=[0.0],
                colors=[palette.support_colour(int(cases[i]))],
                linewidths=0.6,
            )
    over.add_patch(Circle((0, 0), EDGE, fill=False, color=palette.DARK, lw=1.0))
    if hi[0] - lo[0] < 2 * EDGE:
        over.add_patch(
            Rectangle(tuple(lo), *(hi - lo), fill=False, ec=palette.INK, lw=1.2, ls="--")
        )
    _axes_marks(over, centre, np.array([-EDGE, -EDGE]) * 1.1, np.array([EDGE, EDGE]) * 1.1, busy)
    _marks(over, smap, centre, what)
    over.set_xlim(-EDGE * 1.08, EDGE * 1.08)
    over.set_ylim(-EDGE * 1.08, EDGE * 1.08)
    over.set_aspect("equal")
    over.axis("off")
    back = _beyond(smap, centre)
    over.set_title(
        f"the hemisphere about the {about} direction\n(dashed: the zoomed map)", fontsize=9
    )
    note = (
        "opposite hemisphere: no safe direction"
        if back <= smap.fraction.error
        else f"opposite hemisphere (not drawn):\n{format_share(back)} of the sphere also safe"
    )
    legend = fig.add_subplot(grid[1, 1])
    legend.axis("off")
    legend.legend(handles=handles, loc="upper left", fontsize=8, frameon=False, title=note,
                  title_fontsize=8, alignment="left")  # fmt: skip

    frac = smap.fraction
    share = "none"
    if frac.fraction > 0:
        share = format_share(frac.fraction)  # as the check's message writes it
        if frac.error >= 5e-5:  # shown only where it shows at two decimals (exact: rounding)
            share += f" ± {100 * frac.error:.2f}%"
    fig.suptitle(
        f"{scene.name} — {verdict_title(result)}\n{what} directions safe for every "
        f"retracted support: {share} of the sphere",
        fontsize=12, color=verdict_colour(result), y=0.985,
    )  # fmt: skip
    ax.set_title(
        f"equal-area (Lambert azimuthal) map centred on the {about} direction "
        f"{format_direction(centre, 2)}\ngreen: safe for every retraction, shaded by margin; "
        "black: its boundary",
        fontsize=8.5, color=palette.MUTED,
    )  # fmt: skip
    return fig
