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

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from kcheck.mechanics.kinematics import point_velocity
from kcheck.mechanics.lift_off import LIFT_EDGES, LiftOff, contact_rows, lcp, motion
from kcheck.numerics.lemke import lemke_batch
from kcheck.numerics.thresholds import LIFT_SHARE

__all__ = ["Held", "SecondAnswer", "second_answer", "second_answers", "subsets"]


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


@dataclass(frozen=True)
class Held:
    """One body friction can hold, as :func:`second_answer` takes it."""

    points: np.ndarray
    normals: np.ndarray
    mu: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    wrench: np.ndarray
    retracted: tuple[np.ndarray, np.ndarray]


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
    held = Held(points, normals, mu, com, inertia, wrench, retracted)
    return second_answers([held], edges)[0]


def _noise(held: Held, lever: np.ndarray) -> float:
    """The acceleration below which a motion is rounding noise: LIFT_SHARE of the free
    body's under the wrench (its largest component plus its contacts' largest speed-up)."""
    nw = 1 if held.points.shape[1] == 2 else 3
    mass = np.eye(nw + held.points.shape[1])
    mass[:nw, :nw] = held.inertia
    free = np.linalg.solve(mass, held.wrench)
    scale = float(np.max(np.abs(free))) + float(np.max(np.abs(point_velocity(free, lever))))
    return LIFT_SHARE * scale


def second_answers(cases: list[Held], edges: int = LIFT_EDGES) -> list[SecondAnswer | None]:
    """:func:`second_answer` of each case. The lift-off problems of every case's subsets of
    one size are solved as one batch (:func:`~kcheck.numerics.lemke.lemke_batch`: each the
    same pivots as alone), sizes largest first; a case's answer is its first subset in the
    order of :func:`subsets` that gives a motion, as when they are tried in turn, and a case
    answered drops out of the smaller sizes."""
    every = [contact_rows(h.points, h.normals, h.mu, h.com, h.inertia, edges) for h in cases]
    noise = [_noise(h, e.lever) for h, e in zip(cases, every, strict=True)]
    answers: list[SecondAnswer | None] = [None] * len(cases)
    open_cases = set(range(len(cases)))
    for size in range(max((len(h.points) for h in cases), default=0), 0, -1):
        # Problems of one size share a batch only when their contacts share a dimension.
        for dim in (2, 3):
            work = [
                (i, np.array(k))
                for i in sorted(open_cases)
                if cases[i].points.shape[1] == dim
                for k in combinations(range(len(cases[i].points)), size)
            ]
            if not work:
                continue
            pieces = [every[i].subset(k) for i, k in work]
            problems = [lcp(p, cases[i].wrench) for (i, _), p in zip(work, pieces, strict=True)]
            solutions = lemke_batch(
                np.stack([a for a, _ in problems]), np.stack([q for _, q in problems])
            )
            for (i, k), piece, z in zip(work, pieces, solutions, strict=True):
                if z is None or i not in open_cases:
                    continue
                h = cases[i]
                found = motion(piece, h.wrench, z, h.com, h.retracted)
                if not found.moves or np.any(found.lifted):
                    continue
                keep = np.zeros(len(h.points), dtype=bool)
                keep[k] = True
                if np.all(every[i].rows[: len(h.points)][~keep] @ found.acceleration >= -noise[i]):
                    answers[i] = SecondAnswer(keep, found)
                    open_cases.discard(i)
    return answers
