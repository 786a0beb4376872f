"""Jamming: can friction hold the body where it is when a support is retracted?

For every retracted support the check asks whether a static equilibrium exists in which the
external wrench (load, weight, preloads, torque) is balanced by the remaining supports with
every contact force inside its friction cone (:mod:`kcheck.mechanics.statics`). If so, the body may
stay put whatever the forward dynamics say. Outcomes per case at the design direction:

* ``jams``: an equilibrium exists and, without friction, the body would close the gap;
* ``holds``: an equilibrium exists although, without friction, the load would open the gap;
* ``moves``: no equilibrium: friction cannot hold the body.

A case friction holds may be held *or* move: the rigid model can admit a motion from rest
beside the equilibrium (:mod:`kcheck.mechanics.second_answer`); its details then say
``unique: false`` and the supports the motion lifts off, and its message says so. The
verdict does not change.

Planar scenes are exact. Spatial scenes decide the design direction exactly (second-order
cones, clarabel) and bound the maps between inscribed and circumscribed pyramids.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from kcheck.analysis.cases import ranges_deg
from kcheck.analysis.friction_ranges import coefficients_used
from kcheck.analysis.held_alternatives import held_alternatives
from kcheck.analysis.jamming_cases import (
    CaseArcs,
    JamAnalysis,
    JamMap,
    NoClosingForce,
    analyse_jamming,
    case_arcs,
    closing_force_missing,
    held_at,
    jam_map,
    jam_statics,
    least_holding_friction,
    needs_body,
    tidy,
)
from kcheck.fmt import (
    format_angle,
    format_number,
    format_ranges,
    format_share_bounds,
    rounded_bound,
)
from kcheck.mechanics.arcs import FULL, TAU, ArcSet, complement, intersect, margin
from kcheck.mechanics.statics import PYRAMID_EDGES
from kcheck.numerics.margins import MARGINAL_FRICTION_RATIO
from kcheck.numerics.thresholds import IN_SWEEP_PLANE, UNDETERMINED
from kcheck.plugin import Check, Field, Inputs, Options
from kcheck.result import CaseResult, CheckResult, Finding, MassProperties, Status
from kcheck.scene import Scene
from kcheck_checks.marginal import with_margin

__all__ = ["Jamming", "JammingOptions", "jamming_result", "run_jamming"]


class JammingOptions(Options):
    """Options of the ``jamming`` check."""

    min_margin_deg: float = Field(
        0.0, ge=0, description="Least angular distance of the design direction from a held one"
    )
    pyramid_edges: int = Field(
        PYRAMID_EDGES, ge=4, le=64, description="Sides of the pyramids bounding a spatial cone"
    )
    sphere_points: int = Field(
        20000, ge=100, le=1_000_000, description="Fibonacci directions of the spatial map"
    )
    marginal_friction_ratio: float = Field(
        MARGINAL_FRICTION_RATIO,
        ge=1,
        description="A pass whose least holding friction is below this multiple of the design "
        "friction is marginal (1: no marginal band)",
    )


def _ranges(arcs: ArcSet) -> list[list[float]]:
    return [list(r) for r in ranges_deg(arcs)]


def _text(arcs: ArcSet) -> str:
    return format_ranges(ranges_deg(arcs))


def _case(
    analysis: JamAnalysis, r: int, arcs: CaseArcs | None, angle: float | None
) -> tuple[CaseResult, float | None]:
    """Result of one case and its least holding friction at the design direction."""
    statics, case = analysis.statics, analysis.cases[r]
    name = statics.names[r]
    details: dict[str, Any] = {"determinacy": case.free.determinacy}
    if not case.determined:
        details["diagnostic"] = (
            "the free motion is not unique (the remaining normals are degenerate)"
            if case.free.determinacy <= UNDETERMINED
            else "removing this support frees no motion that closes its gap"
        )
        return CaseResult(name, "undetermined", details=details), None
    if arcs is not None:
        details["held_deg"] = _ranges(arcs.held)
        details["closing_deg"] = _ranges(arcs.closing)
        details["jamming_deg"] = _ranges(arcs.jamming)
        details["holds_opening_deg"] = _ranges(arcs.holding_open)
        if statics.dim == 2:
            if arcs.lifts_off is None:
                details["friction_pole_construction"] = "not applicable"
                details["diagnostic"] = (
                    "the rotation about the friction pole presses into a remaining contact: "
                    "Koster's friction-pole construction does not describe the equilibria here"
                )
            else:
                details["lifts_off_deg"] = _ranges(arcs.lifts_off)
    if case.held.kind != "cone":
        details["held_everywhere" if case.held.kind == "everywhere" else "held_nowhere"] = True
    outcome, mu_least = "swept", None
    design = analysis.design
    if design is not None:
        mu_least = least_holding_friction(analysis, case, design)
        details["holding_friction"] = mu_least
        a, c = case.closing
        held = held_at(analysis, case, design, statics.friction)
        outcome = ("jams" if a + c @ design > 0 else "holds") if held else "moves"
    safe = None if arcs is None else ranges_deg(tidy(complement(arcs.held)))
    return CaseResult(
        name, outcome, limiting_friction=None, safe_ranges_deg=safe, details=details
    ), mu_least


def _moves(lifted: list[str]) -> str:
    """The second answer's motion in words."""
    if not lifted:
        return "it slides on every remaining support"
    names = lifted[0] if len(lifted) == 1 else ", ".join(lifted[:-1]) + " and " + lifted[-1]
    return f"it lifts off {names}"


