"""What a retracted case does for a force direction: the outcome rule of methods.md §3 on
the affine unknowns ``x(d) = a + C d`` that :mod:`kcheck.mechanics.dynamics` solves for, vectorised
over directions, and the exact safe arcs and limiting friction that follow from it.
"""

from __future__ import annotations

from typing import Literal, get_args

import numpy as np

from kcheck.mechanics.arcs import ArcSet, affine_arcs
from kcheck.mechanics.dynamics import Case

__all__ = [
    "Outcome",
    "OUTCOMES",
    "closing_conditions",
    "outcome",
    "outcomes",
    "safe_arcs",
]

Outcome = Literal[
    "closes",
    "loses_contact",
    "opens",
    "opens_loses_contact",
    "jams",
    "ambiguous",
    "undetermined",
    "ill_conditioned",
]
#: Every outcome of a retracted case; only ``closes`` passes.
OUTCOMES: tuple[str, ...] = get_args(Outcome)


def closing_conditions(case: Case) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Conditions ``a_k + c_k . d > 0`` that together mean "the case closes": under forward
    sliding ``lambda > 0`` and every ``N_j > 0``. Returns ``(a, c, error)``.

    Closing is then the only sliding solution: backward sliding with positive normal forces
    as well would give, subtracting the two Newton–Euler systems and multiplying by ``xi``,
    ``(lambda_f - lambda_b) xi^T M xi = -mu sum (N_f + N_b) |u_j| < 0``, impossible with
    ``lambda_f > 0 > lambda_b``. A Painlevé-type case gets one condition that never holds.
    """
    assert case.forward is not None
    fwd = case.forward
    if case.painleve:
        return np.array([-1.0]), np.zeros((1, fwd.c.shape[1])), np.zeros(1)
    return fwd.a, fwd.c, fwd.error


def _decide(forward: np.ndarray, backward: np.ndarray, painleve: bool) -> np.ndarray:
    """The outcome rule on forward and backward unknowns (..., n) (methods.md §3).

    Forward sliding first: ``lambda > 0`` closes (all ``N > 0``) or loses contact; else
    backward: ``lambda < 0`` opens (all ``N > 0``) or opens while losing contact; else friction
    holds the body (jams). Every direction of a Painlevé-type case is ambiguous.
    """
    fwd = forward[..., 0] > 0
    bwd = backward[..., 0] < 0
    if painleve:
        return np.full(fwd.shape, "ambiguous")
    kept_f = np.all(forward[..., 1:] > 0, axis=-1)
    kept_b = np.all(backward[..., 1:] > 0, axis=-1)
    return np.select(
        [fwd & kept_f, fwd, bwd & kept_b, bwd],
        ["closes", "loses_contact", "opens", "opens_loses_contact"],
        "jams",
    )


def _decide_one(forward: np.ndarray, backward: np.ndarray, painleve: bool) -> Outcome:
    """:func:`_decide` for one direction, without array overhead."""
    if painleve:
        return "ambiguous"
    if forward[0] > 0:
        return "closes" if bool(np.all(forward[1:] > 0)) else "loses_contact"
    if backward[0] < 0:
        return "opens" if bool(np.all(backward[1:] > 0)) else "opens_loses_contact"
    return "jams"


def outcome(case: Case, direction: np.ndarray | None) -> tuple[Outcome, np.ndarray | None]:
    """Outcome for one force direction (or the fixed wrench alone), and the unknowns of the
    assumption that holds (forward for closes/loses contact, backward for the opening
    outcomes; None when jammed or ambiguous) (:func:`_decide`)."""
    if not case.determined:
        return "undetermined", None
    if not case.well_conditioned:
        return "ill_conditioned", None
    assert case.forward is not None and case.backward is not None
    x, xb = case.forward.at(direction), case.backward.at(direction)
    state = _decide_one(x, xb, case.painleve)
    if state in ("closes", "loses_contact"):
        return state, x
    if state in ("opens", "opens_loses_contact"):
        return state, xb
    return state, None


def outcomes(case: Case, directions: np.ndarray) -> np.ndarray:
    """Outcome (m,) for each unit force direction (m, dim) of a determined, well-conditioned
    case: :func:`outcome` vectorised over directions."""
    assert case.forward is not None and case.backward is not None
    forward = case.forward.a + directions @ case.forward.c.T
    backward = case.backward.a + directions @ case.backward.c.T
    return _decide(forward, backward, case.painleve)


def safe_arcs(case: Case, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, float | None]:
    """Force angles in the sweep plane where the case closes, uniquely
    (:func:`closing_conditions`).

    Returns the arc set (radians from ``e1`` towards ``e2``) and an estimate of the absolute
    error of its ends in radians, None without ends (:func:`kcheck.mechanics.arcs.affine_arcs`).
    """
    a, c, error = closing_conditions(case)
    return affine_arcs(a, c, e1, e2, error)
