"""Picture of the graphical-2d check: Koster's construction like the thesis's Figure 2.8.

matplotlib comes in through :mod:`kcheck.pictures.plotting`; the computation lives in
:mod:`kcheck_checks.graphical_2d`, which never imports this module at load time. The picture
says what the construction cannot see (it is mass-free: contact loss is not checked), labels
every pole and friction pole, draws a pole at infinity as a direction inside the frame, and
marks where 0° is and which way angles turn.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.errors import KcheckError
from kcheck.fmt import format_angle, format_point, format_ranges
from kcheck.mechanics.arcs import FULL, TAU, ArcSet, complement, intersect, union
from kcheck.pictures import colours as palette
from kcheck.pictures.labels import say_why_empty
from kcheck.plugin import Check, Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.graphical_2d import MASS_FREE, Construction, attachment, construct

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_graphical", "draw_construction"]

LABEL_BOX = {"boxstyle": "square,pad=0.15", "fc": palette.PAPER, "ec": "none", "alpha": 0.85}
SENSE_COLOURS = palette.SENSE_COLOURS
SENSE_MARK = {"ccw": "↺", "cw": "↻"}


def plot_graphical(inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
    """Write the construction picture of one scene; return the files written."""
    point = result.details.get("attachment_point")
    com = None if inputs.mass is None else inputs.mass.center_of_mass
    where = attachment(inputs.scene, None if point is None else np.asarray(point), com)
    if isinstance(where, str):
        return ()
    built = construct(inputs.scene, where)
    if built is None:
        return ()
    from kcheck.pictures.plotting import figure, save, slug
    from kcheck_checks.pictures.titles import verdict_title

    # Fixed margins (inches) instead of a layout engine: a third of the drawing cost; a line
    # more for the scene's verdict when it is worse.
    top = 0.72 + 0.2 * verdict_title(result).count("\n")
    fig = figure(figsize=(11.0, 7.0 + top - 0.72), layout=None)
    fig.subplots_adjust(
        left=0.75 / 11, right=0.99, top=1 - top / (7.0 + top - 0.72), bottom=0.9 / 7, wspace=0.08
    )
    ax, side = fig.subplots(1, 2, width_ratios=[2.5, 1.0])
    draw_construction(ax, inputs.scene, built, result)
    side.axis("off")
    side.legend(*ax.get_legend_handles_labels(), loc="upper left", fontsize=8, frameon=False)
    _compass(side.inset_axes((0.0, 0.3, 0.4, 0.2)), built)
    side.text(
        0.0, 0.0, _case_summary(result, inputs.scene.scale, inputs.scene.units),
        transform=side.transAxes, fontsize=7.5, family="monospace", va="bottom", ha="left",
    )  # fmt: skip
    return save(fig, directory, f"{slug(inputs.scene.name)}-graphical-2d")


def _body_outline(scene: Scene, z: float) -> list[np.ndarray]:
    """Polylines (m, (n, 2)) of the body's mesh cut at height ``z``; [] without a mesh."""
    if scene.body is None or not scene.body.parts:
        return []
    from kcheck.body.mass import placed_mesh

    lines: list[np.ndarray] = []
    for part in scene.body.parts:
        try:
            mesh = placed_mesh(part)
        except KcheckError:
            continue
        section = mesh.section(plane_origin=[0.0, 0.0, z], plane_normal=[0.0, 0.0, 1.0])
        if section is not None:
            lines.extend(np.asarray(d)[:, :2] for d in section.discrete)
    return lines


def _to_plot_angle(built: Construction, alpha: float) -> float:
    """Sweep angle (rad) to the picture's angle from +x (deg)."""
    d = np.cos(alpha) * built.e1 + np.sin(alpha) * built.e2
    return float(np.degrees(np.arctan2(d[1], d[0])))