def _uniqueness(
    scene: Scene,
    analysis: JamAnalysis,
    results: list[CaseResult],
    mass: MassProperties | None,
) -> tuple[list[CaseResult], dict[int, str]]:
    """The cases friction holds at the design direction, with whether the rigid model also
    admits a motion from rest (kcheck.analysis.held_alternatives): ``unique`` false and the
    motion in ``alternative`` ("held or moves"). Needs the body's mass properties; without
    them ``unique`` is None and says why. Returns the results and each non-unique case's
    motion in words."""
    held = [r for r, res in enumerate(results) if res.outcome in ("jams", "holds")]
    if not held:
        return results, {}
    out = list(results)
    if mass is None:
        for r in held:
            details = {
                **results[r].details,
                "unique": None,
                "unique_not_checked": "the motion beside rest needs the body's mass and inertia "
                "(give the scene a body)",
            }
            out[r] = replace(results[r], details=details)
        return out, {}
    found = held_alternatives(scene, mass, [(r, analysis.cases[r].keep) for r in held])
    words: dict[int, str] = {}
    for r in held:
        lifted = found[r]
        details = {**results[r].details, "unique": lifted is None}
        if lifted is not None:
            details["alternative_lifts_off"] = lifted
            words[r] = _moves(lifted)
        out[r] = replace(results[r], details=details)
    return out, words


