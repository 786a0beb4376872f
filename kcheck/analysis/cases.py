"""From a scene to the dynamics of every retracted case: the shared engine of the analytical
checks (planar and spatial use the same code, only ``dim`` differs)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from kcheck.fmt import clean, clean3, format_ranges
from kcheck.mechanics.arcs import FULL, ArcSet, contains, intersect, margin, to_degrees
from kcheck.mechanics.dynamics import Case, Problem, analyse_cases_many, build_problem, with_load
from kcheck.mechanics.friction import FrictionIntervals, friction_intervals_batch
from kcheck.mechanics.holding_certificates import holding_certified
from kcheck.mechanics.kinematics import Frame, norm3, row_norms, unit3, unit_rows
from kcheck.mechanics.lift_off import lift_off
from kcheck.mechanics.outcomes import Outcome, outcome, safe_arcs
from kcheck.mechanics.statics import Statics, contact_columns, holds_exactly, kept_columns
from kcheck.numerics.thresholds import (
    EPS,
    FORCE_SCREEN_ROUNDINGS,
    FORCE_SCREEN_RTOL,
    HOLDING_CERTIFICATE_BATCH,
    IN_SWEEP_PLANE,
    INFINITE_POLE,
    NO_PITCH,
    UNDETERMINED,
)
from kcheck.records import dataclass
from kcheck.result import CaseResult, MassProperties
from kcheck.scene import Scene

__all__ = [
    "support_layout",
    "closing_force_reason",
    "problem_for",
    "motion_details",
    "Analysis",
    "analyse_fixed",
    "analyse_fixed_many",
    "closing_analysis",
    "closing_cases",
    "closing_force_screen",
    "cases_close_many",
    "load_design",
    "swept_design",
    "sweep_ranges",
    "nearest_end",
    "describe_ranges",
    "ranges_deg",
    "intervals_json",
]


def support_layout(scene: Scene) -> tuple[Frame, np.ndarray, np.ndarray]:
    """Nondimensional frame, support points (k, dim) and unit normals (k, dim) of a scene."""
    positions = np.array([s.position for s in scene.supports])
    frame = Frame.for_points(positions, scene.dim, 1.0)
    normals = np.array([s.normal for s in scene.supports])[:, : scene.dim]
    return frame, frame.point(positions), unit_rows(normals)


def has_preloads(scene: Scene) -> bool:
    """Whether the scene's preloads push with any force in the plane of motion."""
    return any(np.any(p.force[: scene.dim] != 0) for p in scene.preloads)


def closing_force_reason(scene: Scene) -> str | None:
    """Why the scene has nothing to analyse dynamically, or None."""
    if scene.body is None:
        return "needs the body's mass properties; the scene has no `body`"
    has_load = scene.load is not None and scene.load.magnitude > 0
    if not has_load and not np.any(scene.gravity[: scene.dim]) and not has_preloads(scene):
        return (
            "the scene has no closing force (no load magnitude, no gravity and no preload in "
            "the plane)"
            if scene.dim == 2
            else "the scene has no closing force (no load magnitude, no gravity, no preload)"
        )
    return None


def problem_for(scene: Scene, mass: MassProperties, friction: np.ndarray | None = None) -> Problem:
    """The nondimensional dynamics of a scene, with the supports' kinetic coefficients (the
    upper ends of their ranges) or ``friction`` (k,) instead."""
    load = scene.load
    return build_problem(
        points=np.array([s.position for s in scene.supports]),
        normals=np.array([s.normal for s in scene.supports]),
        friction=scene.friction_range("kinetic")[1] if friction is None else friction,
        names=tuple(s.name for s in scene.supports),
        dim=scene.dim,
        mass=mass.mass,
        com=mass.center_of_mass,
        inertia=mass.inertia,
        gravity=scene.gravity,
        load_magnitude=0.0 if load is None else load.magnitude,
        load_point=None if load is None else load.point,
        torque=np.zeros(3) if load is None else load.torque,
        preloads=tuple((p.point, p.force) for p in scene.preloads),
    )


