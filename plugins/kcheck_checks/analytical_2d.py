"""Analytical 2D: equations of motion of a planar coupling, exact safe force-angle ranges."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from pydantic import Field

from kcheck.analysis import Analysis, analyse, closing_force_reason, describe_ranges, ranges_deg
from kcheck.arcs import ArcSet, affine_arcs
from kcheck.dynamics import Affine
from kcheck.plugin import Check, Inputs, Options
from kcheck.result import CaseResult, CheckResult, Status
from kcheck.scene import Scene

# Range ends less certain than this (deg) are reported with a diagnostic.
UNCERTAIN_DEG = 0.01

__all__ = ["Analytical2D", "AnalyticalOptions", "analytical_result"]


class AnalyticalOptions(Options):
    """Options of the analytical checks."""

    min_margin_deg: float = Field(
        0.0, ge=0, description="Least angular distance of the design direction from a boundary"
    )


def analytical_result(check_id: str, analysis: Analysis, min_margin_deg: float) -> CheckResult:
    """Verdict of an analytical check from its analysis (planar sweep semantics)."""
    bad = [r for r in analysis.results if r.outcome in ("undetermined", "ill_conditioned")]
    combined = analysis.combined
    details: dict[str, object] = {"max_condition": analysis.max_condition}
    if analysis.design_margin_deg is not None:
        details["design_margin_deg"] = analysis.design_margin_deg
    ranges = None if combined is None else ranges_deg(combined)
    if bad:
        names = ", ".join(f"{r.retracted} ({r.outcome})" for r in bad)
        return CheckResult(
            check_id,
            Status.FAIL,
            f"no trustworthy answer for {names}",
            error_estimate=None,
            cases=analysis.results,
            details=details,
        )
    failing = [r for r in analysis.results if r.outcome not in ("closes", "swept")]
    parts = []
    ok = True
    if combined is not None:
        parts.append(f"safe force angles: {describe_ranges(combined)}")
        ok = bool(combined)
    if failing:
        ok = False
        parts.append(
            "at the design direction "
            + ", ".join(f"{r.retracted} {r.outcome.replace('_', ' ')}" for r in failing)
        )
    if analysis.design_margin_deg is not None:
        parts.append(f"design direction margin {analysis.design_margin_deg:.2f}°")
        if analysis.design_margin_deg < min_margin_deg:
            ok = False
            parts.append(f"(required {min_margin_deg:g}°)")
    return CheckResult(
        check_id,
        Status.PASS if ok else Status.FAIL,
        "; ".join(parts),
        error_estimate=analysis.error_deg,
        safe_ranges_deg=ranges,
        cases=analysis.results,
        details=details,
    )


class Analytical2D(Check):
    """Newton–Euler for each retracted support of a planar scene, with Coulomb friction."""

    id = "analytical-2d"
    summary = (
        "equations of motion per retracted support: outcome, normal forces, limiting friction, "
        "exact safe force-angle ranges"
    )
    applies_to = "planar scenes (3 supports) with a body and a closing force"
    needs_mass = True
    options = AnalyticalOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Planar scenes with mass properties and a closing force only."""
        if scene.kind != "planar":
            return "applies to planar (3-support) scenes; this one is spatial"
        return closing_force_reason(scene)

    def run(self, inputs: Inputs) -> CheckResult:
        """Analyse every retracted case and intersect the safe ranges."""
        assert inputs.mass is not None and isinstance(inputs.options, AnalyticalOptions)
        analysis = analyse(inputs.scene, inputs.mass)
        result = analytical_result(self.id, analysis, inputs.options.min_margin_deg)
        return with_partial_ranges(result, analysis, inputs.scene)

    def plot(self, inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
        """Normal forces and acceleration against force angle, one panel per retracted support
        (thesis Figures 2.17-2.20), from the exact affine forms (needs the `plot` extra)."""
        from kcheck_checks.plots_analytical_2d import plot_analytical_2d

        return plot_analytical_2d(inputs, result, directory)


# --- partial ranges (the thesis reports motion and contact separately) ------------------------


def partial_ranges(affine: Affine, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, ArcSet]:
    """Force angles (rad) where the forward-sliding ``lambda > 0`` (the body moves the desired
    way, thesis Figure 2.17) and where every normal force is positive (Figures 2.18-2.20)."""
    motion, _ = affine_arcs(affine.a[:1], affine.c[:1], e1, e2, affine.error[:1])
    contact, _ = affine_arcs(affine.a[1:], affine.c[1:], e1, e2, affine.error[1:])
    return motion, contact


def with_partial_ranges(result: CheckResult, analysis: Analysis, scene: Scene) -> CheckResult:
    """Add per case ``desired_motion_deg`` and ``contacts_kept_deg``, and a diagnostic when
    the range ends are uncertain by more than ``UNCERTAIN_DEG``."""
    if analysis.arcs is None:
        return result
    e1, e2 = scene.sweep.e1[:2], scene.sweep.e2[:2]
    cases: list[CaseResult] = []
    for case, case_result in zip(analysis.cases, result.cases, strict=True):
        if case.forward is None or case_result.safe_ranges_deg is None:
            cases.append(case_result)
            continue
        motion, contact = partial_ranges(case.forward, e1, e2)
        details = dict(case_result.details)
        details["desired_motion_deg"] = [list(r) for r in ranges_deg(motion)]
        details["contacts_kept_deg"] = [list(r) for r in ranges_deg(contact)]
        cases.append(dataclasses.replace(case_result, details=details))
    details = dict(result.details)
    message = result.message
    if analysis.error_deg > UNCERTAIN_DEG:
        details["diagnostic"] = (
            f"range ends uncertain by up to {analysis.error_deg:.2g}° (nearly cancelling terms)"
        )
        message += f"; {details['diagnostic']}"
    return dataclasses.replace(result, cases=tuple(cases), details=details, message=message)
