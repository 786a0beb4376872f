"""Pictures of the safe set against the friction coefficient, per check (``--plots``).

The check's own computation is repeated at coefficients from 0 to 1.5 times the scene's
(largest) one, the supports keeping their ratios (the dynamics take the kinetic coefficients,
holding and Koster's construction the static ones):

* planar checks: the safe force angles as bands against μ (analytical-2d, graphical-2d; for
  jamming the angles that close without friction and where no case can be held);
* analytical-3d: the safe share of the sphere of directions and the design direction's margin.

The scene's coefficient is a vertical line, a range a shaded column; over a range, the angles
that are safe for every coefficient of it are drawn across it. matplotlib comes in through
:mod:`kcheck.pictures.plotting`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from kcheck.fmt import format_number
from kcheck.pictures import colours as palette
from kcheck.pictures.labels import say_why_empty
from kcheck.plugin import Inputs
from kcheck.result import CheckResult
from kcheck.scene import Scene

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_friction", "friction_axis", "scene_at"]

SAFE = palette.SAFE
RANGE = palette.FRICTION_RANGE
ANGLES = 720  # angle bins of a band picture (0.5 deg)


def friction_axis(
    scene: Scene, kind: str, count: int
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The coefficients drawn: ``(mus, pattern, low, high)`` — ``count`` values from 0 to 1.5
    times the scene's largest ``kind`` coefficient (0.5 for a frictionless scene), the
    supports' ratios (k,), and the reference support's range."""
    low, high = scene.friction_range(kind)  # type: ignore[arg-type]
    top = float(high.max()) if len(high) else 0.0
    pattern = high / top if top > 0 else np.ones(len(high))
    ref = int(np.argmax(high))
    upper = 1.5 * top if top > 0 else 0.5
    return np.linspace(0.0, upper, count), pattern, float(low[ref]), float(high[ref])


def scene_at(scene: Scene, mu: np.ndarray) -> Scene:
    """The scene with plain coefficients ``mu`` (k,) at its supports."""
    supports = tuple(
        dataclasses.replace(s, friction=float(m), friction_spec=None)
        for s, m in zip(scene.supports, mu, strict=True)
    )
    return dataclasses.replace(scene, supports=supports)


def _bands(ranges: Sequence[Sequence[Sequence[float]] | None]) -> np.ndarray:
    """Rasterised ranges (deg) per coefficient: (ANGLES, count) booleans."""
    centres = (np.arange(ANGLES) + 0.5) * 360.0 / ANGLES
    out = np.zeros((ANGLES, len(ranges)), bool)
    for j, arcs in enumerate(ranges):
        for start, end in arcs or ():
            width = (end - start) % 360.0 or (360.0 if end != start else 0.0)
            out[:, j] |= (centres - start) % 360.0 <= width
    return out


def _range_marks(ax: Axes, scene_mu: tuple[float, float], label: str) -> None:
    low, high = scene_mu
    if high > low:
        ax.axvspan(low, high, color=RANGE, alpha=0.12, lw=0, label=f"{label} range")
    else:
        ax.axvline(high, color=RANGE, lw=1.2, label=f"scene's {label}")


def _band_picture(
    scene: Scene,
    result: CheckResult,
    check: str,
    kind: str,
    safe_at: Callable[[Scene], Sequence[Sequence[float]] | None],
    what: str,
    directory: Path,
) -> Sequence[Path]:
    from kcheck.pictures.plotting import figure, save, slug
    from kcheck_checks.pictures.titles import verdict_colour, verdict_title

    mus, pattern, low, high = friction_axis(scene, kind, 121)
    bands = _bands([safe_at(scene_at(scene, pattern * m)) for m in mus])
    fig = figure(figsize=(7.5, 4.2))
    ax = fig.subplots()
    step = mus[1] - mus[0]
    ax.imshow(
        np.where(bands, 1.0, np.nan),
        origin="lower",
        aspect="auto",
        extent=(mus[0] - step / 2, mus[-1] + step / 2, 0.0, 360.0),
        cmap=palette.SAFE_MAP,
        vmin=0.0,
        vmax=1.6,
        interpolation="nearest",
    )
    ax.plot([], [], color=SAFE, lw=6, alpha=0.6, label=what)
    if not bands.any():
        say_why_empty(
            ax, f"no {what} at any {kind} μ from 0 to {format_number(mus[-1], 3)}:\n"
            "every force angle fails at every coefficient drawn",
        )  # fmt: skip
    _range_marks(ax, (low, high), f"{kind} μ")
    if high > low and result.safe_ranges_deg is not None:
        label: str | None = "safe over the whole range"
        for start, end in result.safe_ranges_deg:
            for a, b in ((start, end),) if end > start else ((start, 360.0), (0.0, end)):
                ax.fill_between(
                    [low, high],
                    a,
                    b,
                    facecolor="none",
                    hatch="///",
                    edgecolor=palette.INK,
                    lw=0.8,
                    label=label,
                )
                label = None
    design = scene.design_angle_deg
    if design is not None:
        ax.axhline(design, color=palette.DESIGN, ls="--", lw=1.0, label=f"design {design:.1f}°")
    ax.set_xlim(mus[0], mus[-1])
    ax.set_ylim(0.0, 360.0)
    ax.set_yticks(np.arange(0, 361, 45))
    ax.set_xlabel(f"{kind} friction coefficient μ" + ("" if _uniform(pattern) else " (largest)"))
    ax.set_ylabel("force angle (°)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    ax.set_title(f"{scene.name}: {what} against μ\n{verdict_title(result)}", fontsize=10,
                 color=verdict_colour(result))  # fmt: skip
    return save(fig, directory, f"{slug(scene.name)}-{check}-friction")


