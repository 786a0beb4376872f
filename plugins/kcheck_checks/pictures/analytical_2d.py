"""Pictures of the analytical-2d check: normal forces and acceleration against force angle
(thesis Figures 2.17-2.20), drawn from the exact affine forms. matplotlib comes in through
:mod:`kcheck.pictures.plotting`.

One panel per retracted support; every support keeps its colour and line style in every panel
(so two curves that coincide stay distinguishable: a wide pale line under a narrow dashed
one), one legend for the whole figure, and at the design angle the value that decides the
outcome is marked ("y1: N = -0.087 N"). Outcomes without a colour of their own get a neutral
one, so new outcome names never break the picture.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis import analyse
from kcheck.analysis.cases import Analysis
from kcheck.fmt import format_angle, format_number, format_point, format_ranges
from kcheck.mechanics.dynamics import Case
from kcheck.mechanics.outcomes import outcomes
from kcheck.pictures import colours as palette
from kcheck.pictures.colours import outcome_colour
from kcheck.pictures.plotting import sweep_note
from kcheck.plugin import Check, Inputs
from kcheck.result import CaseResult, CheckResult
from kcheck.scene import Scene

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_analytical_2d", "support_style"]

# Wide and pale first, then narrower patterned lines drawn on top of it.
SUPPORT_LINES = (
    {"ls": "-", "lw": 4.0, "alpha": 0.45},
    {"ls": (0, (5, 2)), "lw": 1.8, "alpha": 1.0},
    {"ls": (0, (1, 1.5)), "lw": 2.2, "alpha": 1.0},
)
DESIGN = palette.DESIGN
GOOD = ("closes", "swept")


def support_style(j: int) -> dict[str, Any]:
    """Colour and line of support ``j``'s normal force, the same in every panel."""
    return {"color": palette.support_colour(j), **SUPPORT_LINES[j % 3]}


def plot_analytical_2d(inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
    """One panel per retracted support and a strip with the combined range; the files written."""
    assert inputs.mass is not None
    from kcheck.pictures.plotting import figure, save, slug

    scene = inputs.scene
    analysis = analyse(scene, inputs.mass)
    if analysis.arcs is None:
        return ()
    from kcheck_checks.pictures.titles import verdict_colour, verdict_title

    n = len(analysis.cases)
    status = verdict_title(result)
    extra = 0.2 * status.count("\n")  # a line for the scene's verdict when it is worse
    height = 2.45 * n + 2.3 + extra
    # Fixed margins (inches) instead of a layout engine: the same layout every time, at a
    # third of the drawing cost.
    fig = figure(figsize=(9.5, height), layout=None)
    fig.subplots_adjust(
        left=0.85 / 9.5, right=1 - 0.85 / 9.5, top=1 - (0.95 + extra) / height,
        bottom=1.25 / height,
        hspace=0.42,
    )  # fmt: skip
    axes = fig.subplots(n + 1, 1, sharex=True, height_ratios=[1.0] * n + [0.24])
    states: set[str] = set()
    for ax, case, case_result in zip(axes[:-1], analysis.cases, result.cases, strict=True):
        states |= _case_panel(ax, scene, analysis, case, case_result)
    _combined_strip(axes[-1], scene, analysis, result)
    _legend(fig, analysis, states)
    fig.suptitle(
        f"{scene.name} — {status}\n{_summary(scene, result)}",
        fontsize=11, color=verdict_colour(result), y=1 - 0.12 / height, va="top",
    )  # fmt: skip
    return save(fig, directory, f"{slug(scene.name)}-analytical-2d")


def _summary(scene: Scene, result: CheckResult) -> str:
    text = f"safe for every retraction: {format_ranges(result.safe_ranges_deg, 1)}"
    design = scene.design_angle_deg
    if design is not None:
        bad = [c for c in result.cases if c.outcome not in GOOD]
        if bad:
            what = ", ".join(f"{c.retracted} {c.outcome.replace('_', ' ')}" for c in bad)
            text += f"; at the design angle {format_angle(design, 1)}: {what}"
        else:
            text += f"; design {format_angle(design, 1)}"
    return text


def _curves(case: Case, analysis: Analysis, scene: Scene, deg: np.ndarray) -> dict[str, Any]:
    """Outcome, acceleration (m/s^2) and normal forces (N) on an angle grid from the exact
    affine forms, under forward sliding (friction opposing motion towards the support) as in
    the thesis's figures; ``forward`` marks where that assumption holds (lambda > 0)."""
    problem = analysis.problem
    rad = np.radians(deg)
    d = np.cos(rad)[:, None] * scene.sweep.e1[:2] + np.sin(rad)[:, None] * scene.sweep.e2[:2]
    assert case.forward is not None
    fwd = case.forward.a[None, :] + d @ case.forward.c.T
    return {
        "accel": fwd[:, 0] * problem.acceleration_scale() * case.free.closing,
        "forces": fwd[:, 1:] * problem.frame.force,
        "state": outcomes(case, d),
        "forward": fwd[:, 0] > 0,
    }


def _plot_split(ax: Axes, deg: np.ndarray, y: np.ndarray, valid: np.ndarray, **style: Any) -> None:
    """A curve drawn as styled where ``valid`` and thin dotted elsewhere."""
    ax.plot(deg, np.where(valid, y, np.nan), **style)
    faint = {k: v for k, v in style.items() if k in ("color", "zorder")}
    ax.plot(deg, np.where(valid, np.nan, y), ls=":", lw=0.8, alpha=0.5, **faint)


def _spans(ranges: Sequence[Sequence[float]]) -> list[tuple[float, float]]:
    """Arc ranges in degrees split at 360 into pieces inside [0, 360]."""
    out: list[tuple[float, float]] = []
    for start, end in ranges:
        if end - start >= 360.0:
            out.append((0.0, 360.0))
            continue
        s, width = start % 360.0, (end - start) % 360.0
        if s + width <= 360.0:
            out.append((s, s + width))
        else:
            out.extend([(s, 360.0), (0.0, s + width - 360.0)])
    return out


def _outcome_strip(ax: Axes, deg: np.ndarray, state: np.ndarray) -> None:
    """Coloured bar at the top of a panel: the outcome at each force angle."""
    change = np.flatnonzero(state[1:] != state[:-1]) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [len(deg) - 1]])
    for i, j in zip(starts, ends, strict=True):
        ax.axvspan(deg[i], deg[j], ymin=0.92, ymax=1.0, color=outcome_colour(str(state[i])), lw=0)


