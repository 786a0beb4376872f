"""The statics of every retracted case of a scene, for the ``jamming`` check.

For every retracted support ``r`` the check asks whether a static equilibrium exists in which
the external wrench (the load, the weight, preloads, a torque) is balanced by the remaining
supports with every contact force inside its friction cone (:mod:`kcheck.mechanics.statics`). If so,
the body may stay put whatever the forward dynamics say. Per case and direction ``d`` of the
swept force:

* ``jams``: an equilibrium exists and, without friction, the body would close the gap
  (``xi_r . W(d) > 0``, graphical-2d's funnel): friction holds a load that should close it;
* ``holds``: an equilibrium exists but, without friction, the load would not close the gap
  (it would open it): friction keeps the body in place against it;
* ``moves``: no equilibrium: friction cannot hold the body.

Planar scenes are exact (two rays per friction cone). Spatial scenes bound the circular cones
between inscribed and circumscribed pyramids for maps and ranges (the held region reported is
the circumscribed one: it contains every direction where jamming is possible), and decide the
design direction exactly with a conic solver.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from kcheck.mechanics.arcs import ArcSet, complement, intersect, positive_arc
from kcheck.mechanics.kinematics import FreeTwist, free_twist
from kcheck.mechanics.lattice_cells import LatticeCells, lattice_cells, lattice_slack
from kcheck.mechanics.least_friction import (
    friction_candidates,
    least_friction,
    least_friction_exactly,
    rough_supports,
)
from kcheck.mechanics.sliding_limit import certified_holding
from kcheck.mechanics.statics import (
    PYRAMID_EDGES,
    Equilibria,
    Statics,
    build_statics,
    closing_condition,
    equilibria,
    forward_limit,
    holds,
    holds_exactly,
    planar_holding,
)
from kcheck.numerics.thresholds import (
    FREE_CANDIDATE_TOL,
    JAM_MU_RTOL,
    OUTSIDE_PYRAMIDS,
    SLIVER,
    UNDETERMINED,
)
from kcheck.records import dataclass
from kcheck.result import MassProperties
from kcheck.scene import Scene

__all__ = [
    "JamCase",
    "JamAnalysis",
    "closing_force_missing",
    "jam_statics",
    "analyse_jamming",
    "case_arcs",
    "tidy",
    "CaseArcs",
    "least_holding_friction",
    "held_at",
    "needs_body",
    "JamMap",
    "jam_map",
]

Outcome = Literal["jams", "holds", "moves", "swept", "undetermined"]

#: Directions measured exactly first, for a lower bound of the freest direction's depth.
FREE_SAMPLE = 64
#: Absolute guard on per-cell bounds of unit-vector products against rounding (1e-16).
CELL_GUARD = 1e-12
#: Direction-facet products of the freest direction's exact screen at once (8 MB).
ANY_BELOW_CHUNK = 1_000_000


# --- from a scene to its statics ------------------------------------------------------------


def _gravity(scene: Scene) -> np.ndarray:
    return np.append(scene.gravity[: scene.dim], np.zeros(3 - scene.dim))


def closing_force_missing(scene: Scene) -> str | None:
    """Why a scene gives the check nothing to hold, or None (no mesh read)."""
    load = scene.load
    has_load = load is not None and load.magnitude > 0
    weight = bool(np.any(_gravity(scene)))
    if not has_load and not weight:
        return "needs a closing force: a load with a magnitude, or gravity"
    at_com = not has_load or (load is not None and load.point is None)
    if (weight or at_com) and scene.body is None:
        what = "the weight" if weight else "the load at the centre of mass"
        return f"{what} needs the body's mass properties; the scene has no `body`"
    return None


def needs_body(scene: Scene) -> bool:
    """Whether the weight or the centre of mass enters the balance."""
    load = scene.load
    at_com = load is None or load.magnitude <= 0 or load.point is None
    return at_com or bool(np.any(_gravity(scene)))


def _magnitude(vector: np.ndarray) -> float:
    """|v| in the units of v, scaled first so that squaring cannot overflow or underflow."""
    big = float(np.abs(vector).max())
    return big * float(np.linalg.norm(np.asarray(vector) / big)) if big > 0 else 0.0


class NoClosingForce(Exception):
    """The scene's closing force is zero or beyond floating point (an extreme but valid
    scene): the check has nothing to decide."""


def jam_statics(
    scene: Scene, mass: MassProperties | None
) -> tuple[Statics, Literal["load", "gravity"], np.ndarray | None]:
    """The scene's statics, what is swept, and the design direction (unit, dim) or None.

    The load is swept when it has a magnitude (its direction is the design's); otherwise the
    weight is, and the scene's gravity is the design direction. Forces are scaled by the largest
    force in the balance (swept, weight or preload), so that none overflows when a swept weight
    is tiny beside a preload.
    """
    load, dim = scene.load, scene.dim
    gravity = _gravity(scene)
    com = None if mass is None else mass.center_of_mass
    weight = None if mass is None else mass.mass * gravity
    fixed = [(p.point, p.force) for p in scene.preloads]
    torque = None if load is None else load.torque
    swept: Literal["load", "gravity"]
    if load is not None and load.magnitude > 0:
        point = load.point if load.point is not None else com
        if weight is not None and np.any(weight):
            assert com is not None  # a weight: mass properties
            fixed.append((com, weight))
        force, swept = load.magnitude, "load"
        design = None if load.direction is None else load.direction[:dim]
    else:
        assert mass is not None and com is not None
        # Scaled by the largest component first: |g| of an extreme but valid gravity would
        # underflow (or overflow) when squared.
        big = float(np.abs(gravity[:dim]).max())
        unit = gravity[:dim] / big
        point, swept = com, "gravity"
        force = float(mass.mass * big * np.linalg.norm(unit))
        if not (0.0 < force < np.inf):
            raise NoClosingForce(
                f"the weight (mass × gravity = {force:g} N) is not a representable force, so "
                "there is no closing force to hold"
            )
        design = unit / np.linalg.norm(unit)
    scale = max([force, *(_magnitude(vector) for _, vector in fixed)])
    # A load without a point acts at the centre of mass: the check runs only with mass
    # properties then (closing_force_missing).
    assert point is not None
    statics = build_statics(
        points=np.array([s.position for s in scene.supports]),
        normals=np.array([s.normal for s in scene.supports]),
        friction=scene.friction_range("static")[1],
        names=tuple(s.name for s in scene.supports),
        dim=dim,
        force=scale,
        swept_point=point,
        swept_magnitude=force,
        fixed_forces=tuple(fixed),
        torque=torque,
    )
    return statics, swept, design


# --- per case -------------------------------------------------------------------------------


@dataclass(frozen=True)
class JamCase:
    """One retracted support: free motion, frictionless closing condition, held directions.

    ``held`` is exact (planar) or from the circumscribed pyramids (spatial, contains the true
    set); ``held_inner`` from the inscribed ones (spatial, inside the true set). ``limit`` is
    Koster's friction-pole condition (planar, when it is a facet of the cone;
    :func:`kcheck.mechanics.statics.forward_limit`).
    """

    retracted: int
    keep: np.ndarray
    free: FreeTwist
    closing: tuple[float, np.ndarray]
    held: Equilibria
    held_inner: Equilibria | None
    limit: tuple[float, np.ndarray] | None

    @property
    def determined(self) -> bool:
        """Whether removing the support frees exactly one motion that closes its gap."""
        return self.free.determinacy > UNDETERMINED and self.free.closing > UNDETERMINED


@dataclass(frozen=True)
class JamAnalysis:
    """Every case of a scene, with what is swept and the design direction."""

    statics: Statics
    cases: tuple[JamCase, ...]
    swept: Literal["load", "gravity"]
    design: np.ndarray | None
    edges: int


def analyse_jamming(
    statics: Statics,
    swept: Literal["load", "gravity"],
    design: np.ndarray | None,
    edges: int = PYRAMID_EDGES,
) -> JamAnalysis:
    """Held directions of every retracted case."""
    cases = []
    spatial = statics.dim == 3
    for r in range(len(statics.names)):
        keep = np.flatnonzero(np.arange(len(statics.names)) != r)
        free = free_twist(statics.points, statics.normals, r)
        cases.append(
            JamCase(
                retracted=r,
                keep=keep,
                free=free,
                closing=closing_condition(statics, free.twist),
                held=equilibria(statics, keep, edges=edges, pyramid="circumscribed"),
                held_inner=equilibria(statics, keep, edges=edges, pyramid="inscribed")
                if spatial
                else None,
                limit=None if spatial else forward_limit(statics, keep, free.twist),
            )
        )
    return JamAnalysis(statics, tuple(cases), swept, design, edges)


@dataclass(frozen=True)
class CaseArcs:
    """A case's sets of swept angles in the sweep plane (rad)."""

    held: ArcSet
    closing: ArcSet
    jamming: ArcSet  # held and closing
    holding_open: ArcSet  # held, not closing
    lifts_off: ArcSet | None  # planar: Koster's jamming area where no equilibrium exists
    error: float  # rad: rounding (planar) or the inscribed/circumscribed band (spatial)


