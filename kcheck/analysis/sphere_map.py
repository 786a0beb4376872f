"""The map of safe directions of a spatial scene: every case's closing conditions as caps on
the sphere of force (or gravity) directions, and their exact intersection
(:mod:`kcheck.mechanics.caps`): area, margins, the nearest and the most robust direction, and the
default sweep plane.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from kcheck.analysis.cases import Analysis
from kcheck.mechanics.caps import FOUR_PI, Region, region, regions, signed_distance
from kcheck.mechanics.deepest import deepest_point
from kcheck.mechanics.dynamics import Problem, with_load
from kcheck.mechanics.friction_range import range_caps
from kcheck.mechanics.kinematics import unit_rows
from kcheck.mechanics.outcomes import closing_conditions
from kcheck.mechanics.sphere import SafeFraction, safe_fraction
from kcheck.numerics.thresholds import EPS, PLANE_BASIS_SIN
from kcheck.records import dataclass
from kcheck.scene import Scene

__all__ = [
    "SphereMap",
    "direction_caps",
    "sphere_map",
    "sphere_maps",
    "map_design",
    "sweep_given",
    "default_plane",
    "chosen_plane",
    "disjoint_cases",
]


@dataclass(frozen=True)
class SphereMap:
    """Safe directions on the sphere of force (or gravity) directions, all cases together.

    ``a`` (k,), ``c`` (k, 3) are the caps ``a + c . d > 0`` (every closing condition of every
    case); ``owner`` (k,) the index of the case each cap belongs to. Angles in rad. The safe
    region is exact (``region``); ``design_margin`` is the design direction's signed distance
    to its boundary (negative outside: minus the distance to the region), ``nearest`` the
    nearest safe direction; both None when nothing is safe.
    """

    swept: Literal["load", "gravity"]
    a: np.ndarray
    c: np.ndarray
    owner: np.ndarray
    design: np.ndarray | None
    fraction: SafeFraction
    robust: np.ndarray
    robust_margin: float
    design_margin: float | None
    case_fractions: np.ndarray
    boundary_error: float  # rad, estimated error of the region's boundary (and so of margins)
    region: Region | None = None
    #: rad: the largest cap any condition's rounding could open or move (a full or empty map
    #: has no boundary; this is what it may hide)
    hidden_error: float = 0.0
    nearest: np.ndarray | None = None
    lattice: SafeFraction | None = None

    @property
    def empty(self) -> bool:
        """Whether no direction is safe."""
        return self.region is not None and self.region.empty


def direction_caps(
    problem: Problem, analysis: Analysis
) -> tuple[Literal["load", "gravity"], np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Caps of every case's closing conditions as affine functions of the swept direction.

    With a load the direction is the load's; without one it is gravity's, whose magnitude is
    kept: the wrench ``[torque; |m g| d]`` plus the preloads about the centre of mass.
    Returns ``(swept, a, c, owner, cap_errors)``: ``cap_errors`` (k,) the angular error (rad)
    of each cap's boundary. Over a kinetic friction range, each case's caps are those of
    :func:`kcheck.mechanics.friction_range.range_caps` (closing for every coefficient), and their
    error includes how far a sampled envelope may lie from the true boundary.
    """
    swept = problem.swept
    a_all, c_all, owner, err_all, extra = [], [], [], [], []
    b0, big_b = problem.gravity_basis()
    ranged = analysis.friction_range
    forms = None
    if ranged is not None:
        forms = ranged.range_cases if swept == "load" else ranged.for_wrench(b0, big_b)
    for i, case in enumerate(analysis.cases):
        if case.forward is None or not case.well_conditioned:
            continue
        if swept == "gravity":
            case = with_load(case, b0, big_b)
        a, c, err = closing_conditions(case)
        moved = 0.0
        if forms is not None and forms[i] is not None:
            # Over a friction range: the caps that close for every coefficient of it, their
            # coefficients as exact as the equations (condition number times rounding).
            a, c, moved = range_caps(forms[i])
            assert case.forward is not None  # checked above (with_load keeps it)
            err = case.forward.condition * EPS * (np.abs(a) + np.abs(c).sum(axis=1))
        a_all.append(a)
        c_all.append(c)
        owner.append(np.full(len(a), i))
        err_all.append(err)
        extra.append(np.full(len(a), moved))
    if not a_all:
        return swept, np.zeros(0), np.zeros((0, 3)), np.zeros(0, int), np.zeros(0)
    a_cat, c_cat = np.concatenate(a_all), np.vstack(c_all)
    errors = _cap_errors(a_cat, c_cat, np.concatenate(err_all)) + np.concatenate(extra)
    return swept, a_cat, c_cat, np.concatenate(owner), errors