def _mark_design(
    ax: Axes, twin: Axes, scene: Scene, result: CaseResult, names: Sequence[str]
) -> None:
    """At the design angle, mark what decides a bad outcome: a negative normal force, or a
    negative acceleration, with its value."""
    design = scene.design_angle_deg
    if design is None or result.outcome in GOOD:
        return
    marks: list[tuple[Axes, float, str]] = []
    for name, value in (result.normal_forces or {}).items():
        if value < 0:
            marks.append((ax, value, f"{name}: N = {_minus(format_number(value, 2))} N"))
    accel = result.acceleration
    if accel is not None and accel <= 0:
        marks.append((twin, accel, f"a = {_minus(format_number(accel, 2))} m/s²"))
    if not marks:
        marks.append((ax, 0.0, result.outcome.replace("_", " ")))
    for k, (target, value, text) in enumerate(marks):
        target.plot(design, value, "o", ms=9, mfc="none", mec=palette.FAILING, mew=2.0, zorder=9)
        target.annotate(
            text, (design, value), textcoords="offset points", xytext=(12, 12 + 14 * k),
            fontsize=9, weight="bold", color=palette.FAILING, zorder=9,
            arrowprops={"arrowstyle": "-", "color": palette.FAILING, "lw": 1.0},
            bbox={"boxstyle": "round,pad=0.2", "fc": palette.PAPER, "ec": palette.FAILING,
                  "lw": 0.8},
            ha="left" if design < 250 else "right",
        )  # fmt: skip


def _minus(text: str) -> str:
    return text.replace("-", "−")  # a typographic minus, as on the axes


def _title(result: CaseResult, scene: Scene) -> str:
    title = f"{result.retracted} retracted"
    motion = result.details.get("motion")
    if motion == "rotation":
        pole = np.asarray(result.details["pole"]) / scene.scale
        title += f": {result.details['sense']} about the pole {format_point(pole, 2)} {scene.units}"
    elif motion == "translation":
        title += ": translation"
    return title


