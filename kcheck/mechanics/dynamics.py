"""Newton–Euler at the instant of retraction, one implementation for planar and spatial scenes.

The body starts from rest, so its acceleration is ``lambda * xi_r`` along the free twist of the
retracted case (methods.md §3). Unknowns ``lambda`` and the normal forces ``N_j`` of the
remaining supports solve a square linear system whose matrix depends on the friction
assumption only, and whose right-hand side (the external wrench about the centre of mass) is
affine in the force direction ``d``. So every unknown is ``x(d) = a + C d`` — exact safe ranges
follow in closed form (:mod:`kcheck.mechanics.arcs`).

All arrays are nondimensional (:mod:`kcheck.mechanics.problem`): lengths by the layout size
``L``, forces by the force scale ``F`` (the largest of the load, the weight and the preloads),
masses by ``m`` (so the nondimensional mass is 1 and inertia is ``I / (m L^2)``). Equations are
ordered ``[moment about the centre of mass; force]``, like the wrenches of
:mod:`kcheck.mechanics.kinematics`.

Painlevé-type cases: with friction the system matrix ``K(mu)`` can turn singular as ``mu``
grows; ``det K(mu) / det K(0)`` is the effective mass along the free twist under that friction
(``xi'^T M xi`` with ``xi'`` the free twist of the friction-tilted reaction lines, followed
continuously from ``mu = 0``). Where it is not positive for forward or backward sliding,
rigid-body Coulomb friction gives more than one consistent outcome, or none: such a case is
``ambiguous`` and has no safe direction.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from kcheck.mechanics.kinematics import (
    FreeTwist,
    free_twist_arrays,
    other_supports,
    point_velocity,
    wrenches,
)
from kcheck.mechanics.problem import Problem, build_problem, log_size, relative
from kcheck.numerics.thresholds import EPS, ILL_CONDITIONED, SLIP_TOL, TINY, UNDETERMINED
from kcheck.records import dataclass

__all__ = [
    "Problem",
    "Affine",
    "Case",
    "SLIP_TOL",
    "ILL_CONDITIONED",
    "build_problem",
    "log_size",
    "relative",
    "friction_directions",
    "system_matrix",
    "system_parts",
    "friction_matrices",
    "contact_matrices",
    "solve_affine",
    "analyse_case",
    "analyse_cases",
    "analyse_cases_many",
    "with_load",
]

# Forward error of a solve: this many roundings per unit of condition number, and of a free
# twist per unit of its inverse determinacy (calibrated against 50-digit solutions: the
# estimate stays above the actual error, typically within 10x; tests/kcheck/test_errors.py).
ROUNDINGS = 1.0
TWIST_ROUNDINGS = 1.0


@dataclass(frozen=True)
class Affine:
    """Unknowns ``x(d) = a + c @ d`` (``x = [lambda, N_1, ...]``) for one friction assumption."""

    matrix: np.ndarray
    a: np.ndarray
    c: np.ndarray
    condition: float
    error: np.ndarray  # estimated absolute error of each unknown (nondimensional)

    def at(self, direction: np.ndarray | None) -> np.ndarray:
        """Unknowns for a unit force direction, or for the fixed wrench alone."""
        return self.a if direction is None else self.a + self.c @ direction


@dataclass(frozen=True)
class Case:
    """One retracted support: free motion, sliding of the others, both friction assumptions.

    ``effective_mass`` is ``det K / det K(mu = 0)`` under forward and under backward friction:
    the effective mass along the free twist relative to the frictionless one (1 without
    friction); a value <= 0 makes the case Painlevé-type (``ambiguous``).
    """

    retracted: int
    keep: np.ndarray  # indices of the remaining supports
    free: FreeTwist
    sliding: np.ndarray  # (k-1,) bool: does the contact slide under the free twist
    forward: Affine | None
    backward: Affine | None
    effective_mass: tuple[float, float] | None = None
    k0: np.ndarray | None = None  # system matrix without friction
    k_friction: np.ndarray | None = None  # its change per unit of mu (scene's pattern)

    @property
    def determined(self) -> bool:
        """Whether the free motion is unique (one-dimensional null space, closes the gap)."""
        return self.free.determinacy > UNDETERMINED and self.free.closing > UNDETERMINED

    @property
    def well_conditioned(self) -> bool:
        """Whether both linear systems are far enough from singular to trust their numbers."""
        return all(
            s is not None and s.condition < ILL_CONDITIONED for s in (self.forward, self.backward)
        )

    @property
    def painleve(self) -> bool:
        """Whether friction makes the effective mass along the free twist non-positive."""
        return self.effective_mass is not None and min(self.effective_mass) <= 0.0


def friction_directions(
    twist: np.ndarray, points: np.ndarray, sense: int
) -> tuple[np.ndarray, np.ndarray]:
    """Unit friction directions opposing sliding at contacts, and which contacts slide.

    ``sense`` +1 opposes the motion along the twist (forward), -1 the reverse. Contacts that do
    not slide get a zero direction (undetermined friction, set to zero as in the thesis).
    """
    u = point_velocity(twist, points)
    speed = np.sqrt(np.einsum("ij,ij->i", u, u))
    sliding = speed > SLIP_TOL
    t = np.where(sliding[:, None], -sense * u / np.where(sliding, speed, 1.0)[:, None], 0.0)
    return t, sliding


def contact_matrices(
    twists: np.ndarray,
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    com: np.ndarray,
    inertia: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``K0``, ``F`` (..., n, n) and sliding (..., k-1) of free twists (..., n) with the
    remaining supports' points and unit normals (..., k-1, dim) and coefficients (..., k-1),
    about the centre of mass ``com`` (..., dim) with inertia ``inertia`` (..., nw, nw), both
    broadcast against the twists' leading axes (nondimensional; any leading axes, e.g. cases,
    samples and cases, or problems and cases). See :func:`system_parts`."""
    nw = 1 if points.shape[-1] == 2 else 3
    u = point_velocity(twists[..., None, :], points)
    speed = np.sqrt(np.sum(u * u, axis=-1))
    sliding = speed > SLIP_TOL
    t = np.where(sliding[..., None], -u / np.where(sliding, speed, 1.0)[..., None], 0.0)
    lever = points - com[..., None, :]
    normal = -wrenches(lever, normals)  # (..., k-1, n)
    friction = -wrenches(lever, mu[..., None] * t)
    # I w row by row, not a matrix product: the same sums whatever the stack, so a batch of
    # problems gives each problem's own result bit for bit.
    spin = np.sum(inertia * twists[..., None, :nw], axis=-1)
    inertial = np.concatenate([spin, point_velocity(twists, com)], axis=-1)  # (..., n)
    k0 = np.concatenate([inertial[..., :, None], np.swapaxes(normal, -1, -2)], axis=-1)
    zero = np.zeros_like(inertial)[..., :, None]
    big_f = np.concatenate([zero, np.swapaxes(friction, -1, -2)], axis=-1)
    return k0, big_f, sliding