def jamming_result(
    check_id: str,
    scene: Scene,
    analysis: JamAnalysis,
    options: JammingOptions,
    mass: MassProperties | None = None,
) -> tuple[CheckResult, JamMap | None]:
    """Verdict: fail when friction can hold the body at the design direction in some case,
    or, without one, when no swept direction closes every case free of jamming. Where the
    rigid model also admits a motion from rest (``mass`` given), the case is "held or
    moves": the verdict stays, the message says which motion."""
    dim = analysis.statics.dim
    smap = jam_map(analysis, options.sphere_points) if dim == 3 else None
    e1, e2, chosen = _sweep_plane(scene, analysis, smap)
    design = analysis.design
    angle = None
    if design is not None and (dim == 2 or abs(float(design @ np.cross(e1, e2))) < IN_SWEEP_PLANE):
        angle = float(np.arctan2(design @ e2, design @ e1) % TAU)
    all_arcs = [case_arcs(c, e1, e2) if c.determined else None for c in analysis.cases]
    results, least = [], []
    for r in range(len(analysis.cases)):
        res, mu = _case(analysis, r, all_arcs[r], angle)
        results.append(res)
        least.append(mu)
    results, alternatives = _uniqueness(scene, analysis, results, mass)
    determined = [a for a in all_arcs if a is not None]
    # Rounding leaves slivers where boundaries of different cases coincide: drop them.
    jam_free = tidy(intersect(*(complement(a.held) for a in determined)))
    safe = tidy(intersect(*(intersect(a.closing, complement(a.held)) for a in determined)))
    error_deg = float(np.degrees(max((a.error for a in determined), default=0.0)))
    what = "force" if analysis.swept == "load" else "gravity"
    details: dict[str, Any] = {
        "swept_direction": analysis.swept,
        # A case's `safe_ranges_deg` here are the angles friction cannot hold it at.
        "case_ranges_label": f"jam-free {what} angles",
        "jam_free_deg": _ranges(jam_free),
        "pyramid_edges": analysis.edges if dim == 3 else None,
    }
    if dim == 2:
        details.pop("pyramid_edges")
    used = coefficients_used(scene, "static")
    if used is not None:
        # The held set only grows with friction: the top of a static range is its worst.
        details["friction_range"] = {**used, "worst_mu": used["max"]}
    findings: list[Finding] = []
    undetermined = [r for r in results if r.outcome == "undetermined"]
    for r, res in enumerate(results):
        if res.outcome in ("jams", "holds") or (design is None and all_arcs[r] is not None):
            finding = _finding(
                scene,
                analysis,
                r,
                all_arcs[r],
                least[r],
                res.outcome,
                _held_everywhere(smap, analysis, r),
                alternatives.get(r),
            )
            if finding is not None:
                findings.append(finding)
    held_at_design = [r for r in results if r.outcome in ("jams", "holds")]
    parts: list[str] = []
    ok = not undetermined and not held_at_design
    if design is not None:
        if held_at_design:
            parts.append(
                "friction can hold the body at the design direction: "
                + ", ".join(
                    f"retract {r.retracted} ({r.outcome}"
                    + (", or moves" if r.details.get("unique") is False else "")
                    + ")"
                    for r in held_at_design
                )
            )
        else:
            # Good news said as good news: "friction cannot hold the body" read as a failure.
            parts.append(
                "jam-free at the design direction: friction holds the body back in no "
                "retracted case"
            )
        if angle is not None and not jam_free:
            ok = False  # every angle of the plane can be held: no margin to speak of
        elif angle is not None and jam_free != FULL:
            design_margin = float(np.degrees(margin(jam_free, angle)))
            details["design_margin_deg"] = design_margin
            if design_margin < 0:
                parts.append(f"it lies {format_angle(-design_margin)} inside a held range")
            else:
                parts.append(f"margin {format_angle(design_margin)} to a held direction")
            if design_margin < options.min_margin_deg:
                ok = False
                if options.min_margin_deg > 0:
                    parts.append(f"(required {options.min_margin_deg:g}°)")
    else:
        if smap is None:
            ok = ok and bool(safe)
            parts.append(f"closing and jam-free force angles: {_text(safe)}")
        else:
            ok = ok and smap.safe > 0
    if undetermined:
        parts.append("no answer for " + ", ".join(r.retracted for r in undetermined))
    parts.append(f"jam-free in the sweep plane: {_text(jam_free)}")
    if dim == 3:
        details["sweep_plane"] = {
            "normal": np.cross(e1, e2).tolist(),
            "zero": e1.tolist(),
            "chosen": chosen,
        }
    if smap is not None:
        details.update(
            {
                "sphere_points": smap.points,
                "jam_free_solid_angle_fraction": smap.jam_free,
                "jam_free_solid_angle_fraction_upper": smap.jam_free_upper,
                "safe_solid_angle_fraction": smap.safe,
                "safe_solid_angle_fraction_upper": smap.safe_upper,
                "polyhedral_error_deg": smap.error_deg,
            }
        )
        share = format_share_bounds(smap.jam_free, smap.jam_free_upper, 1)
        parts.append(f"{what} directions free of jamming: {share} of the sphere")
        results = [_with_map_share(res, smap, i, analysis) for i, res in enumerate(results)]
    result = CheckResult(
        check_id,
        Status.PASS if ok else Status.FAIL,
        "; ".join(parts),
        error_estimate=error_deg if smap is None else max(error_deg, smap.error_deg),
        safe_ranges_deg=ranges_deg(safe),
        cases=tuple(results),
        details=details,
        findings=tuple(findings),
    )
    return _friction_margin(result, analysis, results, least, options), smap