def motion_details(problem: Problem, case: Case) -> dict[str, object]:
    """The free motion in physical terms: the pole (2D), the screw axis and pitch, or the pure
    rotation axis (3D), or the translation direction; rounding noise cleaned away."""
    frame, twist = problem.frame, case.free.twist
    nw = 1 if problem.dim == 2 else 3
    w, v = twist[:nw], twist[nw:]
    wn = float(np.linalg.norm(w))
    if wn <= INFINITE_POLE * float(np.linalg.norm(v)):
        direction = unit_rows(clean(v))
        return {"motion": "translation", "direction": _pad(direction, problem.dim).tolist()}
    if problem.dim == 2:
        pole = np.array([-v[1], v[0]]) / w[0]
        return {
            "motion": "rotation",
            "pole": clean(
                frame.origin[:2] + frame.length * clean(pole, 1.0 + float(row_norms(pole)))
            ),
            "sense": "ccw" if w[0] > 0 else "cw",
        }
    # Plain float arithmetic on the three components (numpy's per-call overhead on 3-vectors
    # was most of this function's time): the operations of clean, unit_rows, row_norms and
    # cross3 in their order, so the same bits; the norms and the dot product stay numpy's.
    w0, w1, w2 = w.tolist()
    v0, v1, v2 = v.tolist()
    axis = unit3(clean3([w0 / wn, w1 / wn, w2 / wn]))
    pitch = float(w @ v) / wn**2
    moment = [w1 * v2 - w2 * v1, w2 * v0 - w0 * v2, w0 * v1 - w1 * v0]
    square = wn**2
    foot = clean3([m / square for m in moment], 1.0 + norm3(moment) / square)
    length = frame.length
    point = [o + length * f for o, f in zip(frame.origin.tolist(), foot, strict=True)]
    if abs(pitch) <= NO_PITCH:
        return {"motion": "rotation", "axis": axis, "axis_point": point}
    return {
        "motion": "screw",
        "axis": axis,
        "axis_point": point,
        "pitch_m": pitch * frame.length,
    }


def _pad(vector: np.ndarray, dim: int) -> np.ndarray:
    return vector if dim == 3 else np.append(vector, 0.0)


@dataclass(frozen=True)
class Analysis:
    """Everything the analytical checks report, before a verdict.

    ``arcs`` (per case) and ``combined`` are the exact safe ranges in the sweep plane ``plane``
    (``(e1, e2)``, nondimensional components); None without a load to sweep. ``design_margin_deg``
    is the design direction's signed distance to the combined ranges (negative outside: the
    distance to the nearest safe angle, ``nearest_safe_deg``); None when nothing is safe.
    ``friction`` holds each evaluated case's friction intervals. ``friction_range``: when the
    kinetic coefficients are ranges, what holds over them (:mod:`kcheck.analysis.friction_ranges`);
    the arcs are then those that close for every coefficient of the range.
    """

    problem: Problem
    cases: tuple[Case, ...]
    results: tuple[CaseResult, ...]
    arcs: tuple[ArcSet, ...] | None  # per case, None without a load to sweep
    combined: ArcSet | None
    design: np.ndarray | None  # unit direction (dim,) or None
    design_margin_deg: float | None
    error_deg: float | None
    max_condition: float
    plane: tuple[np.ndarray, np.ndarray] | None = None
    nearest_safe_deg: float | None = None
    friction: tuple[FrictionIntervals | None, ...] = ()
    friction_range: Any = None  # kcheck.analysis.friction_ranges.RangeInfo

    @property
    def every_case_closes(self) -> bool:
        """Whether every case closes at the design direction (or under the fixed wrench)."""
        return all(r.outcome == "closes" for r in self.results)

    @property
    def trustworthy(self) -> bool:
        """Whether every case has a determined, well-conditioned answer."""
        return all(r.outcome not in ("undetermined", "ill_conditioned") for r in self.results)


