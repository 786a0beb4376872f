"""Picture of the `reseat` check: for the case with the largest seat error (re-simulated at
the check's time step), each support's gap and normal force against time, and the path of
the centre of mass. matplotlib comes in through :mod:`kcheck.pictures.plotting`."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from kcheck.analysis.reseat import simulate
from kcheck.pictures import colours
from kcheck.pictures.plotting import current_formats, figure, save, slug
from kcheck.plugin import Check, Inputs
from kcheck.result import CheckResult
from kcheck_checks.pictures.titles import verdict_colour, verdict_title
from kcheck_checks.reseat import ReseatOptions, friction_ends, settings_of

__all__ = ["draw", "worst_case"]


def worst_case(result: CheckResult) -> int | None:
    """Index of the case with the largest seat error or closing gap, or None."""
    if not result.cases:
        return None
    errors = [max(c.details["seat_error_um"], c.details["closing_gap_um"]) for c in result.cases]
    return int(np.argmax(errors))


def draw(check: Check, inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
    """Write ``<scene>-reseat.png/.svg`` for the worst case; return the paths."""
    index = worst_case(result)
    if index is None or inputs.mass is None:
        return []
    assert isinstance(inputs.options, ReseatOptions)
    scene, settings = inputs.scene, settings_of(inputs.options)
    k = len(scene.supports)
    label, mu = friction_ends(scene)[index // k]
    run = simulate(scene, inputs.mass, index % k, mu, settings)
    trace = run.trace
    names = [s.name for s in scene.supports]
    fig = figure(figsize=(15.0, 4.8))
    axes = fig.subplots(1, 3)
    t = trace.time * 1e3
    for i, name in enumerate(names):
        style = "-" if i != run.retracted else "--"
        axes[0].plot(
            t, trace.gaps[:, i] * 1e6, style, lw=1.2, label=name, color=colours.support_colour(i)
        )
        axes[1].plot(
            t, trace.forces[:, i], style, lw=1.2, label=name, color=colours.support_colour(i)
        )
    for ax in axes[:2]:
        ax.axvline(0, color=colours.FAINT, lw=0.8)
        ax.axvline(settings.duration * 1e3, color=colours.FAINT, lw=0.8)
        ax.set_xlabel("time, ms (0: retraction, grey: return starts)")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("gap from the seat, µm (dashed: retracted)")
    axes[0].set_title("gaps", fontsize=10)
    axes[0].axhline(0, color=colours.FAINT, lw=0.8)
    # A negative gap is the soft contact pressed deeper than in the settled seat (penetration).
    axes[0].text(
        0.01, 0.01, "below 0: pressed deeper than in the seat (soft-contact penetration)",
        transform=axes[0].transAxes, fontsize=7, color=colours.FAINT, va="bottom",
    )  # fmt: skip
    axes[1].set_ylabel("normal force, N")
    axes[1].set_title("contact forces", fontsize=10)
    _trajectory(axes[2], trace.reference, trace.time, scene.kind == "planar")
    case = result.cases[index]
    fig.suptitle(
        f"{scene.name} — {verdict_title(result)}\nretract {case.retracted}: "
        f"{case.details['verdict']}, seat error {case.details['seat_error_um']:.3g} µm, "
        f"first motion {case.details['first_motion'].replace('_', ' ')}",
        fontsize=10, color=verdict_colour(result),
    )  # fmt: skip
    paths = list(save(fig, directory, f"{slug(scene.name)}-reseat"))
    if "svg" in current_formats():
        motion = directory / f"{slug(scene.name)}-reseat-motion.svg"
        motion.write_text(motion_svg(trace, scene.kind == "planar", names), encoding="utf-8")
        paths.append(motion)
    return paths


#: Frames of the animation, and its loop time (s).
FRAMES = 240
LOOP_S = 8.0


def motion_svg(trace: Any, planar: bool, names: Sequence[str]) -> str:
    """An animated SVG (SMIL, no script: the HTML report inlines it) of the body's contact
    points over the case, seen in the xy-plane (planar) or the plane of the largest motions,
    displacements exaggerated so the largest is a fifth of the layout: the supports' seats as
    crosses, the contact points as dots moving through settle, retraction and return."""
    contacts = trace.contacts
    start = int(np.searchsorted(trace.time, 0.0))
    seat = contacts[start]
    moved = contacts - seat
    if planar:
        axes = np.eye(3)[:2]
    else:
        flat = moved.reshape(-1, 3)
        _, _, vt = np.linalg.svd(flat - flat.mean(axis=0), full_matrices=False)
        axes = vt[:2]
    layout = (seat - seat.mean(axis=0)) @ axes.T
    size = float(np.max(np.abs(layout))) or 1.0
    largest = float(np.max(np.linalg.norm(moved, axis=2))) or 1e-12
    gain = 0.2 * size / largest
    picks = np.linspace(0, len(trace.time) - 1, FRAMES).round().astype(int)
    path = layout[None] + gain * (moved[picks] @ axes.T)

    def px(xy: np.ndarray) -> tuple[float, float]:
        return 200 + 150 * xy[0] / size, 200 - 150 * xy[1] / size

    parts = [
        '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 400 440" width="400" '
        'height="440" font-family="sans-serif" font-size="11">',
        f'<rect width="400" height="440" fill="{colours.PAPER}"/>',
    ]
    for i, name in enumerate(names):
        x, y = px(layout[i])
        parts.append(
            f'<path d="M{x - 5:.1f},{y:.1f}h10M{x:.1f},{y - 5:.1f}v10" stroke="{colours.INK}"/>'
            f'<text x="{x + 7:.1f}" y="{y - 7:.1f}">{name}</text>'
        )
        xs = ";".join(f"{px(p)[0]:.2f}" for p in path[:, i])
        ys = ";".join(f"{px(p)[1]:.2f}" for p in path[:, i])
        parts.append(
            f'<circle r="4" fill="{colours.support_colour(i)}"><animate attributeName="cx" '
            f'values="{xs}" dur="{LOOP_S}s" repeatCount="indefinite"/><animate '
            f'attributeName="cy" values="{ys}" dur="{LOOP_S}s" repeatCount="indefinite"/>'
            "</circle>"
        )
    span = trace.time[-1] - trace.time[0]
    parts.append(
        '<text x="10" y="412">contact points (dots) and their seats (crosses)</text>'
        f'<text x="10" y="428">displacements × {gain:.3g}; one loop = {span:.2f} s simulated'
        "</text></svg>"
    )
    return "".join(parts)


def _trajectory(ax: Any, reference: np.ndarray, time: np.ndarray, planar: bool) -> None:
    """The centre of mass's path (µm from the seat), coloured by time: the xy-plane for a
    planar scene, else the plane of its two largest motions."""
    moved = (reference - reference[np.searchsorted(time, 0.0)]) * 1e6
    if planar:
        xy, labels = moved[:, :2], ("x, µm", "y, µm")
    else:
        _, _, vt = np.linalg.svd(moved - moved.mean(axis=0), full_matrices=False)
        xy = moved @ vt[:2].T
        labels = ("along the largest motion, µm", "along the second, µm")
    points = ax.scatter(xy[:, 0], xy[:, 1], c=time * 1e3, s=4, cmap=colours.TIME_MAP)
    ax.plot(xy[:, 0], xy[:, 1], color=colours.FAINT, lw=0.5)
    ax.plot([0], [0], "+", color=colours.INK, ms=12, label="seat")
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_title("path of the centre of mass", fontsize=10)
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7)
    ax.figure.colorbar(points, ax=ax, label="time, ms")