def tidy(arcs: ArcSet, tol: float = SLIVER) -> ArcSet:
    """An arc set with slivers dropped and near-touching arcs joined (both below ``tol``)."""
    kept = [(s, e) for s, e in arcs if e - s > tol]
    if not kept:
        return ()
    gaps = complement(tuple(kept))
    return complement(tuple((s, e) for s, e in gaps if e - s > tol))


def _condition_arcs(condition: tuple[float, np.ndarray], e1: np.ndarray, e2: np.ndarray) -> ArcSet:
    a, c = condition
    return positive_arc(a, float(c @ e1), float(c @ e2))


def case_arcs(case: JamCase, e1: np.ndarray, e2: np.ndarray) -> CaseArcs:
    """Held, closing, jamming and holding-open angles of one case in the sweep plane."""
    held, error = case.held.arcs(e1, e2)
    closing = _condition_arcs(case.closing, e1, e2)
    lifts = None
    if case.limit is not None:
        lifts = tidy(intersect(closing, _condition_arcs(case.limit, e1, e2), complement(held)))
    if case.held_inner is not None:
        inner, _ = case.held_inner.arcs(e1, e2)
        band = intersect(held, complement(inner))
        error = max([error] + [e - s for s, e in band])
    return CaseArcs(
        held=held,
        closing=closing,
        jamming=tidy(intersect(held, closing)),
        holding_open=tidy(intersect(held, complement(closing))),
        lifts_off=lifts,
        error=error,
    )


