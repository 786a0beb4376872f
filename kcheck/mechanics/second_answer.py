"""The rigid model's second answer to a body friction can hold: a first motion from rest that
is consistent as well.

Where an equilibrium exists on the remaining contacts, rest is one solution of the rigid-body
contact problem with Coulomb friction; it need not be the only one (the problem is an LCP,
which may have several). A motion is a second solution when it keeps some contacts ``K``
(each with a normal force in its friction cone, none lifting) and every other remaining
contact separates (non-negative normal acceleration, zero force). This module looks for one:
for each nonempty subset ``K`` in a fixed order (largest first, then lexicographic), the
lift-off problem on ``K`` alone (:func:`kcheck.mechanics.lift_off.lift_off`), accepting the
first nonzero motion that lifts none of ``K`` and separates every contact outside it.
Lemke's method returns one solution per subset, so None means none was found this way, not
that none exists.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np

from kcheck.mechanics.kinematics import point_velocity, wrenches
from kcheck.mechanics.lift_off import LIFT_EDGES, LiftOff, lift_off
from kcheck.numerics.thresholds import LIFT_SHARE
from kcheck.records import dataclass

__all__ = ["SecondAnswer", "second_answer", "subsets"]


@dataclass(frozen=True)
class SecondAnswer:
    """A consistent first motion from rest: ``kept`` (c,) the remaining contacts it stays on,
    the others separating, and ``motion`` the lift-off solution on the kept ones."""

    kept: np.ndarray
    motion: LiftOff

    @property
    def lifted(self) -> np.ndarray:
        """The remaining contacts the motion separates from (c,)."""
        return ~self.kept


def subsets(count: int) -> list[tuple[int, ...]]:
    """The nonempty subsets of ``count`` contacts in the order they are tried: largest first,
    then lexicographic (5 contacts: 31, 2: 3)."""
    return [k for size in range(count, 0, -1) for k in combinations(range(count), size)]


def second_answer(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    com: np.ndarray,
    inertia: np.ndarray,
    wrench: np.ndarray,
    retracted: tuple[np.ndarray, np.ndarray],
    edges: int = LIFT_EDGES,
) -> SecondAnswer | None:
    """The first consistent nonzero first motion from rest of a body (unit mass, ``inertia``
    (nw, nw) about ``com`` (dim,), under ``wrench`` (n,: moment about the centre of mass,
    force; nondimensional as in :func:`~kcheck.mechanics.lift_off.lift_off`) on some of the
    remaining contacts ``points``, unit ``normals`` (c, dim), coefficients ``mu`` (c,), every
    other remaining contact separating; ``retracted`` is the retracted support's point and
    unit normal. None when no subset gives one."""
    c = len(points)
    lever = points - com
    nw = 1 if points.shape[1] == 2 else 3
    mass = np.eye(nw + points.shape[1])
    mass[:nw, :nw] = inertia
    free = np.linalg.solve(mass, wrench)
    scale = float(np.max(np.abs(free))) + float(np.max(np.abs(point_velocity(free, lever))))
    rows = wrenches(lever, normals)  # normal acceleration of each contact per twist (c, n)
    for k in subsets(c):
        keep = np.zeros(c, dtype=bool)
        keep[list(k)] = True
        motion = lift_off(
            points[keep], normals[keep], mu[keep], com, inertia, wrench, retracted, edges
        )
        if motion is None or not motion.moves or np.any(motion.lifted):
            continue
        if np.all(rows[~keep] @ motion.acceleration >= -LIFT_SHARE * scale):
            return SecondAnswer(keep, motion)
    return None
