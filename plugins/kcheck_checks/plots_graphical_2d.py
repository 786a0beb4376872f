"""Picture of the graphical-2d check: Koster's construction like the thesis's Figure 2.8.

matplotlib comes in through :mod:`kcheck.plotting`; the computation lives in
:mod:`kcheck_checks.graphical_2d`, which never imports this module at load time.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis import describe_ranges
from kcheck.arcs import FULL, TAU, ArcSet, complement, intersect, union
from kcheck.errors import KcheckError
from kcheck.plugin import Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.graphical_2d import Construction, attachment, construct

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_graphical", "draw_construction"]


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
    from kcheck.plotting import figure, save, slug

    fig = figure(figsize=(10.5, 7.0))
    ax, side = fig.subplots(1, 2, width_ratios=[2.6, 1.0])
    draw_construction(ax, inputs.scene, built, result)
    side.axis("off")
    side.legend(*ax.get_legend_handles_labels(), loc="upper left", fontsize=8, frameon=False)
    side.text(
        0.0,
        0.0,
        _case_summary(result, inputs.scene.scale, inputs.scene.units),
        transform=side.transAxes,
        fontsize=8,
        family="monospace",
        va="bottom",
        ha="left",
    )
    return save(fig, directory, f"{slug(inputs.scene.name)}-graphical-2d")


LABEL_BOX = {"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8}
SENSE_COLOURS = {"ccw": "tab:blue", "cw": "tab:purple", "translation": "tab:gray"}


def _body_outline(scene: Scene, z: float) -> list[np.ndarray]:
    """Polylines (m, (n, 2)) of the body's mesh cut at height ``z``; [] without a mesh."""
    if scene.body is None or not scene.body.parts:
        return []
    from kcheck.mass import load_mesh

    lines: list[np.ndarray] = []
    for part in scene.body.parts:
        try:
            mesh = load_mesh(part.mesh, scene.scale, part.field)
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
        if e - s >= TAU - 1e-12:
            t1, t2 = 0.0, 360.0
        elif t2 <= t1:
            t2 += 360.0
        kw = dict(style)
        if not first:
            kw.pop("label", None)
        ax.add_patch(Wedge(tuple(centre), radius, t1, t2, **kw))
        first = False