def held_at(analysis: JamAnalysis, case: JamCase, design: np.ndarray, mu: np.ndarray) -> bool:
    """Exact decision at the design direction (clarabel for spatial cones; no solve where the
    circumscribed pyramids already exclude it, :func:`_outside_pyramids`)."""
    wrench = analysis.statics.wrench(design)
    if analysis.statics.dim == 2:
        return holds(analysis.statics, case.keep, wrench, mu)
    if _outside_pyramids(analysis, case, design, mu):
        return False
    known = certified_holding(analysis.statics, case.keep, wrench, mu)  # the least-mu search's
    if known is not None:
        return known
    return holds_exactly(analysis.statics, case.keep, wrench, mu)


def _outside_pyramids(
    analysis: JamAnalysis, case: JamCase, design: np.ndarray, mu: np.ndarray
) -> bool:
    """Spatial: whether the circumscribed pyramids at the scene's friction, which contain the
    circular cones, leave the design direction out by more than OUTSIDE_PYRAMIDS (a facet's
    slack): then no equilibrium exists at coefficients ``mu`` equal to the scene's, and the
    conic solver (which would find none) need not be asked."""
    held = case.held
    if held.kind != "cone" or not len(held.a):
        return False
    if not np.array_equal(mu[case.keep], analysis.statics.friction[case.keep]):
        return False
    return bool(np.min(held.a + held.c @ design) < -OUTSIDE_PYRAMIDS)


def least_holding_friction(
    analysis: JamAnalysis, case: JamCase, design: np.ndarray
) -> float | None:
    """Smallest common friction coefficient (on the scene's rough supports) for which an
    equilibrium exists at the design direction; None if none up to 100 does."""
    statics = analysis.statics
    rough = rough_supports(statics.friction).astype(float)
    start = max(float(statics.friction.max()), 0.05)
    # Planar: exact, among the coefficients where the cone's boundary can pass the wrench.
    # Spatial: within JAM_MU_RTOL (relative); messages show three significant digits.
    wrench = statics.wrench(design)
    if statics.dim == 3:
        # The first coefficient tried is often the scene's own, which the pyramids may exclude
        # (asked only if the sliding limit leaves the answer to the conic search).
        def fails() -> bool:
            return _outside_pyramids(analysis, case, design, start * rough)

        return least_friction_exactly(
            statics, case.keep, wrench, rough, start, rtol=JAM_MU_RTOL, upper_fails=fails
        )
    candidates = friction_candidates(statics, case.keep, wrench, rough)
    # held_at(analysis, case, design, mu * rough), the case's parts built once.
    return least_friction(
        planar_holding(statics, case.keep, wrench, rough),
        start,
        rtol=JAM_MU_RTOL,
        candidates=candidates,
    )


