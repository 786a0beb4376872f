"""Analytical 3D: Newton–Euler of a six-support coupling with the full inertia tensor.

Besides the planar-style report (outcome, forces, friction intervals, exact ranges in a sweep
plane), the spatial check maps the safe force directions on the whole sphere: per retracted
case every unknown is affine in the unit force direction, so each condition is a spherical cap
and the safe region is their intersection, computed exactly (:mod:`kcheck.mechanics.caps`): its
area, the design direction's signed distance to it, the nearest safe direction and the most robust
one. Without a load, gravity is the closing force and the map is over gravity directions relative to
the body (its tilt).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from kcheck.analysis import analyse, analyse_many
from kcheck.analysis.cases import (
    Analysis,
    closing_analysis,
    closing_cases,
    closing_force_reason,
    describe_ranges,
    sweep_ranges,
)
from kcheck.analysis.friction_ranges import range_details
from kcheck.fmt import clean, format_angle, format_share, format_vector
from kcheck.numerics.thresholds import MARGIN_SCREEN_DEG
from kcheck.plugin import Check, Field, Inputs
from kcheck.result import CheckResult, Finding, Status
from kcheck.scene import Scene
from kcheck_checks.marginal import with_angle_margin
from kcheck_checks.options import AnalyticalOptions
from kcheck_checks.wording import (
    case_findings,
    friction_way_out,
    load_field,
    merge_findings,
    move_support_text,
    support_field,
    verdict,
    with_closing_force_way_out,
    with_friction_way_out,
)

__all__ = [
    "Analytical3D",
    "Analytical3DOptions",
]

if TYPE_CHECKING:
    from kcheck.analysis.sphere_map import SphereMap

#: Re-exported from :mod:`kcheck.analysis.sphere_map`, imported on first use: discovering the
#: checks (every run) does not load the sphere map's modules.
_SPHERE_MAP_NAMES = ("SphereMap", "direction_caps", "sphere_map", "default_plane")


def __getattr__(name: str) -> Any:
    if name in _SPHERE_MAP_NAMES:
        from kcheck.analysis import sphere_map as module

        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class Analytical3DOptions(AnalyticalOptions):
    """Options of the ``analytical-3d`` check."""

    sphere_points: int = Field(
        0,
        ge=0,
        le=5_000_000,
        description="Also count the safe share on a Fibonacci lattice of this many directions "
        "(a cross-check of the exact area; 0: off)",
    )


def tilt_words(scene: Scene) -> str:
    """How a gravity-only scene's tolerated tilt is measured: "from level" when the scene's
    gravity points straight down (−z), else "from the installed attitude"."""
    g = np.asarray(scene.gravity, float)
    n = float(np.linalg.norm(g))
    if n > 0 and np.allclose(g / n, (0.0, 0.0, -1.0), atol=1e-9):
        return "from level"
    return "from the installed attitude"


def _sphere_findings(
    scene: Scene, analysis: Analysis, smap: SphereMap, what: str, min_margin_deg: float
) -> list[Finding]:
    """Why the map fails: nothing safe (and why), the design direction outside (how far, the
    nearest safe direction) or too close to a boundary. A gravity-only scene (gravity swept)
    is told its tolerated tilt and the friction or supports to change, never a direction of
    gravity: nobody turns gravity (a printer bed stays level)."""
    from kcheck.analysis.sphere_map import disjoint_cases

    deg = float(np.degrees(1.0))
    names = analysis.problem.names
    gravity = smap.swept != "load"
    by_friction = friction_way_out(analysis)
    if smap.empty:
        nowhere = [i for i in np.unique(smap.owner) if smap.case_fractions[i] == 0]
        if nowhere:
            return [
                Finding(
                    f"retract {names[i]} → no {what} direction closes it",
                    code="no-safe-direction",
                    field=support_field(scene, names[i]),
                    hint=by_friction or move_support_text([names[i]]),
                )
                for i in nowhere
            ]
        pair = disjoint_cases(smap, analysis)
        if pair is not None:
            i, j = pair
            return [
                Finding(
                    f"the {what} directions that close {names[i]} "
                    f"({format_share(smap.case_fractions[i])} of the sphere) and those that "
                    f"close {names[j]} ({format_share(smap.case_fractions[j])}) do not overlap",
                    code="ranges-disjoint",
                    field=support_field(scene, names[i]),
                    hint=by_friction or move_support_text([names[i], names[j]]),
                )
            ]
        return [
            Finding(
                f"no {what} direction closes every retraction (each closes on its own, "
                "not all together)",
                code="no-safe-direction",
                field=("supports",),
                hint=by_friction,
            )
        ]
    if smap.design is None or smap.design_margin is None:
        if smap.robust_margin * deg < min_margin_deg:
            return [
                Finding(
                    f"the most robust {what} direction {format_vector(smap.robust, 3)} is "
                    f"only {format_angle(smap.robust_margin * deg)} from the nearest "
                    f"boundary, less than the required {min_margin_deg:g}°",
                    code="margin",
                    field=("load",) if smap.swept == "load" else ("gravity",),
                )
            ]
        return []
    field = load_field(scene) if smap.swept == "load" else ("gravity",)
    margin = smap.design_margin * deg
    if margin < 0 and gravity:
        return [
            Finding(
                f"as installed (gravity along {format_vector(smap.design, 3)}), the weight "
                f"does not close every retraction: a tilt of {format_angle(-margin)} would be "
                "needed to reach the safe region",
                code="design-outside",
                field=field,
                hint=by_friction,
            )
        ]
    if margin < 0:
        assert smap.nearest is not None
        return [
            Finding(
                f"the design {what} direction {format_vector(smap.design, 3)} lies "
                f"{format_angle(-margin)} outside the safe region; the nearest safe direction "
                f"is {format_vector(smap.nearest, 3)}",
                code="design-outside",
                field=field,
                hint=f"turn the {what} to {format_vector(smap.robust, 3)}, the most robust "
                f"direction ({format_angle(smap.robust_margin * deg)} from every boundary; "
                f"the nearest safe one is {format_angle(-margin)} away)"
                + ("" if by_friction is None else f"; or {by_friction}"),
            )
        ]
    if margin < min_margin_deg and gravity:
        return [
            Finding(
                f"the installation is safe for tilts up to {format_angle(margin)} "
                f"{tilt_words(scene)} only, less than the required {min_margin_deg:g}°",
                code="margin",
                field=field,
            )
        ]
    if margin < min_margin_deg:
        return [
            Finding(
                f"the design {what} direction {format_vector(smap.design, 3)} is "
                f"{format_angle(margin)} from the nearest boundary, less than the required "
                f"{min_margin_deg:g}°",
                code="margin",
                field=field,
                hint=f"turn the {what} to {format_vector(smap.robust, 3)}, the most robust "
                f"direction: it keeps {format_angle(smap.robust_margin * deg)}"
                if smap.robust_margin * deg >= min_margin_deg
                else f"no {what} direction keeps {min_margin_deg:g}° (the most robust, "
                f"{format_vector(smap.robust, 3)}, keeps "
                f"{format_angle(smap.robust_margin * deg)}): move the force's point or the "
                "supports (kcheck suggest searches the points)",
            )
        ]
    return []


def _plane_text(analysis: Analysis, chosen: str | None) -> str:
    """The sweep-plane part of the message; ``chosen``: why the check chose the plane (None:
    the scene's)."""
    if chosen is None:
        where = "in the sweep plane"
    else:
        where = f"in {chosen}" if chosen.startswith("the ") else f"in the plane {chosen}"
    if analysis.combined is None:
        return ""
    if not analysis.combined:
        return f"no safe direction {where}"
    return f"{where}: {describe_ranges(analysis.combined)}"


def spatial_result(
    check_id: str, scene: Scene, analysis: Analysis, options: Analytical3DOptions
) -> tuple[CheckResult, SphereMap | None, Analysis]:
    """Verdict of the spatial check: the sphere map decides, a sweep plane is reported.

    Returns the result, the map and the analysis (with the sweep plane actually used)."""
    return spatial_results(check_id, [scene], [analysis], [options])[0]


def spatial_results(
    check_id: str,
    scenes: Sequence[Scene],
    analyses: Sequence[Analysis],
    options: Sequence[Analytical3DOptions],
) -> list[tuple[CheckResult, SphereMap | None, Analysis]]:
    """:func:`spatial_result` of several scenes, their sphere maps' case regions in one
    batch (:func:`kcheck.analysis.sphere_map.sphere_maps`); each is the scene's alone."""
    from kcheck.analysis.sphere_map import sphere_maps

    smaps: list[SphereMap | None] = [None] * len(scenes)
    for points in {o.sphere_points for o in options}:
        mapped = [
            i
            for i, a in enumerate(analyses)
            if a.trustworthy and options[i].sphere_points == points
        ]
        found = sphere_maps([scenes[i] for i in mapped], [analyses[i] for i in mapped], points)
        for i, smap in zip(mapped, found, strict=True):
            smaps[i] = smap
    return [
        _spatial_result(check_id, *each)
        for each in zip(scenes, analyses, options, smaps, strict=True)
    ]


def _spatial_result(
    check_id: str,
    scene: Scene,
    analysis: Analysis,
    options: Analytical3DOptions,
    smap: SphereMap | None,
) -> tuple[CheckResult, SphereMap | None, Analysis]:
    """:func:`spatial_result` given the scene's map (None: untrustworthy, or nothing to map).
    The analysis may lack the ranges in the scene's plane (``analyse_many(sweep=False)``):
    they are added here where that plane is the one reported; where the check chooses its
    own plane, the case findings' hints then do without them."""
    from kcheck.analysis.cases import scene_plane_ranges
    from kcheck.analysis.sphere_map import chosen_plane, sweep_given

    chosen = None
    if smap is not None and not sweep_given(scene):
        # The most robust direction only where it means one: not on an empty or full map.
        meaningful = not smap.empty and not (smap.region is not None and smap.region.full)
        chosen = chosen_plane(smap.design, smap.robust if meaningful else None)
    if chosen is None:
        analysis = scene_plane_ranges(scene, analysis)
    deg = float(np.degrees(1.0))
    details: dict[str, object] = {"max_condition": analysis.max_condition}
    span = range_details(scene, analysis)
    if span is not None:
        details["friction_range"] = span
    findings = case_findings(scene, analysis)
    if chosen is not None:
        analysis = sweep_ranges(analysis, chosen[0], chosen[1])
    elif smap is not None and analysis.plane is None:
        # Gravity swept (no load): `analyse` sweeps only a load; the scene's plane here.
        analysis = sweep_ranges(analysis, scene.sweep.e1, scene.sweep.e2)
    if analysis.plane is not None:
        e1, e2 = analysis.plane
        details["sweep_plane"] = {
            "normal": np.cross(e1, e2).tolist(),
            "zero": np.asarray(e1).tolist(),
            "chosen": chosen[2]
            if chosen is not None
            else ("the scene's sweep" if sweep_given(scene) else "the xy-plane: no sweep given"),
        }
        if analysis.design_margin_deg is not None:
            details["sweep_design_margin_deg"] = analysis.design_margin_deg
    if smap is None:
        names = ", ".join(
            f"{r.retracted} ({r.outcome.replace('_', ' ')})"
            for r in analysis.results
            if r.outcome in ("undetermined", "ill_conditioned")
        )
        message = f"no trustworthy answer for {names}" if names else "nothing to map"
        result = CheckResult(
            check_id,
            Status.FAIL,
            message,
            cases=analysis.results,
            details=details,
            findings=tuple(findings),
        )
        return result, smap, analysis
    what = "force" if smap.swept == "load" else "gravity"
    details.update(
        {
            "swept_direction": smap.swept,
            "safe_solid_angle_fraction": smap.fraction.fraction,
            "safe_solid_angle_fraction_error": smap.fraction.error,
        }
    )
    if smap.swept == "gravity" and analysis.plane is not None:
        details["case_ranges_label"] = "safe gravity angles"  # the cases' safe_ranges_deg
    if smap.lattice is not None:
        details["sphere_points"] = smap.lattice.points
        details["lattice_fraction"] = smap.lattice.fraction
        details["lattice_fraction_error"] = smap.lattice.error
    full = smap.region is not None and smap.region.full
    if not smap.empty and not full:
        details["most_robust_direction"] = clean(smap.robust).tolist()
        details["robust_margin_deg"] = smap.robust_margin * deg
    if smap.design_margin is not None and not full:
        details["design_margin_deg"] = smap.design_margin * deg
    if smap.swept != "load" and smap.design_margin is not None:
        # What a gravity-only scene's designer can read off: the tilt the installation takes.
        details["tolerated_tilt_deg"] = 180.0 if full else max(0.0, smap.design_margin * deg)
    if smap.nearest is not None:
        details["nearest_safe_direction"] = clean(smap.nearest).tolist()
    cases = tuple(
        dataclasses.replace(
            r,
            details={**r.details, "closing_solid_angle_fraction": float(smap.case_fractions[i])},
        )
        if np.isfinite(smap.case_fractions[i])
        else r
        for i, r in enumerate(analysis.results)
    )
    # Each case's reason (with the map's word about that case), the map's verdict first.
    findings = merge_findings(
        findings, _sphere_findings(scene, analysis, smap, what, options.min_margin_deg)
    )
    findings.sort(key=lambda f: f.code not in ("design-outside", "margin"))
    if smap.empty:
        parts = [f"no safe {what} direction"]
    elif full:
        parts = [f"every {what} direction closes every retraction"]
        if smap.swept != "load":
            parts.append("safe at any tilt")
    else:
        parts = [f"safe {what} directions: {format_share(smap.fraction.fraction)} of the sphere"]
        if smap.design_margin is not None and smap.design_margin >= 0 and not findings:
            if smap.swept == "load":
                parts.append(
                    f"design direction {format_angle(smap.design_margin * deg)} from the "
                    "nearest boundary"
                )
            else:
                # Nobody turns gravity: the margin said as the tilt the installation tolerates.
                parts.append(
                    f"safe for tilts up to {format_angle(smap.design_margin * deg)} "
                    f"{tilt_words(scene)}"
                )
        elif smap.design is None and not findings and smap.swept == "load":
            parts.append(
                f"most robust {format_vector(smap.robust, 3)}, "
                f"{format_angle(smap.robust_margin * deg)} from every boundary"
            )
        plane = _plane_text(analysis, None if chosen is None else chosen[2])
        if plane:
            parts.append(plane)
    result = CheckResult(
        check_id,
        Status.PASS if not findings else Status.FAIL,
        verdict(parts, findings),
        # Degrees: the sweep-plane range ends and the map's margins, whichever is worse.
        error_estimate=_error_deg(analysis, smap),
        safe_ranges_deg=None if analysis.combined is None else _ranges(analysis),
        cases=cases,
        details=details,
        findings=tuple(findings),
    )
    field = load_field(scene) if scene.load is not None else None
    result = with_angle_margin(result, options.marginal_deg, field, gravity=what == "gravity")
    return result, smap, analysis


def _error_deg(analysis: Analysis, smap: SphereMap) -> float:
    """The check's error estimate (deg): the sweep-plane range ends and the safe region's
    boundary (its margins), whichever is worse; a map with no boundary (every direction safe,
    or none) the largest cap its conditions' rounding could open (gravity alone: no sweep
    plane, a full map)."""
    errors = [] if analysis.error_deg is None else [analysis.error_deg]
    if not smap.empty and (smap.region is None or not smap.region.full):
        errors.append(float(np.degrees(smap.boundary_error)))
    else:
        errors.append(float(np.degrees(smap.hidden_error)))
    return max(errors)


def _ranges(analysis: Analysis) -> tuple[tuple[float, float], ...]:
    from kcheck.analysis.cases import ranges_deg

    assert analysis.combined is not None
    return ranges_deg(analysis.combined)


def _map_passes(scene: Scene, analysis: Analysis, options: Analytical3DOptions) -> bool | None:
    """Whether the check passes (``spatial_result(...)[0].status`` is ``pass``) on an analysis
    whose every case closes at the design direction or is swept
    (:func:`kcheck.analysis.cases.closing_cases`: no case finding), from the caps and the
    safe region alone: no case's own region, most robust direction, area error, ranges or
    wording. None where that needs the whole map (no design direction: the most robust
    one's margin decides).

    The same tests as :func:`_spatial_result` on the same numbers: nothing to map or an empty
    region fails; the design direction's margin below zero or ``min_margin_deg`` is a
    finding (:func:`_sphere_findings`); a region that is not the whole sphere with a margin
    below ``marginal_deg`` is marginal (:func:`kcheck_checks.marginal.with_angle_margin`)."""
    from kcheck.analysis.sphere_map import direction_caps, map_design
    from kcheck.mechanics.caps import region, signed_distance

    caps = direction_caps(analysis.problem, analysis)
    if _short_of_margin(analysis, options, caps):
        return False
    swept, a, c, _, _ = caps
    if not len(a):
        return False  # nothing to map: a fail
    safe = region(a, c)
    if safe.empty:
        return False  # no safe direction: a finding
    design = map_design(scene, analysis, swept)
    if design is None:
        return None
    margin, _ = signed_distance(safe, design)
    if margin is None:
        return None
    deg = float(np.degrees(1.0))
    if margin * deg < 0 or margin * deg < options.min_margin_deg:
        return False
    if safe.full:
        return True  # no margin reported: nothing marginal
    value = float(margin * deg)
    return not (math.isfinite(value) and value < options.marginal_deg)


def _short_of_margin(
    analysis: Analysis,
    options: Analytical3DOptions,
    caps: tuple[Any, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> bool:
    """Whether the design load direction of an analysis whose every case closes there is
    surely closer to the safe region's edge than the check allows (a `margin` finding, or the
    `marginal` band): its margin in closed form, the least over every case's closing caps
    (:func:`kcheck.mechanics.arcs.cap_margins`: inside every cap, the distance to the
    intersection's boundary), below the limit by more than MARGIN_SCREEN_DEG. A cheap first
    test of a way-out trial before its sphere map; False where the map must decide (gravity
    swept, no design direction)."""
    from kcheck.analysis.sphere_map import direction_caps
    from kcheck.mechanics.arcs import cap_margins

    design = analysis.design
    if design is None or analysis.problem.swept != "load":
        return False
    _, a, c, _, _ = direction_caps(analysis.problem, analysis) if caps is None else caps
    d = np.asarray(design, float)
    margin = float(np.degrees(cap_margins(a, c, (d / np.linalg.norm(d))[None, :])[0]))
    limit = max(options.min_margin_deg, options.marginal_deg)
    return margin < limit - MARGIN_SCREEN_DEG


class Analytical3D(Check):
    """Every retracted support of a spatial scene: free screw, outcome, forces, ranges, map."""

    id = "analytical-3d"
    pictures = "kcheck_checks.pictures.spatial:draw"
    summary = (
        "Newton–Euler per retracted support with the full inertia tensor: outcome, normal "
        "forces, friction intervals, exact safe region on the sphere of directions (share, "
        "margins, most robust direction) and ranges in a sweep plane"
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
        return self.run_many([inputs])[0]

    def run_many(self, inputs: Sequence[Inputs]) -> list[CheckResult]:
        """:meth:`run` of several scenes, their cases' algebra stacked in one batch
        (:func:`kcheck.analysis.analyse_many`: each analysis is the scene's alone)."""
        masses, options = [], []
        for one in inputs:
            assert one.mass is not None and isinstance(one.options, Analytical3DOptions)
            masses.append(one.mass)
            options.append(one.options)
        scenes = [i.scene for i in inputs]
        # Without hints (a study), the ranges in the scene's plane only where that plane is
        # reported: the check sweeps a plane of its own when the scene gives none.
        analyses = analyse_many(scenes, masses, sweep=any(i.hints for i in inputs))
        found = spatial_results(self.id, scenes, analyses, options)
        return [self._result(one, each[0]) for one, each in zip(inputs, found, strict=True)]

    def _result(self, inputs: Inputs, result: CheckResult) -> CheckResult:
        """One scene's result, with the way-out searches behind its hints when asked for."""
        assert inputs.mass is not None and isinstance(inputs.options, Analytical3DOptions)
        mass, options = inputs.mass, inputs.options

        def passes(scene: Scene) -> bool:
            # Exact shortcut: the outcomes from the cases' algebra alone reject most trial
            # forces of a failing scene (a case that does not close fails below), and the
            # rest need no friction intervals nor friction_may_hold, which only word the
            # findings, nor case results: every case closes (closing_cases), so the map's
            # safe region alone decides (_map_passes).
            low, high = scene.friction_range("kinetic")
            if np.array_equal(low, high):
                found = closing_cases(scene, mass)
                if found is None:
                    return False
                decided = _map_passes(scene, found, options)
                if decided is not None:
                    return decided
                found = closing_analysis(scene, mass)
                if found is None or _short_of_margin(found, options):
                    return False
                trial = found
            else:
                trial = analyse(scene, mass)
            # Exact shortcut: a case that does not close (or an untrustworthy analysis) fails
            # the check whatever the sphere map finds, as spatial_result keeps every case
            # finding; only the rest need the map (a failing scene's closing-force search
            # judged ~23 trial forces, each with a sphere map: 250-520 ms instead of 13 ms).
            if not trial.trustworthy or case_findings(scene, trial):
                return False
            again = spatial_result(self.id, scene, trial, options)[0]
            return again.status == Status.PASS

        if not inputs.hints:
            return result
        from kcheck.analysis.way_out import trial_screens

        by_friction, by_force = trial_screens(inputs.scene, mass)
        result = with_friction_way_out(result, inputs.scene, passes, by_friction)
        return with_closing_force_way_out(result, inputs.scene, passes, by_force)
