"""Newton–Euler at the instant of retraction, one implementation for planar and spatial scenes.

The body starts from rest, so its acceleration is ``lambda * xi_r`` along the free twist of the
retracted case (methods.md §3). Unknowns ``lambda`` and the normal forces ``N_j`` of the
remaining supports solve a square linear system whose matrix depends on the friction
assumption only, and whose right-hand side (the external wrench about the centre of mass) is
affine in the force direction ``d``. So every unknown is ``x(d) = a + C d`` — exact safe ranges
follow in closed form (:mod:`kcheck.arcs`).

All arrays are nondimensional (:class:`kcheck.kinematics.Frame`): lengths by the layout size
``L``, forces by the force scale ``F`` (the load, or the weight without one), masses by ``m``
(so the nondimensional mass is 1 and inertia is ``I / (m L^2)``). Equations are ordered
``[moment about the centre of mass; force]``, like the wrenches of :mod:`kcheck.kinematics`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from kcheck.arcs import ArcSet, affine_arcs
from kcheck.kinematics import Frame, FreeTwist, free_twist, point_velocity, wrenches

__all__ = [
    "Problem",
    "Affine",
    "Case",
    "Outcome",
    "SLIP_TOL",
    "ILL_CONDITIONED",
    "build_problem",
    "friction_directions",
    "system_matrix",
    "solve_affine",
    "analyse_case",
    "outcome",
    "outcomes",
    "safe_arcs",
    "limiting_friction",
]

Outcome = Literal["closes", "loses_contact", "opens", "jams", "undetermined", "ill_conditioned"]

# A contact whose nondimensional speed under the unit free twist is below this does not slide:
# its friction direction is undetermined and, as in the thesis, its friction is set to zero.
SLIP_TOL = 1e-9
# Condition number (of the equilibrated system) above which numbers are not reported.
ILL_CONDITIONED = 1e12
# Free-motion determinacy (smallest/largest singular value) below which it is not unique.
UNDETERMINED = 1e-10
EPS = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Problem:
    """A scene's dynamics, nondimensional. ``dim`` is 2 (planar) or 3 (spatial)."""

    frame: Frame
    names: tuple[str, ...]
    points: np.ndarray  # (k, dim)
    normals: np.ndarray  # (k, dim) unit
    friction: np.ndarray  # (k,)
    com: np.ndarray  # (dim,)
    inertia: np.ndarray  # (nw, nw), I / (m L^2) about the centre of mass
    gravity: np.ndarray  # (dim,), m g / F
    torque: np.ndarray  # (nw,), M / (F L)
    load_point: np.ndarray  # (dim,)
    load_scale: float  # load magnitude / F (1, or 0 when gravity is the closing force)
    mass: float  # kg, for converting back

    @property
    def dim(self) -> int:
        """2 or 3."""
        return self.points.shape[1]

    def load_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """External wrench about the centre of mass as ``b0 + B d``: returns ``(b0, B)``."""
        r = self.load_point - self.com
        eye = np.eye(self.dim)
        lever = wrenches(np.broadcast_to(r, (self.dim, self.dim)), eye).T  # (n, dim)
        b0 = np.concatenate([self.torque, self.gravity])
        return b0, self.load_scale * lever

    def wrench(self, direction: np.ndarray | None) -> np.ndarray:
        """External wrench for a unit force direction (dim,), or gravity and torque alone."""
        b0, big_b = self.load_basis()
        return b0 if direction is None else b0 + big_b @ direction

    def acceleration_scale(self) -> float:
        """m/s^2 per unit of nondimensional lambda."""
        return self.frame.force / self.mass


@dataclass(frozen=True)
class Affine:
    """Unknowns ``x(d) = a + c @ d`` (``x = [lambda, N_1, ...]``) for one friction assumption."""

    matrix: np.ndarray
    a: np.ndarray
    c: np.ndarray
    condition: float
    error: np.ndarray  # estimated absolute error of each unknown (nondimensional)

    def at(self, direction: np.ndarray | None) -> np.ndarray:
        """Unknowns for a unit force direction, or for gravity and torque alone."""
        return self.a if direction is None else self.a + self.c @ direction


@dataclass(frozen=True)
class Case:
    """One retracted support: free motion, sliding of the others, both friction assumptions."""

    retracted: int
    keep: np.ndarray  # indices of the remaining supports
    free: FreeTwist
    sliding: np.ndarray  # (k-1,) bool: does the contact slide under the free twist
    forward: Affine | None
    backward: Affine | None

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


