"""What the analytical checks say: one located finding per reason, in a designer's words.

Numbers go through :mod:`kcheck.fmt` (angles, ranges, numbers), so every check writes them the
same way. A finding names the retracted support (``("supports", i)``) or the load direction
(``("load", "direction")``) it is about, says why, and where it can, what would close the case.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import re
from collections.abc import Callable, Sequence

import numpy as np

from kcheck.analysis.cases import Analysis
from kcheck.errors import FieldPath
from kcheck.fmt import format_angle, format_number, format_ranges, rounded_bound
from kcheck.mechanics.arcs import ArcSet, intersect
from kcheck.mechanics.friction import FrictionIntervals, describe_friction
from kcheck.numerics.thresholds import FULL_TURN_SLACK_DEG
from kcheck.result import CaseResult, CheckResult, Finding, Status
from kcheck.scene import Scene

__all__ = [
    "verdict",
    "merge_findings",
    "support_field",
    "load_field",
    "ranges_text",
    "mu_text",
    "case_findings",
    "with_friction_way_out",
    "with_closing_force_way_out",
    "friction_bound_text",
    "friction_way_out",
    "move_support_text",
    "way_out",
    "empty_range_findings",
    "design_findings",
]


def support_field(scene: Scene, name: str) -> FieldPath:
    """The scene field of a support, by name (:meth:`Scene.support_field`)."""
    for i, s in enumerate(scene.supports):
        if s.name == name:
            return scene.support_field(i)
    return ("supports",)


def load_field(scene: Scene) -> FieldPath:
    """The field of the design direction (``load.direction`` or ``load.angle``)."""
    if ("load", "angle") in scene.lines:
        return ("load", "angle")
    return ("load", "direction")


def ranges_text(ranges: Sequence[Sequence[float]] | None) -> str:
    """Ranges in degrees, "every direction" or "none" (:func:`kcheck.fmt.format_ranges`)."""
    if ranges and len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= 360.0 - FULL_TURN_SLACK_DEG:
        return "every direction"
    return format_ranges(ranges)


def mu_text(intervals: FrictionIntervals) -> str:
    """The scene's friction coefficient, e.g. "μ = 0.1" (the largest one when they differ)."""
    text = f"μ = {format_number(intervals.mu, 3)}"
    return text if intervals.uniform else text + " (largest coefficient, the others in proportion)"


def _friction_tail(intervals: FrictionIntervals | None) -> str:
    """ "; it closes for μ ≤ 0.122" when some other friction would close the case, else ""."""
    if intervals is None or not intervals.intervals:
        return ""
    return f"; it {describe_friction(intervals)}"


def _lost(result: CaseResult) -> str:
    """Which remaining supports lose contact, with their normal forces."""
    lifts = result.details.get("lifts_off")
    if isinstance(lifts, list) and lifts:
        verb = "lifts" if len(lifts) == 1 else "lift"
        return (
            f"{' and '.join(lifts)} {verb} off (friction cannot hold the body, and it cannot "
            "slide on every remaining support)"
        )
    forces = result.normal_forces or {}
    lost = [(n, f) for n, f in forces.items() if not f > 0]
    if not lost:
        return "a support loses contact"
    names = " and ".join(n for n, _ in lost)
    values = ", ".join(f"N = {format_number(f, 3)} N" for _, f in lost)
    verb = "loses" if len(lost) == 1 else "lose"
    return f"{names} {verb} contact ({values})"


#: What a moving case that friction can also hold says (kcheck.analysis.cases).
MAY_HOLD = (
    "or friction holds the body (an equilibrium exists too: the rigid model admits both, "
    "see jamming)"
)