def _parts(
    problem: Problem, twists: np.ndarray, keeps: np.ndarray, mu: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`system_parts` for a stack of cases: twists (c, n), kept supports (c, k-1), friction
    coefficients ``mu`` (k,) per support. Returns ``K0``, ``F`` (c, n, n) and sliding (c, k-1)."""
    return contact_matrices(
        twists,
        problem.points[keeps],
        problem.normals[keeps],
        mu[keeps],
        problem.com,
        problem.inertia,
    )


def system_parts(
    problem: Problem, twist: np.ndarray, keep: np.ndarray, mu: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``K = K0 + F`` under forward friction ``mu`` (``K0 - F`` under backward): ``(K0, F)``,
    and which contacts slide.

    Column 0 of ``K0`` is the inertial wrench of the unit twist acceleration ``[I w, m u(c)]``;
    column ``1 + j`` is minus the wrench of the unit normal force ``n_j``; ``F`` holds minus the
    wrenches of the friction forces ``mu_j t_j`` (``t_j`` opposing forward sliding). ``mu``
    holds the coefficients of the kept supports.
    """
    full = np.zeros(len(problem.points))
    full[keep] = mu
    k0, big_f, sliding = _parts(problem, twist[None], np.asarray(keep)[None], full)
    return k0[0], big_f[0], sliding[0]


def friction_matrices(problem: Problem, cases: Sequence[Case], mu: np.ndarray) -> np.ndarray:
    """The friction part ``F`` (c, n, n) of each case's forward system for per-support
    coefficients ``mu`` (k,): ``K = K0 + F`` (backward ``K0 - F``); linear in ``mu``."""
    twists = np.array([c.free.twist for c in cases])
    keeps = np.array([c.keep for c in cases])
    return _parts(problem, twists, keeps, np.asarray(mu, float))[1]


def system_matrix(
    problem: Problem, twist: np.ndarray, keep: np.ndarray, mu: np.ndarray, sense: int
) -> np.ndarray:
    """Matrix of ``[lambda, N_j]`` in Newton–Euler about the centre of mass, friction ``mu``
    opposing forward (``sense = +1``) or backward (``-1``) sliding (:func:`system_parts`)."""
    k0, big_f, _ = system_parts(problem, twist, keep, mu)
    return k0 + sense * big_f


def solve_each(matrices: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.linalg.solve`` of a stack (s, n, n) with right-hand sides (s, n, m), and which
    were solved (s,): a batch fails as a whole when LAPACK finds one matrix singular; then
    each is solved alone, so one singular system does not spoil the others of a stack (NaN)."""
    try:
        return np.linalg.solve(matrices, rhs), np.ones(len(matrices), bool)
    except np.linalg.LinAlgError:
        out = np.full(rhs.shape, np.nan)
        ok = np.zeros(len(matrices), bool)
        for i, (a, b) in enumerate(zip(matrices, rhs, strict=True)):
            try:
                out[i], ok[i] = np.linalg.solve(a, b), True
            except np.linalg.LinAlgError:
                pass
        return out, ok


def _equilibrate(matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row and column scale factors (..., n) making every row and column's largest entry 1."""
    size = np.abs(matrices)
    rows = size.max(axis=-1)
    # A row or column below the smallest normal number carries nothing: leave it unscaled
    # (its reciprocal would overflow).
    rows = 1.0 / np.where(rows > TINY, rows, 1.0)
    cols = (size * rows[..., :, None]).max(axis=-2)
    cols = 1.0 / np.where(cols > TINY, cols, 1.0)
    return rows, cols


@dataclass(frozen=True)
class _Systems:
    """What the solves of a stack of matrices (s, n, n) share whatever the right-hand side:
    the row and column scale factors, the equilibrated matrices, their condition numbers,
    which can be solved, and the relative error the matrices carry (:func:`_systems`)."""

    matrices: np.ndarray
    rows: np.ndarray
    cols: np.ndarray
    scaled: np.ndarray
    condition: np.ndarray
    good: np.ndarray
    built: np.ndarray

    def part(self, start: int, stop: int) -> _Systems:
        """The systems ``start:stop`` of the stack (views)."""
        return _Systems(*(getattr(self, f)[start:stop] for f in _SYSTEMS_FIELDS))


_SYSTEMS_FIELDS = ("matrices", "rows", "cols", "scaled", "condition", "good", "built")


def _join(parts: Sequence[_Systems]) -> _Systems:
    """Stacks of systems one after another."""
    return _Systems(*(np.concatenate([getattr(p, f) for p in parts]) for f in _SYSTEMS_FIELDS))


def _systems(matrices: np.ndarray, matrix_error: np.ndarray | None = None) -> _Systems:
    """Equilibration and condition numbers of a stack of matrices (s, n, n): everything of
    :func:`_solve_many` but the right-hand side. ``matrix_error`` (s,): the relative error
    the matrices carry from their construction (e.g. the free twist's)."""
    rows, cols = _equilibrate(matrices)
    scaled = matrices * rows[..., :, None] * cols[..., None, :]
    with np.errstate(all="ignore"):
        try:
            singular = np.linalg.svd(scaled, compute_uv=False)
        except np.linalg.LinAlgError:  # non-finite entries
            singular = np.zeros(scaled.shape[:-1])
        condition = np.where(singular[..., -1] > 0, singular[..., 0] / singular[..., -1], np.inf)
    good = np.isfinite(condition) & (condition <= 1 / EPS)
    built = np.zeros(len(matrices)) if matrix_error is None else np.asarray(matrix_error, float)
    return _Systems(matrices, rows, cols, scaled, condition, good, built)


def _solve_systems(systems: _Systems, rhs: np.ndarray) -> list[Affine]:
    """:func:`_solve_many` of prepared systems (:func:`_systems`), each matrix equilibrated,
    decomposed and solved on its own (a stack gives each system's own values)."""
    matrices, rows, cols, scaled = systems.matrices, systems.rows, systems.cols, systems.scaled
    condition, good = systems.condition, systems.good.copy()
    n = rhs.shape[-2]
    rhs = np.broadcast_to(rhs, (len(matrices), *rhs.shape[-2:]))
    out: list[Affine] = []
    sol = np.full((len(matrices), n, rhs.shape[-1]), np.nan)
    if np.any(good):
        scaled_rhs = rhs[good] * rows[good][:, :, None]
        solved, ok = solve_each(scaled[good], scaled_rhs)
        sol[good] = solved * cols[good][:, :, None]
        good[good] = ok
    # Forward error: the condition number times the matrix's own relative error and the
    # solve's rounding (LU with pivoting is backward stable: its residual is of that size).
    with np.errstate(all="ignore"):
        errors = (condition * (EPS * ROUNDINGS + systems.built))[:, None] * np.abs(sol).sum(axis=2)
    errors[~good] = np.inf
    conditions = np.where(good, condition, np.inf).tolist()
    for k, matrix in enumerate(matrices):
        x = sol[k]
        out.append(Affine(matrix, x[:, 0], x[:, 1:], conditions[k], errors[k]))
    return out


def _solve_many(
    matrices: np.ndarray, rhs: np.ndarray, matrix_error: np.ndarray | None = None
) -> list[Affine]:
    """:func:`solve_affine` for a stack of matrices (s, n, n) with one right-hand side
    (n, 1 + dim) or one each (s, n, 1 + dim), in one batch of numpy calls. ``matrix_error``
    (s,): the relative error the matrices carry from their construction (e.g. the free
    twist's), for the error estimate."""
    return _solve_systems(_systems(matrices, matrix_error), rhs)


def solve_affine(matrix: np.ndarray, b0: np.ndarray, big_b: np.ndarray) -> Affine:
    """Solve ``K x = b0 + B d`` for the affine coefficients, with conditioning and error.

    Rows and columns are equilibrated first, so the condition number measures the geometry,
    not the choice of units or how mass compares with inertia. A singular (or non-finite)
    system gives NaN coefficients and an infinite condition number.
    """
    return _solve_many(matrix[None], np.column_stack([b0, big_b]))[0]


def _effective_masses(k0: np.ndarray, big_f: np.ndarray) -> list[tuple[float, float] | None]:
    """Per case, ``det(K0 + F) / det K0`` and ``det(K0 - F) / det K0`` (see :class:`Case`);
    ``k0``, ``big_f`` (c, n, n)."""
    rows, cols = _equilibrate(k0)
    scale = rows[:, None, :, None] * cols[:, None, None, :]  # one scaling keeps the ratios
    stack = np.stack([k0, k0 + big_f, k0 - big_f], axis=1) * scale
    with np.errstate(all="ignore"):
        try:
            sign, logdet = np.linalg.slogdet(stack)
        except np.linalg.LinAlgError:
            return [None] * len(k0)
        ratio = sign[:, 1:] * sign[:, :1] * np.exp(logdet[:, 1:] - logdet[:, :1])
    good = (sign[:, 0] != 0) & np.all(np.isfinite(logdet), axis=1)
    return [(float(r[0]), float(r[1])) if g else None for r, g in zip(ratio, good, strict=True)]


def analyse_cases(problem: Problem, retracted: Sequence[int] | None = None) -> tuple[Case, ...]:
    """Free motion and both friction-assumption systems for each retracted support (default:
    every support), in one batch of numpy calls (:func:`analyse_cases_many` of one problem)."""
    return analyse_cases_many([problem], retracted)[0]


def analyse_cases_many(
    problems: Sequence[Problem], retracted: Sequence[int] | None = None
) -> list[tuple[Case, ...]]:
    """:func:`analyse_cases` of several problems (e.g. the scenes of a worker's chunk): the
    problems with the same number of supports and dimension are stacked and solved in one
    batch of numpy calls (each matrix factorised on its own, so every problem's values are
    those it gets alone)."""
    out: list[tuple[Case, ...]] = [()] * len(problems)
    groups: dict[tuple[int, int], list[int]] = {}
    for i, problem in enumerate(problems):
        groups.setdefault(problem.points.shape, []).append(i)
    for (k, _), members in groups.items():
        which = np.arange(k) if retracted is None else np.asarray(retracted, dtype=int)
        solved = _cases_stacked([problems[i] for i in members], which)
        for i, cases in zip(members, solved, strict=True):
            out[i] = cases
    return out


@dataclass(frozen=True)
class _Geometry:
    """What a problem's cases are without its load (:func:`_geometries`): the free twists,
    the systems without friction and their change per unit of the pattern, which contacts
    slide, and, for the cases with a free motion (``live``), both friction systems prepared
    for solving (every forward one, then every backward one, :func:`_systems`) and the
    effective masses."""

    twists: np.ndarray  # (c, n)
    determinacy: np.ndarray  # (c,)
    closing: np.ndarray  # (c,)
    k0: np.ndarray  # (c, n, n)
    unit_f: np.ndarray  # (c, n, n)
    sliding: np.ndarray  # (c, k-1)
    live: np.ndarray  # (l,) indices of the cases solved
    forward: _Systems | None  # (l,)
    backward: _Systems | None  # (l,)
    masses: list[tuple[float, float] | None]
    joint: _Systems | None = None  # forward then backward in one stack, when computed so


#: The geometries of the last problems analysed, by :func:`_geometry_key`: a way-out
#: search's trial scenes differ from their scene only in the closing force, which is in the
#: right-hand side alone (nondimensional lengths, masses and friction do not depend on it).
_GEOMETRIES: dict[bytes, _Geometry] = {}
RECENT_GEOMETRIES = 64


def _geometry_key(problem: Problem, which: np.ndarray) -> bytes:
    """Every input of a problem's :class:`_Geometry`, as bytes."""
    pattern, mu = problem.friction_pattern()
    parts = (problem.points, problem.normals, pattern, problem.com, problem.inertia, which)
    return b"|".join(
        [
            repr((problem.points.shape, mu, len(which))).encode(),
            *(np.ascontiguousarray(x, float).tobytes() for x in parts),
        ]
    )


def _geometries(
    problems: Sequence[Problem], which: np.ndarray
) -> tuple[list[_Geometry], _Systems | None]:
    """The :class:`_Geometry` of problems with the same number of supports and dimension, in
    one batch of numpy calls (each matrix decomposed on its own: each problem's own values),
    and the batch's systems (every live case's forward one, then every backward one)."""
    k = len(problems[0].points)
    points = np.stack([p.points for p in problems])  # (P, k, dim)
    normals = np.stack([p.normals for p in problems])
    twists, determinacy, closing = free_twist_arrays(points, normals, which)  # (P, c, ...)
    keeps = other_supports(k)[which]  # (c, k-1)
    patterns = [p.friction_pattern() for p in problems]
    pattern = np.stack([pat for pat, _ in patterns])  # (P, k)
    mu = np.array([m for _, m in patterns])
    com = np.stack([p.com for p in problems])
    inertia = np.stack([p.inertia for p in problems])
    k0, unit_f, sliding = contact_matrices(
        twists,
        points[:, keeps],
        normals[:, keeps],
        pattern[:, keeps],
        com[:, None, :],
        inertia[:, None, :, :],
    )
    big_f = mu[:, None, None, None] * unit_f
    live = (determinacy > UNDETERMINED) & (closing > UNDETERMINED)  # (P, c)
    owner, case = np.nonzero(live)  # by problem, then case
    systems = None
    masses: list[tuple[float, float] | None] = []
    m = len(owner)
    if m:
        k0l, fl = k0[owner, case], big_f[owner, case]
        # The free twist (a null vector) is off by about eps over its singular-value gap; the
        # matrix built from it (inertial column, friction directions) inherits that.
        twist_error = TWIST_ROUNDINGS * EPS / determinacy[owner, case]
        systems = _systems(
            np.concatenate([k0l + fl, k0l - fl]), np.concatenate([twist_error, twist_error])
        )
        masses = _effective_masses(k0l, fl)
    ends = np.searchsorted(owner, np.arange(len(problems) + 1)).tolist()
    out = []
    for p in range(len(problems)):
        lo, hi = ends[p], ends[p + 1]
        forward = backward = None
        if systems is not None and hi > lo:
            forward, backward = systems.part(lo, hi), systems.part(m + lo, m + hi)
        out.append(
            _Geometry(
                twists[p],
                determinacy[p],
                closing[p],
                k0[p],
                unit_f[p],
                sliding[p],
                case[lo:hi],
                forward,
                backward,
                masses[lo:hi],
                systems if len(problems) == 1 else None,
            )
        )
    return out, systems


def _read_only(geometry: _Geometry) -> None:
    """Mark the arrays of a geometry that its cases hold read-only (later problems with the
    same key share them): the twists, ``K0``, the friction parts, sliding and the systems'
    matrices (the solved ``Affine.matrix``)."""
    systems = [s for s in (geometry.forward, geometry.backward, geometry.joint) if s is not None]
    arrays = [geometry.twists, geometry.k0, geometry.unit_f, geometry.sliding]
    for array in arrays + [s.matrices for s in systems]:
        array.flags.writeable = False


def _cases_stacked(problems: Sequence[Problem], which: np.ndarray) -> list[tuple[Case, ...]]:
    """:func:`analyse_cases_many` of problems with the same number of supports and dimension:
    their geometries (:func:`_geometries`, those of recent problems reused), then every
    live case's two systems solved for its problem's load in one batch."""
    keys = [_geometry_key(p, which) for p in problems]
    known = {i: _GEOMETRIES[key] for i, key in enumerate(keys) if key in _GEOMETRIES}
    missing = [i for i in range(len(problems)) if i not in known]
    batch: _Systems | None = None  # the systems of a batch computed here whole
    if missing:
        fresh, batch = _geometries([problems[i] for i in missing], which)
        for i, found in zip(missing, fresh, strict=True):
            _read_only(found)  # shared by every later problem with the same key
            known[i] = found
            if len(_GEOMETRIES) >= RECENT_GEOMETRIES:
                del _GEOMETRIES[next(iter(_GEOMETRIES))]
            _GEOMETRIES[keys[i]] = found
    geometries = [known[i] for i in range(len(problems))]
    keeps = other_supports(len(problems[0].points))[which]  # (c, k-1)
    solving = [p for p, g in enumerate(geometries) if g.forward is not None]
    by_problem: dict[int, tuple[list[Affine], list[Affine]]] = {}
    if solving:
        bases = {p: np.column_stack(problems[p].load_basis()) for p in solving}
        counts = [len(geometries[p].live) for p in solving]
        if len(solving) == 1:  # its stack, forward then backward; one right-hand side
            g = geometries[solving[0]]
            # A batch computed here holds only its solving problems' systems: this one's.
            joint = g.joint if g.joint is not None else batch
            if joint is None:
                assert g.forward is not None and g.backward is not None
                joint = _join([g.forward, g.backward])
            rhs = bases[solving[0]]
        else:  # every forward system, then every backward one, as a fresh batch has them
            if batch is None or len(missing) < len(problems):
                parts = [geometries[p].forward for p in solving]
                parts += [geometries[p].backward for p in solving]
                batch = _join([s for s in parts if s is not None])
            joint = batch
            each = np.stack(
                [bases[p] for p, n in zip(solving, counts, strict=True) for _ in range(n)]
            )
            rhs = np.concatenate([each, each])
        solved = _solve_systems(joint, rhs)
        m, start = sum(counts), 0
        for p, n in zip(solving, counts, strict=True):
            by_problem[p] = (solved[start : start + n], solved[m + start : m + start + n])
            start += n
    out = []
    for p, g in enumerate(geometries):
        by_case: dict[int, tuple[Affine, Affine, tuple[float, float] | None]] = {}
        if p in by_problem:
            forwards, backwards = by_problem[p]
            for j, c in enumerate(g.live.tolist()):
                by_case[c] = (forwards[j], backwards[j], g.masses[j])
        cases = []
        for i, r in enumerate(which.tolist()):
            free = FreeTwist(g.twists[i], float(g.determinacy[i]), float(g.closing[i]))
            forward, backward, mass = by_case.get(i, (None, None, None))
            matrices = g.k0[i], g.unit_f[i]
            cases.append(Case(r, keeps[i], free, g.sliding[i], forward, backward, mass, *matrices))
        out.append(tuple(cases))
    return out


def analyse_case(problem: Problem, retracted: int) -> Case:
    """Free motion and both friction-assumption systems for one retracted support."""
    return analyse_cases(problem, [retracted])[0]


def with_load(case: Case, b0: np.ndarray, big_b: np.ndarray) -> Case:
    """The same case with another external wrench ``b0 + B d`` (e.g. gravity's direction swept
    instead of the load's): both systems solved again, the friction assumptions unchanged."""
    if case.forward is None or case.backward is None:
        return case
    fwd, bwd = _solve_many(
        np.stack([case.forward.matrix, case.backward.matrix]), np.column_stack([b0, big_b])
    )
    return replace(case, forward=fwd, backward=bwd)
