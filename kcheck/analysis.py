"""From a scene to the dynamics of every retracted case: the shared engine of the analytical
checks (planar and spatial use the same code, only ``dim`` differs)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kcheck.arcs import ArcSet, intersect, margin, to_degrees
from kcheck.dynamics import (
    Case,
    Problem,
    analyse_case,
    build_problem,
    limiting_friction,
    outcome,
    safe_arcs,
)
from kcheck.fmt import format_ranges
from kcheck.kinematics import Frame
from kcheck.mass import MassProperties
from kcheck.result import CaseResult
from kcheck.scene import Scene

__all__ = [
    "support_layout",
    "closing_force_reason",
    "problem_for",
    "motion_details",
    "Analysis",
    "analyse",
    "describe_ranges",
    "ranges_deg",
]


def support_layout(scene: Scene) -> tuple[Frame, np.ndarray, np.ndarray]:
    """Nondimensional frame, support points (k, dim) and unit normals (k, dim) of a scene."""
    positions = np.array([s.position for s in scene.supports])
    frame = Frame.for_points(positions, scene.dim, 1.0)
    normals = np.array([s.normal for s in scene.supports])[:, : scene.dim]
    return frame, frame.point(positions), normals / np.linalg.norm(normals, axis=1, keepdims=True)


def closing_force_reason(scene: Scene) -> str | None:
    """Why the scene has nothing to analyse dynamically, or None."""
    if scene.body is None:
        return "needs the body's mass properties; the scene has no `body`"
    has_load = scene.load is not None and scene.load.magnitude > 0
    if not has_load and not np.any(scene.gravity[: scene.dim]):
        return "the scene has no closing force (no load magnitude and no gravity in the plane)"
    return None


def problem_for(scene: Scene, mass: MassProperties) -> Problem:
    """The nondimensional dynamics of a scene."""
    load = scene.load
    return build_problem(
        points=np.array([s.position for s in scene.supports]),
        normals=np.array([s.normal for s in scene.supports]),
        friction=np.array([s.friction for s in scene.supports]),
        names=tuple(s.name for s in scene.supports),
        dim=scene.dim,
        mass=mass.mass,
        com=mass.center_of_mass,
        inertia=mass.inertia,
        gravity=scene.gravity,
        load_magnitude=0.0 if load is None else load.magnitude,
        load_point=None if load is None else load.point,
        torque=np.zeros(3) if load is None else load.torque,
    )


def motion_details(problem: Problem, case: Case) -> dict[str, object]:
    """The free motion in physical terms: the pole (2D) or screw axis and pitch (3D)."""
    frame, twist = problem.frame, case.free.twist
    nw = 1 if problem.dim == 2 else 3
    w, v = twist[:nw], twist[nw:]
    wn = float(np.linalg.norm(w))
    # A rotation whose pole lies beyond 1e12 layout sizes is reported as a translation.
    if wn <= 1e-12 * float(np.linalg.norm(v)):
        direction = v / np.linalg.norm(v)
        return {"motion": "translation", "direction": _pad(direction, problem.dim).tolist()}
    if problem.dim == 2:
        pole = np.array([-v[1], v[0]]) / w[0]
        return {
            "motion": "rotation",
            "pole": (frame.origin[:2] + frame.length * pole).tolist(),
            "sense": "ccw" if w[0] > 0 else "cw",
        }
    axis = w / wn
    pitch = float(w @ v) / wn**2 * frame.length
    point = np.cross(w, v) / wn**2 * frame.length + frame.origin
    return {
        "motion": "screw",
        "axis": axis.tolist(),
        "axis_point": point.tolist(),
        "pitch_m": pitch,
    }


def _pad(vector: np.ndarray, dim: int) -> np.ndarray:
    return vector if dim == 3 else np.append(vector, 0.0)


@dataclass(frozen=True)
class Analysis:
    """Everything the analytical checks report, before a verdict."""

    problem: Problem
    cases: tuple[Case, ...]
    results: tuple[CaseResult, ...]
    arcs: tuple[ArcSet, ...] | None  # per case, None without a load to sweep
    combined: ArcSet | None
    design: np.ndarray | None  # unit direction (dim,) or None
    design_margin_deg: float | None
    error_deg: float
    max_condition: float

    @property
    def every_case_closes(self) -> bool:
        """Whether every case closes at the design direction (or gravity alone)."""
        return all(r.outcome == "closes" for r in self.results)


def analyse(scene: Scene, mass: MassProperties) -> Analysis:
    """Free motion, outcome, forces, limiting friction and exact safe arcs for every case."""
    problem = problem_for(scene, mass)
    dim = problem.dim
    e1, e2 = scene.sweep.e1[:dim], scene.sweep.e2[:dim]
    load = scene.load
    sweeping = load is not None and load.magnitude > 0
    design = None
    if sweeping and load is not None and load.direction is not None:
        design = load.direction[:dim]
    evaluate = design is not None or not sweeping
    force, accel_scale = problem.frame.force, problem.acceleration_scale()
    cases, results, arcs = [], [], []
    error = 0.0
    max_condition = 0.0
    names = problem.names
    for r in range(len(names)):
        case = analyse_case(problem, r)
        cases.append(case)
        details: dict[str, object] = {"determinacy": case.free.determinacy}
        if not case.determined:
            details["diagnostic"] = (
                "the free motion is not unique (the remaining normals are degenerate)"
                if case.free.determinacy <= 1e-10
                else "the layout is singular (e.g. normals through one point): the motion "
                "freed by removing this support does not move it towards the support"
            )
            results.append(CaseResult(names[r], "undetermined", details=details))
            arcs.append(())
            continue
        details.update(motion_details(problem, case))
        assert case.forward is not None and case.backward is not None
        condition = max(case.forward.condition, case.backward.condition)
        max_condition = max(max_condition, condition)
        details["condition"] = condition
        stuck = [names[j] for j, s in zip(case.keep, case.sliding, strict=True) if not s]
        if stuck:
            details["friction_undetermined"] = stuck
            details["diagnostic"] = (
                f"contact(s) {', '.join(stuck)} do not slide (the pole is on them): friction "
                "direction undetermined, taken as zero"
            )
        if not case.well_conditioned:
            details["diagnostic"] = (
                f"equations of motion nearly singular (condition {condition:.1e}); "
                "no numbers reported"
            )
            results.append(CaseResult(names[r], "ill_conditioned", details=details))
            arcs.append(())
            continue
        case_arcs = None
        if sweeping:
            case_arcs, arc_error = safe_arcs(case.forward, e1, e2)
            error = max(error, float(np.degrees(arc_error)))
            arcs.append(case_arcs)
        verdict, forces, accel, mu_lim = "swept", None, None, None
        if evaluate:
            verdict, x = outcome(case, design)
            if x is not None:
                forces = {names[j]: float(x[1 + i] * force) for i, j in enumerate(case.keep)}
                accel = float(x[0] * accel_scale * case.free.closing)
            mu_lim = limiting_friction(problem, case, design)
        results.append(
            CaseResult(
                names[r],
                verdict,
                normal_forces=forces,
                acceleration=accel,
                limiting_friction=mu_lim,
                safe_ranges_deg=None if case_arcs is None else ranges_deg(case_arcs),
                details=details,
            )
        )
    combined = intersect(*arcs) if sweeping else None
    design_margin = None
    if combined is not None and design is not None:
        angle = float(np.arctan2(design @ e2, design @ e1))
        design_margin = float(np.degrees(margin(combined, angle)))
    return Analysis(
        problem=problem,
        cases=tuple(cases),
        results=tuple(results),
        arcs=tuple(arcs) if sweeping else None,
        combined=combined,
        design=design,
        design_margin_deg=design_margin,
        error_deg=error,
        max_condition=max_condition,
    )


def ranges_deg(arcs: ArcSet) -> tuple[tuple[float, float], ...]:
    """Arc set in degrees as a tuple of ``(start, end)``."""
    return tuple((s, e) for s, e in to_degrees(arcs))


def describe_ranges(arcs: ArcSet) -> str:
    """Human text for an arc set, in the one angle convention (:func:`kcheck.fmt.format_ranges`):
    ``292.41°–5.05° (through 0°)``, ``every direction``, ``no direction``."""
    if not arcs:
        return "no direction"
    return format_ranges(ranges_deg(arcs))