def _uniform(pattern: np.ndarray) -> bool:
    rough = pattern[pattern > 0]
    return bool(len(rough) == 0 or np.ptp(rough) == 0)


def _spatial_picture(inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
    """analytical-3d: the safe share of the sphere and the design margin against μ."""
    from kcheck.analysis import analyse
    from kcheck.analysis.sphere_map import sphere_map
    from kcheck.pictures.plotting import figure, save, slug
    from kcheck_checks.pictures.titles import verdict_colour, verdict_title

    scene, mass = inputs.scene, inputs.mass
    assert mass is not None
    mus, pattern, low, high = friction_axis(scene, "kinetic", 41)
    share, margin = [], []
    for m in mus:
        at = scene_at(scene, pattern * m)
        smap = sphere_map(at, analyse(at, mass))
        share.append(np.nan if smap is None else 100.0 * smap.fraction.fraction)
        value = None if smap is None else smap.design_margin
        margin.append(np.nan if value is None else float(np.degrees(value)))
    fig = figure(figsize=(7.5, 5.2))
    top, bottom = fig.subplots(2, 1, sharex=True)
    top.plot(mus, share, color=SAFE, lw=1.8)
    if not np.nansum(share) > 0:
        why = (
            "no safe direction at any coefficient drawn"
            if np.any(np.isfinite(share))
            else "no sphere map at any coefficient drawn (the check made none)"
        )
        say_why_empty(top, f"{why} (kinetic μ 0 to {format_number(mus[-1], 3)})")
    if not np.any(np.isfinite(margin)):
        say_why_empty(bottom, "no design direction: no design margin to draw")
    top.fill_between(mus, 0.0, share, color=SAFE, alpha=0.25)
    top.set_ylabel("safe directions (% of sphere)")
    over = result.details.get("safe_solid_angle_fraction")
    if high > low and isinstance(over, float):
        top.hlines(
            100.0 * over,
            low,
            high,
            colors=palette.INK,
            linestyles="--",
            lw=1.2,
            label=f"safe over the whole range: {100.0 * over:.3g}%",
        )
    bottom.plot(mus, margin, color=palette.DESIGN, lw=1.5, label="design direction's margin")
    bottom.axhline(0.0, color=palette.FAILING, lw=0.8)
    need = result.details.get("friction_range")
    for ax in (top, bottom):
        _range_marks(ax, (low, high), "kinetic μ")
        ax.grid(alpha=0.3)
    if isinstance(need, dict) and "worst_mu" in need and "worst_margin_deg" in need:
        bottom.plot(
            [need["worst_mu"]],
            [need["worst_margin_deg"]],
            "o",
            color=RANGE,
            label=f"worst in the range: μ = {need['worst_mu']:.3g}",
        )
    bottom.set_ylabel("design margin (°)")
    bottom.set_xlabel(
        "kinetic friction coefficient μ" + ("" if _uniform(pattern) else " (largest)")
    )
    bottom.set_xlim(mus[0], mus[-1])
    bottom.legend(loc="best", fontsize=8)
    top.legend(loc="upper right", fontsize=8)
    top.set_title(f"{scene.name}: safe directions against μ\n{verdict_title(result)}",
                  fontsize=10, color=verdict_colour(result))  # fmt: skip
    return save(fig, directory, f"{slug(scene.name)}-analytical-3d-friction")


def plot_friction(
    check: str, inputs: Inputs, result: CheckResult, directory: Path
) -> Sequence[Path]:
    """The picture of ``check`` (analytical-2d, analytical-3d, graphical-2d or jamming,
    planar) against the friction coefficient; the files written (none where it has none)."""
    scene = inputs.scene
    if check == "analytical-3d":
        return _spatial_picture(inputs, result, directory)
    if scene.kind != "planar":
        return ()
    if check == "analytical-2d":
        from kcheck.analysis import analyse
        from kcheck.analysis.cases import ranges_deg

        def safe(at: Scene) -> Sequence[Sequence[float]] | None:
            combined = analyse(at, inputs.mass).combined  # type: ignore[arg-type]
            return None if combined is None else ranges_deg(combined)

        return _band_picture(scene, result, check, "kinetic", safe, "safe angles", directory)
    if check == "graphical-2d":
        from kcheck.analysis.cases import ranges_deg
        from kcheck_checks.graphical_2d import attachment_of, construct

        where = attachment_of(inputs)
        if isinstance(where, str):
            return ()

        def koster(at: Scene) -> Sequence[Sequence[float]] | None:
            built = construct(at, where)
            return None if built is None else ranges_deg(built.combined)

        return _band_picture(scene, result, check, "static", koster, "safe angles", directory)
    if check == "jamming":
        from kcheck.analysis.cases import ranges_deg
        from kcheck.analysis.jamming_cases import analyse_jamming, case_arcs, jam_statics, tidy
        from kcheck.mechanics.arcs import complement, intersect

        e1, e2 = scene.sweep.e1[:2], scene.sweep.e2[:2]

        def jam_free(at: Scene) -> Sequence[Sequence[float]] | None:
            # the check's safe angles (closing without friction, held in no case), without
            # its design-direction extras (least holding friction)
            statics, swept, design = jam_statics(at, inputs.mass)
            cases = analyse_jamming(statics, swept, design).cases
            arcs = [case_arcs(c, e1, e2) for c in cases if c.determined]
            safe = intersect(*(intersect(a.closing, complement(a.held)) for a in arcs))
            return ranges_deg(tidy(safe))

        what = "closing, jam-free angles"
        return _band_picture(scene, result, check, "static", jam_free, what, directory)
    return ()