def build_problem(
    *,
    points: np.ndarray,
    normals: np.ndarray,
    friction: np.ndarray,
    names: tuple[str, ...],
    dim: int,
    mass: float,
    com: np.ndarray,
    inertia: np.ndarray,
    gravity: np.ndarray,
    load_magnitude: float,
    load_point: np.ndarray | None,
    torque: np.ndarray,
) -> Problem:
    """Nondimensionalise a scene (SI inputs, 3-vectors) into a :class:`Problem`.

    The force scale is the load magnitude, or the weight when there is no load.
    """
    g = np.asarray(gravity, float)[:dim]
    force = load_magnitude if load_magnitude > 0 else mass * float(np.linalg.norm(g))
    if not force > 0:
        raise ValueError("no closing force: the load magnitude and gravity are both zero")
    frame = Frame.for_points(points, dim, force)
    nw = 1 if dim == 2 else 3
    moments = np.asarray(inertia, float)
    moments = moments[2:, 2:] if dim == 2 else moments
    q = com if load_point is None else load_point
    return Problem(
        frame=frame,
        names=names,
        points=frame.point(points),
        normals=np.asarray(normals, float)[:, :dim]
        / np.linalg.norm(np.asarray(normals, float)[:, :dim], axis=1, keepdims=True),
        friction=np.asarray(friction, float),
        com=frame.point(com),
        inertia=moments / (mass * frame.length**2),
        gravity=mass * g / force,
        torque=np.asarray(torque, float)[3 - nw :] / (force * frame.length),
        load_point=frame.point(q),
        load_scale=load_magnitude / force,
        mass=mass,
    )


def friction_directions(
    twist: np.ndarray, points: np.ndarray, sense: int
) -> tuple[np.ndarray, np.ndarray]:
    """Unit friction directions opposing sliding at contacts, and which contacts slide.

    ``sense`` +1 opposes the motion along the twist (forward), -1 the reverse. Contacts that do
    not slide get a zero direction (undetermined friction, set to zero as in the thesis).
    """
    u = point_velocity(twist, points)
    speed = np.linalg.norm(u, axis=1)
    sliding = speed > SLIP_TOL
    t = np.zeros_like(u)
    t[sliding] = -sense * u[sliding] / speed[sliding, None]
    return t, sliding


def system_matrix(
    problem: Problem, twist: np.ndarray, keep: np.ndarray, mu: np.ndarray, sense: int
) -> np.ndarray:
    """Matrix of ``[lambda, N_j]`` in Newton–Euler about the centre of mass.

    Column 0 is the inertial wrench of the unit twist acceleration ``[I w, m u(c)]``; column
    ``1 + j`` is minus the wrench of the contact force ``n_j + mu_j t_j`` (unit normal force).
    """
    nw = 1 if problem.dim == 2 else 3
    t, _ = friction_directions(twist, problem.points[keep], sense)
    forces = problem.normals[keep] + mu[:, None] * t
    contact = -wrenches(problem.points[keep] - problem.com, forces)
    inertial = np.concatenate([problem.inertia @ twist[:nw], point_velocity(twist, problem.com)])
    return np.column_stack([inertial, contact.T])