def intervals_json(intervals: tuple[tuple[float, float], ...]) -> list[list[float | None]]:
    """Friction intervals as JSON lists ``[lo, hi]``, ``hi`` None when unbounded."""
    return [[lo, hi if np.isfinite(hi) else None] for lo, hi in intervals]


def _case_details(problem: Problem, case: Case) -> dict[str, object]:
    """Determinacy, motion, conditioning and diagnostics of one case."""
    names = problem.names
    details: dict[str, object] = {"determinacy": case.free.determinacy}
    if not case.determined:
        details["diagnostic"] = (
            "the free motion is not unique (the remaining normals are degenerate)"
            if case.free.determinacy <= UNDETERMINED
            else "the layout is singular (e.g. normals through one point): the motion "
            "freed by removing this support does not move it towards the support"
        )
        return details
    details.update(motion_details(problem, case))
    assert case.forward is not None and case.backward is not None
    condition = max(case.forward.condition, case.backward.condition)
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
            f"equations of motion nearly singular (condition {condition:.1e}); no numbers reported"
        )
    elif case.effective_mass is not None and case.painleve:
        details["effective_mass"] = list(case.effective_mass)
    return details


def _evaluated(
    problem: Problem,
    case: Case,
    direction: np.ndarray | None,
    intervals: FrictionIntervals | None,
    details: dict[str, object],
    holding: _Holding,
) -> tuple[str, dict[str, float] | None, float | None]:
    """Outcome, normal forces (N) and acceleration (m/s^2) at a direction (or under the fixed
    wrench alone); adds the friction details (without ``intervals``: none of them, and no
    ``friction_may_hold``)."""
    names = problem.names
    known = holding.outcomes.get(case.retracted)
    verdict, x = outcome(case, direction) if known is None else known
    forces = accel = None
    if verdict == "jams":
        verdict, forces, accel = _jam_or_lift(problem, case, holding, details)
    elif verdict in MOVING and intervals is not None and _may_hold(problem, case, holding):
        details["friction_may_hold"] = True
    if x is not None:
        # Forces beyond the largest float (a mass of 1e308 kg) become inf: JSON null.
        newtons = problem.newtons(x[1:])
        forces = {names[j]: float(newtons[i]) for i, j in enumerate(case.keep)}
        with np.errstate(over="ignore"):
            accel = float(x[0] * problem.acceleration_scale() * case.free.closing)
    if intervals is None:
        return verdict, forces, accel
    details["friction_intervals"] = intervals_json(intervals.intervals)
    if intervals.errors:
        details["friction_intervals_error"] = [list(e) for e in intervals.errors]
    if intervals.unresolved:
        details["friction_intervals_unresolved"] = intervals_json(intervals.unresolved)
    if not intervals.uniform:
        details["friction_scaled"] = True
    start = intervals.painleve_from
    if verdict == "ambiguous" and start is not None:
        details["painleve_from_mu"] = start
    return verdict, forces, accel


#: Outcomes in which the body moves.
MOVING = ("closes", "loses_contact", "opens", "opens_loses_contact")


def _about_com(problem: Problem, wrench: np.ndarray) -> Statics:
    """The problem's supports as statics about the centre of mass, under ``wrench``."""
    return Statics(
        frame=problem.frame,
        names=problem.names,
        points=problem.points - problem.com,
        normals=problem.normals,
        friction=problem.friction,
        fixed=wrench,
        swept=np.zeros((len(wrench), problem.dim)),
    )


