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

from collections.abc import Sequence
from dataclasses import replace
from itertools import combinations

import numpy as np

from kcheck.mechanics.lift_off import (
    LIFT_EDGES,
    LiftOff,
    closing,
    contact_rows,
    free_speeds,
    lcp,
    motion,
)
from kcheck.numerics.lemke import lemke, lemke_padded
from kcheck.numerics.thresholds import LIFT_SHARE
from kcheck.records import dataclass

__all__ = ["Body", "SecondAnswer", "second_answers", "subsets"]


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


#: Problems of one stage from which they are solved as one batch (measured on planar and spatial
#: scenes: three planar problems are cheaper one by one).
BATCH_FROM = 4
#: Subset sizes up to this one are solved as one stage, the larger ones as another (each
#: padded to its largest).
MERGED = 3


def subsets(count: int) -> list[tuple[int, ...]]:
    """The nonempty subsets of ``count`` contacts in the order they are tried: largest first,
    then lexicographic (5 contacts: 31, 2: 3)."""
    return [k for size in range(count, 0, -1) for k in combinations(range(count), size)]


@dataclass(frozen=True)
class Body:
    """A body on its supports, as :func:`second_answers` takes it: ``points``, unit
    ``normals`` (k, dim), kinetic coefficients ``mu`` (k,), unit mass with ``inertia``
    (nw, nw) about ``com`` (dim,), under ``wrench`` (n,; nondimensional as in
    :func:`~kcheck.mechanics.lift_off.lift_off`)."""

    points: np.ndarray
    normals: np.ndarray
    mu: np.ndarray
    com: np.ndarray
    inertia: np.ndarray
    wrench: np.ndarray


def second_answers(
    body: Body,
    cases: Sequence[tuple[tuple[np.ndarray, np.ndarray], np.ndarray]],
    edges: int = LIFT_EDGES,
) -> list[SecondAnswer | None]:
    """Each case's second answer: the first consistent nonzero first motion from rest of
    ``body`` on some of the case's remaining supports, every other remaining support
    separating; None when no subset gives one. A case is ``(retracted, remaining)``: the
    retracted support's point and unit normal, and the indices (c,) of the supports that
    remain.

    A subset's lift-off problem depends on its contacts alone, not on the case (the retracted
    support only moves its ``closing``, the other remaining contacts only decide whether the
    motion is accepted), and every piece of it is built row by row: so each distinct subset of
    supports is solved once for all cases. The problems are solved in two batches, the sizes
    above MERGED then the rest, each padded to its largest
    (:func:`~kcheck.numerics.lemke.lemke_padded`: each the same pivots as alone); a case's
    answer is its first subset in the order of :func:`subsets` that gives a motion, as when
    they are tried in turn, and a case answered drops out of the second batch."""
    every = contact_rows(body.points, body.normals, body.mu, body.com, body.inertia, edges)
    remaining = [np.asarray(kept, dtype=int) for _, kept in cases]
    # free_scale's pieces once, row by row: a set of contacts' scale is the top plus the
    # largest of its rows (free_scale(every, body.wrench, keep), without recomputing them).
    top, speed = free_speeds(every, body.wrench)

    def scale_on(contacts: Sequence[int] | np.ndarray) -> float:
        return top + float(np.max(speed[contacts]))

    # Rounding noise of the acceptance test: the scale on the case's remaining contacts.
    noise = [LIFT_SHARE * scale_on(kept) for kept in remaining]
    answers: list[SecondAnswer | None] = [None] * len(cases)
    open_cases = list(range(len(cases)))
    largest = max((len(k) for k in remaining), default=0)
    # Two stages, each one padded batch: the sizes above MERGED and those up to it (a batch
    # step's numpy calls cost more than the padding's arithmetic; measured 0.95 of one stage a
    # size). Accepted in order of size all the same.
    stages = [list(range(largest, MERGED, -1))] + [list(range(MERGED, 0, -1))]
    for sizes in stages:
        # Each case's subsets of these sizes in its order: (supports, positions among its own).
        tried = {
            i: [(tuple(int(j) for j in remaining[i][list(k)]), k)
                for size in sizes
                for k in combinations(range(len(remaining[i])), size)]
            for i in open_cases
        }  # fmt: skip
        distinct = list(dict.fromkeys(k for i in open_cases for k, _ in tried[i]))
        if not distinct:
            continue
        pieces = {k: every.subset(np.array(k)) for k in distinct}
        problems = [lcp(pieces[k], body.wrench) for k in distinct]
        # A batch step costs about twice a single pivot's numpy calls: worth it from four
        # problems (a planar case's three subsets are solved one by one).
        if len(problems) >= BATCH_FROM:
            solutions = dict(zip(distinct, lemke_padded(problems), strict=True))
        else:
            solutions = {k: lemke(a, q) for k, (a, q) in zip(distinct, problems, strict=True)}
        motions: dict[tuple[int, ...], LiftOff | None] = {}
        for k in distinct:
            z = solutions[k]
            scale = scale_on(list(k))  # the motion's noise: the scale on the subset's contacts
            found = None if z is None else motion(pieces[k], body.wrench, z, body.com, None, scale)
            # Only a motion that lifts none of its contacts can be an answer.
            motions[k] = (
                found if found is not None and found.moves and not found.lifted.any() else None
            )
        for i in list(open_cases):
            kept = remaining[i]
            rows = every.rows[kept]  # the remaining contacts' normal rows (c, n)
            for k, local in tried[i]:
                found = motions[k]
                if found is None:
                    continue
                keep = np.zeros(len(kept), dtype=bool)
                keep[list(local)] = True
                if np.all(rows[~keep] @ found.acceleration >= -noise[i]):
                    retracted = cases[i][0]
                    found = replace(found, closing=closing(found.acceleration, body.com, retracted))
                    answers[i] = SecondAnswer(keep, found)
                    open_cases.remove(i)
                    break
    return answers
