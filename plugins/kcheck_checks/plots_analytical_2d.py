"""Pictures of the analytical-2d check: normal forces and acceleration against force angle
(thesis Figures 2.17-2.20), drawn from the exact affine forms. matplotlib comes in through
:mod:`kcheck.plotting`."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis import Analysis, analyse
from kcheck.dynamics import Case, outcomes
from kcheck.plugin import Inputs
from kcheck.result import CaseResult, CheckResult
from kcheck.scene import Scene

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_analytical_2d", "describe_ranges_deg"]

# Support curves in colours that do not collide with the outcome colours.
SUPPORT_COLOURS = ("#1f77b4", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")
OUTCOME_COLOURS = {
    "closes": "#2ca02c",
    "loses_contact": "#ff7f0e",
    "jams": "#7f7f7f",
    "opens": "#d62728",
    "opens_loses_contact": "#8b0000",
    "ambiguous": "#9467bd",
}


def plot_analytical_2d(inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
    """One panel per retracted support and a strip with the combined range; the files written."""
    assert inputs.mass is not None
    from kcheck.plotting import figure, save, slug

    analysis = analyse(inputs.scene, inputs.mass)
    if analysis.arcs is None:
        return ()
    n = len(analysis.cases)
    fig = figure(figsize=(9.0, 2.5 * n + 1.2))
    axes = fig.subplots(n + 1, 1, sharex=True, height_ratios=[1.0] * n + [0.22])
    for ax, case, case_result in zip(axes[:-1], analysis.cases, result.cases, strict=True):
        _case_panel(ax, inputs.scene, analysis, case, case_result)
    _combined_strip(axes[-1], inputs.scene, analysis, result)
    status = result.status.value.upper()
    fig.suptitle(f"{inputs.scene.name}: analytical-2d {status} — {result.message}", fontsize=10)
    return save(fig, directory, f"{slug(inputs.scene.name)}-analytical-2d")


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
    """A curve drawn solid where ``valid`` and thin dotted elsewhere (one legend entry)."""
    ax.plot(deg, np.where(valid, y, np.nan), **style)
    faint = {k: v for k, v in style.items() if k not in ("label", "ls", "lw")}
    ax.plot(deg, np.where(valid, np.nan, y), ls=":", lw=0.9, alpha=0.6, **faint)


def _spans(ranges: Sequence[Sequence[float]]) -> list[tuple[float, float]]:
    """Arc ranges in degrees split at 360 into pieces inside [0, 360]."""
    out = []
    for start, end in ranges:
        width, s = end - start, start % 360.0
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
        ax.axvspan(deg[i], deg[j], ymin=0.93, ymax=1.0, color=OUTCOME_COLOURS[str(state[i])], lw=0)


def _case_panel(ax: Axes, scene: Scene, analysis: Analysis, case: Case, result: CaseResult) -> None:
    """One retracted support: its safe band, normal forces (N, left) and acceleration (right)."""
    names = analysis.problem.names
    ax.set_xlim(0, 360)
    ax.axhline(0, color="black", lw=0.8)
    title = f"{result.retracted} retracted"
    motion = result.details.get("motion")
    if motion == "rotation":
        pole = np.asarray(result.details["pole"]) / scene.scale
        title += f": rotation about pole ({pole[0]:.4g}, {pole[1]:.4g}) {scene.units}"
        title += f" {result.details['sense']}"
    elif motion == "translation":
        title += ": translation"
    if case.forward is None or result.safe_ranges_deg is None:
        ax.set_title(f"{title} — {result.outcome}", fontsize=9, loc="left")
        ax.text(
            180, 0, str(result.details.get("diagnostic", result.outcome)), ha="center", fontsize=9
        )
        return
    deg = np.linspace(0.0, 360.0, 1441)
    curves = _curves(case, analysis, scene, deg)
    for s, e in _spans(result.safe_ranges_deg):
        ax.axvspan(s, e, color="#2ca02c", alpha=0.15, lw=0)
    _outcome_strip(ax, deg, curves["state"])
    for k, j in enumerate(case.keep):
        colour = SUPPORT_COLOURS[j % len(SUPPORT_COLOURS)]
        _plot_split(
            ax,
            deg,
            curves["forces"][:, k],
            curves["forward"],
            color=colour,
            lw=1.8 if k == 0 else 1.4,
            ls="-" if k == 0 else "-.",  # overlapping curves stay visible
            label=f"N {names[j]} (N)",
        )
    limit = float(np.abs(curves["forces"]).max()) * 1.15 or 1.0
    ax.set_ylim(-limit, limit / 0.93 * 1.0)
    ax.set_ylabel("normal force (N)", fontsize=8)
    twin = ax.twinx()
    _plot_split(
        twin,
        deg,
        curves["accel"],
        curves["forward"],
        color="black",
        lw=1.2,
        ls="--",
        label="acceleration (m/s²)",
    )
    twin.axhline(0, color="black", lw=0.8)
    alimit = float(np.abs(curves["accel"]).max()) * 1.15 or 1.0
    twin.set_ylim(-alimit, alimit / 0.93)
    twin.set_ylabel(f"accel. of contact {result.retracted}\ntowards it (m/s²)", fontsize=8)
    twin.tick_params(labelsize=8)
    ax.tick_params(labelsize=8)
    safe = describe_ranges_deg(result.safe_ranges_deg)
    ax.set_title(f"{title} — safe {safe}", fontsize=9, loc="left")
    if analysis.design is not None:
        design = scene.design_angle_deg
        ax.axvline(design, color="#1f3b73", lw=1.4, ls=":")
    lines = ax.get_legend_handles_labels()
    more = twin.get_legend_handles_labels()
    ax.legend(
        lines[0] + more[0],
        lines[1] + more[1],
        fontsize=7,
        loc="upper left",
        bbox_to_anchor=(0.0, 0.92),
        ncol=3,
        framealpha=0.85,
    )
    ax.grid(alpha=0.3)


def describe_ranges_deg(ranges: Sequence[Sequence[float]]) -> str:
    """Ranges in degrees as text, ``none`` when empty."""
    if not ranges:
        return "none"
    if len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 360.0:
        return "every angle"
    return ", ".join(f"{s % 360:.1f}°–{e % 360 if e - s < 360 else e:.1f}°" for s, e in ranges)


def _combined_strip(ax: Axes, scene: Scene, analysis: Analysis, result: CheckResult) -> None:
    """Bottom strip: the combined safe range, the design direction and the outcome legend."""
    from matplotlib.patches import Patch

    ax.set_yticks([])
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 45))
    ax.set_xlabel("force angle α (deg from +x)", fontsize=9)
    for s, e in _spans(result.safe_ranges_deg or ()):
        ax.axvspan(s, e, color="#2ca02c", alpha=0.6, lw=0)
    combined = describe_ranges_deg(result.safe_ranges_deg or ())
    ax.text(
        2,
        0.5,
        f"safe for every retraction: {combined}",
        transform=ax.get_xaxis_transform(),
        va="center",
        fontsize=8,
    )
    handles = [Patch(color=c, label=k.replace("_", " ")) for k, c in OUTCOME_COLOURS.items()]
    handles.append(Patch(color="#2ca02c", alpha=0.25, label="safe band"))
    if analysis.design is not None:
        design = scene.design_angle_deg
        ax.axvline(design, color="#1f3b73", lw=1.4, ls=":")
        margin = result.details.get("design_margin_deg")
        ax.annotate(
            f"design {design:.1f}°" + ("" if margin is None else f" (margin {margin:.1f}°)"),
            (design, 1.0),
            xycoords=ax.get_xaxis_transform(),
            xytext=(3, 2),
            textcoords="offset points",
            fontsize=8,
            color="#1f3b73",
        )
    ax.legend(
        handles=handles,
        fontsize=7,
        ncol=5,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.9),
        frameon=False,
        title="outcome bar (top of each panel); curves: forward sliding, dotted where the body "
        "does not move towards the support",
        title_fontsize=7,
    )