class _Holding:
    """Whether friction holds the body on a case's kept contacts, at one scene's wrench: the
    wrench, the statics about the centre of mass and every support's equilibrium columns are
    built once per scene (on first use), not once per case."""

    def __init__(self, problem: Problem, direction: np.ndarray | None) -> None:
        self.problem, self.direction = problem, direction
        self._parts: tuple[np.ndarray, Statics, np.ndarray | None] | None = None
        # Answers decided beforehand by checked certificates (holding_certificates), and
        # the outcomes at the direction found on the way (by retracted support).
        self.known: dict[tuple[int, ...], bool] = {}
        self.outcomes: dict[int, tuple[Outcome, np.ndarray | None]] = {}

    @property
    def wrench(self) -> np.ndarray:
        """The external wrench about the centre of mass at the direction."""
        return self._built()[0]

    def _built(self) -> tuple[np.ndarray, Statics, np.ndarray | None]:
        if self._parts is None:
            wrench = self.problem.wrench(self.direction)
            statics = _about_com(self.problem, wrench)
            columns = contact_columns(statics) if self.problem.dim == 3 else None
            self._parts = (wrench, statics, columns)
        return self._parts

    def holds(self, keep: np.ndarray) -> bool:
        """:func:`~kcheck.mechanics.statics.holds_exactly` on the contacts ``keep``."""
        known = self.known.get(tuple(int(j) for j in keep))
        if known is not None:
            return known
        wrench, statics, columns = self._built()
        return holds_exactly(statics, keep, wrench, columns=columns)

    def question(self, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The conic programme :meth:`holds` asks on ``keep``: the kept contacts' columns
        (3k, 6), the wrench (6,) and their friction coefficients (k,)."""
        wrench, statics, columns = self._built()
        assert columns is not None
        return kept_columns(columns, keep), wrench, statics.friction[keep]


def _asks_holding(problem: Problem, case: Case, verdict: str) -> bool:
    """Whether :func:`_evaluated` asks :meth:`_Holding.holds` of a case with friction
    intervals and this outcome at the direction (:func:`_jam_or_lift`, :func:`_may_hold`)."""
    return verdict == "jams" or (verdict in MOVING and _kept_rough(problem, case))


def _kept_rough(problem: Problem, case: Case) -> bool:
    """Whether some contact the case keeps has friction (frictionless ones hold nothing the
    free motion moves)."""
    return bool(np.any(problem.friction[np.asarray(case.keep)] > 0))


def _certify_holding(
    problems: Sequence[Problem],
    all_cases: Sequence[Sequence[Case]],
    frictions: Sequence[Sequence[FrictionIntervals | None]],
    designs: Sequence[np.ndarray | None],
) -> list[_Holding]:
    """Every scene's :class:`_Holding`, the spatial equilibrium questions its assembly will
    ask answered beforehand where checked certificates decide them (all the chunk's at once,
    :func:`~kcheck.mechanics.holding_certificates.holding_certified`), when there are at
    least HOLDING_CERTIFICATE_BATCH; the others are left to the conic programme. Every case
    with friction intervals has its outcome at the direction found here once, for the
    assembly too."""
    holdings = [_Holding(p, d) for p, d in zip(problems, designs, strict=True)]
    evaluated: list[tuple[_Holding, Case]] = []
    for cases, friction, design, holding in zip(
        all_cases, frictions, designs, holdings, strict=True
    ):
        for case, intervals in zip(cases, friction, strict=True):
            if intervals is not None and case.determined and case.well_conditioned:
                holding.outcomes[case.retracted] = outcome(case, design)
                evaluated.append((holding, case))
    if len(evaluated) < HOLDING_CERTIFICATE_BATCH:  # not even one question per case
        return holdings
    asked = [
        (holding, np.asarray(case.keep))
        for holding, case in evaluated
        if holding.problem.dim == 3
        and _asks_holding(holding.problem, case, holding.outcomes[case.retracted][0])
    ]
    if len(asked) < HOLDING_CERTIFICATE_BATCH:
        return holdings
    questions = [h.question(keep) for h, keep in asked]
    answers = holding_certified(*(list(x) for x in zip(*questions, strict=True)))
    for (holding, keep), answer in zip(asked, answers, strict=True):
        if answer is not None:
            holding.known[tuple(int(j) for j in keep)] = answer
    return holdings


def _may_hold(problem: Problem, case: Case, holding: _Holding) -> bool:
    """Whether friction can also hold the body of a moving case: an equilibrium exists on the
    kept contacts, so rest is a second answer of the rigid model (the `jamming` check's
    question; frictionless kept contacts hold nothing the free motion moves)."""
    return _kept_rough(problem, case) and holding.holds(np.asarray(case.keep))


def _jam_or_lift(
    problem: Problem, case: Case, holding: _Holding, details: dict[str, object]
) -> tuple[Outcome, dict[str, float] | None, float | None]:
    """A case neither sliding assumption fits: ``jams`` when friction can hold the body (an
    equilibrium exists on the kept contacts), else the first motion with contacts free to lift
    off (:mod:`kcheck.mechanics.lift_off`), whose lifted contacts go into ``details``. Returns
    the outcome, the normal forces (N) and the retracted contact's acceleration towards its
    support (m/s^2)."""
    keep = np.asarray(case.keep)
    if holding.holds(keep):
        return "jams", None, None
    wrench = holding.wrench
    r = case.retracted
    motion = lift_off(
        problem.points[keep],
        problem.normals[keep],
        problem.friction[keep],
        problem.com,
        problem.inertia,
        wrench,
        (problem.points[r], problem.normals[r]),
    )
    if motion is None or not motion.moves or not np.any(motion.lifted):
        details["no_equilibrium"] = True
        return "jams", None, None
    names = problem.names
    details["lifts_off"] = [names[j] for j, up in zip(keep, motion.lifted, strict=True) if up]
    newtons = problem.newtons(np.where(motion.lifted, 0.0, motion.forces))
    forces = {names[j]: float(f) for j, f in zip(keep, newtons, strict=True)}
    with np.errstate(over="ignore"):
        accel = float(motion.closing * problem.acceleration_scale())
    return ("loses_contact" if motion.closing > 0 else "opens_loses_contact"), forces, accel


def analyse_fixed(
    scene: Scene,
    mass: MassProperties,
    plane: tuple[np.ndarray, np.ndarray] | None = None,
    friction: np.ndarray | None = None,
) -> Analysis:
    """Free motion, outcome, forces, friction intervals and exact safe arcs for every case, at
    fixed friction coefficients: ``friction`` (k,), or the supports' kinetic coefficients (the
    upper ends of ranges; :func:`kcheck.analysis.analyse` decides ranges over all of them).

    ``plane`` (``e1, e2``, 3-vectors) overrides the scene's sweep plane for the ranges.
    """
    return analyse_fixed_many([scene], [mass], plane, friction)[0]


def load_design(scene: Scene, dim: int) -> tuple[bool, np.ndarray | None]:
    """Whether a load is swept, and the load's design direction (dim,) or None."""
    load = scene.load
    sweeping = load is not None and load.magnitude > 0
    if sweeping and load is not None and load.direction is not None:
        return sweeping, load.direction[:dim]
    return sweeping, None


