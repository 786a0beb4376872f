"""Graphical 2D: Koster's construction (methods.md §5) in twist form, mass-free.

For every retracted support ``r`` the free twist ``xi_r`` of the two remaining supports (from
:func:`kcheck.kinematics.free_twist`, oriented to close the gap) is a rotation about the pole
``(-v_y, v_x) / w`` (homogeneous ``(-v_y, v_x, w)``; ``w = 0`` is the pole at infinity, a
translation). No line intersections are computed, so parallel and nearly parallel normals need
no special case.

For a force of direction ``d`` (per unit force; ``arm = M_z / F`` in metres adds a torque) at
the attachment point ``q``:

* funnel (frictionless): ``xi_r . W(d) = w arm + d . u_r(q) > 0`` — the moment about the pole
  has the needed sense; a half circle of directions (less or more with a torque);
* friction: with forward-sliding friction the remaining reaction lines tilt to
  ``n_j + mu_j t_j``; their free twist ``xi'_r`` is the rotation about the friction pole
  ``P'`` where they meet, oriented so ``xi'_r . xi_r > 0`` (nondimensional metric);
  ``xi'_r . W(d) > 0`` is the right moment sense about ``P'``. Directions the funnel allows
  but this forbids are the jamming area: both contact forces inside their friction cones
  balance the load.

Safe per case = funnel ∩ friction; the check's safe set is the intersection over cases, exact
in closed form (:mod:`kcheck.arcs`). The construction cannot see contact loss (methods.md
§3, requirement 3), so its ranges contain those of ``analytical-2d``; where ``analytical-2d``'s
forward ``lambda`` changes sign is exactly a friction boundary here (inertia plays no part at
``lambda = 0``).

Mass: the check declares ``needs_mass = False`` so it runs on scenes without a body. It needs
only the attachment point: ``load.point`` when the scene gives one; otherwise the load acts at
the centre of mass, and ``needs_mass_for`` asks the runner for the mass properties (computed
once per scene, shared with the other checks; explicit mass properties need no mesh). Without
a load point and without a body it is skipped with that reason. With a
load the construction ignores gravity (it is mass-free; ``analytical-2d`` includes it); with no
load but gravity in the plane, the weight at the centre of mass is the force swept.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import Field

from kcheck.analysis import describe_ranges, ranges_deg, support_layout
from kcheck.arcs import (
    ArcSet,
    affine_arcs,
    complement,
    contains,
    intersect,
    margin,
    union,
)
from kcheck.dynamics import friction_directions
from kcheck.kinematics import (
    RANK_RTOL,
    Frame,
    FreeTwist,
    free_twist,
    layout_singular_values,
    point_velocity,
    wrenches,
)
from kcheck.plugin import Check, Inputs, Options
from kcheck.result import CaseResult, CheckResult, Status
from kcheck.scene import Scene

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

EPS = float(np.finfo(float).eps)
# What the construction cannot see (reports show it next to the verdict).
LIMITATION = "mass-free: contact loss not checked"
# A rotation whose pole lies beyond 1e12 layout sizes is reported as a translation
# (the same threshold as kcheck.analysis.motion_details).
INFINITE_POLE = 1e-12


class GraphicalOptions(Options):
    """Options of the ``graphical-2d`` check."""

    min_margin_deg: float = Field(
        0.0, ge=0, description="Least angular distance of the design direction from a boundary"
    )


@dataclass(frozen=True)
class Attachment:
    """Where and how the swept force acts: point (m, 3), ``arm = M_z / F`` (m), design
    direction (unit 3-vector or None), and notes for the result."""

    point: np.ndarray
    arm: float
    design: np.ndarray | None
    source: str
    notes: tuple[str, ...]


@dataclass(frozen=True)
class GraphicalCase:
    """The construction for one retracted support (nondimensional twists, arcs in radians)."""

    retracted: int
    keep: np.ndarray
    free: FreeTwist
    tilted: np.ndarray | None  # friction twist xi'_r, None when it cannot be oriented
    sliding: np.ndarray  # (2,) bool per remaining support
    funnel: ArcSet
    friction: ArcSet
    jamming: ArcSet
    safe: ArcSet
    error_rad: float


# --- pure construction -------------------------------------------------------------------


def homogeneous_pole(twist: np.ndarray) -> np.ndarray:
    """Homogeneous pole ``(-v_y, v_x, w)`` of a planar twist ``(w, v_x, v_y)``."""
    return np.array([-twist[2], twist[1], twist[0]])


def virtual_power(twist: np.ndarray, point: np.ndarray, arm: float) -> tuple[float, np.ndarray]:
    """``xi . W(d) = a + c . d`` for a unit force ``d`` at ``point`` with torque ``arm * |F|``.

    Nondimensional: ``point`` and ``arm`` in layout lengths. ``c = u(point)``, ``a = w arm``.
    """
    return float(twist[0] * arm), point_velocity(twist, point)


def tilted_twist(
    points: np.ndarray, normals: np.ndarray, mu: np.ndarray, free: FreeTwist, keep: np.ndarray
) -> tuple[np.ndarray | None, np.ndarray, float]:
    """Free twist of the friction-tilted reaction lines ``n_j + mu_j t_j`` of the kept supports.

    ``t_j`` opposes forward sliding under ``free``; a contact that does not slide keeps its
    normal (friction undetermined, zero as in the thesis). Returns the twist oriented to
    ``xi' . xi > 0`` (None if it is orthogonal to ``xi``), the sliding mask and the
    determinacy (smallest over largest singular value) of the tilted rows.
    """
    t, sliding = friction_directions(free.twist, points[keep], +1)
    forces = normals[keep] + mu[keep, None] * t
    _, s, vt = np.linalg.svd(wrenches(points[keep], forces))
    tilted = vt[-1]
    determinacy = float(s[-1] / s[0]) if s[0] > 0 else 0.0
    dot = float(tilted @ free.twist)
    if abs(dot) <= 1e-9:
        return None, sliding, determinacy
    return (tilted if dot > 0 else -tilted), sliding, determinacy


def condition_arc(
    a: float, c: np.ndarray, e1: np.ndarray, e2: np.ndarray, coef_error: float
) -> tuple[ArcSet, float]:
    """Angles from ``e1`` towards ``e2`` where ``a + c . d > 0``, and the ends' error (rad)."""
    return affine_arcs(np.array([a]), c[None, :], e1, e2, np.array([coef_error]))