def _why(result: CaseResult, intervals: FrictionIntervals | None) -> tuple[str, str] | None:
    """(code, sentence after "retract x →") for a case that does not close, or None."""
    details = result.details
    mu = "" if intervals is None else f" at {mu_text(intervals)}"
    tail = _friction_tail(intervals)
    if details.get("friction_may_hold"):
        tail = f", {MAY_HOLD}{tail}"
    at = note = ""  # over a friction range: the coefficient the outcome is reported at
    span = details.get("friction_range")
    if isinstance(span, dict) and "worst_mu" in span:
        low, high = (format_number(span[k], 3) for k in ("min", "max"))
        mu = at = f" at μ = {format_number(span['worst_mu'], 3)}"
        note = f", the worst of the friction range {low}–{high}"
    match result.outcome:
        case "jams" if details.get("no_equilibrium"):
            return (
                "jams",
                f"jams{mu}: the body can neither slide on every remaining support nor be held "
                f"by friction, and no first motion with a support lifting off was found (the "
                f"rigid model may have no answer){note}{tail}",
            )
        case "jams":
            return "jams", f"jams{mu} (friction holds the body){note}{tail}"
        case "loses_contact":
            return "loses-contact", f"{_lost(result)}{at}{note}{tail}"
        case "opens":
            return (
                "opens",
                f"the body moves away from the retracted support (opens){at}{note}{tail}",
            )
        case "opens_loses_contact":
            return (
                "opens-loses-contact",
                f"the body moves away from the retracted support and {_lost(result)}{at}{note}"
                f"{tail}",
            )
        case "ambiguous":
            start = details.get("painleve_from_mu")
            if "effective_mass" in details:
                since = "" if start is None else f" from μ = {format_number(start, 3)} on"
                return (
                    "ambiguous",
                    "ambiguous: friction makes the effective mass along the free motion "
                    f"negative{since} (Painlevé), so rigid-body friction predicts two motions "
                    f"or none{tail}",
                )
            return (
                "ambiguous",
                f"ambiguous: sliding towards and away from the support are both consistent{tail}",
            )
        case "undetermined" | "ill_conditioned":
            diagnostic = str(details.get("diagnostic", result.outcome.replace("_", " ")))
            return result.outcome.replace("_", "-"), f"no trustworthy answer: {diagnostic}"
    return None


def friction_bound(
    intervals: Sequence[tuple[float, float]], mu: float
) -> tuple[float | None, float | None] | None:
    """The closing interval of μ nearest the scene's ``mu``, its ends rounded inwards
    (:func:`rounded_bound`) so that any μ inside closes: ``(low, high)``, None for no end (μ from 0,
    or without bound); None when no interval is wide enough to round inwards."""

    def distance(interval: tuple[float, float]) -> float:
        lo, hi = interval
        return 0.0 if lo <= mu <= hi else min(abs(lo - mu), abs(hi - mu))

    for lo, hi in sorted(intervals, key=distance):
        for digits in range(3, 8):
            low = rounded_bound(lo, digits, up=True) if lo > 0 else None
            high = rounded_bound(hi, digits, up=False) if math.isfinite(hi) else None
            if high is not None and high <= 0:
                continue
            if low is None or high is None or low < high:
                return low, high
    return None


def friction_bound_text(
    intervals: Sequence[tuple[float, float]], mu: float, uniform: bool = True
) -> str | None:
    """ "closes for μ ≤ 0.096" (or "μ ≥ 0.3", "0.1 ≤ μ ≤ 0.2"): the nearest friction that closes,
    rounded inwards (:func:`friction_bound`); None when none does."""
    bound = friction_bound(intervals, mu)
    if bound is None:
        return None
    low, high = bound
    if low is None and high is None:
        return None
    if low is None:
        text = f"μ ≤ {format_number(high, 7)}"
    elif high is None:
        text = f"μ ≥ {format_number(low, 7)}"
    else:
        text = f"{format_number(low, 7)} ≤ μ ≤ {format_number(high, 7)}"
    tail = "" if uniform else " (the largest coefficient, the others in proportion)"
    return f"closes for {text}{tail}"


def common_intervals(
    sets: Sequence[Sequence[tuple[float, float]]],
) -> tuple[tuple[float, float], ...]:
    """The μ intervals common to every set (each sorted, closed)."""
    out: list[tuple[float, float]] = [(0.0, math.inf)]
    for intervals in sets:
        out = [
            (max(a, c), min(b, d)) for a, b in out for c, d in intervals if max(a, c) < min(b, d)
        ]
    return tuple(out)


def friction_way_out(analysis: Analysis) -> str | None:
    """The friction at which every case closes at the design direction ("every retraction
    closes for μ ≤ 0.096"), the nearest to the scene's; None when none does (or unknown)."""
    found = [f for f in analysis.friction if f is not None]
    if not found or len(found) != len(analysis.friction):
        return None
    text = friction_bound_text(
        common_intervals([f.intervals for f in found]), found[0].mu, found[0].uniform
    )
    return None if text is None else f"every retraction {text}"


