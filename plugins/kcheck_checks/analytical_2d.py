"""Analytical 2D: equations of motion of a planar coupling, exact safe force-angle ranges."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pydantic import Field

from kcheck.analysis import Analysis, analyse, closing_force_reason, describe_ranges, ranges_deg
from kcheck.plugin import Check, Inputs, Options
from kcheck.result import CheckResult, Status
from kcheck.scene import Scene

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
        return analytical_result(self.id, analysis, inputs.options.min_margin_deg)

    def plot(self, inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
        """Normal forces and acceleration against force angle (needs the `plot` extra)."""
        return ()