def _equilibrate(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Row and column scale factors that make every row and column's largest entry 1."""
    rows = np.abs(matrix).max(axis=1)
    rows = np.where(rows > 0, 1.0 / np.where(rows > 0, rows, 1.0), 1.0)
    cols = np.abs(matrix * rows[:, None]).max(axis=0)
    cols = np.where(cols > 0, 1.0 / np.where(cols > 0, cols, 1.0), 1.0)
    return rows, cols


def solve_affine(matrix: np.ndarray, b0: np.ndarray, big_b: np.ndarray) -> Affine:
    """Solve ``K x = b0 + B d`` for the affine coefficients, with conditioning and error.

    Rows and columns are equilibrated first, so the condition number measures the geometry,
    not the choice of units or how mass compares with inertia.
    """
    rows, cols = _equilibrate(matrix)
    scaled = matrix * rows[:, None] * cols[None, :]
    singular = np.linalg.svd(scaled, compute_uv=False)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else float("inf")
    rhs = np.column_stack([b0, big_b]) * rows[:, None]
    if not np.isfinite(condition) or condition > 1 / EPS:
        nan = np.full((len(b0), 1 + big_b.shape[1]), np.nan)
        return Affine(matrix, nan[:, 0], nan[:, 1:], condition, np.full(len(b0), np.inf))
    sol = np.linalg.solve(scaled, rhs) * cols[:, None]
    residual = np.abs(matrix @ sol - np.column_stack([b0, big_b])).max()
    scale = np.abs(sol).sum(axis=1)
    # Forward error: conditioning times rounding, plus the residual carried through.
    error = (condition * EPS * 8) * scale + condition * residual * cols
    return Affine(matrix, sol[:, 0], sol[:, 1:], condition, error)


def analyse_case(problem: Problem, retracted: int) -> Case:
    """Free motion and both friction-assumption systems for one retracted support."""
    keep = np.flatnonzero(np.arange(len(problem.points)) != retracted)
    free = free_twist(problem.points, problem.normals, retracted)
    _, sliding = friction_directions(free.twist, problem.points[keep], +1)
    case = Case(retracted, keep, free, sliding, None, None)
    if not case.determined:
        return case
    b0, big_b = problem.load_basis()
    mu = problem.friction[keep]
    fwd = solve_affine(system_matrix(problem, free.twist, keep, mu, +1), b0, big_b)
    bwd = solve_affine(system_matrix(problem, free.twist, keep, mu, -1), b0, big_b)
    return Case(retracted, keep, free, sliding, fwd, bwd)


def _decide(forward: np.ndarray, backward_lambda: np.ndarray) -> np.ndarray:
    """The outcome rule on forward unknowns (..., n) and the backward ``lambda`` (...,).

    Forward first: ``lambda > 0`` with all ``N > 0`` closes, with some ``N <= 0`` loses
    contact; else backward: ``lambda < 0`` opens; else friction holds the body: jams.
    """
    closing = np.where(np.all(forward[..., 1:] > 0, axis=-1), "closes", "loses_contact")
    held = np.where(backward_lambda < 0, "opens", "jams")
    return np.where(forward[..., 0] > 0, closing, held)


def outcome(case: Case, direction: np.ndarray | None) -> tuple[Outcome, np.ndarray | None]:
    """Outcome for one force direction (or gravity and torque alone), and the unknowns of the
    assumption that holds (:func:`_decide`)."""
    if not case.determined:
        return "undetermined", None
    if not case.well_conditioned:
        return "ill_conditioned", None
    assert case.forward is not None and case.backward is not None
    x, xb = case.forward.at(direction), case.backward.at(direction)
    state = str(_decide(x, xb[0]))
    return state, (xb if state == "opens" else x)  # type: ignore[return-value]


def outcomes(case: Case, directions: np.ndarray) -> np.ndarray:
    """Outcome (m,) for each unit force direction (m, dim) of a determined, well-conditioned
    case: :func:`outcome` vectorised over directions."""
    assert case.forward is not None and case.backward is not None
    forward = case.forward.a + directions @ case.forward.c.T
    backward_lambda = case.backward.a[0] + directions @ case.backward.c[0]
    return _decide(forward, backward_lambda)


def safe_arcs(affine: Affine, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, float]:
    """Force angles in the sweep plane where the case closes (every unknown positive).

    Returns the arc set (radians from ``e1`` towards ``e2``) and an estimate of the absolute
    error of its ends in radians (:func:`kcheck.arcs.affine_arcs`).
    """
    return affine_arcs(affine.a, affine.c, e1, e2, affine.error)


def limiting_friction(problem: Problem, case: Case, direction: np.ndarray | None) -> float | None:
    """Largest common friction coefficient for which the case still closes at ``direction``.

    Every support gets the same ``mu``, except that supports the scene makes frictionless
    (``friction: 0`` while others have friction: rollers, air bearings, the plane carrying a
    planar body) stay frictionless. The closing state can only change where ``lambda`` or
    an ``N_j`` crosses zero or the system turns singular; with ``K(mu) = K0 + mu K1`` those are
    the real roots of ``det K(mu)`` and of ``det`` of ``K(mu)`` with one column replaced by
    the right-hand side (Cramer) — generalised eigenvalues (compare Patti & Vogels 2019).
    Returns ``None`` when the case does not close even without friction and ``inf`` when no
    friction coefficient stops it.
    """
    from scipy.linalg import eigvals

    if not case.determined:
        return None
    twist, keep = case.free.twist, case.keep
    zeros = np.zeros(len(keep))
    rough = problem.friction[keep] > 0 if np.any(problem.friction > 0) else np.ones(len(keep))
    k0 = system_matrix(problem, twist, keep, zeros, +1)
    k1 = system_matrix(problem, twist, keep, np.asarray(rough, float), +1) - k0
    rhs = problem.wrench(direction)

    def closes(mu: float) -> bool:
        sol = solve_affine(k0 + mu * k1, rhs, np.zeros((len(rhs), 0)))
        return bool(sol.condition < ILL_CONDITIONED and sol.a[0] > 0 and np.all(sol.a[1:] > 0))

    if not closes(0.0):
        return None
    candidates = []
    pencils = [(k0, k1)]
    for k in range(k0.shape[1]):
        a0, a1 = k0.copy(), k1.copy()
        a0[:, k], a1[:, k] = rhs, 0.0
        pencils.append((a0, a1))
    for a0, a1 in pencils:
        with np.errstate(all="ignore"):
            values = eigvals(a0, -a1)
        real = values[np.isfinite(values) & (np.abs(values.imag) <= 1e-9 * (1 + np.abs(values)))]
        candidates.extend(float(v) for v in real.real if v > 0)
    candidates = sorted(set(candidates))
    for i, mu in enumerate(candidates):
        upper = candidates[i + 1] if i + 1 < len(candidates) else 2 * mu + 1
        if not closes(0.5 * (mu + upper)):
            return mu
    return float("inf")