def analyse_fixed_many(
    scenes: Sequence[Scene],
    masses: Sequence[MassProperties],
    plane: tuple[np.ndarray, np.ndarray] | None = None,
    friction: np.ndarray | None = None,
    sweep: bool = True,
) -> list[Analysis]:
    """:func:`analyse_fixed` of several scenes (e.g. a worker's chunk): the cases' algebra of
    all of them (free twists, both friction systems, friction intervals) stacked in one batch
    of numpy calls (:func:`~kcheck.mechanics.dynamics.analyse_cases_many`,
    :func:`~kcheck.mechanics.friction.friction_intervals_batch`); every scene's values are
    those it gets alone. ``sweep`` False leaves the ranges in the scene's plane out (a caller
    that sweeps another plane; :func:`scene_plane_ranges` adds them as they would be)."""
    problems = [problem_for(s, m, friction) for s, m in zip(scenes, masses, strict=True)]
    designs = [load_design(s, p.dim) for s, p in zip(scenes, problems, strict=True)]
    all_cases = analyse_cases_many(problems)
    goods = [[c.determined and c.well_conditioned for c in cases] for cases in all_cases]
    chosen = [
        [c for c, g in zip(cases, good, strict=True) if g]
        if design is not None or not sweeping
        else []
        for cases, good, (sweeping, design) in zip(all_cases, goods, designs, strict=True)
    ]
    found = friction_intervals_batch(problems, chosen, [d for _, d in designs])
    frictions: list[list[FrictionIntervals | None]] = []
    for cases, good, (sweeping, design), intervals in zip(
        all_cases, goods, designs, found, strict=True
    ):
        case_friction: list[FrictionIntervals | None] = [None] * len(cases)
        if design is not None or not sweeping:
            each = iter(intervals)
            case_friction = [next(each) if g else None for g in good]
        frictions.append(case_friction)
    holdings = _certify_holding(problems, all_cases, frictions, [d for _, d in designs])
    return [
        _assemble(
            scene, problem, cases, case_friction, design, sweeping and sweep, plane, holding=h
        )
        for scene, problem, cases, case_friction, (sweeping, design), h in zip(
            scenes, problems, all_cases, frictions, designs, holdings, strict=True
        )
    ]


