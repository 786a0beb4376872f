"""Pictures of the jamming check: per retracted support, the circle of load angles with the
directions where friction can hold the body (planar), or an equal-area map of the sphere of
load directions (spatial, the projection of analytical-3d's map). matplotlib comes in through
:mod:`kcheck.pictures.plotting`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from kcheck.analysis.jamming_cases import JamAnalysis, JamMap, case_arcs
from kcheck.fmt import format_angle, format_number, format_share_bounds
from kcheck.mechanics.arcs import ArcSet
from kcheck.pictures import colours as palette
from kcheck.pictures.labels import say_why_empty
from kcheck.pictures.plotting import figure, save, slug
from kcheck.plugin import Check, Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.pictures.sphere import lambert_forward, lambert_inverse, ring
from kcheck_checks.pictures.titles import verdict_colour, verdict_title

__all__ = ["plot_jamming", "circle_panel", "sphere_panel"]

COLOURS = {
    "closing": palette.SAFE_PALE,  # frictionless closing (the funnel)
    "jams": palette.JAMMING,
    "holds": palette.JAMMING_PALE,
    "lifts": palette.PULL,
}


def plot_jamming(
    scene: Scene,
    analysis: JamAnalysis | None,
    smap: JamMap | None,
    result: CheckResult,
    directory: Path,
) -> list[Path]:
    """Write ``<scene>-jamming.png/.svg``; return the paths."""
    if analysis is None:
        return []
    stem = f"{slug(scene.name)}-jamming"
    if analysis.statics.dim == 2:
        # Fixed margins (inches) instead of a layout engine, which left the legend on the
        # 270° labels and the title's third line on the panels' titles: room for the title's
        # lines, two lines of panel title, the 90° label above and the 270° label and the
        # legend below each circle.
        lines = 2 + verdict_title(result).count("\n")
        head, foot, circle = 0.2 + 0.23 * lines + 0.7, 0.75, 3.7
        fig = figure(figsize=(13, circle + head + foot), layout=None)
        fig.subplots_adjust(
            left=0.03, right=0.97, top=1 - head / (circle + head + foot),
            bottom=foot / (circle + head + foot), wspace=0.3,
        )  # fmt: skip
        circle_panel(fig, scene, analysis, result)
    else:
        fig = figure(figsize=(12, 6.8))
        sphere_panel(fig, scene, analysis, result)
    return list(save(fig, directory, stem))


def _bars(ax: Any, arcs: ArcSet, radius: float, height: float, **kw: Any) -> None:
    for s, e in arcs:
        ax.bar((s + e) / 2, height, width=e - s, bottom=radius, **kw)


def _end_labels(ax: Any, ends: list[float]) -> None:
    """Angle labels (rad) outside the rings; a label within 12° of the one before it moves
    further out so that the two do not overlap."""
    previous: tuple[float, float] | None = None
    for end in sorted(e % (2 * np.pi) for e in ends):
        close = previous is not None and abs(end - previous[0]) < np.radians(12)
        radius = 1.26 if close and previous is not None and previous[1] == 1.12 else 1.12
        ax.text(end, radius, format_angle(np.degrees(end) % 360, 1), fontsize=7,
                ha="center", va="center")  # fmt: skip
        previous = (end, radius)


def circle_panel(fig: Any, scene: Scene, analysis: JamAnalysis, result: CheckResult) -> None:
    """One polar panel per retracted support: rings of closing, held and lift-off angles."""
    e1, e2 = scene.sweep.e1[:2], scene.sweep.e2[:2]
    cases = {r.retracted: r for r in result.cases}
    n = len(analysis.cases)
    for i, case in enumerate(analysis.cases):
        ax = fig.add_subplot(1, n, i + 1, projection="polar")
        name = analysis.statics.names[i]
        title = f"{name} retracted"
        if case.determined:
            arcs = case_arcs(case, e1, e2)
            _bars(ax, arcs.closing, 0.55, 0.45, color=COLOURS["closing"], edgecolor="none")
            _bars(ax, arcs.jamming, 0.7, 0.3, color=COLOURS["jams"], edgecolor=palette.INK, lw=0.4)
            _bars(ax, arcs.holding_open, 0.7, 0.3, color=COLOURS["holds"], edgecolor=palette.INK,
                  lw=0.4)  # fmt: skip
            if arcs.lifts_off:
                _bars(ax, arcs.lifts_off, 0.7, 0.3, color=palette.PAPER, edgecolor=COLOURS["lifts"],
                      hatch="////", lw=0.4)  # fmt: skip
            _end_labels(ax, [end for s, e in arcs.held for end in (s, e)])
            if not arcs.held and not arcs.closing:
                say_why_empty(ax, "no load angle closes this case\nand friction holds none")
            res = cases.get(name)
            if res is not None:
                title += f": {res.outcome}"
                least = res.details.get("holding_friction")
                if least is not None:
                    title += f"\nheld at the design for μ ≥ {format_number(least, 3)}"
                elif "holding_friction" in res.details:
                    title += "\nnot held for any μ ≤ 100"
        else:
            title += ": undetermined"
            say_why_empty(ax, "undetermined: the supports left\ndo not fix the body's motion")
        if analysis.design is not None:
            angle = float(np.arctan2(analysis.design @ e2, analysis.design @ e1))
            ax.annotate(
                "", xy=(angle, 1.0), xytext=(angle, 0.0),
                arrowprops={"arrowstyle": "-|>", "color": palette.DESIGN, "lw": 1.8},
            )  # fmt: skip
        ax.set_ylim(0, 1.2)
        ax.set_yticks([])
        ax.set_xticks(np.radians(np.arange(0, 360, 45)))
        ax.tick_params(labelsize=7)
        ax.set_title(title, fontsize=9, pad=14)
    handles = [
        _patch(COLOURS["closing"], "closes without friction (inner ring)"),
        _patch(COLOURS["jams"], "jams: friction holds a closing load"),
        _patch(COLOURS["holds"], "holds: friction holds an opening load"),
        _patch(
            palette.PAPER,
            "Koster's jamming area a support would have to pull in",
            hatch="////",
            edge=COLOURS["lifts"],
        ),  # fmt: skip
    ]
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 0.0))  # fmt: skip
    what = "load" if analysis.swept == "load" else "gravity"
    fig.suptitle(
        f"{scene.name} — {verdict_title(result)}\n{what} angles (° from +x, ccw) where friction "
        "can hold the body, per retracted support; arrow: design direction",
        fontsize=11, color=verdict_colour(result), y=1 - 0.1 / fig.get_figheight(), va="top",
    )  # fmt: skip


def _reds(n: int) -> list[Any]:
    """White for no case, then darker reds for more cases."""
    import matplotlib

    return [palette.PAPER] + [
        tuple(c) for c in matplotlib.colormaps[palette.JAMMING_MAP](np.linspace(0.3, 0.95, n - 1))
    ]


def _patch(colour: str, label: str, hatch: str | None = None, edge: str = palette.INK) -> Any:
    from matplotlib.patches import Patch

    return Patch(facecolor=colour, edgecolor=edge, hatch=hatch, label=label)


def _sweep_circle(ax: Any, plane: Any, c0: np.ndarray, first: bool) -> None:
    """The sweep plane's great circle on a Lambert map about ``c0``, dashed, with its angles
    every 45° (those the check's ranges are measured in)."""
    if not isinstance(plane, dict) or "normal" not in plane or "zero" not in plane:
        return
    e1 = np.asarray(plane["zero"], float)
    e2 = np.cross(np.asarray(plane["normal"], float), e1)
    t = np.radians(np.arange(0.0, 360.5, 0.5))
    dirs = np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2
    # Cosmetic: the near hemisphere, its rim included despite rounding (-1e-9).
    front = dirs @ c0 >= -1e-9
    xy = np.array([lambert_forward(d, c0) for d in dirs])
    xy[~front] = np.nan
    ax.plot(xy[:, 0], xy[:, 1], "--", color=palette.DARK, lw=1.0,
            label="sweep plane (angles of the ranges)" if first else None)  # fmt: skip
    for angle in range(0, 360, 45):
        i = 2 * angle
        if front[i]:
            ax.plot(*xy[i], "o", color=palette.DARK, ms=3)
            ax.annotate(format_angle(angle, 0), xy[i], xytext=(3, -9), textcoords="offset points",
                        fontsize=7, color=palette.DARK)  # fmt: skip


def sphere_panel(fig: Any, scene: Scene, analysis: JamAnalysis, result: CheckResult) -> None:
    """Equal-area map of where friction can hold the body: the hemisphere about the design
    direction and the opposite one, coloured by how many cases can be held there."""
    centre = analysis.design if analysis.design is not None else np.array([0.0, 0.0, -1.0])
    edge = np.sqrt(2.0)
    t = np.linspace(-edge, edge, 241)
    x, y = np.meshgrid(t, t)
    # Cosmetic: grid points on the disc's edge, to rounding, are inside.
    inside = np.hypot(x, y) <= edge * (1 + 1e-9)
    axes = fig.subplots(1, 2)
    levels = np.arange(-0.5, len(analysis.cases) + 1.0)
    filled = None
    for k, (ax, sign) in enumerate(zip(axes, (1.0, -1.0), strict=True)):
        c0 = sign * centre
        dirs = lambert_inverse(x, y, c0).reshape(-1, 3)
        count = np.zeros(len(dirs))
        for i, case in enumerate(analysis.cases):
            if not case.determined:
                continue
            held = case.held.contains(dirs)
            count += held
            grid = np.where(inside, held.reshape(x.shape).astype(float), np.nan)
            if np.nanmin(grid) < 0.5 < np.nanmax(grid):
                ax.contour(
                    x, y, grid, levels=[0.5], colors=[palette.support_colour(i)], linewidths=0.9
                )
            if k == 0:
                ax.plot([], [], color=palette.support_colour(i), lw=0.9,
                        label=f"{analysis.statics.names[i]} can be held inside")  # fmt: skip
        shown = np.where(inside, count.reshape(x.shape), np.nan)
        filled = ax.contourf(x, y, shown, levels=levels, colors=_reds(len(levels) - 1))
        if not np.nanmax(shown) > 0:
            say_why_empty(ax, "friction holds no retracted case\nanywhere on this hemisphere")
        for angle in (30, 60, 90):
            r = 2 * np.sin(np.radians(angle) / 2)
            ax.add_patch(ring(r, solid=angle == 90))
            label = f"{angle}°" if sign > 0 else f"{180 - angle}°"
            ax.text(0.71 * r, 0.71 * r, label, fontsize=7, color=palette.MUTED)
        for label, vec in (("+x", (1, 0, 0)), ("+y", (0, 1, 0)), ("+z", (0, 0, 1)),
                           ("−x", (-1, 0, 0)), ("−y", (0, -1, 0)), ("−z", (0, 0, -1))):  # fmt: skip
            v = np.array(vec, float)
            # Cosmetic: label the axes on the near hemisphere, its rim included despite rounding.
            if v @ c0 >= -1e-9:
                px, py = lambert_forward(v, c0)
                ax.plot(px, py, "+", color=palette.DARK, ms=8)
                ax.text(px, py, f" {label}", fontsize=9, color=palette.DARK, va="bottom")
        _sweep_circle(ax, result.details.get("sweep_plane"), c0, first=k == 0)
        if analysis.design is not None and sign > 0:
            ax.plot(0, 0, "*", mfc=palette.DESIGN, mec=palette.PAPER, ms=16,
                    label="design direction" if k == 0 else None)  # fmt: skip
        ax.set_aspect("equal")
        ax.set_xlim(-edge * 1.05, edge * 1.05)
        ax.set_ylim(-edge * 1.05, edge * 1.05)
        ax.axis("off")
        ax.set_title(
            "within 90° of the design direction" if sign > 0 else "the opposite hemisphere",
            fontsize=10,
        )
    assert filled is not None
    bar = fig.colorbar(filled, ax=list(axes), shrink=0.7, pad=0.02)
    bar.set_ticks(np.arange(len(analysis.cases) + 1))
    bar.set_label("retracted cases friction can hold (circumscribed pyramids)")
    fig.legend(loc="outside lower center", ncol=4, fontsize=8, frameon=False)
    what = "load" if analysis.swept == "load" else "gravity"
    details = result.details
    low = details.get("jam_free_solid_angle_fraction")
    high = details.get("jam_free_solid_angle_fraction_upper")
    share = ""
    if low is not None:
        # As the check's message writes it.
        assert high is not None  # given with the lower bound
        share = f": {format_share_bounds(low, high, 1)} of the sphere is jam-free"
    fig.suptitle(
        f"{scene.name} — {verdict_title(result)}\n{what} directions where friction can hold "
        f"the body{share}\nequal-area (Lambert azimuthal) views; white: no retracted case can "
        "be held",
        fontsize=11, color=verdict_colour(result),
    )  # fmt: skip


def draw(check: Check, inputs: Inputs, result: CheckResult, directory: Path) -> list[Path]:
    """jamming's pictures: the sweep circle per case (planar) or the sphere map (spatial), and
    the safe set against friction."""
    from kcheck_checks.jamming import run_jamming
    from kcheck_checks.pictures.friction import plot_friction

    _, analysis, smap = run_jamming(inputs)
    if analysis is None:
        return []
    paths = plot_jamming(inputs.scene, analysis, smap, result, directory)
    return [*paths, *plot_friction(check.id, inputs, result, directory)]
