"""Graphical 2D: Koster's construction (methods.md §5) in twist form, mass-free.

For every retracted support ``r`` the free twist ``xi_r`` of the two remaining supports (from
:func:`kcheck.mechanics.kinematics.free_twist`, oriented to close the gap) is a rotation about the
pole
``(-v_y, v_x) / w`` (homogeneous ``(-v_y, v_x, w)``; ``w = 0`` is the pole at infinity, a
translation). No line intersections are computed, so parallel and nearly parallel normals need
no special case.

For a force of direction ``d`` (per unit force; ``arm = M_z / F`` in metres adds a torque) at
the attachment point ``q``, together with the fixed forces — the weight at the centre of mass
and the scene's preloads, a resultant whose line of action moves with ``d`` — the virtual
power along a twist is ``a + c . d`` with ``c = u(q)`` and
``a = w arm + sum_k (f_k / F) . u(p_k)``:

* funnel (frictionless): ``xi_r . W(d) > 0`` — the moment of the resultant about the pole has
  the needed sense; a half circle of directions (less or more with a torque or fixed forces);
* friction: with forward-sliding friction the remaining reaction lines tilt to
  ``n_j + mu_j t_j``; their free twist ``xi'_r`` is the rotation about the friction pole
  ``P'`` where they meet, followed continuously from ``xi_r`` as friction grows from zero
  (the cross product of the two tilted constraint rows, signed as at ``mu = 0``);
  ``xi'_r . W(d) > 0`` is the right moment sense about ``P'``. Directions the funnel allows
  but this forbids are the jamming area: both contact forces inside their friction cones
  balance the resultant.

Safe per case = funnel ∩ friction; the check's safe set is the intersection over cases, exact
in closed form (:mod:`kcheck.mechanics.arcs`). The construction cannot see contact loss (methods.md
§3, requirement 3), so its ranges contain those of ``analytical-2d``; where ``analytical-2d``'s
forward ``lambda`` changes sign is exactly a friction boundary here (inertia plays no part at
``lambda = 0``).

Mass: the check declares ``needs_mass = False`` so it runs on scenes without a body. It needs
the attachment point — ``load.point`` when the scene gives one, else the centre of mass — and,
with gravity in the plane, the weight and the centre of mass; only then does
``needs_mass_for`` ask the runner for the mass properties (computed once per scene, shared with
the other checks; explicit mass properties need no mesh). Without a load point and without a
body it is skipped with that reason; a scene with gravity but no body is constructed without
the weight, and says so. With no load but gravity in the plane, the weight at the centre of
mass is the force swept. The construction has no inertia (it is "mass-free"): it cannot see
contact loss, and the message says so.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from kcheck.analysis.cases import describe_ranges, nearest_end, ranges_deg, support_layout
from kcheck.analysis.friction_ranges import coefficients_used
from kcheck.fmt import format_angle
from kcheck.mechanics.arcs import (
    ArcSet,
    complement,
    contains,
    intersect,
    margin,
    union,
)
from kcheck.mechanics.kinematics import (
    RANK_RTOL,
    Frame,
    layout_singular_values,
)
from kcheck.mechanics.koster import (
    GraphicalCase,
    condition_arc,
    construct_case,
    friction_over_range,
    homogeneous_pole,
    tilted_twist,
    virtual_power,
)
from kcheck.numerics.thresholds import INFINITE_POLE
from kcheck.plugin import Check, Inputs
from kcheck.records import dataclass
from kcheck.result import CaseResult, CheckResult, Finding, Status
from kcheck.scene import Scene
from kcheck_checks.graphical_attachment import (
    Attachment,
    attachment,
    attachment_of,
    missing_force,
    needs_centre_of_mass,
)
from kcheck_checks.marginal import with_angle_margin
from kcheck_checks.options import AnalyticalOptions
from kcheck_checks.wording import (
    design_findings,
    empty_range_findings,
    load_field,
    ranges_text,
    support_field,
    verdict,
)

__all__ = [
    "Graphical2D",
    "GraphicalOptions",
    "GraphicalCase",
    "Construction",
    "Attachment",
    "missing_force",
    "attachment",
    "construct",
    "homogeneous_pole",
    "virtual_power",
    "tilted_twist",
    "condition_arc",
    "complement",
    "union",
    "construct_case",
]

# Said with every verdict: the construction has no inertia.
MASS_FREE = "mass-free: contact loss not checked"


class GraphicalOptions(AnalyticalOptions):
    """Options of the ``graphical-2d`` check: the analytical checks' margin and marginal band."""


def _pole_details(frame: Frame, twist: np.ndarray, prefix: str = "") -> dict[str, Any]:
    """Pole in metres, or the translation direction when it lies at infinity."""
    w, v = float(twist[0]), twist[1:]
    if abs(w) <= INFINITE_POLE * float(np.linalg.norm(v)):
        direction = v / np.linalg.norm(v)
        return {
            f"{prefix}pole": None,
            f"{prefix}pole_at_infinity": True,
            f"{prefix}translation_direction": direction.tolist(),
            f"{prefix}sense": "translation",
        }
    h = homogeneous_pole(twist)
    return {
        f"{prefix}pole": (frame.origin[:2] + frame.length * h[:2] / h[2]).tolist(),
        f"{prefix}pole_at_infinity": False,
        f"{prefix}sense": "ccw" if w > 0 else "cw",
    }