def cases_close_many(scenes: Sequence[Scene], masses: Sequence[MassProperties]) -> list[bool]:
    """Per scene (at its fixed friction coefficients), whether every case is determined,
    well-conditioned and closes at the design direction (or is swept, without one): the first
    test of :func:`closing_analysis` (None there exactly where False here), for many trial
    scenes in one batch of the cases' algebra."""
    problems = [problem_for(s, m) for s, m in zip(scenes, masses, strict=True)]
    out = []
    for scene, problem, cases in zip(scenes, problems, analyse_cases_many(problems), strict=True):
        out.append(_cases_close(scene, problem, cases))
    return out


def _cases_close(scene: Scene, problem: Problem, cases: Sequence[Case]) -> bool:
    sweeping, design = load_design(scene, problem.dim)
    evaluated = design is not None or not sweeping
    for case in cases:
        if not (case.determined and case.well_conditioned):
            return False
        if evaluated and outcome(case, design)[0] != "closes":
            return False
    return True


def closing_force_screen(
    scene: Scene, mass: MassProperties, preload: bool
) -> Callable[[float], bool] | None:
    """For trial scenes that differ from ``scene`` only by a factor ``t`` on its closing force
    (the preloads with ``preload``, else the load magnitude; :mod:`kcheck.analysis.way_out`):
    a test of ``t``, False where :func:`cases_close` surely fails. None when it cannot tell.

    Every case's system matrices do not depend on the force (nondimensional masses and lengths,
    the friction's directions), so its forward unknowns at the design direction are
    ``K^-1 (u + t v)`` (``v`` the part that scales) up to a positive factor: solved once here,
    each trial is a few multiplications; a trial fails only where an unknown is negative by
    more than FORCE_SCREEN_RTOL of the solution's size (near a sign change it is judged in
    full). A case that is undetermined, ill-conditioned or Painlevé-type is so at every force
    (every trial fails)."""
    problem = problem_for(scene, mass)
    sweeping, design = load_design(scene, problem.dim)
    if sweeping and design is None:
        return None  # nothing evaluated at a direction: cases_close asks the cases only
    b0, big_b = problem.load_basis()
    loaded = np.zeros_like(b0) if design is None else big_b @ design
    if preload:
        if problem.preload is None:
            return None
        scaled, fixed = problem.preload, b0 - problem.preload + loaded
    else:
        scaled, fixed = loaded, b0
    cases = analyse_cases_many([problem])[0]
    if any(not (c.determined and c.well_conditioned) or c.painleve for c in cases):
        return lambda t: False
    parts = []
    for case in cases:
        assert case.forward is not None
        solved = with_load(case, fixed, scaled[:, None]).forward
        assert solved is not None
        rtol = max(FORCE_SCREEN_RTOL, FORCE_SCREEN_ROUNDINGS * case.forward.condition * EPS)
        u, v = solved.a, solved.c[:, 0]
        parts.append((u, v, rtol, float(np.abs(u).max()), float(np.abs(v).max())))

    def may_close(t: float) -> bool:
        # The band is on the size of the whole solution: an unknown that is itself a
        # cancellation carries the rounding of the largest one.
        for u, v, rtol, u_size, v_size in parts:
            if np.any(u + t * v < -rtol * (u_size + abs(t) * v_size)):
                return False
        return True

    return may_close


