"""Analytical 3D: Newton–Euler of a six-support coupling with the full inertia tensor.

Besides the planar-style report (outcome, forces, limiting friction, exact ranges in the sweep
plane), the spatial check maps the safe force directions on the whole sphere: per retracted
case every unknown is affine in the unit force direction, so each condition is a spherical cap
and the safe region is their intersection (:mod:`kcheck.sphere`). Without a load, gravity is
the closing force and the map is over gravity directions relative to the body (its tilt).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field

from kcheck.analysis import Analysis, analyse, closing_force_reason, describe_ranges
from kcheck.arcs import cap_margin_matrix, cap_margins
from kcheck.dynamics import Problem, solve_affine
from kcheck.fmt import format_direction
from kcheck.plugin import Check, Inputs
from kcheck.result import CheckResult, Status
from kcheck.scene import Scene
from kcheck.sphere import (
    SafeFraction,
    fibonacci_sphere,
    most_robust_direction,
    safe_fraction,
)
from kcheck_checks.analytical_2d import AnalyticalOptions, analytical_result

__all__ = ["Analytical3D", "Analytical3DOptions", "SphereMap", "direction_caps", "sphere_map"]


class Analytical3DOptions(AnalyticalOptions):
    """Options of the ``analytical-3d`` check."""

    sphere_points: int = Field(
        20000, ge=100, le=5_000_000, description="Fibonacci points for the safe solid angle"
    )


@dataclass(frozen=True)
class SphereMap:
    """Safe directions on the sphere of force (or gravity) directions, all cases together.

    ``a`` (k,), ``c`` (k, 3) are the caps ``a + c . d > 0`` (forward assumption, every unknown
    of every case); ``owner`` (k,) the index of the case each cap belongs to. Angles in rad.
    """

    swept: Literal["load", "gravity"]
    a: np.ndarray
    c: np.ndarray
    owner: np.ndarray
    design: np.ndarray | None
    fraction: SafeFraction
    robust: np.ndarray
    robust_margin: float
    design_margin: float | None
    case_fractions: np.ndarray
    boundary_error: float  # rad, estimated error of the cap boundaries (and so of margins)


def direction_caps(
    problem: Problem, analysis: Analysis
) -> tuple[Literal["load", "gravity"], np.ndarray, np.ndarray, np.ndarray]:
    """Caps of every case's unknowns as affine functions of the swept unit direction.

    With a load the direction is the load's (``Case.forward``); without one it is gravity's,
    whose magnitude is kept: the wrench ``[torque; |m g| d]`` about the centre of mass.
    """
    swept: Literal["load", "gravity"] = "load" if problem.load_scale > 0 else "gravity"
    a_all, c_all, owner, err_all = [], [], [], []
    for i, case in enumerate(analysis.cases):
        if case.forward is None or not case.well_conditioned:
            continue
        if swept == "load":
            a, c, err = case.forward.a, case.forward.c, case.forward.error
        else:
            weight = float(np.linalg.norm(problem.gravity))
            b0 = np.concatenate([problem.torque, np.zeros(3)])
            big_b = np.vstack([np.zeros((3, 3)), weight * np.eye(3)])
            affine = solve_affine(case.forward.matrix, b0, big_b)
            a, c, err = affine.a, affine.c, affine.error
        a_all.append(a)
        c_all.append(c)
        owner.append(np.full(len(a), i))
        err_all.append(err)
    if not a_all:
        return swept, np.zeros(0), np.zeros((0, 3)), np.zeros(0, int), np.zeros(0)
    a_cat, c_cat = np.concatenate(a_all), np.vstack(c_all)
    return swept, a_cat, c_cat, np.concatenate(owner), _boundary_error(a_cat, c_cat, err_all)


def _boundary_error(a: np.ndarray, c: np.ndarray, errors: list[np.ndarray]) -> float:
    """Angular error (rad) of the cap boundaries: each condition's coefficient error over its
    rate of change across the boundary, ``sqrt(|c|^2 - a^2)`` (as for the sweep-plane arcs)."""
    slope2 = np.sum(c * c, axis=1) - a * a
    err = np.concatenate(errors)
    with np.errstate(divide="ignore", invalid="ignore"):
        per_cap = np.where(slope2 > 0, err / np.sqrt(np.maximum(slope2, 0)), 0.0)
    return float(np.nanmax(per_cap)) if len(per_cap) else 0.0


def sphere_map(scene: Scene, analysis: Analysis, points: int) -> SphereMap | None:
    """The safe-direction map of a spatial scene, or None when no case can be mapped."""
    problem = analysis.problem
    swept, a, c, owner, boundary_error = direction_caps(problem, analysis)
    if not len(a):
        return None
    design = None
    if swept == "load":
        design = analysis.design
    elif np.any(scene.gravity):
        design = scene.gravity / np.linalg.norm(scene.gravity)
    # One evaluation of the grid serves the fraction, the robust search and the case shares.
    per_cap = cap_margin_matrix(a, c, fibonacci_sphere(points))
    margins = per_cap.min(axis=1)
    robust, robust_margin = most_robust_direction(a, c, points, margins=margins)
    design_margin = None if design is None else float(cap_margins(a, c, design[None])[0])
    cases = np.unique(owner)
    case_fractions = np.full(len(analysis.cases), np.nan)
    for i in cases:
        case_fractions[i] = np.count_nonzero(per_cap[:, owner == i].min(axis=1) > 0) / points
    return SphereMap(
        swept=swept,
        a=a,
        c=c,
        owner=owner,
        design=design,
        fraction=safe_fraction(a, c, points, margins=margins),
        robust=robust,
        robust_margin=robust_margin,
        design_margin=design_margin,
        case_fractions=case_fractions,
        boundary_error=boundary_error,
    )


def _vector(v: np.ndarray) -> str:
    return format_direction(v)  # noise cleaned: (0, 0, -1), not (-0.000, -0.000, -1.000)


def spatial_result(
    check_id: str, scene: Scene, analysis: Analysis, options: Analytical3DOptions
) -> tuple[CheckResult, SphereMap | None]:
    """Verdict of the spatial check: the sphere map decides, the sweep plane is reported."""
    base = analytical_result(check_id, analysis, options.min_margin_deg)
    smap = sphere_map(scene, analysis, options.sphere_points)
    details = dict(base.details)
    details.pop("design_margin_deg", None)
    if analysis.design_margin_deg is not None and analysis.design is not None:
        normal = scene.sweep.normal
        if abs(float(analysis.design @ normal)) < 1e-9:
            details["sweep_design_margin_deg"] = analysis.design_margin_deg
    bad = [r for r in analysis.results if r.outcome in ("undetermined", "ill_conditioned")]
    if smap is None or bad:
        return base, smap
    deg = float(np.degrees(1.0))
    details.update(
        {
            "swept_direction": smap.swept,
            "safe_solid_angle_fraction": smap.fraction.fraction,
            "safe_solid_angle_fraction_error": smap.fraction.error,
            "sphere_points": smap.fraction.points,
            "most_robust_direction": smap.robust.tolist(),
            "robust_margin_deg": smap.robust_margin * deg,
        }
    )
    cases = tuple(
        dataclasses.replace(
            r,
            details={**r.details, "closing_solid_angle_fraction": float(smap.case_fractions[i])},
        )
        if np.isfinite(smap.case_fractions[i])
        else r
        for i, r in enumerate(base.cases)
    )
    what = "force" if smap.swept == "load" else "gravity"
    parts = [
        f"safe {what} directions {100 * smap.fraction.fraction:.2f}% "
        f"(±{100 * smap.fraction.error:.2f}%) of the sphere",
        f"most robust {_vector(smap.robust)} with margin {smap.robust_margin * deg:.2f}°",
    ]
    failing = [r for r in analysis.results if r.outcome not in ("closes", "swept")]
    if smap.design is not None and smap.design_margin is not None:
        margin = smap.design_margin * deg
        details["design_margin_deg"] = margin
        ok = not failing and margin > 0 and margin >= options.min_margin_deg
        parts.append(f"design {what} direction margin {margin:.2f}°")
        if margin < options.min_margin_deg:
            parts.append(f"(required {options.min_margin_deg:g}°)")
        if failing:
            parts.append(
                "at the design direction "
                + ", ".join(f"{r.retracted} {r.outcome.replace('_', ' ')}" for r in failing)
            )
    else:
        margin = smap.robust_margin * deg
        ok = margin > 0 and margin >= options.min_margin_deg
        if margin < options.min_margin_deg:
            parts.append(f"(required {options.min_margin_deg:g}°)")
    if analysis.combined is not None:
        parts.append(f"sweep plane: {describe_ranges(analysis.combined)}")
    result = dataclasses.replace(
        base,
        status=Status.PASS if ok else Status.FAIL,
        message="; ".join(parts),
        cases=cases,
        details=details,
        # Degrees: the sweep-plane range ends and the sphere map's margins, whichever is worse.
        error_estimate=max(base.error_estimate or 0.0, smap.boundary_error * deg),
    )
    return result, smap


class Analytical3D(Check):
    """Every retracted support of a spatial scene: free screw, outcome, forces, ranges, map."""

    id = "analytical-3d"
    summary = (
        "Newton–Euler per retracted support with the full inertia tensor: outcome, normal "
        "forces, limiting friction, exact safe ranges in the sweep plane, map of safe "
        "directions on the sphere"
    )
    applies_to = "spatial scenes (6 supports) with a body and a closing force"
    needs_mass = True
    options = Analytical3DOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Spatial scenes with mass properties and a closing force only."""
        if scene.kind != "spatial":
            return "applies to spatial (6-support) scenes; this one is planar"
        return closing_force_reason(scene)

    def run(self, inputs: Inputs) -> CheckResult:
        """Analyse every retracted case and map the safe directions on the sphere."""
        assert inputs.mass is not None and isinstance(inputs.options, Analytical3DOptions)
        analysis = analyse(inputs.scene, inputs.mass)
        return spatial_result(self.id, inputs.scene, analysis, inputs.options)[0]

    def plot(self, inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
        """Scene with screw axes, safe-direction map, normal forces per case (PNG and SVG)."""
        from kcheck_checks.plots_3d import plot_spatial

        assert inputs.mass is not None and isinstance(inputs.options, Analytical3DOptions)
        analysis = analyse(inputs.scene, inputs.mass)
        _, smap = spatial_result(self.id, inputs.scene, analysis, inputs.options)
        return plot_spatial(inputs.scene, analysis, smap, result, directory)