# --- the sphere of directions (spatial) -----------------------------------------------------


@dataclass(frozen=True)
class JamMap:
    """Shares of the sphere of swept directions, from a Fibonacci lattice.

    Per case: where friction can hold the body, with the circumscribed pyramids (``held``,
    an upper bound) and the inscribed ones (``held_inner``, a lower bound). ``jam_free`` is
    the share where no case can be held (circumscribed: a lower bound); ``safe`` where every
    case would close without friction and none can be held. ``error_deg`` bounds how far the
    reported (circumscribed) boundary may lie from the true one.
    """

    points: int
    held: np.ndarray
    held_inner: np.ndarray
    jam_free: float
    jam_free_upper: float
    safe: float
    error_deg: float
    safe_upper: float = 0.0  # as ``safe``, with the inscribed pyramids: an upper bound
    # The lattice direction farthest from every case's held region (circumscribed: jam-free
    # for certain; else inscribed: where jamming may be absent), and which; None when none is
    # jam-free even with the inscribed pyramids, or nothing is held anywhere.
    freest: np.ndarray | None = None
    freest_pyramids: Literal["circumscribed", "inscribed"] | None = None


def jam_map(analysis: JamAnalysis, points: int) -> JamMap:
    """Classify ``points`` Fibonacci directions per case: one matrix product per cone."""
    from kcheck.mechanics.sphere import grid_spacing

    cells = lattice_cells(points)
    dirs = cells.fine
    held_any = np.zeros(points, bool)
    inner_any = np.zeros(points, bool)
    closing_all = np.ones(points, bool)
    held, inner = [], []
    band_width = 0.0
    # Least facet slacks, exact down to -FREE_CANDIDATE_TOL, per case: circumscribed, inscribed.
    slacks: tuple[list[np.ndarray], list[np.ndarray]] = ([], [])
    for case in analysis.cases:
        if not case.determined:
            continue
        assert case.held_inner is not None
        outer = _lattice_slack(case.held, cells)
        # The inscribed pyramids hold less than the circumscribed ones (a subset): only the
        # directions the circumscribed ones hold, to far more than rounding, can be held.
        maybe = outer >= -FREE_CANDIDATE_TOL
        inner_slack = _lattice_slack(case.held_inner, cells, maybe)  # -inf elsewhere
        slacks[0].append(outer)
        slacks[1].append(inner_slack)
        outer_in, inner_in = outer >= 0, inner_slack >= 0
        band = outer_in & ~inner_in
        if np.any(band) and case.held.kind == "cone":
            band_width = max(band_width, _widest_margin(case.held.a, case.held.c, dirs[band]))
        a, c = case.closing
        closing_all &= a + dirs @ c > 0
        held_any |= outer_in
        inner_any |= inner_in
        held.append(np.count_nonzero(outer_in) / points)
        inner.append(np.count_nonzero(inner_in) / points)
    freest, pyramids = None, None
    for kind, sets, slack in (
        ("circumscribed", [c.held for c in analysis.cases if c.determined], slacks[0]),
        ("inscribed", [c.held_inner for c in analysis.cases if c.determined], slacks[1]),
    ):
        best = _freest(sets, cells, slack)  # type: ignore[arg-type]
        if best is not None:
            freest, pyramids = dirs[best], kind
            break
    return JamMap(
        points=points,
        held=np.array(held),
        held_inner=np.array(inner),
        jam_free=np.count_nonzero(~held_any) / points,
        jam_free_upper=np.count_nonzero(~inner_any) / points,
        safe=np.count_nonzero(closing_all & ~held_any) / points,
        error_deg=float(np.degrees(band_width + grid_spacing(points))),
        safe_upper=np.count_nonzero(closing_all & ~inner_any) / points,
        freest=freest,
        freest_pyramids=pyramids,  # type: ignore[arg-type]
    )