def _cap_errors(a: np.ndarray, c: np.ndarray, error: np.ndarray) -> np.ndarray:
    """Angular error (rad) of each cap's boundary: the condition's coefficient error over its
    rate of change across the boundary, ``sqrt(|c|^2 - a^2)`` (as for the sweep-plane arcs),
    scaled per condition so that nothing overflows.

    A condition with no boundary (``|a| >= |c|``: it holds for every direction, or for none)
    gets the angular radius of the cap its coefficients' error could open,
    ``arccos((|a| - error) / |c|)`` (0 when it cannot open one, π for a condition that is
    zero to within its error): what a full or empty map may hide."""
    size = np.maximum(np.abs(a), np.abs(c).max(axis=1)) if len(a) else np.zeros(0)
    size = np.where(size > 0, size, 1.0)
    an, cn, en = a / size, c / size[:, None], error / size
    norm = np.linalg.norm(cn, axis=1) if len(a) else np.zeros(0)
    slope = np.sqrt(np.maximum(norm * norm - an * an, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        hidden = np.where(
            norm > 0,
            np.arccos(np.clip((np.abs(an) - en) / np.where(norm > 0, norm, 1.0), -1.0, 1.0)),
            np.where(np.abs(an) <= en, np.pi, 0.0),
        )
        return np.where(slope > 0, en / slope, hidden)


def sphere_map(scene: Scene, analysis: Analysis, lattice_points: int = 0) -> SphereMap | None:
    """The safe-direction map of a spatial scene, or None when no case can be mapped.

    ``lattice_points`` > 0 also counts the safe share on that many lattice directions.
    """
    return sphere_maps([scene], [analysis], lattice_points)[0]


def sphere_maps(
    scenes: Sequence[Scene], analyses: Sequence[Analysis], lattice_points: int = 0
) -> list[SphereMap | None]:
    """:func:`sphere_map` of several scenes (a worker's chunk: a study's variants): the
    regions of every case of every scene in one batch (:func:`kcheck.mechanics.caps.regions`);
    each map is the scene's alone."""
    caps = [direction_caps(a.problem, a) for a in analyses]
    owners = [np.unique(owner) for _, _, _, owner, _ in caps]
    # Every case's own region (its share of the sphere), all scenes' at once. (Each scene's
    # safe region, of its every cap, alone: stacked, those larger arrays leave the cache.)
    each = iter(
        regions(
            [
                (a[owner == i], c[owner == i])
                for (_, a, c, owner, _), ids in zip(caps, owners, strict=True)
                for i in ids
            ]
        )
    )
    safe = [region(a, c) if len(a) else None for _, a, c, _, _ in caps]
    out: list[SphereMap | None] = []
    for scene, analysis, (swept, a, c, owner, cap_errors), ids, region_ in zip(
        scenes, analyses, caps, owners, safe, strict=True
    ):
        case_fractions = np.full(len(analysis.cases), np.nan)
        for i in ids:
            case_fractions[i] = next(each).fraction
        if region_ is None:
            out.append(None)
            continue
        out.append(
            _assemble(
                scene,
                analysis,
                swept,
                region_,
                a,
                c,
                owner,
                cap_errors,
                case_fractions,
                lattice_points,
            )
        )
    return out


def _assemble(
    scene: Scene,
    analysis: Analysis,
    swept: Literal["load", "gravity"],
    safe: Region,
    a: np.ndarray,
    c: np.ndarray,
    owner: np.ndarray,
    cap_errors: np.ndarray,
    case_fractions: np.ndarray,
    lattice_points: int,
) -> SphereMap:
    """One scene's map from its caps, its safe region (of every cap) and its cases' shares:
    the region's margins, the nearest and most robust directions, the area's error."""
    design = map_design(scene, analysis, swept)
    # The region's boundary (and so every margin) moves by the error of the caps that bound it.
    bounding = safe.caps.source[safe.bounding]
    boundary_error = float(cap_errors[bounding].max()) if len(bounding) else 0.0
    robust, robust_margin = deepest_point(safe)
    if robust is None or robust_margin is None:  # no cap bounds anything: every direction
        robust, robust_margin = (np.array([0.0, 0.0, 1.0]) if design is None else design), np.pi
    design_margin = nearest = None
    if design is not None:
        design_margin, nearest = signed_distance(safe, design)
    # Area error: each cap's part of the boundary moves by the cap's angular error along its
    # length — independent roundings, so added in quadrature — plus the rounding of the arc
    # integrals (a few eps of the area and of the boundary's length).
    moved = 0.0
    if safe.lengths is not None:
        moved = float(np.sqrt(np.sum((safe.lengths * cap_errors[safe.caps.source]) ** 2)))
    error = (moved + 4 * EPS * (safe.area + safe.perimeter)) / FOUR_PI
    return SphereMap(
        swept=swept,
        a=a,
        c=c,
        owner=owner,
        design=design,
        fraction=SafeFraction(safe.fraction, error, 0),
        robust=robust,
        robust_margin=robust_margin,
        design_margin=design_margin,
        case_fractions=case_fractions,
        boundary_error=boundary_error,
        region=safe,
        hidden_error=float(cap_errors.max()),
        nearest=None if design_margin is None or design_margin >= 0 else nearest,
        lattice=safe_fraction(a, c, lattice_points) if lattice_points > 0 else None,
    )


def map_design(
    scene: Scene, analysis: Analysis, swept: Literal["load", "gravity"]
) -> np.ndarray | None:
    """The map's design direction: the load's (``swept`` load), else the scene's gravity's
    (unit), else None."""
    if swept == "load":
        return analysis.design
    if np.any(scene.gravity):
        return unit_rows(scene.gravity)
    return None


def sweep_given(scene: Scene) -> bool:
    """Whether the scene chose its sweep plane (a ``sweep:`` entry, or a plane other than the
    default xy-plane set programmatically)."""
    if scene.sweep.given:
        return True
    default = np.allclose(scene.sweep.normal, [0, 0, 1]) and np.allclose(scene.sweep.e1, [1, 0, 0])
    return not default


def default_plane(design: np.ndarray | None, robust: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The sweep plane ``(e1, e2)`` through the design direction (angle 0) and the most robust
    direction; without a design direction (or with the two parallel), the vertical plane
    through the most robust direction (or the xz-plane when it is vertical)."""
    zero = robust if design is None else design
    zero = zero / np.linalg.norm(zero)
    for towards in (robust, np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])):
        e2 = towards - (towards @ zero) * zero
        if np.linalg.norm(e2) > PLANE_BASIS_SIN:
            return zero, e2 / np.linalg.norm(e2)
    return zero, np.array([0.0, 1.0, 0.0])  # unreachable: x and z cannot both be parallel


def chosen_plane(
    design: np.ndarray | None, towards: np.ndarray | None, what: str = "most robust"
) -> tuple[np.ndarray, np.ndarray, str] | None:
    """The sweep plane ``(e1, e2)`` of a spatial scene without ``sweep:``, and why (the
    ``sweep_plane.chosen`` text): through the design direction (angle 0) and ``towards`` (the
    map's ``what`` direction, e.g. its most robust one) (:func:`default_plane`); without a
    ``towards``, the vertical plane through the design direction; None without either."""
    if towards is not None:
        e1, e2 = default_plane(design, towards)
        if design is None:
            return e1, e2, f"through the {what} direction"
        return e1, e2, f"through the design and {what} directions"
    if design is not None:
        e1, e2 = default_plane(design, design)
        return e1, e2, "the vertical plane through the design direction"
    return None


def disjoint_cases(smap: SphereMap, analysis: Analysis) -> tuple[int, int] | None:
    """Two cases whose safe regions do not overlap, if any (the first such pair in order).

    Every pair's region in one batch (:func:`kcheck.mechanics.caps.regions`, each the one it
    gets alone): an empty map asks about all of them anyway when no pair is disjoint."""
    cases = [i for i in np.unique(smap.owner) if smap.case_fractions[i] > 0]
    pairs = [(i, j) for n, i in enumerate(cases) for j in cases[n + 1 :]]
    masks = [(smap.owner == i) | (smap.owner == j) for i, j in pairs]
    found = regions([(smap.a[both], smap.c[both]) for both in masks])
    for (i, j), pair_region in zip(pairs, found, strict=True):
        if pair_region.empty:
            return int(i), int(j)
    return None