def construct_case(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    retracted: int,
    q: np.ndarray,
    arm: float,
    e1: np.ndarray,
    e2: np.ndarray,
) -> GraphicalCase:
    """Koster's construction for one retracted support (all inputs nondimensional)."""
    keep = np.flatnonzero(np.arange(len(points)) != retracted)
    free = free_twist(points, normals, retracted)
    scale = 1.0 + float(np.linalg.norm(q)) + abs(arm)
    # A null vector is perturbed by about eps over its singular-value gap.
    a, c = virtual_power(free.twist, q, arm)
    funnel, err_f = condition_arc(a, c, e1, e2, 8 * EPS / max(free.determinacy, EPS) * scale)
    tilted, sliding, det_t = tilted_twist(points, normals, mu, free, keep)
    if tilted is None:
        friction: ArcSet = ()
        err_t = 0.0
    else:
        at, ct = virtual_power(tilted, q, arm)
        friction, err_t = condition_arc(at, ct, e1, e2, 8 * EPS / max(det_t, EPS) * scale)
    return GraphicalCase(
        retracted=retracted,
        keep=keep,
        free=free,
        tilted=tilted,
        sliding=sliding,
        funnel=funnel,
        friction=friction,
        jamming=intersect(funnel, complement(friction)),
        safe=intersect(funnel, friction),
        error_rad=max(err_f, err_t),
    )


# --- scene level ---------------------------------------------------------------------------


def missing_force(scene: Scene) -> str | None:
    """Why a planar scene gives the construction no force to sweep, or None (no mesh read)."""
    load = scene.load
    has_load = load is not None and load.magnitude > 0
    if not has_load and not np.any(scene.gravity[:2]):
        return "needs a closing force: a load with a magnitude, or gravity in the plane"
    if not has_load and load is not None and load.torque[2] != 0:
        return "a torque without a load magnitude needs the weight; give `load.magnitude`"
    if (not has_load or load is None or load.point is None) and scene.body is None:
        return (
            "the force acts at the centre of mass, but the scene has no `body` to find it; "
            "give `load.point` or a body"
        )
    return None


def needs_centre_of_mass(scene: Scene) -> bool:
    """Whether the swept force acts at the centre of mass (no load point, or the weight)."""
    load = scene.load
    return load is None or load.magnitude <= 0 or load.point is None