def _friction_margin(
    result: CheckResult,
    analysis: JamAnalysis,
    results: list[CaseResult],
    least: list[float | None],
    options: JammingOptions,
) -> CheckResult:
    """The marginal band of jamming: the least holding friction over every case at the design
    direction against the design friction (the top of a static range), as a ratio."""
    design_mu = float(analysis.statics.friction.max())
    if (
        analysis.design is None
        or design_mu <= 0
        or any(r.outcome == "undetermined" for r in results)
    ):
        return result
    # None: no coefficient up to 100 holds the body (comfortable).
    holding = [np.inf if mu is None else mu for mu in least]
    r = int(np.argmin(holding))
    ratio = float(holding[r]) / design_mu
    mu_text = format_number(float(holding[r]), 3)
    message = (
        f"retract {results[r].retracted} → friction would hold the body from μ = {mu_text}, only "
        f"{format_number(ratio, 3)}× the design μ = {format_number(design_mu, 3)}, less than "
        f"the {options.marginal_friction_ratio:g}× minimum margin (friction scatter, wear)"
    )
    hint = (
        f"keep μ below {format_number(float(holding[r]) / options.marginal_friction_ratio, 3)} "
        "(lubricate, or harder and smoother seats), or turn the force away from the held "
        "directions (the option `marginal_friction_ratio` sets the band)"
    )
    return with_margin(
        result,
        "least holding friction / design friction",
        ratio,
        options.marginal_friction_ratio,
        "at least",
        message,
        hint=hint,
        field=("friction",),
    )


def _sweep_plane(
    scene: Scene, analysis: JamAnalysis, smap: JamMap | None
) -> tuple[np.ndarray, np.ndarray, str]:
    """The plane of the ranges ``(e1, e2, why)``: the scene's; for a spatial scene without
    ``sweep:`` and with a design direction, the plane through it (angle 0) and the lattice
    direction farthest from every held region (as analytical-3d's plane goes through its most
    robust direction; :func:`kcheck.analysis.sphere_map.chosen_plane`)."""
    dim = analysis.statics.dim
    plane = scene.sweep.e1[:dim], scene.sweep.e2[:dim]
    if dim == 2:
        return *plane, "the scene's sweep"
    from kcheck.analysis.sphere_map import chosen_plane, sweep_given

    if sweep_given(scene):
        return *plane, "the scene's sweep"
    if smap is None or analysis.design is None:
        return *plane, "the xy-plane: no sweep given"
    chosen = chosen_plane(analysis.design, smap.freest, "most jam-free")
    assert chosen is not None  # a design direction was given
    e1, e2, why = chosen
    if smap.freest_pyramids == "inscribed":
        why += ", inscribed pyramids: none is jam-free for certain"
    elif smap.freest is None:
        why += ": every direction is jam-free" if smap.jam_free >= 1 else ": none is jam-free"
    return e1, e2, why


def _with_map_share(res: CaseResult, smap: JamMap, i: int, analysis: JamAnalysis) -> CaseResult:
    import dataclasses

    determined = [k for k, c in enumerate(analysis.cases) if c.determined]
    if i not in determined:
        return res
    k = determined.index(i)
    details = {
        **res.details,
        "held_solid_angle_fraction": float(smap.held[k]),
        "held_solid_angle_fraction_lower": float(smap.held_inner[k]),
    }
    return dataclasses.replace(res, details=details)


def _held_everywhere(smap: JamMap | None, analysis: JamAnalysis, r: int) -> bool:
    """Whether case ``r`` can be held for every swept direction on the sphere (the inscribed
    pyramids, a lower bound of the held share, hold it at every lattice direction)."""
    determined = [k for k, c in enumerate(analysis.cases) if c.determined]
    if smap is None or r not in determined:
        return False
    return bool(smap.held_inner[determined.index(r)] >= 1.0)


