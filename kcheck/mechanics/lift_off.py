"""The first motion from rest with contacts free to lift off: the acceleration-level rigid-body
contact problem with Coulomb friction, as a linear complementarity problem.

The retraction cases of :mod:`kcheck.mechanics.dynamics` keep every remaining contact and let
the body slide along the one free twist, towards the support or away from it. When neither
sliding is consistent the outcome rule calls the case ``jams``; that is only true when friction
can hold the body (an equilibrium exists, :func:`kcheck.mechanics.statics.holds_exactly`).
When it cannot, the body must move, and since sliding on every kept contact is inconsistent,
a kept contact lifts off. This module finds that motion.

From rest, with acceleration ``a = [alpha; a_c]`` about the centre of mass (nondimensional,
mass 1, inertia ``I``), each kept contact ``j`` has a normal force ``N_j >= 0`` complementary
to its normal acceleration ``n_j . a(p_j) >= 0``, and a friction force in its cone opposing
its tangential acceleration (Trinkle, Pang, Sudarsky & Lo 1997, the acceleration form of
Stewart & Trinkle's polyhedral-cone LCP): friction is ``D_j beta_j`` with ``beta_j >= 0``
on the cone's ``m`` edge directions, ``sum beta_j <= mu_j N_j``, and a slip rate ``s_j``
with ``D_j^T a(p_j) + s_j >= 0`` complementary to ``beta_j``. Planar cones are exact (two
edges); spatial ones are inscribed pyramids of LIFT_EDGES edges. Solved by Lemke's method
(:mod:`kcheck.numerics.lemke`); a rigid problem with friction may have several solutions
(Painlevé) and the method returns one.
"""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.kinematics import point_velocity, wrenches
from kcheck.numerics.lemke import lemke
from kcheck.numerics.thresholds import LIFT_SHARE
from kcheck.records import dataclass

__all__ = [
    "LIFT_EDGES",
    "ContactRows",
    "LiftOff",
    "closing",
    "contact_rows",
    "free_scale",
    "free_speeds",
    "lcp",
    "lift_off",
    "motion",
]

#: Edges of the inscribed friction pyramid of a spatial contact (its friction reaches
#: cos(pi / 16) = 98 % of the circular cone's between edges).
LIFT_EDGES = 16


@dataclass(frozen=True)
class LiftOff:
    """The first motion from rest: acceleration twist ``acceleration`` (n,) about the centre
    of mass, normal forces ``forces`` (c,) of the kept contacts, which of them lift
    (``lifted``, c), and ``closing`` the retracted contact point's acceleration towards its
    support (``-n_r . a(p_r)``; nondimensional)."""

    acceleration: np.ndarray
    forces: np.ndarray
    lifted: np.ndarray
    closing: float

    @property
    def moves(self) -> bool:
        """Whether the body accelerates at all."""
        return bool(np.any(self.acceleration != 0))


def _edges(normals: np.ndarray, edges: int) -> np.ndarray:
    """Unit tangent directions (c, m, dim) of each contact's friction pyramid edges."""
    dim = normals.shape[1]
    if dim == 2:
        t = np.stack([-normals[:, 1], normals[:, 0]], axis=-1)
        return np.stack([t, -t], axis=1)
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(normals, t1)
    angles = 2 * np.pi * np.arange(edges) / edges
    return np.cos(angles)[None, :, None] * t1[:, None] + np.sin(angles)[None, :, None] * t2[:, None]


@dataclass(frozen=True)
class ContactRows:
    """What a lift-off problem on some contacts needs, built once for all of them: ``lever``
    (c, dim) the contact points about the centre of mass, ``normals`` (c, dim), ``mu`` (c,),
    ``rows`` (c + c m, n) the normal rows then each contact's ``m`` pyramid-edge rows
    (acceleration along them per twist), ``inverse`` (n, n) the inverse mass matrix. Its
    :meth:`subset` is the same as building it on those contacts alone, bit for bit (every
    piece is computed row by row)."""

    lever: np.ndarray
    normals: np.ndarray
    mu: np.ndarray
    rows: np.ndarray
    inverse: np.ndarray
    m: int

    def subset(self, keep: np.ndarray) -> ContactRows:
        """The rows of the contacts ``keep`` (indices, increasing)."""
        c = len(self.lever)
        edge_rows = c + (keep[:, None] * self.m + np.arange(self.m)).ravel()
        return ContactRows(
            self.lever[keep],
            self.normals[keep],
            self.mu[keep],
            self.rows[np.concatenate([keep, edge_rows])],
            self.inverse,
            self.m,
        )