def _wedges(
    ax: Axes, built: Construction, centre: np.ndarray, radius: float, arcs: ArcSet, **style: Any
) -> None:
    from matplotlib.patches import Wedge

    first = True
    for s, e in arcs:
        t1, t2 = _to_plot_angle(built, s), _to_plot_angle(built, e)
        if np.cross(np.append(built.e1, 0), np.append(built.e2, 0))[2] < 0:
            t1, t2 = t2, t1
        # Cosmetic: an arc a full turn to rounding is drawn as the whole circle.
        if e - s >= TAU - 1e-12:
            t1, t2 = 0.0, 360.0
        elif t2 <= t1:
            t2 += 360.0
        kw = dict(style)
        if not first:
            kw.pop("label", None)
        hatch = kw.get("hatch")
        ax.add_patch(Wedge(tuple(centre), radius, t1, t2, **kw))
        if hatch:  # again, opaque: SVG fades a hatch with its fill's alpha
            ax.add_patch(
                Wedge(tuple(centre), radius, t1, t2, fill=False, hatch=hatch, lw=0,
                      ec=kw.get("ec"), zorder=kw.get("zorder"))
            )  # fmt: skip
        first = False


def _supports(ax: Axes, scene: Scene, built: Construction, to_plot: Any, size: float) -> None:
    """Normal lines and support arrows (names: :func:`_support_names`, once the frame is set)."""
    for k, s in enumerate(scene.supports):
        p = to_plot(s.position[:2])
        n = built.normals[k]
        ax.axline(tuple(p), tuple(p + n), color=palette.FAINT, lw=0.7, ls="--", zorder=1)
        tail = p - 0.28 * size * n
        ax.annotate(
            "", xy=tuple(p), xytext=tuple(tail),
            arrowprops={"arrowstyle": "-|>", "color": palette.SUPPORT, "lw": 1.8}, zorder=5,
        )  # fmt: skip
    ax.plot([], [], color=palette.SUPPORT, lw=1.8, label="support and normal (pushes the body)")


def _support_names(ax: Axes, scene: Scene, built: Construction, to_plot: Any, size: float) -> None:
    """Each support's name beside its point, across its arrow, inside the frame."""
    from kcheck.pictures.labels import label_supports

    points = np.array([to_plot(s.position[:2]) for s in scene.supports])
    label_supports(
        ax, points, -np.asarray(built.normals, float), [s.name for s in scene.supports], size,
        fontsize=10, weight="bold", color=palette.SUPPORT,
    )  # fmt: skip


def _away(pp: np.ndarray, other: np.ndarray | None, default: tuple[float, float]) -> dict:
    """Offset (points) and alignment of a label at ``pp`` on the side away from ``other``."""
    if other is None or np.linalg.norm(other - pp) == 0:
        u = np.array(default, float)
    else:
        u = (pp - other) / np.linalg.norm(other - pp)
    return {
        "xytext": tuple(9 * u),
        "ha": "left" if u[0] > 0.3 else "right" if u[0] < -0.3 else "center",
        "va": "bottom" if u[1] > 0.3 else "top" if u[1] < -0.3 else "center",
    }


def _far_poles(
    ax: Axes,
    items: list[tuple[np.ndarray, str, str, str | None]],
    centre: np.ndarray,
    half: float,
    q: np.ndarray,
) -> None:
    """Poles off the picture or at infinity: an arrow at the frame's edge pointing their way,
    on the side of the frame away from the force fan, the name beside it."""
    for k, (direction, text, colour, label) in enumerate(items):
        u = direction / np.linalg.norm(direction)
        side = np.array([-u[1], u[0]])
        shift = 0.45 - 0.2 * k
        if np.linalg.norm(centre + shift * half * side - q) < np.linalg.norm(
            centre - shift * half * side - q
        ):
            side = -side
        tip = centre + 0.95 * half * u + shift * half * side
        tail = tip - 0.18 * half * u
        ax.annotate(
            "", xy=tuple(tip), xytext=tuple(tail),
            arrowprops={"arrowstyle": "-|>", "color": colour, "lw": 2.5}, zorder=6,
        )  # fmt: skip
        ax.plot([], [], color=colour, lw=2.5, label=label)
        inward = -u
        ax.annotate(
            text, tuple(tail), textcoords="offset points", xytext=tuple(4 * inward),
            color=colour, fontsize=9, weight="bold", zorder=7, bbox=LABEL_BOX,
            ha="right" if u[0] > 0.3 else "left" if u[0] < -0.3 else "center",
            va="top" if u[1] > 0.3 else "bottom" if u[1] < -0.3 else "center",
        )  # fmt: skip


