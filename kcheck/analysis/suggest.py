"""Where to put the closing force: search attachment points and force directions for the
largest angular margin over every retracted support (``kcheck suggest``, docs/suggest.md).

For one friction assumption the system matrix of a retracted case does not depend on where the
load acts or where it points (:mod:`kcheck.mechanics.dynamics`); the right-hand side is
``b0 + s [(q - c) x d; d]`` for a unit direction ``d`` at the point ``q``. So every unknown is

    x_k(q, d) = a_k + C_k(q) . d,    C_k(q) = g_k x (q - c) + h_k

with ``a = M^-1 b0`` and ``[g_k, h_k]`` the rows of ``s M^-1``, all fixed per case: each
candidate point's caps on the sphere of directions follow in closed form, for all points at
once. The margin of a point is the largest, over directions, of the smallest angular distance
to a cap boundary (:func:`kcheck.mechanics.arcs.cap_margin_matrix`, the quantity `analytical-3d`
reports as the design margin); the best points are refined with
:func:`kcheck.mechanics.sphere.most_robust_direction`, and the best few points then with a
continuous search over the point (:func:`polish_point`).

A planar scene is the same in the plane: ``C_k(q) = g_k perp(q - c) + h_k`` with the scalar
moment row ``g_k``, arcs instead of caps, and the exact most robust angle
(:func:`kcheck.mechanics.robust_angle.most_robust_angle`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import TYPE_CHECKING

import numpy as np

from kcheck.analysis import analyse
from kcheck.analysis.candidates import Sampler, SuggestError
from kcheck.analysis.cases import problem_for
from kcheck.mechanics.arcs import cap_margin_matrix, cap_margins
from kcheck.mechanics.deepest import most_robust_direction
from kcheck.mechanics.dynamics import Problem, analyse_case, solve_affine
from kcheck.mechanics.robust_angle import most_robust_angle
from kcheck.mechanics.sphere import fibonacci_sphere
from kcheck.numerics.thresholds import (
    LEAST_FORCE_RTOL,
    POLISH_FTOL,
    POLISH_XTOL,
    SAME_POINT_RTOL,
)
from kcheck.records import dataclass
from kcheck.scene import Load, Scene

if TYPE_CHECKING:
    from kcheck.result import MassProperties

__all__ = [
    "Caps",
    "Candidate",
    "Search",
    "point_caps",
    "caps_at",
    "point_margins",
    "search",
    "polish_point",
    "direction_grid",
    "best_direction",
    "limiting_friction_at",
    "with_load",
    "best_margin",
    "least_force",
]

# Entries of the (directions x points x caps) margin block evaluated at once (~32 MB).
BLOCK = 4_000_000


@dataclass(frozen=True)
class Caps:
    """Every case's unknowns as ``a + (g x r + h) . d`` with ``r = q~ - c~`` (nondimensional).

    ``a`` (k,), ``g`` and ``h`` (k, 3); ``owner`` (k,) the retracted support of each cap and
    ``friction`` (k,) the (largest) friction coefficient of the set it was built for.
    """

    problem: Problem
    a: np.ndarray
    g: np.ndarray
    h: np.ndarray
    owner: np.ndarray
    friction: np.ndarray


def point_caps(problem: Problem, frictions: Sequence[np.ndarray] | None = None) -> Caps:
    """Caps of every case, for each set of friction coefficients (k,) given (default the
    scene's); with several sets, the caps of all of them: a point must be safe for each."""
    if not problem.load_scale > 0:
        raise SuggestError("the scene has no closing load to place (give `load` or --magnitude)")
    a_all, g_all, h_all, owner, mu = [], [], [], [], []
    b0, _ = problem.load_basis()
    nw = 1 if problem.dim == 2 else 3  # moment components of a wrench
    unit = problem.load_scale * np.eye(nw + problem.dim)
    for mu_set in [problem.friction] if frictions is None else frictions:
        scaled = dataclasses.replace(problem, friction=np.asarray(mu_set, float))
        for r in range(len(problem.names)):
            case = analyse_case(scaled, r)
            if case.forward is None or not case.well_conditioned:
                raise SuggestError(
                    f"retracting {problem.names[r]} leaves no unique motion or nearly singular "
                    "equations: no closing force can be placed (see the maxwell check)"
                )
            solved = solve_affine(case.forward.matrix, b0, unit)
            a_all.append(solved.a)
            g_all.append(solved.c[:, :nw])
            h_all.append(solved.c[:, nw:])
            owner.append(np.full(len(solved.a), r))
            mu.append(np.full(len(solved.a), float(np.max(mu_set))))
    return Caps(
        problem,
        np.concatenate(a_all),
        np.vstack(g_all),
        np.vstack(h_all),
        np.concatenate(owner),
        np.concatenate(mu),
    )


def caps_at(caps: Caps, points: np.ndarray) -> np.ndarray:
    """Direction coefficients ``C`` (m, k, 3) of every cap at points (m, 3) in metres."""
    r = caps.problem.frame.point(np.asarray(points, float)) - caps.problem.com
    if caps.problem.dim == 2:  # the moment of d at r is r x d = perp(r) . d, perp(r) = (-ry, rx)
        perp = np.column_stack([-r[:, 1], r[:, 0]])
        return caps.g[None, :, :] * perp[:, None, :] + caps.h[None, :, :]
    return np.cross(caps.g[None, :, :], r[:, None, :]) + caps.h[None, :, :]


def direction_grid(dim: int, count: int) -> np.ndarray:
    """``count`` unit directions spread evenly: a Fibonacci sphere, or a circle in a plane."""
    if dim == 3:
        return fibonacci_sphere(count)
    angles = np.arange(count) * (2.0 * np.pi / count)
    return np.column_stack([np.cos(angles), np.sin(angles)])


def grid_spacing(dim: int, count: int) -> float:
    """Typical angle (rad) between neighbours of :func:`direction_grid`."""
    return float(np.sqrt(4 * np.pi / count)) if dim == 3 else 2.0 * np.pi / count


def best_direction(caps: Caps, c: np.ndarray) -> tuple[np.ndarray, float]:
    """The exact most robust direction (3,) for the direction coefficients ``c`` (k, dim) of
    one point, and its margin (rad): on the sphere, or in the plane (``z = 0``)."""
    if caps.problem.dim == 3:
        direction, margin = most_robust_direction(caps.a, c)
        # The margin the direction really has: the deepest point of the caps that bound the
        # region knows nothing of a condition that holds nowhere (its c is 0 and a < 0).
        return direction, min(margin, float(cap_margins(caps.a, c, direction[None])[0]))
    direction, margin = most_robust_angle(caps.a, c)
    return np.append(direction, 0.0), margin


def point_margins(
    caps: Caps, points: np.ndarray, directions: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Best grid margin (rad) and the index of its direction, for each point (m, 3) in m.

    Evaluates the exact cap margins of ``directions`` (n, 3) at every point, in blocks.
    """
    points = np.asarray(points, float)
    k, n = len(caps.a), len(directions)
    chunk = max(1, BLOCK // max(1, n * k))
    best = np.empty(len(points))
    index = np.empty(len(points), dtype=int)
    for start in range(0, len(points), chunk):
        c = caps_at(caps, points[start : start + chunk])
        m = len(c)
        a = np.broadcast_to(caps.a, (m, k)).reshape(-1)
        block = cap_margin_matrix(a, c.reshape(m * k, -1), directions).reshape(n, m, k).min(axis=2)
        index[start : start + m] = np.argmax(block, axis=0)
        best[start : start + m] = block[index[start : start + m], np.arange(m)]
    return best, index


@dataclass(frozen=True)
class Candidate:
    """A suggested attachment point (m) and unit force direction, its margin (rad) over every
    retracted case, the limiting friction there, and the surface's outward normal."""

    point: np.ndarray
    direction: np.ndarray
    margin: float
    limiting_friction: float | None
    normal: np.ndarray | None = None

    @property
    def pushes(self) -> bool | None:
        """Whether the force pushes into the surface (None off the surface)."""
        return None if self.normal is None else bool(self.direction @ self.normal < 0)


@dataclass(frozen=True)
class Search:
    """Every candidate point (m, 3) with its best grid margin (rad) and direction, the
    refined best candidates (best first), the grid spacing (rad) and the friction values
    searched over (the largest coefficient of each set)."""

    points: np.ndarray
    margins: np.ndarray
    directions: np.ndarray
    best: tuple[Candidate, ...]
    spacing: float
    frictions: tuple[float, ...]


def _margins_job(args: tuple[Caps, np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    return point_margins(*args)


def _chunks(points: np.ndarray, size: int) -> Iterator[np.ndarray]:
    for start in range(0, len(points), size):
        yield points[start : start + size]


def limiting_friction_at(
    scene: Scene, mass: MassProperties, point: np.ndarray, direction: np.ndarray
) -> float | None:
    """Smallest, over the retracted cases, of the limiting friction with the load at ``point``
    pointing along ``direction`` (:func:`kcheck.mechanics.friction.limiting_friction`)."""
    analysis = analyse(with_load(scene, point, direction), mass)
    values = [r.limiting_friction for r in analysis.results]
    if any(v is None for v in values):
        return None
    return float(min(v for v in values if v is not None))


def with_load(
    scene: Scene, point: np.ndarray, direction: np.ndarray, magnitude: float | None = None
) -> Scene:
    """The scene with its closing load moved to ``point`` (m) along ``direction``."""
    old = scene.load
    torque = np.zeros(3) if old is None else old.torque
    size = magnitude if magnitude is not None else (0.0 if old is None else old.magnitude)
    unit = np.asarray(direction, float) / np.linalg.norm(direction)
    return dataclasses.replace(scene, load=Load(size, np.asarray(point, float), unit, torque))


def _grid_margins(
    caps: Caps,
    points: np.ndarray,
    grid: np.ndarray,
    jobs: int,
    progress: Callable[[int], None] | None,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`point_margins` in chunks, over ``jobs`` processes, reporting progress."""
    size = max(16, min(512, len(points) // max(1, 4 * jobs) or 16))
    margins, index = np.empty(len(points)), np.empty(len(points), dtype=int)
    pieces = [(caps, chunk, grid) for chunk in _chunks(points, size)]
    done = 0
    results: Iterable[tuple[np.ndarray, np.ndarray]]
    if jobs > 1 and len(pieces) > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(_margins_job, pieces))
    else:
        results = map(_margins_job, pieces)
    for (_, chunk, _), (m, i) in zip(pieces, results, strict=True):
        margins[done : done + len(chunk)], index[done : done + len(chunk)] = m, i
        done += len(chunk)
        if progress is not None:
            progress(done)
    return margins, index


def _distinct(points: np.ndarray, order: np.ndarray, count: int, gap: float) -> list[int]:
    """The first ``count`` indices of ``order`` whose points lie ``gap`` (m) or more apart."""
    kept: list[int] = []
    for j in order:
        if all(np.linalg.norm(points[j] - points[k]) >= gap for k in kept):
            kept.append(int(j))
            if len(kept) == count:
                break
    return kept


def search(
    scene: Scene,
    mass: MassProperties,
    sampler: Sampler,
    count: int,
    *,
    directions: int = 500,
    keep: int = 5,
    refine: int = 40,
    rounds: int = 4,
    frictions: Sequence[np.ndarray] | None = None,
    jobs: int = 1,
    progress: Callable[[int], None] | None = None,
    polish: int = 3,
) -> Search:
    """Search ``count`` candidate points from ``sampler`` for the ``keep`` best candidates.

    Every point gets its best margin over ``directions`` Fibonacci directions; then ``rounds``
    times, points are added near the best five within a radius halving from twice the
    sampler's spacing; finally the ``refine`` best points get their direction refined
    (:func:`kcheck.mechanics.sphere.most_robust_direction`, exact margins) and the best ``keep`` the
    limiting friction. The ``polish`` best of these get a continuous local search over the
    point (:func:`polish_point`). ``jobs`` processes share the first pass; ``progress`` is
    called with the number of points done.
    """
    problem = problem_for(scene, mass)
    caps = point_caps(problem, frictions)
    grid = direction_grid(problem.dim, directions)
    points, normals = sampler.initial(count)
    margins, index = _grid_margins(caps, points, grid, jobs, progress)
    radius = 2.0 * sampler.spacing
    for _ in range(rounds):
        centres = points[np.argsort(-margins)[:5]]
        new, new_normals = sampler.near(centres, radius, max(20, count // 50))
        if len(new):
            m, i = point_margins(caps, new, grid)
            points, margins = np.vstack([points, new]), np.concatenate([margins, m])
            index = np.concatenate([index, i])
            if normals is not None and new_normals is not None:
                normals = np.vstack([normals, new_normals])
        radius *= 0.5
    # refine the best points (the same point found twice counts once)
    span = float(np.ptp(points, axis=0).max()) or 1.0
    order = _distinct(points, np.argsort(-margins), max(keep, refine), SAME_POINT_RTOL * span)
    refined = []
    for j in order:
        c = caps_at(caps, points[j : j + 1])[0]
        direction, margin = best_direction(caps, c)
        refined.append((margin, j, direction))
    refined.sort(key=lambda t: -t[0])
    # a few more than kept: starts the search joins count once
    chosen = _distinct(points, np.array([j for _, j, _ in refined]), keep + polish, sampler.spacing)
    by_index = {j: (margin, direction) for margin, j, direction in refined}
    # The sampled optimum is within a sampling step of the true one: a continuous search over
    # the point (its direction exact at every step) closes that gap.
    found: list[tuple[float, np.ndarray, np.ndarray, np.ndarray | None]] = []
    for rank, j in enumerate(chosen):
        normal = None if normals is None else normals[j]
        margin, direction = by_index[j]
        start = (margin, points[j], direction, normal)
        found.append(polish_point(caps, sampler, start) if rank < polish else start)
    found.sort(key=lambda t: -t[0])
    at = np.array([f[1] for f in found])
    best = []
    for k in _distinct(at, np.arange(len(found)), keep, sampler.spacing):
        margin, point, direction, normal = found[k]
        friction = limiting_friction_at(scene, mass, point, direction) if margin > 0 else None
        best.append(Candidate(point, direction, margin, friction, normal))
    return Search(
        points,
        margins,
        np.pad(grid[index], ((0, 0), (0, 3 - problem.dim))),  # a plane's as (x, y, 0)
        tuple(best),
        grid_spacing(problem.dim, directions),
        tuple(float(f) for f in np.unique(caps.friction)),
    )


def polish_point(
    caps: Caps,
    sampler: Sampler,
    start: tuple[float, np.ndarray, np.ndarray, np.ndarray | None],
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray | None]:
    """Nelder–Mead over the point about ``start`` ``(margin, point, direction, normal)``: in
    the surface's tangent plane (each step moved onto the mesh) or the box, the direction
    exact at every point (:func:`kcheck.mechanics.sphere.most_robust_direction`), the
    simplex first a sampling step wide. Returns the better of the start and the end."""
    from scipy.optimize import minimize

    step = sampler.spacing or 1e-3
    chart = sampler.chart(start[1], 4.0 * step)
    if chart.dims == 0:
        return start

    def margin_at(x: np.ndarray) -> float:
        point, _ = chart.point(x)
        return -best_direction(caps, caps_at(caps, point[None])[0])[1]

    simplex = np.vstack([np.zeros(chart.dims), step * np.eye(chart.dims)])
    end = minimize(
        margin_at,
        np.zeros(chart.dims),
        method="Nelder-Mead",
        options={
            "initial_simplex": simplex,
            "xatol": POLISH_XTOL * step,
            "fatol": POLISH_FTOL,
            "maxfev": 400,
        },
    )
    point, normal = chart.point(end.x)
    direction, margin = best_direction(caps, caps_at(caps, point[None])[0])
    if margin <= start[0]:
        return start
    return margin, point, direction, start[3] if normal is None else normal


def best_margin(
    scene: Scene, mass: MassProperties, points: np.ndarray, magnitude: float, directions: int
) -> float:
    """The best grid margin (rad) over candidate points with the load at ``magnitude`` (N)."""
    loaded = with_load(scene, points[0], np.array([0.0, 0.0, 1.0]), magnitude)
    caps = point_caps(problem_for(loaded, mass))
    margins, _ = point_margins(caps, points, direction_grid(scene.dim, directions))
    return float(margins.max())


def least_force(
    scene: Scene,
    mass: MassProperties,
    points: np.ndarray,
    *,
    start: float,
    directions: int = 500,
    rtol: float = LEAST_FORCE_RTOL,
    limit: float = 1000.0,
) -> float | None:
    """The least load magnitude (N) at which some candidate point has a safe direction.

    Doubles from ``start`` (where none is safe) until one is, up to ``limit`` times ``start``,
    then bisects to ``rtol``; None when even the limit is not enough.
    """
    low, high = start, start
    while best_margin(scene, mass, points, high, directions) <= 0:
        low, high = high, 2.0 * high
        if high > limit * start:
            return None
    while high - low > rtol * high:
        mid = 0.5 * (low + high)
        if best_margin(scene, mass, points, mid, directions) > 0:
            high = mid
        else:
            low = mid
    return high