def contact_rows(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    com: np.ndarray,
    inertia: np.ndarray,
    edges: int = LIFT_EDGES,
) -> ContactRows:
    """The lift-off problem's pieces for contacts ``points``, unit ``normals`` (c, dim),
    coefficients ``mu`` (c,) of a body with unit mass and ``inertia`` (nw, nw) about ``com``."""
    c, dim = points.shape
    nw = 1 if dim == 2 else 3
    lever = points - com
    directions = _edges(normals, edges)
    m = directions.shape[1]
    g_n = wrenches(lever, normals)  # (c, n)
    g_d = wrenches(np.repeat(lever, m, axis=0), directions.reshape(c * m, dim))  # (c m, n)
    mass = np.zeros((nw + dim, nw + dim))
    mass[:nw, :nw] = inertia
    mass[nw:, nw:] = np.eye(dim)
    return ContactRows(lever, normals, mu, np.vstack([g_n, g_d]), np.linalg.inv(mass), m)


def lcp(rows: ContactRows, wrench: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lift-off problem's LCP ``(A, q)``: unknowns the normal forces (c), the pyramid-edge
    friction (c m) and the slip rates (c)."""
    c, m, g, inv = len(rows.lever), rows.m, rows.rows, rows.inverse
    block = np.zeros((c * m, c))
    block[np.arange(c * m), np.repeat(np.arange(c), m)] = 1.0
    size = c + c * m + c
    a = np.zeros((size, size))
    a[: c + c * m, : c + c * m] = g @ inv @ g.T
    a[c : c + c * m, c + c * m :] = block
    a[c + c * m :, :c] = np.diag(rows.mu)
    a[c + c * m :, c : c + c * m] = -block.T
    q = np.concatenate([g @ inv @ wrench, np.zeros(c)])
    return a, q


def motion(
    rows: ContactRows,
    wrench: np.ndarray,
    z: np.ndarray,
    com: np.ndarray,
    retracted: tuple[np.ndarray, np.ndarray] | None,
    scale: float | None = None,
) -> LiftOff:
    """The first motion of the LCP's solution ``z`` (:func:`lcp`); ``closing`` NaN without
    ``retracted``. ``scale``: :func:`free_scale` of these rows when the caller has it."""
    c, m, g, inv, lever = len(rows.lever), rows.m, rows.rows, rows.inverse, rows.lever
    forces = z[:c]
    accel = inv @ (wrench + g.T @ z[: c + c * m])
    if scale is None:
        scale = free_scale(rows, wrench)
    if float(np.max(np.abs(accel))) <= LIFT_SHARE * scale:
        accel = np.zeros_like(accel)
    contact = point_velocity(accel, lever)
    normal_accel = np.einsum("ij,ij->i", contact, rows.normals)
    lifted = normal_accel > LIFT_SHARE * scale
    return LiftOff(
        accel, forces, lifted, np.nan if retracted is None else closing(accel, com, retracted)
    )


def free_speeds(rows: ContactRows, wrench: np.ndarray) -> tuple[float, np.ndarray]:
    """The free body's acceleration under ``wrench`` (nondimensional): its largest component
    and each contact's largest component at its point (c,). Row by row, so a subset's are
    these rows'."""
    free = rows.inverse @ wrench
    speed = np.max(np.abs(point_velocity(free, rows.lever)), axis=1)
    return float(np.max(np.abs(free))), speed


def free_scale(rows: ContactRows, wrench: np.ndarray, keep: np.ndarray | None = None) -> float:
    """What rounding noise is measured against (the one definition, for :func:`motion` and the
    second answer's acceptance): the free body's acceleration under ``wrench``, its largest
    component plus the largest of the contacts' (those ``keep``, indices, when given)."""
    top, speed = free_speeds(rows, wrench)
    return top + float(np.max(speed if keep is None else speed[keep]))


def closing(
    acceleration: np.ndarray, com: np.ndarray, retracted: tuple[np.ndarray, np.ndarray]
) -> float:
    """The retracted contact point's acceleration towards its support under ``acceleration``
    (n,) about ``com``: ``-n_r . a(p_r)``."""
    point, normal = retracted
    return -float(point_velocity(acceleration, point - com) @ normal)


def lift_off(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    com: np.ndarray,
    inertia: np.ndarray,
    wrench: np.ndarray,
    retracted: tuple[np.ndarray, np.ndarray],
    edges: int = LIFT_EDGES,
) -> LiftOff | None:
    """The first motion from rest of a body (unit mass, ``inertia`` (nw, nw) about ``com``
    (dim,)) under ``wrench`` (n,: moment about the centre of mass, force) on the kept contacts
    ``points``, unit ``normals`` (c, dim) with coefficients ``mu`` (c,); ``retracted`` is the
    retracted support's point and unit normal. None when Lemke's method finds no solution."""
    rows = contact_rows(points, normals, mu, com, inertia, edges)
    z = lemke(*lcp(rows, wrench))
    return None if z is None else motion(rows, wrench, z, com, retracted)