def closing_analysis(scene: Scene, mass: MassProperties) -> Analysis | None:
    """:func:`analyse_fixed` (the scene's fixed coefficients) of a scene whose every case is
    determined, well-conditioned and closes at the design direction (or is swept, without
    one); None for any other scene, decided from the cases' algebra alone.

    For a search that judges many trial scenes by a verdict (a way-out search): most trials
    are rejected before the friction intervals, equilibrium tests and safe ranges, which do
    not change whether a case closes. The analysis returned has the same outcomes, forces,
    safe ranges and margins as :func:`analyse_fixed`'s, but no friction intervals (``friction``
    all None, no ``limiting_friction``, no friction details) and no ``friction_may_hold``."""
    problem = problem_for(scene, mass)
    cases = analyse_cases_many([problem])[0]
    if not _cases_close(scene, problem, cases):
        return None
    sweeping, design = load_design(scene, problem.dim)
    evaluated = design is not None or not sweeping
    return _assemble(scene, problem, cases, [None] * len(cases), design, sweeping, None, evaluated)


def closing_cases(scene: Scene, mass: MassProperties) -> Analysis | None:
    """:func:`closing_analysis`'s first test, and of its answer only what a sphere map reads:
    the problem, the cases and the design direction of a scene whose every case is determined,
    well-conditioned and closes at the design direction (or is swept, without one); None for
    any other scene, as :func:`closing_analysis`.

    For a search that needs a trial's verdict only: the analysis has no case results (every
    case closes, or is swept: :func:`closing_analysis` would say so), no details and no
    ranges."""
    problem = problem_for(scene, mass)
    cases = analyse_cases_many([problem])[0]
    if not _cases_close(scene, problem, cases):
        return None
    _, design = load_design(scene, problem.dim)
    return Analysis(
        problem=problem,
        cases=tuple(cases),
        results=(),
        arcs=None,
        combined=None,
        design=design,
        design_margin_deg=None,
        error_deg=None,
        max_condition=0.0,
        friction=(None,) * len(cases),
    )


def scene_plane_ranges(scene: Scene, analysis: Analysis) -> Analysis:
    """The ranges in the scene's sweep plane that :func:`analyse_fixed_many` leaves out with
    ``sweep`` False (the analysis unchanged when it has them, or when no load is swept)."""
    sweeping, _ = load_design(scene, analysis.problem.dim)
    if not sweeping or analysis.plane is not None:
        return analysis
    dim = analysis.problem.dim
    return sweep_ranges(
        analysis, np.asarray(scene.sweep.e1)[:dim], np.asarray(scene.sweep.e2)[:dim]
    )


def _assemble(
    scene: Scene,
    problem: Problem,
    cases: tuple[Case, ...],
    case_friction: list[FrictionIntervals | None],
    design: np.ndarray | None,
    sweeping: bool,
    plane: tuple[np.ndarray, np.ndarray] | None,
    evaluate: bool = False,
    holding: _Holding | None = None,
) -> Analysis:
    """The analysis of a scene from its solved cases and friction intervals; ``evaluate``:
    the outcomes at the design direction of the cases without intervals too; ``holding``:
    the scene's equilibrium questions, some answered beforehand (:func:`_certify_holding`)."""
    results = []
    max_condition = 0.0
    names = problem.names
    holding = _Holding(problem, design) if holding is None else holding
    for r, case in enumerate(cases):
        details = _case_details(problem, case)
        if not case.determined:
            results.append(CaseResult(names[r], "undetermined", details=details))
            continue
        max_condition = max(max_condition, float(details["condition"]))  # type: ignore[arg-type]
        if not case.well_conditioned:
            results.append(CaseResult(names[r], "ill_conditioned", details=details))
            continue
        verdict, forces, accel, intervals = "swept", None, None, case_friction[r]
        if intervals is not None or evaluate:
            verdict, forces, accel = _evaluated(problem, case, design, intervals, details, holding)
        results.append(
            CaseResult(
                names[r],
                verdict,
                normal_forces=forces,
                acceleration=accel,
                limiting_friction=None if intervals is None else intervals.limiting,
                details=details,
            )
        )
    analysis = Analysis(
        problem=problem,
        cases=tuple(cases),
        results=tuple(results),
        arcs=None,
        combined=None,
        design=design,
        design_margin_deg=None,
        error_deg=None,
        max_condition=max_condition,
        friction=tuple(case_friction),
    )
    if not sweeping:
        return analysis
    e1, e2 = (scene.sweep.e1, scene.sweep.e2) if plane is None else plane
    return sweep_ranges(analysis, np.asarray(e1)[: problem.dim], np.asarray(e2)[: problem.dim])