def _widest_margin(a: np.ndarray, c: np.ndarray, dirs: np.ndarray) -> float:
    """``max(cap_margins(a, c, dirs))`` (rad), the same float, with arccos over every facet
    only for the directions that can attain it.

    A direction's margin is its least over the facets of ``radius_f - arccos(axis_f . d)``, so
    its value at any one facet bounds it from above; at the facet of least normalised slack
    ``axis_f . d - cos(radius_f)`` that bound is usually the margin itself. Only directions
    whose bound exceeds the best margin found so far are measured at every facet (the same
    products and operations as :func:`kcheck.mechanics.arcs.cap_margin_matrix`)."""
    from kcheck.mechanics.arcs import cap_geometry, cap_margins

    ratio, axes, radius = cap_geometry(a, c)
    if np.any(np.abs(ratio) >= 1.0) or len(dirs) < 2:
        return float(cap_margins(a, c, dirs).max())
    cosines = np.clip(dirs @ axes.T, -1.0, 1.0)  # cap_margin_matrix's product and clip
    rows = np.arange(len(dirs))
    nearest = np.argmin(cosines - ratio, axis=1)
    bound = radius[nearest] - np.arccos(cosines[rows, nearest])
    first = int(np.argmax(bound))
    best = float(np.min(radius - np.arccos(cosines[first])))
    rest = np.flatnonzero(bound > best)
    if len(rest):
        margins = radius[None, :] - np.arccos(cosines[rest])
        best = max(best, float(margins.min(axis=1).max()))
    return best


def _lattice_slack(
    held: Equilibria, cells: LatticeCells, where: np.ndarray | None = None
) -> np.ndarray:
    """:meth:`Equilibria.least_slack` at every lattice direction (floor
    ``-FREE_CANDIDATE_TOL``), exact wherever it lies within ``FREE_CANDIDATE_TOL`` of 0 (all
    that the map compares it with): whole cells of the lattice beyond that band on either
    side are decided by one bound each (:mod:`kcheck.mechanics.lattice_cells`). ``where``:
    only those directions need an answer (-inf elsewhere)."""
    floor = -FREE_CANDIDATE_TOL
    if held.kind != "cone" or not len(held.a):
        slack = held.least_slack(cells.fine, floor)
    else:
        slack = lattice_slack(held.a, held.c, cells, floor, FREE_CANDIDATE_TOL, where)
    if where is not None:
        slack[~where] = -np.inf
    return slack


