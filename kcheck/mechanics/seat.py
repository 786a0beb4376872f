"""The seated coupling: contact forces under the seated load, the coupling's stiffness at the
seat, and the body's error motion under a disturbing load (docs/checks.md, `hertz`).

With every support in contact (6 in space, 3 in a plane) the contact wrenches ``w_i = (p_i x
n_i, n_i)`` form a square matrix, the same rows as the constraint rows of
:mod:`kcheck.mechanics.kinematics`. Frictionless contacts in equilibrium under an external wrench
``W``: ``sum N_i w_i + W = 0`` — statically determinate, one linear solve. A small body motion
(twist ``xi``, rotation first) changes contact ``i``'s approach by ``-w_i . xi``; with
contact stiffnesses ``k_i = dN_i/d delta_i`` equilibrium gives ``K xi = dW`` with

    K = sum_i k_i w_i w_i^T

the coupling's stiffness matrix about the origin of the wrenches. Because the layout is
determinate the error motion needs no linearisation: the forces follow from statics, each
contact's approach from its own force-approach law, and the twist from the compatibility
``w_i . xi = -(delta_i(N_i + dN_i) - delta_i(N_i))`` — one more solve with the same matrix.

Everything is solved nondimensionally (positions about the supports' centroid by the layout
size ``L``, forces by a force scale); the equilibrated condition number is reported and a
nearly singular layout gives no numbers.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from kcheck.mechanics.dynamics import ILL_CONDITIONED, solve_affine
from kcheck.mechanics.kinematics import Frame, wrenches
from kcheck.records import dataclass
from kcheck.scene import Preload, Scene

if TYPE_CHECKING:
    from kcheck.result import MassProperties

__all__ = [
    "Seat",
    "Solution",
    "seat_layout",
    "external_wrench",
    "contact_forces",
    "stiffness_matrix",
    "tangential_stiffness_matrix",
    "directed_stiffness_matrix",
    "twist_from_approach",
    "point_translation",
    "point_compliance",
    "seated_loads",
]


@dataclass(frozen=True)
class Seat:
    """The contact layout, nondimensional: ``rows`` (k, n) are the contact wrenches
    ``(p x n, n)`` with positions about ``frame.origin`` divided by ``frame.length``."""

    frame: Frame
    rows: np.ndarray

    @property
    def dim(self) -> int:
        """2 (planar) or 3 (spatial)."""
        return self.frame.dim

    @property
    def rotations(self) -> int:
        """Number of rotational components of a twist or wrench: 1 in a plane, 3 in space."""
        return 1 if self.frame.dim == 2 else 3

    def scale(self) -> np.ndarray:
        """Diagonal ``S`` with ``w = S w~``: ``L`` on moment rows, 1 on force rows."""
        n = self.rows.shape[1]
        s = np.ones(n)
        s[: self.rotations] = self.frame.length
        return s


@dataclass(frozen=True)
class Solution:
    """A linear solve on the seat: ``value`` (None when singular), the equilibrated condition
    number and an estimate of each entry's absolute error (same units as ``value``)."""

    value: np.ndarray | None
    condition: float
    error: np.ndarray | None

    @property
    def singular(self) -> bool:
        """Whether the matrix is too close to singular for its numbers to mean anything."""
        return self.value is None


def seat_layout(positions: np.ndarray, normals: np.ndarray, dim: int, force: float) -> Seat:
    """The seat of supports at ``positions`` (k, 3) m with normals (k, 3) into the body.

    ``force`` (N) is the force scale of the nondimensional solves (any typical load).
    """
    frame = Frame.for_points(np.asarray(positions, float), dim, force)
    n = np.asarray(normals, float)[:, :dim]
    n = n / np.linalg.norm(n, axis=1, keepdims=True)
    return Seat(frame, wrenches(frame.point(positions), n))