def move_support_text(names: Sequence[str], what: str | None = "direction") -> str:
    """ "no direction closes this case: move or turn support x1" (the supports named;
    ``what``: what was tried and does not help, None when nothing is claimed)."""
    which = " or ".join(names)
    noun = "support" if len(names) == 1 else "supports"
    tried = "" if what is None else f"no {what} closes this case: "
    return f"{tried}move or turn {noun} {which}"


def _lost_names(result: CaseResult) -> list[str]:
    """The remaining supports that lose contact (no positive normal force)."""
    return [n for n, f in (result.normal_forces or {}).items() if not f > 0]


def way_out(scene: Scene, result: CaseResult, intervals: FrictionIntervals | None) -> str | None:
    """The nearest change that closes a failing case, in one line: the friction that closes
    it, the force angles that close it (a swept load), else the support to move or turn."""
    ways = []
    if intervals is not None and intervals.intervals:
        text = friction_bound_text(intervals.intervals, intervals.mu, intervals.uniform)
        if text is not None:
            ways.append(text)
    gravity_only = _swept(scene) == "gravity"
    if result.safe_ranges_deg and not gravity_only:
        ways.append(f"closes for force angles {ranges_text(result.safe_ranges_deg)}")
    if ways:
        return "; or ".join(ways)
    if result.outcome in ("undetermined", "ill_conditioned"):
        return None
    # What was tried and does not help (friction only when its intervals were computed).
    what: str | None
    if gravity_only:
        # nobody turns gravity: the tilt is not the designer's to change
        what = None if intervals is None else "friction"
    elif result.safe_ranges_deg is None:  # the directions were not swept
        what = None if intervals is None else "friction"
    elif scene.dim == 2:
        what = "direction"
    else:
        what = "force angle in the sweep plane"
        if intervals is not None:
            what = "friction nor " + what
    lost = _lost_names(result)
    text = move_support_text(lost or [result.retracted], what)
    if scene.dim == 2 and not gravity_only:
        text += f", or move {_acting_point(scene)}"
    return text


def _acting_point(scene: Scene) -> str:
    """Where the swept force acts, as a designer would move it."""
    load = scene.load
    if load is not None and load.magnitude > 0 and load.point is not None:
        return "the load point"
    return "the centre of mass (where the force acts)"


def case_findings(scene: Scene, analysis: Analysis) -> list[Finding]:
    """One finding per retracted case that does not close: "retract y1 → jams at μ = 0.6; it
    closes for μ ≤ 0.122", located at the retracted support. With static and kinetic
    coefficients, "kinetic μ" (the dynamics slide)."""
    out = []
    friction = analysis.friction or (None,) * len(analysis.results)
    kinetic = any(s.coefficients.two_valued for s in scene.supports)
    for result, intervals in zip(analysis.results, friction, strict=True):
        if result.outcome in ("closes", "swept"):
            continue
        why = _why(result, intervals)
        if why is not None and kinetic:
            why = (why[0], why[1].replace(" at μ = ", " at kinetic μ = ", 1))
        if why is None:
            continue
        code, sentence = why
        hint = way_out(scene, result, intervals)
        text = f"retract {result.retracted} → {sentence}"
        out.append(
            Finding(text, code=code, field=support_field(scene, result.retracted), hint=hint)
        )
    return out


def _swept(scene: Scene) -> str:
    """What the checks turn: the load, or gravity when the scene has no load magnitude."""
    return "force" if scene.load is not None and scene.load.magnitude > 0 else "gravity"


def _rad(ranges: Sequence[Sequence[float]]) -> ArcSet:
    return tuple((float(np.radians(s)), float(np.radians(e))) for s, e in ranges)


