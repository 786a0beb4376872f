"""Picture of the `reseat` check: for the case with the largest seat error (re-simulated at
the check's time step), each support's gap and normal force against time, and the path of
the centre of mass. matplotlib comes in through :mod:`kcheck.pictures.plotting`."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from kcheck.analysis.reseat import simulate
from kcheck.pictures.plotting import figure, save, slug
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
        axes[0].plot(t, trace.gaps[:, i] * 1e6, style, lw=1.2, label=name)
        axes[1].plot(t, trace.forces[:, i], style, lw=1.2, label=name)
    for ax in axes[:2]:
        ax.axvline(0, color="grey", lw=0.8)
        ax.axvline(settings.duration * 1e3, color="grey", lw=0.8)
        ax.set_xlabel("time, ms (0: retraction, grey: return starts)")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("gap from the seat, µm (dashed: retracted)")
    axes[0].set_title("gaps", fontsize=10)
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
    return list(save(fig, directory, f"{slug(scene.name)}-reseat"))


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
    points = ax.scatter(xy[:, 0], xy[:, 1], c=time * 1e3, s=4, cmap="viridis")
    ax.plot(xy[:, 0], xy[:, 1], color="grey", lw=0.5)
    ax.plot([0], [0], "k+", ms=12, label="seat")
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_title("path of the centre of mass", fontsize=10)
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7)
    ax.figure.colorbar(points, ax=ax, label="time, ms")