def _poles(
    ax: Axes, result: CheckResult, to_plot: Any, centre: np.ndarray, half: float, q: np.ndarray
) -> None:
    """Poles coloured by the sense they need, friction poles P′ hollow, each labelled on the
    side away from its partner; poles off the picture as arrows at the frame's edge."""
    seen: set[str] = set()
    far: list[tuple[np.ndarray, str, str, str | None]] = []
    first_friction = True

    def inside(p: Any) -> bool:
        return p is not None and bool(np.all(np.abs(to_plot(p) - centre) <= half))

    for case in result.cases:
        d = case.details
        sense = str(d.get("sense"))
        colour = SENSE_COLOURS.get(sense, palette.INK)
        label = None
        if sense not in seen:
            label = {
                "ccw": "pole P, needs ccw rotation",
                "cw": "pole P, needs cw rotation",
                "translation": "pole at infinity (translation)",
            }.get(sense)
            seen.add(sense)
        name = f"P({case.retracted} out)"
        pole, fpole = d.get("pole"), d.get("friction_pole")
        pp = None if not inside(pole) else to_plot(pole)
        fp = None if not inside(fpole) else to_plot(fpole)
        if pp is not None:
            ax.plot(*pp, "o", color=colour, ms=11, mec=palette.INK, zorder=6, label=label)
            ax.annotate(
                f"{name} {SENSE_MARK.get(sense, '')}", tuple(pp), textcoords="offset points",
                color=colour, fontsize=10, weight="bold", zorder=7, bbox=LABEL_BOX,
                **_away(pp, fp, (0.7, 0.7)),
            )  # fmt: skip
        elif pole is not None:
            far.append((to_plot(pole) - centre, f"{name} {SENSE_MARK.get(sense, '')} far",
                        colour, label))  # fmt: skip
        elif d.get("translation_direction") is not None:
            far.append((np.asarray(d["translation_direction"], float)[:2],
                        f"{name} at ∞", colour, label))  # fmt: skip
        if fp is not None:
            fcolour = SENSE_COLOURS.get(str(d.get("friction_sense")), palette.INK)
            ax.plot(
                *fp, "o", mfc=palette.PAPER, mec=fcolour, ms=9, mew=1.5, zorder=6,
                label="friction pole P′ (reactions tilted by friction)" if first_friction else None,
            )  # fmt: skip
            ax.annotate(
                f"P′({case.retracted} out)", tuple(fp), textcoords="offset points",
                color=fcolour, fontsize=8, zorder=7, bbox=LABEL_BOX,
                **_away(fp, pp, (0.7, -0.7)),
            )  # fmt: skip
            first_friction = False
    _far_poles(ax, far, centre, half, q)