def empty_range_findings(
    scene: Scene,
    results: Sequence[CaseResult],
    plane_text: str = "",
    analysis: Analysis | None = None,
) -> list[Finding]:
    """Why no force angle is safe: cases that close nowhere, else two cases whose safe ranges
    do not overlap, else all of them together ("the safe ranges of y1 (...) and y2 (...) do not
    overlap")."""
    usable = [r for r in results if r.safe_ranges_deg is not None]
    by_friction = None if analysis is None else friction_way_out(analysis)
    nowhere = [r for r in usable if not r.safe_ranges_deg]
    if nowhere:
        return [
            Finding(
                f"retract {r.retracted} → no force angle{plane_text} closes this retraction",
                code="no-safe-direction",
                field=support_field(scene, r.retracted),
                hint=by_friction or move_support_text([r.retracted]),
            )
            for r in nowhere
        ]
    for i, first in enumerate(usable):
        for second in usable[i + 1 :]:
            if not intersect(_rad(first.safe_ranges_deg or ()), _rad(second.safe_ranges_deg or ())):
                return [
                    Finding(
                        f"the safe ranges of {first.retracted} "
                        f"({ranges_text(first.safe_ranges_deg)}) and {second.retracted} "
                        f"({ranges_text(second.safe_ranges_deg)}) do not overlap{plane_text}",
                        code="ranges-disjoint",
                        field=("load",),
                        hint=by_friction or move_support_text([first.retracted, second.retracted]),
                    )
                ]
    listed = ", ".join(f"{r.retracted} ({ranges_text(r.safe_ranges_deg)})" for r in usable)
    return [
        Finding(
            f"the safe ranges {listed} have no angle in common{plane_text}",
            code="ranges-disjoint",
            field=("load",),
            hint=by_friction,
        )
    ]


def angle_text(value: float) -> str:
    """An angle in [0°, 360°) (:func:`kcheck.fmt.format_angle`)."""
    return format_angle(value % 360.0)


def _subject(finding: Finding) -> str | None:
    """The retracted support a finding is about ("retract A.1 → ..."), or None."""
    head, arrow, _ = finding.message.partition(" → ")
    return head if arrow else None


def merge_findings(first: Sequence[Finding], more: Sequence[Finding]) -> list[Finding]:
    """``first`` then ``more``; a finding of ``more`` about a retracted support that ``first``
    already has a finding for is added to that one's message, once (one finding per support).
    The supports of one coupling share a field, so the support is matched by name."""
    out = list(first)
    for extra in more:
        subject = _subject(extra)
        for i, found in enumerate(out):
            if (
                found.field == extra.field
                and extra.field not in (None, ("supports",))
                and subject is not None
                and _subject(found) == subject
            ):
                tail = extra.message.split(" → ", 1)[-1]
                if tail not in found.message:
                    out[i] = dataclasses.replace(found, message=f"{found.message}; {tail}")
                break
        else:
            out.append(extra)
    return out


def verdict(parts: Sequence[str], findings: Sequence[Finding]) -> str:
    """The one-line message: the summary, the first reason, and how many more the findings
    hold ("...; retract y1 → jams at μ = 0.6 (and 2 more)", as the short summary says)."""
    line = [*parts]
    if findings:
        more = f" (and {len(findings) - 1} more)" if len(findings) > 1 else ""
        line.append(findings[0].message + more)
    return "; ".join(line)


def design_findings(
    scene: Scene,
    design_deg: float,
    margin_deg: float | None,
    nearest_deg: float | None,
    ranges_text: str,
    min_margin_deg: float,
    what: str = "design direction",
    safe: Sequence[Sequence[float]] | None = None,
    by_friction: str | None = None,
) -> list[Finding]:
    """Why a design direction is not good enough: outside the safe ranges (by how much, and
    the nearest safe angle), or inside by less than the required margin. None when no range
    is safe (the empty ranges have their own finding)."""
    if margin_deg is None:
        return []
    design = format_angle(design_deg % 360.0)
    field = load_field(scene)
    if margin_deg < 0:
        near = (
            ""
            if nearest_deg is None
            else f"; the nearest safe angle is {format_angle(nearest_deg)}"
        )
        return [
            Finding(
                f"the {what} {design} lies {format_angle(-margin_deg)} outside the safe "
                f"range {ranges_text}{near}",
                code="design-outside",
                field=field,
                hint=_into_range(scene, safe, by_friction),
            )
        ]
    if margin_deg < min_margin_deg:
        return [
            Finding(
                f"the {what} {design} is {format_angle(margin_deg)} inside the safe range "
                f"{ranges_text}, less than the required {min_margin_deg:g}°",
                code="margin",
                field=field,
                hint=_into_range(scene, safe, None, min_margin_deg),
            )
        ]
    return []