def external_wrench(seat: Seat, loads: Sequence[Preload], torque: np.ndarray) -> np.ndarray:
    """Nondimensional wrench (n,) about the seat's origin of forces at points (each a
    :class:`~kcheck.scene.Preload`: name, point in m, force in N) and a torque (N m)."""
    frame = seat.frame
    total = np.zeros(seat.rows.shape[1])
    for load in loads:
        total += wrenches(frame.point(load.point), np.asarray(load.force, float)[: seat.dim])
    total /= frame.force
    total[: seat.rotations] += np.asarray(torque, float)[3 - seat.rotations :] / (
        frame.force * frame.length
    )
    return total


def _solve(matrix: np.ndarray, rhs: np.ndarray) -> Solution:
    affine = solve_affine(matrix, rhs, np.zeros((len(rhs), 0)))
    if not affine.condition < ILL_CONDITIONED:
        return Solution(None, affine.condition, None)
    return Solution(affine.a, affine.condition, affine.error)


def contact_forces(seat: Seat, wrench: np.ndarray) -> Solution:
    """Normal forces (k,) in N balancing a nondimensional external wrench: ``sum N_i w_i = -W``.

    Negative forces mean the contact would have to pull: the body lifts off there.
    """
    sol = _solve(seat.rows.T, -np.asarray(wrench, float))
    if sol.value is None or sol.error is None:
        return sol
    return Solution(sol.value * seat.frame.force, sol.condition, sol.error * seat.frame.force)


def stiffness_matrix(seat: Seat, stiffness: np.ndarray) -> np.ndarray:
    """The coupling's stiffness matrix (n, n) about the seat's origin, SI units.

    ``K = sum_i k_i w_i w_i^T`` with ``stiffness`` the contact stiffnesses ``k_i`` (N/m).
    Ordered like a twist: rotations first (N m/rad, N/rad), then translations (N, N/m).
    """
    s = seat.scale()
    nondim = np.einsum("i,ia,ib->ab", np.asarray(stiffness, float), seat.rows, seat.rows)
    return nondim * s[:, None] * s[None, :]


def tangential_stiffness_matrix(
    seat: Seat, positions: np.ndarray, normals: np.ndarray, stiffness: np.ndarray
) -> np.ndarray:
    """The stiffness matrix (n, n) of the contacts' tangential (Mindlin, no-slip) compliance,
    SI like :func:`stiffness_matrix`: ``sum_i k_t,i sum_j t_ij t_ij^T`` over the wrenches of
    unit tangents ``t_ij`` (two in space, one in a plane) at each contact; isotropic in the
    tangent plane with ``stiffness`` ``k_t,i`` (N/m)."""
    frame = seat.frame
    dim = seat.dim
    n = np.asarray(normals, float)
    total = np.zeros((seat.rows.shape[1],) * 2)
    points = frame.point(np.asarray(positions, float))
    for i, k_t in enumerate(np.asarray(stiffness, float)):
        if dim == 2:
            tangents = [np.array([-n[i, 1], n[i, 0]])]
        else:
            helper = np.eye(3)[int(np.argmin(np.abs(n[i])))]
            t1 = np.cross(n[i], helper)
            t1 /= np.linalg.norm(t1)
            tangents = [t1, np.cross(n[i], t1)]
        for t in tangents:
            t = t[:dim] / np.linalg.norm(t[:dim])
            w = wrenches(points[i : i + 1], t[None, :])[0]
            total += k_t * np.outer(w, w)
    s = seat.scale()
    return total * s[:, None] * s[None, :]