def _outcome(case: GraphicalCase, angle: float | None) -> str:
    if angle is None:
        return "swept"
    if not contains(case.funnel, angle):
        return "wrong_sense"
    return "closes" if contains(case.friction, angle) else "jams"


def _case_result(
    scene: Scene, frame: Frame, case: GraphicalCase, angle: float | None
) -> CaseResult:
    names = [s.name for s in scene.supports]
    details: dict[str, Any] = {"determinacy": case.free.determinacy}
    details.update(_pole_details(frame, case.free.twist))
    details["funnel_deg"] = ranges_deg(case.funnel)
    details["forbidden_deg"] = ranges_deg(complement(case.funnel))
    diagnostics = []
    if case.tilted is None:
        diagnostics.append("friction twist orthogonal to the free motion: friction undetermined")
    else:
        details.update(_pole_details(frame, case.tilted, "friction_"))
        details["friction_deg"] = ranges_deg(case.friction)
        details["jamming_deg"] = ranges_deg(case.jamming)
    stuck = [names[j] for j, s in zip(case.keep, case.sliding, strict=True) if not s]
    if stuck:
        details["friction_undetermined"] = stuck
        diagnostics.append(
            f"contact(s) {', '.join(stuck)} do not slide (the pole is on them): friction "
            "direction undetermined, taken as zero"
        )
    if diagnostics:
        details["diagnostic"] = "; ".join(diagnostics)
    return CaseResult(
        names[case.retracted],
        _outcome(case, angle),
        safe_ranges_deg=ranges_deg(case.safe),
        details=details,
    )


def _pole_triangle(frame: Frame, cases: Sequence[GraphicalCase]) -> list[list[float] | None]:
    """Poles of the three cases in metres (None at infinity)."""
    out: list[list[float] | None] = []
    for case in cases:
        pole = _pole_details(frame, case.free.twist)["pole"]
        out.append(pole)
    return out


@dataclass(frozen=True)
class Construction:
    """Everything the check computed, for the result and the picture."""

    frame: Frame
    points: np.ndarray
    normals: np.ndarray
    attachment: Attachment
    cases: tuple[GraphicalCase, ...]
    combined: ArcSet
    e1: np.ndarray
    e2: np.ndarray
    sigma: float  # smallest over largest singular value of the scaled layout


def construct(scene: Scene, where: Attachment) -> Construction | None:
    """The construction of every case, or None when the layout is not determined."""
    frame, points, normals = support_layout(scene)
    singular = layout_singular_values(points, normals)
    if not singular[-1] > RANK_RTOL * singular[0]:
        return None
    # Koster's construction is about the start of motion: the static coefficients, and over a
    # range the arcs that hold for every one of them.
    low, mu = scene.friction_range("static")
    q = frame.point(where.point)
    arm = where.arm / frame.length
    fixed = tuple((frame.point(p), f[:2]) for p, f in where.fixed)
    e1, e2 = scene.sweep.e1[:2], scene.sweep.e2[:2]
    cases = tuple(
        construct_case(points, normals, mu, r, q, arm, e1, e2, fixed) for r in range(len(points))
    )
    if not np.array_equal(low, mu):
        cases = tuple(
            friction_over_range(c, points, normals, low, mu, q, arm, e1, e2, fixed) for c in cases
        )
    combined = intersect(*(c.safe for c in cases))
    sigma = float(singular[-1] / singular[0])
    return Construction(frame, points, normals, where, cases, combined, e1, e2, sigma)