def draw_construction(ax: Axes, scene: Scene, built: Construction, result: CheckResult) -> None:
    """Figure 2.8-like construction: outline, supports, poles, funnel, jamming, safe fan."""
    unit = scene.scale
    frame = built.frame
    to_plot = lambda x: np.asarray(x) / unit  # noqa: E731 - m to scene units
    supports = np.array([s.position[:2] for s in scene.supports])
    normals = built.normals
    size = frame.length / unit
    z = float(scene.supports[0].position[2])

    outline = _body_outline(scene, z)
    if outline:
        for i, line in enumerate(outline):
            ax.fill(
                *to_plot(line).T,
                color="0.92",
                ec="0.35",
                lw=1.2,
                label="body (section at the supports)" if i == 0 else None,
                zorder=0,
            )
    else:
        hull = to_plot(np.vstack([supports, supports[:1]]))
        ax.plot(*hull.T, color="0.5", ls=":", lw=1.0, label="support triangle (no mesh)")
    extent = [to_plot(supports), to_plot(built.attachment.point[:2])[None]]
    extent.extend(to_plot(line) for line in outline)

    # Normal lines, support arrows.
    for k, s in enumerate(scene.supports):
        p = to_plot(s.position[:2])
        n = normals[k]
        ax.axline(tuple(p), tuple(p + n), color="0.6", lw=0.7, ls="--", zorder=1)
        tail = p - 0.28 * size * n
        ax.annotate(
            "",
            xy=tuple(p),
            xytext=tuple(tail),
            arrowprops=dict(arrowstyle="-|>", color="k", lw=1.8),
            zorder=5,
        )
        ax.plot(*p, marker="^", color="k", ms=0, zorder=5)
        ax.annotate(
            s.name,
            tuple(tail),
            textcoords="offset points",
            xytext=(-4, -12),
            fontsize=10,
            weight="bold",
            ha="center",
        )
    ax.plot([], [], color="k", lw=1.8, label="support and normal (pushes the body)")

    # Poles coloured by sense; poles at infinity as arrows at the edge.
    bound = np.vstack(extent)
    lo, hi = bound.min(axis=0), bound.max(axis=0)
    span = float((hi - lo).max())
    finite_poles = []
    for case_result in result.cases:
        pole = case_result.details.get("pole")
        if pole is not None and np.all(np.abs(to_plot(pole) - (lo + hi) / 2) < 2.5 * span):
            finite_poles.append(to_plot(pole))
    if finite_poles:
        bound = np.vstack([bound, *finite_poles])
        lo, hi = bound.min(axis=0), bound.max(axis=0)
        span = float((hi - lo).max())
    centre = (lo + hi) / 2
    half = 0.62 * span + 0.1 * size
    seen: set[str] = set()
    for case_result in result.cases:
        d = case_result.details
        sense = str(d.get("sense"))
        colour = SENSE_COLOURS.get(sense, "k")
        label = None
        if sense not in seen:
            label = {
                "ccw": "pole, needs ccw rotation",
                "cw": "pole, needs cw rotation",
                "translation": "pole at infinity (translation)",
            }.get(sense)
            seen.add(sense)
        name = f"P({case_result.retracted} out)"
        pole = d.get("pole")
        if pole is not None:
            pp = to_plot(pole)
            if np.all(np.abs(pp - centre) <= half):
                ax.plot(*pp, "o", color=colour, ms=11, mec="k", zorder=6, label=label)
                ax.annotate(
                    f"{name} {'↺' if sense == 'ccw' else '↻'}",
                    tuple(pp),
                    textcoords="offset points",
                    xytext=(8, 6),
                    color=colour,
                    fontsize=10,
                    weight="bold",
                    zorder=7,
                    bbox=LABEL_BOX,
                )
                continue
            direction = (pp - centre) / np.linalg.norm(pp - centre)
            text = f"{name} far: ({pp[0]:.4g}, {pp[1]:.4g}) {'↺' if sense == 'ccw' else '↻'}"
        elif d.get("translation_direction") is not None:
            direction = np.asarray(d["translation_direction"])[:2]
            text = f"{name} at ∞: translation"
        else:
            continue
        # Off the centre line, so the arrow does not cover a support on the same axis.
        side = np.array([-direction[1], direction[0]])
        tip = centre + 0.9 * half * direction + 0.55 * half * side
        ax.annotate(
            "",
            xy=tuple(tip),
            xytext=tuple(tip - 0.25 * half * direction),
            arrowprops=dict(arrowstyle="-|>", color=colour, lw=2.5),
            zorder=6,
        )
        ax.plot([], [], color=colour, lw=2.5, label=label)
        # Text beside the arrow, on the side of the picture's centre line.
        inward = -side
        ax.annotate(
            text,
            tuple(tip - 0.12 * half * direction),
            textcoords="offset points",
            xytext=tuple(10 * inward),
            color=colour,
            fontsize=9,
            weight="bold",
            ha="right" if inward[0] < -0.5 else "left" if inward[0] > 0.5 else "center",
            va="bottom" if inward[1] > 0.5 else "top" if inward[1] < -0.5 else "center",
            bbox=LABEL_BOX,
        )

    # Friction poles (hollow) where the tilted reaction lines meet.
    first = True
    for case_result in result.cases:
        fp = case_result.details.get("friction_pole")
        if fp is None:
            continue
        pp = to_plot(fp)
        if np.all(np.abs(pp - centre) <= half):
            colour = SENSE_COLOURS.get(str(case_result.details.get("friction_sense")), "k")
            ax.plot(
                *pp,
                "o",
                mfc="none",
                mec=colour,
                ms=9,
                mew=1.5,
                zorder=6,
                label="friction pole P′ (tilted reactions)" if first else None,
            )
            first = False

    # Direction sectors from the attachment point.
    cases = built.cases
    forbidden = union(*(complement(c.funnel) for c in cases))
    funnel = intersect(*(c.funnel for c in cases))
    jamming = intersect(funnel, union(*(complement(c.friction) for c in cases)))
    q = to_plot(built.attachment.point[:2])
    radius = 0.33 * span
    _wedges(
        ax,
        built,
        q,
        radius,
        forbidden,
        fc=(0.85, 0.1, 0.1, 0.12),
        ec="tab:red",
        hatch="///",
        lw=0.8,
        label="forbidden: wrong rotation sense (funnel)",
        zorder=3,
    )
    _wedges(
        ax,
        built,
        q,
        radius,
        jamming,
        fc=(1.0, 0.6, 0.0, 0.18),
        ec="tab:orange",
        hatch="\\\\",
        lw=0.8,
        label="jamming: friction holds the body",
        zorder=3,
    )
    _wedges(
        ax,
        built,
        q,
        radius,
        built.combined,
        fc=(0.1, 0.7, 0.2, 0.45),
        ec="tab:green",
        lw=1.5,
        label="safe force directions",
        zorder=4,
    )
    for s, e in built.combined if built.combined != FULL else ():
        for a in (s, e):
            t = np.radians(_to_plot_angle(built, a))
            tip = q + 1.08 * radius * np.array([np.cos(t), np.sin(t)])
            ax.annotate(
                f"{np.degrees(a) % 360:.1f}°",
                tuple(tip),
                ha="center",
                va="center",
                fontsize=9,
                color="darkgreen",
                weight="bold",
                zorder=8,
            )
    ax.plot(*q, "o", color="k", ms=7, zorder=8, label="force attachment point")
    design = built.attachment.design
    if design is not None:
        d = design[:2] / np.linalg.norm(design[:2])
        ax.annotate(
            "",
            xy=tuple(q + 0.9 * radius * d),
            xytext=tuple(q),
            arrowprops=dict(arrowstyle="-|>", color="navy", lw=2.4),
            zorder=9,
        )
        angle = result.details.get("design_angle_deg")
        ax.plot([], [], color="navy", lw=2.4, label=f"design force direction ({angle:.1f}°)")

    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x ({scene.units})")
    ax.set_ylabel(f"y ({scene.units})")
    ax.grid(True, lw=0.3, alpha=0.5)
    triangle = result.details.get("pole_triangle")
    if triangle is not None and all(p is not None for p in triangle):
        corners = to_plot(np.array([*triangle, triangle[0]]))
        ax.plot(*corners.T, color="tab:blue", lw=1.2, ls="-.", label="pole triangle")
    verdict = result.status.value.upper()
    title = f"{scene.name} — graphical 2D (Koster): {verdict}\n"
    title += f"safe force directions: {describe_ranges(built.combined)}"
    if triangle is not None:
        title += "\nall poles need one sense: a torque, or an arm outside the pole triangle"
    ax.set_title(title, fontsize=11)


def _case_summary(result: CheckResult, scale: float, units: str) -> str:
    """Per retracted support: pole (scene units), sense and safe range, one line each."""
    lines = ["retracted: pole, sense; safe °"]
    for c in result.cases:
        d = c.details
        pole = d.get("pole")
        where = "∞" if pole is None else f"({pole[0] / scale:.4g}, {pole[1] / scale:.4g}) {units}"
        safe = (
            "none"
            if not c.safe_ranges_deg
            else ", ".join(f"{s:.1f}–{e:.1f}" for s, e in c.safe_ranges_deg)
        )
        lines.append(f"{c.retracted}: {where}, {d.get('sense')}; {safe}")
    return "\n".join(lines)