def _case_panel(
    ax: Axes, scene: Scene, analysis: Analysis, case: Case, result: CaseResult
) -> set[str]:
    """One retracted support: its safe band, normal forces (N, left) and acceleration (right);
    returns the outcomes its bar shows."""
    ax.set_xlim(0, 360)
    ax.axhline(0, color=palette.INK, lw=0.8)
    title = _title(result, scene)
    if case.forward is None or result.safe_ranges_deg is None:
        ax.set_title(f"{title} — {result.outcome.replace('_', ' ')}", fontsize=9, loc="left")
        ax.text(180, 0, str(result.details.get("diagnostic", result.outcome)), ha="center",
                fontsize=9)  # fmt: skip
        return set()
    deg = np.linspace(0.0, 360.0, 721)
    curves = _curves(case, analysis, scene, deg)
    for s, e in _spans(result.safe_ranges_deg):
        ax.axvspan(s, e, color=palette.SAFE, alpha=0.13, lw=0)
    _outcome_strip(ax, deg, curves["state"])
    for k, j in enumerate(case.keep):
        _plot_split(ax, deg, curves["forces"][:, k], curves["forward"], **support_style(j))
    limit = float(np.abs(curves["forces"]).max()) * 1.15 or 1.0
    ax.set_ylim(-limit, limit / 0.92)
    ax.set_ylabel("normal force (N)", fontsize=8)
    twin = ax.twinx()
    _plot_split(twin, deg, curves["accel"], curves["forward"], color=palette.INK, lw=1.1, ls="--")
    alimit = float(np.abs(curves["accel"]).max()) * 1.15 or 1.0
    twin.set_ylim(-alimit, alimit / 0.92)
    twin.set_ylabel(f"accel. of {result.retracted}\ntowards it (m/s²)", fontsize=8)
    twin.tick_params(labelsize=8)
    ax.tick_params(labelsize=8)
    ax.set_title(
        f"{title} — safe {format_ranges(result.safe_ranges_deg, 1)}",
        fontsize=9, loc="left", color=outcome_colour(result.outcome),
    )  # fmt: skip
    if analysis.design is not None:
        design = scene.design_angle_deg
        assert design is not None  # the design direction is the load's
        ax.axvline(design, color=DESIGN, lw=1.4, ls=":")
    _mark_design(ax, twin, scene, result, analysis.problem.names)
    ax.grid(alpha=0.3)
    return {str(x) for x in np.unique(curves["state"])}


def _legend(fig: Any, analysis: Analysis, states: set[str]) -> None:
    """One legend for every panel: each support's line, the acceleration, the outcomes."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles: list[Line2D | Patch] = [
        Line2D([], [], label=f"N {name}", **support_style(j))
        for j, name in enumerate(analysis.problem.names)
    ]
    handles.append(Line2D([], [], color=palette.INK, lw=1.1, ls="--", label="acceleration"))
    handles.append(
        Line2D([], [], color=palette.MUTED, lw=0.8, ls=":", label="body moves away (dotted)")
    )
    handles += [
        Patch(color=outcome_colour(k), label=k.replace("_", " "))
        for k in sorted(states | {"closes"}, key=lambda k: (k != "closes", k))
    ]
    handles.append(Patch(color=palette.SAFE, alpha=0.25, label="safe band"))
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=7.5, frameon=False,
               title="curves: forward sliding; bar on top of each panel: the outcome at that angle",
               title_fontsize=7.5)  # fmt: skip


def _combined_strip(ax: Axes, scene: Scene, analysis: Analysis, result: CheckResult) -> None:
    """Bottom strip: the combined safe range and the design direction."""
    ax.set_yticks([])
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 45))
    ax.set_xlabel(
        f"force angle α (°); {sweep_note(scene.sweep.normal, scene.sweep.e1)}", fontsize=8.5
    )
    for s, e in _spans(result.safe_ranges_deg or ()):
        ax.axvspan(s, e, color=palette.SAFE, alpha=0.6, lw=0)
    combined = format_ranges(result.safe_ranges_deg or (), 1)
    ax.text(2, 0.5, f"safe for every retraction: {combined}", transform=ax.get_xaxis_transform(),
            va="center", fontsize=8)  # fmt: skip
    if analysis.design is not None:
        design = scene.design_angle_deg
        assert design is not None  # the design direction is the load's
        ax.axvline(design, color=DESIGN, lw=1.4, ls=":")
        margin = result.details.get("design_margin_deg")
        note = "" if margin is None or not result.safe_ranges_deg else f", margin {margin:.1f}°"
        ax.annotate(
            f"design {format_angle(design, 1)}{note}", (design, 1.0),
            xycoords=ax.get_xaxis_transform(), xytext=(3, 2), textcoords="offset points",
            fontsize=8, color=DESIGN, ha="left" if design < 270 else "right",
        )  # fmt: skip


def draw(check: Check, inputs: Inputs, result: CheckResult, directory: Path) -> list[Path]:
    """analytical-2d's pictures: normal forces and acceleration against force angle, one panel
    per retracted support (thesis Figures 2.17-2.20), and the safe set against friction."""
    from kcheck_checks.pictures.friction import plot_friction

    paths = plot_analytical_2d(inputs, result, directory)
    return [*paths, *plot_friction(check.id, inputs, result, directory)]