def attachment(
    scene: Scene, point: np.ndarray | None = None, com: np.ndarray | None = None
) -> Attachment | str:
    """The swept force's attachment, or the reason the construction has none.

    ``point`` (m) overrides the attachment point, e.g. one already found in a result; ``com``
    (m) is the centre of mass, used when the force acts there.
    """
    reason = missing_force(scene)
    if reason is not None:
        return reason
    load = scene.load
    gravity = scene.gravity[:2]
    notes: list[str] = []
    if load is not None and load.magnitude > 0:
        point = load.point if point is None else point
        if np.any(gravity):
            notes.append(
                "gravity ignored: the construction is mass-free (analytical-2d includes it)"
            )
        arm = float(load.torque[2]) / load.magnitude
        design, source = load.direction, "load"
    else:
        arm, source = 0.0, "weight"
        design = np.append(gravity / np.linalg.norm(gravity), 0.0)
    if point is None:
        if com is None:
            return "the force acts at the centre of mass, which is not known"
        point = com
        notes.append("force at the centre of mass")
    point = np.asarray(point, float)
    if point.shape == (2,):
        point = np.append(point, scene.supports[0].position[2])
    return Attachment(point, arm, design, source, tuple(notes))


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
    mu = np.array([s.friction for s in scene.supports])
    q = frame.point(where.point)
    arm = where.arm / frame.length
    e1, e2 = scene.sweep.e1[:2], scene.sweep.e2[:2]
    cases = tuple(
        construct_case(points, normals, mu, r, q, arm, e1, e2) for r in range(len(points))
    )
    combined = intersect(*(c.safe for c in cases))
    sigma = float(singular[-1] / singular[0])
    return Construction(frame, points, normals, where, cases, combined, e1, e2, sigma)


class Graphical2D(Check):
    """Koster's graphical construction for a planar coupling: poles, funnel, jamming areas."""

    id = "graphical-2d"
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
        where = attachment(scene, com=None if inputs.mass is None else inputs.mass.center_of_mass)
        if isinstance(where, str):
            return CheckResult(self.id, Status.SKIPPED, where)
        built = construct(scene, where)
        details: dict[str, Any] = {
            "attachment_point": where.point[:2].tolist(),
            "force": where.source,
            "limitations": [LIMITATION],
        }
        if where.arm:
            details["torque_arm_m"] = where.arm
        if where.notes:
            details["notes"] = list(where.notes)
        if built is None:
            return CheckResult(
                self.id,
                Status.FAIL,
                "not determined: the three normals meet in one point (or are all parallel), "
                "so a motion stays free with every support in place; no ranges",
                cases=tuple(
                    CaseResult(s.name, "undetermined", details={"diagnostic": "not determined"})
                    for s in scene.supports
                ),
                details=details,
            )
        return _verdict(self.id, scene, built, opts.min_margin_deg, details)

    def plot(self, inputs: Inputs, result: CheckResult, directory: Path) -> Sequence[Path]:
        """The construction like the thesis's Figure 2.8 (needs the `plot` extra)."""
        from kcheck_checks.plots_graphical_2d import plot_graphical

        return plot_graphical(inputs, result, directory)


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
    parts = [f"safe force angles: {describe_ranges(combined)}"]
    ok = bool(combined)
    if not combined and senses[0] in ("ccw", "cw") and len(set(senses)) == 1:
        details["pole_triangle"] = _pole_triangle(built.frame, built.cases)
        details["requires"] = "torque_or_arm_outside_pole_triangle"
        parts.append(
            f"every pole needs the same sense ({senses[0]}): a pure rotation is needed — "
            "a torque, or a force on an arm reaching outside the pole triangle"
        )
    if angle_deg is not None:
        details["design_angle_deg"] = angle_deg
        design_margin = float(np.degrees(margin(combined, angle)))  # type: ignore[arg-type]
        details["design_margin_deg"] = design_margin
        if not combined:
            parts.append(f"design direction {angle_deg:.2f}° therefore unsafe")
            ok = False
        elif design_margin < 0:
            parts.append(f"design direction {angle_deg:.2f}° outside by {-design_margin:.2f}°")
            ok = False
        else:
            parts.append(f"design direction {angle_deg:.2f}° margin {design_margin:.2f}°")
            if design_margin < min_margin_deg:
                ok = False
                parts.append(f"(required {min_margin_deg:g}°)")
    error_deg = float(np.degrees(max(c.error_rad for c in built.cases)))
    return CheckResult(
        check_id,
        Status.PASS if ok else Status.FAIL,
        "; ".join(parts),
        error_estimate=error_deg,
        safe_ranges_deg=ranges_deg(combined),
        cases=results,
        details=details,
    )