def nearest_end(arcs: ArcSet, angle: float) -> float:
    """The angle (rad, in [0, 2 pi)) of the arc set nearest to ``angle`` (itself if inside)."""
    if contains(arcs, angle) or arcs == FULL:
        return angle % (2 * np.pi)
    ends = np.array([x for arc in arcs for x in arc])
    gap = np.abs((angle - ends + np.pi) % (2 * np.pi) - np.pi)
    return float(ends[int(np.argmin(gap))] % (2 * np.pi))


def swept_design(analysis: Analysis) -> np.ndarray | None:
    """The design direction of what is swept (unit, dim): the load's direction, or without a
    load the scene's gravity (:attr:`kcheck.mechanics.problem.Problem.swept`); None when it has
    none."""
    problem = analysis.problem
    if problem.swept == "load":
        return analysis.design
    return unit_rows(problem.gravity) if np.any(problem.gravity) else None


def sweep_ranges(analysis: Analysis, e1: np.ndarray, e2: np.ndarray) -> Analysis:
    """The analysis with exact safe ranges in the plane ``(e1, e2)`` (dim-vectors): per case,
    combined, the design margin and the nearest safe angle.

    Without a load the angles are gravity's direction, its magnitude kept
    (:meth:`kcheck.mechanics.problem.Problem.gravity_basis`), as on the sphere map."""
    from dataclasses import replace

    from kcheck.mechanics.friction_range import range_arcs

    problem = analysis.problem
    gravity = problem.swept == "gravity"
    b0, big_b = problem.gravity_basis()
    forms = None
    if gravity and analysis.friction_range is not None:
        forms = analysis.friction_range.for_wrench(b0, big_b)
    arcs: list[ArcSet] = []
    error: float | None = None
    results = []
    for r, (case, result) in enumerate(zip(analysis.cases, analysis.results, strict=True)):
        if not case.determined or not case.well_conditioned:
            arcs.append(())
            results.append(result)
            continue
        case_arcs, arc_error = safe_arcs(with_load(case, b0, big_b) if gravity else case, e1, e2)
        if arc_error is not None:
            error = max(error or 0.0, float(np.degrees(arc_error)))
        if forms is not None:
            case_arcs = () if forms[r] is None else range_arcs(forms[r], e1, e2)[0]
        elif analysis.friction_range is not None:
            case_arcs = analysis.friction_range.arcs(r, e1, e2)
        arcs.append(case_arcs)
        results.append(replace(result, safe_ranges_deg=ranges_deg(case_arcs)))
    combined = intersect(*arcs)
    design_margin = nearest = None
    design = swept_design(analysis)
    in_plane = (
        design is not None
        and abs(float(np.linalg.norm([design @ e1, design @ e2])) - 1) < IN_SWEEP_PLANE
    )
    if combined and design is not None and in_plane:
        angle = float(np.arctan2(design @ e2, design @ e1))
        design_margin = float(np.degrees(margin(combined, angle)))
        nearest = float(np.degrees(nearest_end(combined, angle)))
    return replace(
        analysis,
        results=tuple(results),
        arcs=tuple(arcs),
        combined=combined,
        design_margin_deg=design_margin,
        nearest_safe_deg=nearest,
        error_deg=error if analysis.trustworthy else None,
        plane=(e1, e2),
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
