"""Pictures of the `hertz` check, drawn from its result: peak pressure of every contact against
its allowable, the contact ellipses to scale, and the stiffness at the error point by direction.
matplotlib comes in through :mod:`kcheck.pictures.plotting`."""

from __future__ import annotations

from collections.abc import Set as AbstractSet
from pathlib import Path
from typing import Any

import numpy as np

from kcheck.fmt import format_vector
from kcheck.pictures import colours as palette
from kcheck.pictures.plotting import figure, save, slug
from kcheck.plugin import Check, Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene
from kcheck_checks.pictures.titles import verdict_colour, verdict_title

__all__ = ["plot_hertz"]


def plot_hertz(scene: Scene, result: CheckResult, directory: Path) -> list[Path]:
    """Write ``<scene>-hertz.png/.svg``; return the paths (none without contact results)."""
    contacts = result.details.get("contacts")
    if not contacts:
        return []
    compliance = result.details.get("point_compliance")
    panels = 3 if compliance is not None else 2
    fig = figure(figsize=(5.2 * panels, 5.0))
    axes = fig.subplots(1, panels, width_ratios=[1.25] + [1] * (panels - 1))
    _pressure_panel(axes[0], contacts, float(result.details["safety_factor"]))
    rings = {r["coupling"] for r in result.details.get("rings", [])}
    _ellipse_panel(axes[1], contacts, rings)
    if compliance is not None:
        axes[2].remove()
        polar = fig.add_subplot(1, panels, 3, projection="polar")
        _stiffness_panel(polar, np.array(compliance), scene, result.details["error_point"])
    materials = result.details.get("materials", "")
    fig.suptitle(
        f"{scene.name} — {verdict_title(result)}\n{result.message.split(';')[0]}\n{materials}",
        fontsize=10, color=verdict_colour(result),
    )  # fmt: skip
    return list(save(fig, directory, f"{slug(scene.name)}-hertz"))


def _pressure_panel(ax: Any, contacts: list[dict[str, Any]], safety_factor: float) -> None:
    """Peak pressure per contact as a share of what is allowed (100 % = allowable / SF)."""
    names = [c["support"] for c in contacts]
    seated = np.array([c["max_pressure"] / c["allowable_pressure"] for c in contacts])
    worst = np.array([c["utilisation"] for c in contacts]) / safety_factor
    share = 100 * safety_factor
    x = np.arange(len(names))
    colours = [palette.status_colour("fail" if u * safety_factor > 1 else "pass") for u in worst]
    ax.bar(x, share * seated, color=colours, alpha=0.85, label="seated")
    # Cosmetic: the disturbed outline only when some bar changes beyond rounding (1e-9).
    if np.any(np.abs(worst - seated) > 1e-9 * np.maximum(worst, 1e-300)):
        ax.bar(x, share * worst, fill=False, edgecolor=palette.INK, label="with the disturbance")
    ax.axhline(100, color=palette.INK, lw=1, ls="--", label="allowable / safety factor")
    ax.set_xticks(x, names, rotation=45 if len(names) > 6 else 0)
    ax.set_ylabel("peak pressure, % of allowed")
    ax.set_title("contact stress (labels: seated peak pressure, MPa)", fontsize=10)
    ax.set_ylim(0, 1.15 * max(float(share * worst.max()), 100.0))
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=3)
    for xi, c in zip(x, contacts, strict=True):
        ax.annotate(
            f"{c['max_pressure'] / 1e6:.0f}",
            (xi, share * c["max_pressure"] / c["allowable_pressure"]),
            ha="center",
            va="bottom",
            fontsize=7,
        )


def _ellipse_panel(
    ax: Any, contacts: list[dict[str, Any]], rings: AbstractSet[str] = frozenset()
) -> None:
    """Each contact ellipse to scale (µm), major axis horizontal, side by side; a ring
    support (ball in a cone, ``rings``: their couplings) as a band of its width running off
    its slot (the circle is far longer than any ellipse)."""
    from matplotlib.patches import Ellipse, Rectangle

    sizes = np.array([c["semi_axes"] for c in contacts]) * 1e6
    line = np.array([c["coupling"] in rings for c in contacts])
    # the scale from the ellipses and the rings' widths, not their lengths
    shown = np.where(line[:, None], sizes[:, 1:2], sizes)
    # No contact carries load (every ellipse a point): a panel one micrometre tall.
    top = float(shown.max()) if shown.max() > 0 else 1.0
    pitch = 2.6 * top
    for i, (c, (a, b)) in enumerate(zip(contacts, sizes, strict=True)):
        colour = palette.support_colour(i)
        if line[i]:
            half = 1.2 * top
            ax.add_patch(
                Rectangle((i * pitch - half, -b), 2 * half, 2 * b, color=colour, alpha=0.6)
            )
            ax.annotate(
                f"{c['support']}\n(ring)", (i * pitch, -1.25 * top), ha="center", fontsize=7
            )
            continue
        ax.add_patch(Ellipse((i * pitch, 0), 2 * a, 2 * b, color=colour, alpha=0.6))
        ax.annotate(c["support"], (i * pitch, -1.25 * top), ha="center", fontsize=7)
    # a scale bar of a round length about the largest semi-axis
    bar = 10 ** np.floor(np.log10(top))
    y = 1.35 * top
    ax.plot([-pitch / 2 + 0.1 * pitch, -pitch / 2 + 0.1 * pitch + bar], [y, y], color=palette.INK)
    ax.annotate(
        f"{bar:g} µm",
        (-pitch / 2 + 0.1 * pitch, y),
        xytext=(0, 3),
        textcoords="offset points",
        fontsize=8,
    )
    ax.set_xlim(-pitch / 2, (len(contacts) - 0.5) * pitch)
    ax.set_ylim(-1.5 * top, 1.6 * top)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title("contact ellipses to scale, seated (major axis horizontal)", fontsize=10)


def _stiffness_panel(ax: Any, compliance: np.ndarray, scene: Scene, point: list[float]) -> None:
    """Stiffness 1 / (e^T C e) of the error point along directions e in three planes."""
    t = np.linspace(0, 2 * np.pi, 361)
    planes = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)} if len(compliance) == 3 else {"xy": (0, 1)}
    styles = zip(("-", "--", ":"), palette.PLANE_COLOURS, strict=True)
    for (label, (i, j)), (style, colour) in zip(planes.items(), styles, strict=False):
        e = np.zeros((len(t), len(compliance)))
        e[:, i], e[:, j] = np.cos(t), np.sin(t)
        k = 1.0 / np.einsum("ni,ij,nj->n", e, compliance, e)
        name = f"{label} plane (angle from {label[0]})"
        ax.plot(t, k / 1e6, style, color=colour, lw=2, label=name)
    shown = format_vector(np.asarray(point) / scene.scale)
    ax.set_title(f"stiffness at {shown} {scene.units}, N/µm", fontsize=9)
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.1, -0.15))


def draw(check: Check, inputs: Inputs, result: CheckResult, directory: Path) -> list[Path]:
    """hertz's pictures: peak pressure per contact against its allowable, and the stiffness at
    the point."""
    return list(plot_hertz(inputs.scene, result, directory))