def _compass(ax: Axes, built: Construction) -> None:
    """Where 0° and 90° of the force angle point and the counter-clockwise sense, drawn in
    its own small axes (equal aspect, so the arrows show the true directions)."""
    for vec, text in ((built.e1, "0°"), (built.e2, "90°")):
        v = np.asarray(vec[:2], float) / np.linalg.norm(vec[:2])
        ax.annotate(
            "", xy=tuple(v), xytext=(0, 0),
            arrowprops={"arrowstyle": "-|>", "color": palette.DARK, "lw": 1.3},
        )  # fmt: skip
        ax.text(
            1.35 * v[0], 1.35 * v[1], text, fontsize=8, ha="center", va="center", color=palette.DARK
        )
    start = float(np.degrees(np.arctan2(built.e1[1], built.e1[0])))
    turn = 1.0 if built.e1[0] * built.e2[1] - built.e1[1] * built.e2[0] > 0 else -1.0
    t = np.radians(start + turn * np.linspace(15, 75, 20))
    arc = 0.55 * np.column_stack([np.cos(t), np.sin(t)])
    ax.plot(*arc[:-1].T, color=palette.DARK, lw=1.0)
    ax.annotate(
        "", xy=tuple(arc[-1]), xytext=tuple(arc[-3]),
        arrowprops={"arrowstyle": "-|>", "color": palette.DARK, "lw": 1.0},
    )  # fmt: skip
    ax.set_xlim(-1.7, 1.7)
    ax.set_ylim(-1.7, 1.7)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("force angle", fontsize=8, color=palette.DARK)


def draw_construction(ax: Axes, scene: Scene, built: Construction, result: CheckResult) -> None:
    """Figure 2.8-like construction: outline, supports, poles, funnel, jamming, safe fan."""
    from matplotlib.colors import to_rgba

    unit = scene.scale
    to_plot = lambda x: np.asarray(x) / unit  # noqa: E731 - m to scene units
    supports = np.array([s.position[:2] for s in scene.supports])
    size = built.frame.length / unit
    z = float(scene.supports[0].position[2])

    outline = _body_outline(scene, z)
    for i, line in enumerate(outline):
        ax.fill(
            *to_plot(line).T, color=palette.BODY, ec=palette.BODY_EDGE, lw=1.2, zorder=0,
            label="body (section at the supports)" if i == 0 else None,
        )  # fmt: skip
    if not outline:
        hull = to_plot(np.vstack([supports, supports[:1]]))
        ax.plot(*hull.T, color=palette.FAINT, ls=":", lw=1.0, label="support triangle (no mesh)")
    extent = [to_plot(supports), to_plot(built.attachment.point[:2])[None]]
    extent.extend(to_plot(line) for line in outline)
    extent.append(to_plot(supports) - 0.4 * size * built.normals)  # arrow tails and names
    _supports(ax, scene, built, to_plot, size)

    bound = np.vstack(extent)
    lo, hi = bound.min(axis=0), bound.max(axis=0)
    span = float((hi - lo).max())
    near = [
        to_plot(c.details["pole"])
        for c in result.cases
        if c.details.get("pole") is not None
        and np.all(np.abs(to_plot(c.details["pole"]) - (lo + hi) / 2) < 2.5 * span)
    ]
    if near:
        bound = np.vstack([bound, *near])
        lo, hi = bound.min(axis=0), bound.max(axis=0)
        span = float((hi - lo).max())
    centre = (lo + hi) / 2
    half = 0.62 * span + 0.1 * size
    q = to_plot(built.attachment.point[:2])
    _poles(ax, result, to_plot, centre, half, q)

    # Direction sectors from the attachment point.
    cases = built.cases
    forbidden = union(*(complement(c.funnel) for c in cases))
    funnel = intersect(*(c.funnel for c in cases))
    jamming = intersect(funnel, union(*(complement(c.friction) for c in cases)))
    radius = 0.33 * span
    _wedges(ax, built, q, radius, forbidden, fc=to_rgba(palette.FAILING, 0.12), ec=palette.FAILING,
            hatch="///", lw=0.8, label="forbidden: wrong rotation sense (funnel)",
            zorder=3)  # fmt: skip
    _wedges(ax, built, q, radius, jamming, fc=to_rgba(palette.JAMMING, 0.18), ec=palette.JAMMING,
            hatch="\\\\", lw=0.8, label="jamming: friction holds the body", zorder=3)  # fmt: skip
    _wedges(ax, built, q, radius, built.combined, fc=to_rgba(palette.SAFE, 0.45), ec=palette.SAFE,
            lw=1.5, label="safe force directions (mass-free)", zorder=4)  # fmt: skip
    if not built.combined:
        say_why_empty(ax, "no safe force direction (mass-free):\nno green fan")
    for s, e in built.combined if built.combined != FULL else ():
        for a in (s, e):
            t = np.radians(_to_plot_angle(built, a))
            tip = q + 1.1 * radius * np.array([np.cos(t), np.sin(t)])
            ax.text(
                tip[0], tip[1], format_angle(np.degrees(a) % 360, 1), ha="center", va="center",
                fontsize=9, color=palette.SAFE_DARK, weight="bold", zorder=8, bbox=LABEL_BOX,
            )  # fmt: skip
    ax.plot(*q, "o", color=palette.INK, ms=7, zorder=8, label="force attachment point")
    design = built.attachment.design
    if design is not None:
        d = design[:2] / np.linalg.norm(design[:2])
        ax.annotate(
            "", xy=tuple(q + 0.9 * radius * d), xytext=tuple(q),
            arrowprops={"arrowstyle": "-|>", "color": palette.DESIGN, "lw": 2.4}, zorder=9,
        )  # fmt: skip
        angle = result.details.get("design_angle_deg")
        if angle is not None:
            ax.plot(
                [],
                [],
                color=palette.DESIGN,
                lw=2.4,
                label=f"design force ({format_angle(angle, 1)})",
            )

    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal")
    _support_names(ax, scene, built, to_plot, 2 * half)
    ax.set_xlabel(f"x ({scene.units})")
    ax.set_ylabel(f"y ({scene.units})")
    ax.grid(True, lw=0.3, alpha=0.5)
    triangle = result.details.get("pole_triangle")
    if triangle is not None and all(p is not None for p in triangle):
        corners = to_plot(np.array([*triangle, triangle[0]]))
        ax.plot(
            *corners.T, color=palette.SENSE_COLOURS["ccw"], lw=1.2, ls="-.", label="pole triangle"
        )
    _title(ax, scene, result, triangle is not None)


