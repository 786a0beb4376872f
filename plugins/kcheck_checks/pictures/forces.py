"""Picture of the spatial check's normal forces: per retracted support, the force of every
remaining support at the design direction (or under gravity), with the outcome above it.
matplotlib comes in through :mod:`kcheck.pictures.plotting`."""

from __future__ import annotations

from typing import Any

from kcheck.pictures import colours as palette
from kcheck.pictures.colours import outcome_colour
from kcheck.pictures.labels import EMPTY_GID
from kcheck.pictures.plotting import figure
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.pictures.titles import verdict_colour, verdict_title

__all__ = ["forces_panel"]


def forces_panel(scene: Scene, result: CheckResult) -> Any:
    """Grouped bars: the normal forces of the remaining supports per retracted support."""
    fig = figure(figsize=(11, 4.8), layout=None)
    fig.subplots_adjust(left=0.07, right=0.9, top=0.84, bottom=0.14)
    ax = fig.add_subplot(1, 1, 1)
    names = [s.name for s in scene.supports]
    width = 0.8 / max(len(names) - 1, 1)
    drawn: set[str] = set()
    for g, case in enumerate(result.cases):
        forces = case.normal_forces or {}
        if not forces:
            ax.text(
                g, 0.5, f"no forces:\n{case.outcome.replace('_', ' ')}", ha="center",
                va="center", fontsize=8, transform=ax.get_xaxis_transform(), gid=EMPTY_GID,
            )  # fmt: skip
        for k, name in enumerate(n for n in names if n in forces):
            x = g - 0.4 + width * (k + 0.5)
            value = forces[name]
            colour = palette.support_colour(names.index(name))
            ax.bar(
                x, value, width, color=colour,
                edgecolor=palette.INK if value <= 0 else colour,
                label=None if name in drawn else name,
            )  # fmt: skip
            drawn.add(name)
            ax.text(x, value, f"{value:.3g}", ha="center", va="bottom" if value >= 0 else "top",
                    fontsize=6.5)  # fmt: skip
        ax.text(
            g, 1.0, case.outcome.replace("_", " "), transform=ax.get_xaxis_transform(),
            ha="center", va="bottom", fontsize=9, color=outcome_colour(case.outcome),
        )  # fmt: skip
    ax.axhline(0, color=palette.INK, linewidth=0.8)
    ax.set_xticks(range(len(result.cases)))
    ax.set_xticklabels([f"{c.retracted}\nretracted" for c in result.cases])
    ax.set_ylabel("normal force (N)")
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda k: names.index(labels[k]))
    legend = ax.legend(
        [handles[k] for k in order], [labels[k] for k in order], title="support",
        fontsize=8, loc="upper left", bbox_to_anchor=(1.005, 1.0),
    )  # fmt: skip
    # Long support names ("front-right.1"): the bars give the legend the room it needs.
    wide = legend.get_window_extent().width / fig.bbox.width
    fig.subplots_adjust(right=min(0.9, 0.99 - wide - 0.01))
    ax.grid(True, axis="y", linewidth=0.4, alpha=0.6)
    load = scene.load
    at = (
        "at the design direction"
        if load is not None and load.magnitude > 0 and load.direction is not None
        else "under gravity"
    )
    ax.set_title(
        f"{scene.name} — {verdict_title(result)}\nnormal forces of the remaining supports {at}",
        pad=22, color=verdict_colour(result),
    )  # fmt: skip
    return fig