def _free_depth(
    sets: list[Equilibria],
    dirs: np.ndarray,
    geometry: list[tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None,
) -> np.ndarray:
    """Per direction (m, 3), the least angular distance (rad) to a held region over the
    cases, each measured to the facet's circle the direction lies farthest outside (a lower
    bound of the distance); negative where some case holds it, inf where none holds
    anything. ``geometry``: the cone sets' :func:`~kcheck.mechanics.arcs.cap_geometry` in
    order, when the caller has it (the same values)."""
    from kcheck.mechanics.arcs import cap_geometry

    depth = np.full(len(dirs), np.inf)
    cones = iter(geometry or ())
    for held in sets:
        if held.kind == "everywhere":
            return np.full(len(dirs), -np.pi)
        if held.kind == "cone" and len(held.a):
            ratio, axes, radius = next(cones) if geometry else cap_geometry(held.a, held.c)
            # arcs.cap_margin_matrix's operations, from the geometry: the same values.
            margins = radius[None, :] - np.arccos(np.clip(dirs @ axes.T, -1.0, 1.0))
            margins[:, ratio <= -1.0] = np.pi
            margins[:, ratio >= 1.0] = -np.pi
            depth = np.minimum(depth, -margins.min(axis=1))
    return depth


def _freest(sets: list[Equilibria], cells: LatticeCells, slacks: list[np.ndarray]) -> int | None:
    """The index of the direction :func:`_free_depth` puts deepest (the first of equals) when
    its depth is positive and finite, else None — computed exactly on a few directions only.

    A direction is deeper than ``L`` in a case iff it lies outside some facet's circle by more
    than ``L``: ``axis . d < cos(radius + L)``, a test without arccos. ``L`` is the best depth
    among a sparse subset of the directions; only those passing the test in every case (with
    a margin for rounding) are measured exactly, so the deepest is among them.
    """
    from kcheck.mechanics.arcs import cap_geometry

    dirs = cells.fine
    cones = [h for h in sets if h.kind == "cone" and len(h.a)]
    if any(h.kind == "everywhere" for h in sets) or not cones:
        return None  # -pi everywhere, or inf everywhere (nothing held): neither counts
    free = np.ones(len(dirs), bool)
    for slack in slacks:  # depth > 0 only outside every held set
        free &= slack < FREE_CANDIDATE_TOL
    candidates = np.flatnonzero(free)
    if not len(candidates):
        return None
    geometry = [cap_geometry(held.a, held.c) for held in cones]
    sample = candidates[:: max(1, len(candidates) // FREE_SAMPLE)]
    floor = float(_free_depth(sets, dirs[sample], geometry).max())
    if floor > 0:
        tests = [_depth_test(ratio, axes, radius, floor) for ratio, axes, radius in geometry]
        # Whole cells first, every case: a cell no member of which lies below any facet of
        # some case drops out before any case tests the directions one by one.
        alive = np.zeros(len(cells.coarse), bool)
        alive[cells.owner[candidates]] = True
        for axes, bound in tests:
            which = np.flatnonzero(alive)
            alive[which] = _some_below(cells, which, axes, bound)
        candidates = candidates[alive[cells.owner[candidates]]]
        # The survivors lie in the deepest cells: a sample of them may raise the floor (it
        # keeps the direction that gave the floor: the screens are conservative). One round:
        # a second and third screen of the cells removed few directions (the cells, not the
        # floor, limit it near the maximum) and cost more than the exact screen they spared.
        sample = candidates[:: max(1, len(candidates) // FREE_SAMPLE)]
        raised = float(_free_depth(sets, dirs[sample], geometry).max(initial=-np.inf))
        if raised > floor:
            floor = raised
            tests = [_depth_test(ratio, axes, radius, floor) for ratio, axes, radius in geometry]
        # Fewest facets first: the first case meets every surviving direction.
        for axes, bound in sorted(tests, key=lambda test: len(test[0])):
            candidates = candidates[_any_below(cells, candidates, axes, bound)]
    depth = _free_depth(sets, dirs[candidates], geometry)
    best = int(np.argmax(depth))
    if depth[best] > 0 and np.isfinite(depth[best]):
        return int(candidates[best])
    return None


def _depth_test(
    ratio: np.ndarray, axes: np.ndarray, radius: np.ndarray, floor: float
) -> tuple[np.ndarray, np.ndarray]:
    """``(axes, bound)``: a direction is deeper than ``floor`` outside a facet's circle iff
    ``axes . d < cos(radius + floor)`` (``bound`` with a margin for rounding)."""
    bound = np.cos(np.minimum(radius + floor, np.pi)) + FREE_CANDIDATE_TOL
    return axes, np.where(ratio >= 1.0, np.inf, np.where(ratio <= -1.0, -np.inf, bound))


def _some_below(
    cells: LatticeCells, which: np.ndarray, axes: np.ndarray, bound: np.ndarray
) -> np.ndarray:
    """Per cell of ``which``, whether its bound leaves ``axes_f . d <= bound_f`` possible for
    some facet ``f`` and member ``d``: ``axes_f . c - |axes_f| r <= bound_f`` at the cell's
    centre ``c`` (radius ``r``; axes unit or zero), with CELL_GUARD for rounding, as one
    matrix product. (Elsewhere no member is below any facet.) An infinite bound (a facet held
    nowhere or everywhere) is decided without the product (no infinities through BLAS)."""
    if np.any(bound == np.inf):
        return np.ones(len(which), bool)
    finite = bound > -np.inf
    axes, bound = axes[finite], bound[finite]
    if not len(bound):
        return np.zeros(len(which), bool)
    centre = np.column_stack([cells.coarse[which], cells.radius[which], np.ones(len(which))])
    facet = np.column_stack([axes, -np.linalg.norm(axes, axis=1), -(bound + CELL_GUARD)])
    return np.any(facet @ centre.T <= 0.0, axis=0)


def _any_below(
    cells: LatticeCells, candidates: np.ndarray, axes: np.ndarray, bound: np.ndarray
) -> np.ndarray:
    """Per candidate lattice direction ``d``, whether ``axes_f . d <= bound_f`` for some ``f``
    (axes unit or zero), direction by direction against every facet: one matrix product.
    (Facet lists per cell, from the cells' bounds, cost about 2.7 times more: the pairs'
    bookkeeping outweighed the products it saved, 5,000 directions and 150 facets at most.)"""
    below = np.empty(len(candidates), bool)
    step = max(1, ANY_BELOW_CHUNK // max(1, len(axes)))
    for i in range(0, len(candidates), step):
        chunk = cells.fine[candidates[i : i + step]]
        # (facets, directions): the reduction over the first axis is the faster one.
        below[i : i + step] = np.any(axes @ chunk.T <= bound[:, None], axis=0)
    return below
