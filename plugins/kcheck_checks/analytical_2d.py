"""Analytical 2D: equations of motion of a planar coupling, exact safe force-angle ranges."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from kcheck.analysis import analyse, analyse_many
from kcheck.analysis.cases import (
    Analysis,
    closing_analysis,
    closing_force_reason,
    describe_ranges,
    ranges_deg,
)
from kcheck.analysis.friction_ranges import range_details
from kcheck.fmt import format_angle
from kcheck.mechanics.arcs import ArcSet, affine_arcs
from kcheck.mechanics.dynamics import Affine
from kcheck.numerics.thresholds import FULL_TURN_SLACK_DEG, UNCERTAIN_DEG
from kcheck.plugin import Check, Inputs
from kcheck.result import CaseResult, CheckResult, Status
from kcheck.scene import Scene
from kcheck_checks.marginal import with_angle_margin
from kcheck_checks.options import AnalyticalOptions
from kcheck_checks.wording import (
    case_findings,
    design_findings,
    empty_range_findings,
    friction_way_out,
    load_field,
    merge_findings,
    verdict,
    with_closing_force_way_out,
    with_friction_way_out,
)

__all__ = ["Analytical2D", "AnalyticalOptions", "analytical_result", "design_findings"]


def analytical_result(
    check_id: str,
    scene: Scene,
    analysis: Analysis,
    min_margin_deg: float,
    marginal_deg: float = 0.0,
) -> CheckResult:
    """Verdict of an analytical check from its analysis (planar sweep semantics)."""
    combined = analysis.combined
    details: dict[str, object] = {"max_condition": analysis.max_condition}
    span = range_details(scene, analysis)
    if span is not None:
        details["friction_range"] = span
    if analysis.design_margin_deg is not None:
        details["design_margin_deg"] = analysis.design_margin_deg
    if analysis.nearest_safe_deg is not None and (analysis.design_margin_deg or 0) < 0:
        details["nearest_safe_deg"] = analysis.nearest_safe_deg
    ranges = None if combined is None else ranges_deg(combined)
    findings = case_findings(scene, analysis)
    if not analysis.trustworthy:
        names = ", ".join(
            f"{r.retracted} ({r.outcome.replace('_', ' ')})"
            for r in analysis.results
            if r.outcome in ("undetermined", "ill_conditioned")
        )
        return CheckResult(
            check_id,
            Status.FAIL,
            f"no trustworthy answer for {names}",
            error_estimate=None,
            cases=analysis.results,
            details=details,
            findings=tuple(findings),
        )
    parts = []
    if combined is not None:
        if combined:
            parts.append(f"safe force angles: {describe_ranges(combined)}")
        else:
            parts.append("no safe force angle")
            findings = merge_findings(
                findings, empty_range_findings(scene, analysis.results, analysis=analysis)
            )
        design_deg = scene.design_angle_deg
        if design_deg is not None:
            findings.extend(
                design_findings(
                    scene,
                    design_deg,
                    analysis.design_margin_deg,
                    analysis.nearest_safe_deg,
                    describe_ranges(combined),
                    min_margin_deg,
                    safe=ranges,
                    by_friction=friction_way_out(analysis),
                )
            )
            if combined and analysis.design_margin_deg is not None and not findings:
                parts.append(
                    f"design {format_angle(design_deg)} is "
                    f"{format_angle(analysis.design_margin_deg)} inside"
                )
    elif not findings:
        parts.append("every retraction closes under the fixed forces (weight, preloads)")
    ok = not findings
    result = CheckResult(
        check_id,
        Status.PASS if ok else Status.FAIL,
        verdict(parts, findings),
        error_estimate=analysis.error_deg,
        safe_ranges_deg=ranges,
        cases=analysis.results,
        details=details,
        findings=tuple(findings),
    )
    field = load_field(scene) if scene.load is not None else None
    return with_angle_margin(result, marginal_deg, field, gravity=scene.load is None)


class Analytical2D(Check):
    """Newton–Euler for each retracted support of a planar scene, with Coulomb friction."""

    id = "analytical-2d"
    pictures = "kcheck_checks.pictures.analytical_2d:draw"
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
        return self.run_many([inputs])[0]

    def run_many(self, inputs: Sequence[Inputs]) -> list[CheckResult]:
        """:meth:`run` of several scenes, their cases' algebra stacked in one batch
        (:func:`kcheck.analysis.analyse_many`: each analysis is the scene's alone)."""
        masses = []
        for each in inputs:
            assert each.mass is not None
            masses.append(each.mass)
        analyses = analyse_many([i.scene for i in inputs], masses)
        return [self._judge(i, a) for i, a in zip(inputs, analyses, strict=True)]

    def _judge(self, inputs: Inputs, analysis: Analysis) -> CheckResult:
        """The result of one scene from its analysis: verdict, way-out hints, tilt."""
        assert inputs.mass is not None and isinstance(inputs.options, AnalyticalOptions)
        mass, opts = inputs.mass, inputs.options

        def judged(scene: Scene, analysis: Analysis) -> CheckResult:
            return analytical_result(
                self.id, scene, analysis, opts.min_margin_deg, opts.marginal_deg
            )

        result = judged(inputs.scene, analysis)

        def passes(scene: Scene) -> bool:
            # Exact shortcut: a case that does not close (or is undetermined, ill-conditioned)
            # fails the check whatever else is found (its case finding); the rest are judged
            # without friction intervals and friction_may_hold, which only word findings.
            if np.array_equal(*scene.friction_range("kinetic")):
                trial = closing_analysis(scene, mass)
                if trial is None:
                    return False
                return judged(scene, trial).status == Status.PASS
            return judged(scene, analyse(scene, mass)).status == Status.PASS

        if inputs.hints:
            from kcheck.analysis.way_out import trial_screens

            by_friction, by_force = trial_screens(inputs.scene, mass)
            result = with_friction_way_out(result, inputs.scene, passes, by_friction)
            result = with_closing_force_way_out(result, inputs.scene, passes, by_force)
        result = with_partial_ranges(result, analysis, inputs.scene)
        if result.error_estimate is None and analysis.trustworthy and inputs.scene.load is None:
            result = dataclasses.replace(result, error_estimate=_gravity_error_deg(analysis))
        return with_tolerated_tilt(result, analysis, inputs.scene)


def planar_tilt_words(scene: Scene) -> str:
    """How a planar gravity-only scene's tilt is measured: "from level" when its gravity points
    along −y (down in the plane of motion), else "from the installed attitude"."""
    g = np.asarray(scene.gravity[:2], float)
    n = float(np.linalg.norm(g))
    if n > 0 and np.allclose(g / n, (0.0, -1.0), atol=1e-9):
        return "from level"
    return "from the installed attitude"


def with_tolerated_tilt(result: CheckResult, analysis: Analysis, scene: Scene) -> CheckResult:
    """A planar scene closed by gravity alone (no load magnitude): the tilt of the installation
    in the plane it tolerates, ``tolerated_tilt_deg`` — the angle from the scene's gravity
    direction to the nearest gravity direction at which a retraction no longer closes (its
    magnitude kept; 180° when every direction closes, 0 when the installed one fails) — and,
    on a pass, "safe for tilts up to 12.34° from level" in the message. Nobody turns gravity."""
    from kcheck.analysis.cases import sweep_ranges

    if scene.load is not None and scene.load.magnitude > 0:
        return result
    if not analysis.trustworthy or not np.any(scene.gravity[:2]):
        return result
    e1, e2 = np.eye(2)
    swept = sweep_ranges(analysis, e1, e2)
    combined = swept.combined
    if combined is None:
        return result
    full = len(combined) == 1 and np.degrees(combined[0][1] - combined[0][0]) >= (
        360.0 - FULL_TURN_SLACK_DEG
    )
    if full:
        tilt = 180.0
    elif not combined or swept.design_margin_deg is None:
        tilt = 0.0
    else:
        tilt = max(0.0, float(swept.design_margin_deg))
    details = {**result.details, "tolerated_tilt_deg": tilt}
    message = result.message
    if result.status == Status.PASS:
        words = (
            "safe at any tilt in the plane"
            if full
            else (f"safe for tilts up to {format_angle(tilt)} {planar_tilt_words(scene)}")
        )
        message = f"{message}; {words}"
    return dataclasses.replace(result, details=details, message=message)


def _gravity_error_deg(analysis: Analysis) -> float | None:
    """Under gravity alone (no load, so no swept range): the error (deg) of the closing
    conditions' boundaries in the plane, as a gravity sweep would report its range ends; the
    verdict at the fixed gravity direction holds when it lies farther than this from each."""
    from kcheck.analysis.cases import sweep_ranges

    e1, e2 = np.eye(2)
    return sweep_ranges(analysis, e1, e2).error_deg


# --- partial ranges (the thesis reports motion and contact separately) ------------------------


def partial_ranges(affine: Affine, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, ArcSet]:
    """Force angles (rad) where the forward-sliding ``lambda > 0`` (the body moves the desired
    way, thesis Figure 2.17) and where every normal force is positive (Figures 2.18-2.20)."""
    motion, _ = affine_arcs(affine.a[:1], affine.c[:1], e1, e2, None)
    contact, _ = affine_arcs(affine.a[1:], affine.c[1:], e1, e2, None)
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
    if analysis.error_deg is not None and analysis.error_deg > UNCERTAIN_DEG:
        details["diagnostic"] = (
            f"range ends uncertain by up to {analysis.error_deg:.2g}° (nearly cancelling terms)"
        )
        message += f"; {details['diagnostic']}"
    return dataclasses.replace(result, cases=tuple(cases), details=details, message=message)