def _title(ax: Axes, scene: Scene, result: CheckResult, triangle: bool) -> None:
    from kcheck.pictures.plotting import sweep_note
    from kcheck_checks.pictures.titles import verdict_colour, verdict_title

    title = f"{scene.name} — Koster's construction\n{verdict_title(result, f' ({MASS_FREE})')}"
    title += f"\nsafe force directions: {format_ranges(result.safe_ranges_deg, 1)}"
    if triangle:
        title += "\nevery pole needs one sense: a torque, or an arm outside the pole triangle"
    ax.set_title(title, fontsize=10.5, color=verdict_colour(result), loc="left")
    ax.text(
        0.0, -0.1, sweep_note(scene.sweep.normal, scene.sweep.e1), transform=ax.transAxes,
        fontsize=7.5, color=palette.MUTED, va="top",
    )  # fmt: skip


def _case_summary(result: CheckResult, scale: float, units: str) -> str:
    """Per retracted support: pole (scene units) and sense; its safe range, two lines each."""
    lines = ["retracted: pole, sense", "  safe force angles"]
    for c in result.cases:
        d = c.details
        pole = d.get("pole")
        where = "at ∞" if pole is None else f"{format_point(np.asarray(pole) / scale, 2)} {units}"
        lines.append(f"{c.retracted}: {where}, {d.get('sense')}")
        lines.append(f"  {format_ranges(c.safe_ranges_deg, 1)}")
    return "\n".join(lines)


def draw(check: Check, inputs: Inputs, result: CheckResult, directory: Path) -> list[Path]:
    """graphical-2d's pictures: the construction like the thesis's Figure 2.8, and the safe
    set against friction."""
    from kcheck_checks.pictures.friction import plot_friction

    paths = plot_graphical(inputs, result, directory)
    return [*paths, *plot_friction(check.id, inputs, result, directory)]