def _into_range(
    scene: Scene,
    safe: Sequence[Sequence[float]] | None,
    by_friction: str | None,
    margin_deg: float = 0.0,
) -> str | None:
    """Where to turn a swept load: the middle of the widest safe range, with what it keeps
    from either end (when that is more than ``margin_deg``); and the friction that closes
    every case at the design. A gravity-only scene gets only the friction: nobody turns
    gravity."""
    ways = []
    if safe and _swept(scene) == "force":
        start, end = max(safe, key=lambda r: (r[1] - r[0]) % 360.0)
        half = ((end - start) % 360.0 or 360.0) / 2.0
        if half > margin_deg:
            middle = (start + half) % 360.0
            ways.append(
                f"turn the force to {format_angle(middle)}, the middle of "
                f"{format_ranges([(start, end)])} ({format_angle(half)} from either end)"
            )
    if by_friction is not None:
        ways.append(by_friction)
    return "; or ".join(ways) or None


@functools.cache
def numeric_way_out() -> re.Pattern[str]:
    """A hint that already names a number to change: a friction bound, force angles, a
    direction. (Compiled when first needed, not on import: start-up, issue 24.)"""
    return re.compile(r"μ [≤≥] \d|below \d|force angles \d|turn the force to")


#: Findings about the whole safe set, which a friction search can answer for the whole check.
CHECK_LEVEL = ("margin", "design-outside", "ranges-disjoint", "no-safe-direction")


def with_friction_way_out(
    result: CheckResult,
    scene: Scene,
    passes: Callable[[Scene], bool],
    screen: Callable[[Sequence[Scene]], Sequence[bool]] | None = None,
) -> CheckResult:
    """A failing result whose findings about the safe set name no number to change, with the
    friction at which the whole check passes added to their hints ("the check passes for
    μ ≤ 0.0812", :func:`kcheck.analysis.way_out.passing_friction`, judged by ``passes``)."""
    wanting = [
        i
        for i, f in enumerate(result.findings)
        if f.code in CHECK_LEVEL and not numeric_way_out().search(f.hint or "")
    ]
    if result.status != Status.FAIL or not wanting:
        return result
    from kcheck.analysis.way_out import passing_friction

    mu = passing_friction(scene, passes, screen)
    if mu is None:
        return result
    uniform = len({s.friction for s in scene.supports if s.friction > 0}) <= 1
    tail = "" if uniform else " (the largest coefficient, the others in proportion)"
    text = f"the check passes for μ ≤ {format_number(mu, 7)}{tail}"
    findings = list(result.findings)
    for i in wanting:
        hint = findings[i].hint
        findings[i] = dataclasses.replace(
            findings[i], hint=text if not hint else f"{hint}; or {text}"
        )
    return dataclasses.replace(result, findings=tuple(findings))


#: Findings a stronger (or weaker) closing force can answer: a case that does not close, and
#: the whole safe set.
FORCE_ANSWERS = ("jams", "loses-contact", "opens", "opens-loses-contact", *CHECK_LEVEL)


def closing_force_text(name: str, kind: str, value: float, sense: str, proportional: bool) -> str:
    """ "the check passes with preload `spring` at least 0.983 N" (or the load magnitude)."""
    what = "a load magnitude" if kind == "load" else f"preload `{name}`"
    tail = " (the other preloads in proportion)" if proportional else ""
    return f"the check passes with {what} {sense} {format_number(value, 7)} N{tail}"


def with_closing_force_way_out(
    result: CheckResult,
    scene: Scene,
    passes: Callable[[Scene], bool],
    screen: Callable[[Sequence[Scene]], Sequence[bool]] | None = None,
) -> CheckResult:
    """A failing result whose findings a closing force can answer (a support loses contact,
    friction holds it, the safe set), with the least preload (or load magnitude) at which the
    whole check passes added to their hints (:func:`kcheck.analysis.way_out.passing_closing_force`,
    judged by ``passes``): "the check passes with preload `spring` at least 0.983 N"."""
    wanting = [i for i, f in enumerate(result.findings) if f.code in FORCE_ANSWERS]
    if result.status != Status.FAIL or not wanting:
        return result
    from kcheck.analysis.way_out import passing_closing_force

    found = passing_closing_force(scene, passes, screen)
    if found is None:
        return result
    force, value, sense = found
    text = closing_force_text(force.name, force.kind, value, sense, force.proportional)
    findings = list(result.findings)
    for i in wanting:
        hint = findings[i].hint
        findings[i] = dataclasses.replace(
            findings[i], hint=text if not hint else f"{hint}; or {text}"
        )
    details = {
        **result.details,
        "passing_closing_force": {
            "kind": force.kind,
            "name": force.name,
            "value": value,
            "sense": sense,
        },
    }
    return dataclasses.replace(result, findings=tuple(findings), details=details)