def _finding(
    scene: Scene,
    analysis: JamAnalysis,
    r: int,
    arcs: CaseArcs | None,
    least: float | None,
    outcome: str,
    everywhere: bool = False,
    alternative: str | None = None,
) -> Finding | None:
    """Why case ``r`` fails: friction can hold the body (at the design, or somewhere);
    ``everywhere``: for every swept direction on the sphere, so turning it cannot help."""
    statics = analysis.statics
    names = statics.names
    others = ", ".join(names[j] for j in analysis.cases[r].keep)
    what = "load" if analysis.swept == "load" else "gravity"
    gravity_only = analysis.swept != "load"
    # The set named is always the one friction holds the body at (the case's `held_deg`),
    # said as such: "friction holds it for load angles ...".
    holds = ""
    if arcs is not None and arcs.held == FULL:
        holds = f"friction holds it for every {what} angle in the sweep plane"
    elif arcs is not None and arcs.held:
        holds = f"friction holds it for {what} angles {_text(arcs.held)}"
    if analysis.design is None:
        if arcs is None or not arcs.jamming:
            return None
        message = f"retract {names[r]} → " + holds.replace(
            "friction holds it", "friction can hold the body", 1
        )
        hint = f"keep the {what} direction out of {_text(arcs.held)}"
        return Finding(message, code="jams", field=scene.support_field(r), hint=hint)
    mu = float(statics.friction[analysis.cases[r].keep].max())
    force = "load" if analysis.swept == "load" else "weight"
    held = f"although the {force} would {'close' if outcome == 'jams' else 'open'} it there"
    # Holding is the start of motion: the static coefficient (the top of its range: the held
    # set only grows with friction).
    which = "μ" if all(s.coefficients.plain for s in scene.supports) else "static μ"
    closes = ""  # where, without friction, the swept force closes the case (`closing_deg`)
    if arcs is not None and arcs.closing == FULL:
        closes = f"; without friction it closes for every {what} angle in the sweep plane"
    elif arcs is not None and arcs.closing:
        closes = f"; without friction it closes for {what} angles {_text(arcs.closing)}"
    message = (
        f"retract {names[r]} → friction can hold the body at the design direction, {held}"
        f"{closes}{'; ' + holds if holds else ''} (equilibrium exists for μ ≥ "
        f"{format_number(least, 3)}; the scene has {which} = {format_number(mu, 3)})"
    )
    if alternative is not None:
        message += f"; or {alternative} (the rigid model admits both: held or moves)"
    # Rounded down, so that the friction named is below the least that holds.
    if least is not None and least > 0:
        below = format_number(rounded_bound(least, 3, up=False), 7)
        hint = f"lower the friction at {others} below {below}"
    else:  # held at any friction (or unknown): no friction bound frees it
        hint = f"no friction frees it: move or turn support {names[r]} or the supports {others}"
    if gravity_only:
        pass  # nobody turns gravity: the friction is what the designer changes here
    elif arcs is not None and arcs.held != FULL:
        hint += f", or turn the {what} out of {_text(arcs.held)}"
    elif statics.dim == 3 and not everywhere:
        hint += f", or turn the {what} away from the held directions (see the sphere map)"
    return Finding(message, code=outcome, field=scene.support_field(r), hint=hint)


def run_jamming(inputs: Inputs) -> tuple[CheckResult, JamAnalysis | None, JamMap | None]:
    """The check's computation, shared by ``run`` and ``plot``."""
    scene, opts = inputs.scene, inputs.options
    assert isinstance(opts, JammingOptions)
    try:
        statics, swept, design = jam_statics(scene, inputs.mass)
    except NoClosingForce as exc:
        return CheckResult(Jamming.id, Status.SKIPPED, str(exc)), None, None
    analysis = analyse_jamming(statics, swept, design, opts.pyramid_edges)
    result, smap = jamming_result(Jamming.id, scene, analysis, opts, inputs.mass)
    return result, analysis, smap


class Jamming(Check):
    """Static equilibrium with friction per retracted support: can the body stay put?"""

    id = "jamming"
    pictures = "kcheck_checks.pictures.jamming:draw"
    summary = (
        "static equilibrium with Coulomb friction per retracted support: where friction can "
        "hold the body, and the least friction that does"
    )
    applies_to = "planar and spatial scenes with a closing force (a body when weight matters)"
    needs_mass = False
    options = JammingOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Scenes with a closing force whose point (and weight) is known."""
        return closing_force_missing(scene)

    def needs_mass_for(self, scene: Scene) -> bool:
        """Only when the weight or the centre of mass enters the balance."""
        return needs_body(scene)

    def run(self, inputs: Inputs) -> CheckResult:
        """Every retracted case: held directions, outcome and least friction at the design."""
        return run_jamming(inputs)[0]