class Graphical2D(Check):
    """Koster's graphical construction for a planar coupling: poles, funnel, jamming areas."""

    id = "graphical-2d"
    pictures = "kcheck_checks.pictures.graphical_2d:draw"
    summary = (
        "Koster's construction (mass-free): poles and senses, frictionless funnel, friction "
        "jamming areas, safe force-angle ranges"
    )
    applies_to = "planar scenes (3 supports) with a load point, or a body for the centre of mass"
    needs_mass = False
    options = GraphicalOptions

    def skip_reason(self, scene: Scene) -> str | None:
        """Planar scenes with a force whose attachment point is known."""
        if scene.kind != "planar":
            return "applies to planar (3-support) scenes; this one is spatial"
        return missing_force(scene)

    def needs_mass_for(self, scene: Scene) -> bool:
        """Only for the centre of mass, when the force acts there."""
        return needs_centre_of_mass(scene)

    def run(self, inputs: Inputs) -> CheckResult:
        """Construct every case and intersect the safe ranges."""
        scene, opts = inputs.scene, inputs.options
        assert isinstance(opts, GraphicalOptions)
        where = attachment_of(inputs)
        if isinstance(where, str):
            return CheckResult(self.id, Status.SKIPPED, where)
        built = construct(scene, where)
        details: dict[str, Any] = {
            "attachment_point": where.point[:2].tolist(),
            "force": where.source,
            "limitations": [MASS_FREE],
        }
        if where.arm:
            details["torque_arm_m"] = where.arm
        if where.notes:
            details["notes"] = list(where.notes)
        used = coefficients_used(scene, "static")
        if used is not None:
            details["friction_range"] = used
        if built is None:
            return CheckResult(
                self.id,
                Status.FAIL,
                "not determined: the three normals meet in one point (or are all parallel), "
                "so a motion stays free with every support in place; no ranges",
                findings=(
                    Finding(
                        "the three normals meet in one point (or are all parallel): a motion "
                        "stays free with every support in place",
                        code="not-determined",
                        field=("supports",),
                        hint="turn one normal so that its line misses the others' meeting point",
                    ),
                ),
                cases=tuple(
                    CaseResult(s.name, "undetermined", details={"diagnostic": "not determined"})
                    for s in scene.supports
                ),
                details=details,
            )
        result = _verdict(self.id, scene, built, opts.min_margin_deg, details)
        field = load_field(scene) if scene.load is not None else None
        return with_angle_margin(result, opts.marginal_deg, field, gravity=scene.load is None)


def _verdict(
    check_id: str, scene: Scene, built: Construction, min_margin_deg: float, details: dict
) -> CheckResult:
    angle_deg = None
    where = built.attachment
    if where.design is not None:
        d = where.design[:2]
        angle_deg = float(np.degrees(np.arctan2(d @ built.e2, d @ built.e1)) % 360.0)
    angle = None if angle_deg is None else float(np.radians(angle_deg))
    results = tuple(_case_result(scene, built.frame, c, angle) for c in built.cases)
    combined = built.combined
    senses = [str(r.details["sense"]) for r in results]
    details["senses"] = senses
    details["smallest_scaled_singular_value"] = built.sigma
    what = "force" if where.source == "load" else "weight"
    findings: list[Finding] = []
    if combined:
        parts = [f"safe {what} angles: {describe_ranges(combined)}"]
    else:
        parts = [f"no safe {what} angle"]
        if senses[0] in ("ccw", "cw") and len(set(senses)) == 1:
            details["pole_triangle"] = _pole_triangle(built.frame, built.cases)
            details["requires"] = "torque_or_arm_outside_pole_triangle"
            findings.append(
                Finding(
                    f"every pole needs the same sense ({senses[0]}): a pure rotation is needed — "
                    "a torque, or a force on an arm reaching outside the pole triangle",
                    code="same-sense",
                    field=("load",),
                    hint="add a torque, or attach the force outside the pole triangle",
                )
            )
        else:
            findings.extend(empty_range_findings(scene, results, ""))
    if angle_deg is not None:
        details["design_angle_deg"] = angle_deg
        for c in results:
            if c.outcome in ("wrong_sense", "jams"):
                why = (
                    "the resultant turns it the wrong way about the pole"
                    if c.outcome == "wrong_sense"
                    else "friction holds the body (the resultant passes through the jamming area)"
                )
                findings.append(
                    Finding(
                        f"retract {c.retracted} → {why}",
                        code=c.outcome.replace("_", "-"),
                        field=support_field(scene, c.retracted),
                        hint=f"closes for force angles {ranges_text(c.safe_ranges_deg)}"
                        if what == "force"
                        # nobody turns gravity: what is left to change is the seat
                        else "lower the friction"
                        if c.outcome == "jams"
                        else f"move or turn support {c.retracted}",
                    )
                )
        if combined:
            design_margin = float(np.degrees(margin(combined, angle)))  # type: ignore[arg-type]
            details["design_margin_deg"] = design_margin
            nearest = None
            if design_margin < 0:
                nearest = float(np.degrees(nearest_end(combined, angle)))  # type: ignore[arg-type]
                details["nearest_safe_deg"] = nearest
            found = design_findings(
                scene,
                angle_deg,
                design_margin,
                nearest,
                describe_ranges(combined),
                min_margin_deg,
                what=f"design {what} direction",
                safe=ranges_deg(combined),
            )
            # The cases that do not close already say why the design direction is outside.
            findings.extend(f for f in found if f.code != "design-outside" or not findings)
            if not found and not findings:
                parts.append(
                    f"design {format_angle(angle_deg)} is {format_angle(design_margin)} inside"
                )
    parts.append(MASS_FREE)
    errors = [c.error_rad for c in built.cases if c.error_rad is not None]
    error_deg = float(np.degrees(max(errors))) if errors else None
    return CheckResult(
        check_id,
        Status.PASS if not findings else Status.FAIL,
        verdict(parts, findings),
        error_estimate=error_deg,
        safe_ranges_deg=ranges_deg(combined),
        cases=results,
        details=details,
        findings=tuple(findings),
    )