def directed_stiffness_matrix(
    seat: Seat, positions: np.ndarray, directions: np.ndarray, stiffness: np.ndarray
) -> np.ndarray:
    """The stiffness matrix (n, n) of springs ``stiffness`` (N/m) at ``positions`` along given
    unit ``directions`` (k, 3), SI like :func:`stiffness_matrix`: ``sum_i k_i w_i w_i^T`` with
    ``w_i`` the wrench of direction ``i`` (a ring contact's tangents: across and along its
    line, each with its own stiffness). Zero stiffness adds nothing."""
    frame, dim = seat.frame, seat.dim
    total = np.zeros((seat.rows.shape[1],) * 2)
    points = frame.point(np.asarray(positions, float))
    d = np.asarray(directions, float)
    for i, k in enumerate(np.asarray(stiffness, float)):
        if k == 0.0:
            continue
        t = d[i, :dim] / np.linalg.norm(d[i, :dim])
        w = wrenches(points[i : i + 1], t[None, :])[0]
        total += k * np.outer(w, w)
    s = seat.scale()
    return total * s[:, None] * s[None, :]


def twist_from_approach(seat: Seat, approach_change: np.ndarray) -> Solution:
    """Small body motion (rotation in rad, then translation of the origin in m) for given
    changes of the contact approaches (k,) in m: ``w_i . xi = -d delta_i``."""
    sol = _solve(seat.rows, -np.asarray(approach_change, float))
    if sol.value is None or sol.error is None:
        return sol
    s = seat.scale()
    return Solution(sol.value / s, sol.condition, sol.error / s)


def point_translation(seat: Seat, twist: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Translation (3,) in m of a body point (3,) in m under a small twist from
    :func:`twist_from_approach` (zero out of the plane for a planar seat)."""
    nw, dim = seat.rotations, seat.dim
    w, v = twist[:nw], twist[nw:]
    r = (np.asarray(point, float) - seat.frame.origin)[:dim]
    if dim == 2:
        u = v + w[0] * np.array([-r[1], r[0]])
        return np.append(u, 0.0)
    return v + np.cross(w, r)


def point_compliance(seat: Seat, stiffness: np.ndarray, point: np.ndarray) -> np.ndarray | None:
    """Compliance (3, 3) in m/N of a body point under forces at that point (rotations free),
    ``J K^-1 J^T`` with ``J = [-[r]x, I]``; None when ``K`` is singular."""
    dim = seat.dim
    r = (np.asarray(point, float) - seat.frame.origin)[:dim]
    if dim == 3:
        cross = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
        jac = np.hstack([-cross, np.eye(3)])
    else:
        jac = np.hstack([np.array([[-r[1]], [r[0]]]), np.eye(2)])
    scale = np.abs(np.diag(stiffness))
    if not np.all(scale > 0):
        return None
    d = 1.0 / np.sqrt(scale)
    balanced = stiffness * d[:, None] * d[None, :]
    if np.linalg.cond(balanced) > ILL_CONDITIONED:
        return None
    inv = np.linalg.inv(balanced) * d[:, None] * d[None, :]
    return jac @ inv @ jac.T


def seated_loads(
    scene: Scene, mass: MassProperties | None
) -> tuple[list[Preload], np.ndarray, list[str]]:
    """Forces holding the body in its seat: weight, preloads, the load at its design direction.

    Returns the point forces, the torque (N m) and notes on what was left out.
    """
    loads: list[Preload] = []
    notes: list[str] = []
    com = None if mass is None else np.asarray(mass.center_of_mass, float)
    if np.any(scene.gravity[: scene.dim]):
        if mass is None:
            notes.append("no body: the weight is left out")
        else:
            loads.append(Preload("weight", com, mass.mass * scene.gravity))  # type: ignore[arg-type]
    for p in scene.preloads:
        loads.append(Preload(f"preload {p.name}", p.point, p.force))
    torque = np.zeros(3)
    load = scene.load
    if load is not None and load.magnitude > 0:
        if load.direction is None:
            notes.append("the load has no design direction (it is swept): left out of the seat")
        else:
            point = load.point if load.point is not None else com
            if point is None:
                notes.append("the load acts at the centre of mass, which needs a body: left out")
            else:
                loads.append(Preload("load", point, load.magnitude * load.direction))
                torque = np.asarray(load.torque, float)
    return loads, torque, notes
