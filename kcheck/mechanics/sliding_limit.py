"""The sliding limit: the least common friction coefficient at which rough contacts in space
balance a wrench, where every contact pressed at that limit slides there, by Newton's method
and checked without a conic solve (:func:`sliding_limit`); the last few such limits,
remembered so that the jamming check's next question about the same contacts needs no conic
solve either (:func:`certified_holding`).

:mod:`kcheck.mechanics.least_friction` asks it first and searches with conic programmes where
it answers None. Nondimensional, as :mod:`kcheck.mechanics.statics`.
"""

from __future__ import annotations

import math

import numpy as np

from kcheck.mechanics.statics import Statics
from kcheck.numerics.thresholds import (
    BALANCE_RTOL,
    LIFT_RTOL,
    NEWTON_RTOL,
    PRESSED_RTOL,
    SLIDING_CERTIFICATE_MARGIN,
    SLIDING_NEWTON_DIVERGED,
    ZERO_GUARD,
)

__all__ = ["certified_holding", "largest_ratio", "remember_limit", "sliding_limit"]


def largest_ratio(local: np.ndarray, scale: np.ndarray) -> float:
    """The largest ``|f_t| / (scale f_n)`` over the contacts with a share of the normal
    force (forces in the contacts' axes, (k, 3)).

    In plain floats (a handful of contacts, where numpy's per-call overhead was most of the
    time): the same operations as :func:`_largest_ratio_numpy` in the same order
    (``np.linalg.norm`` of a row is ``sqrt(t1 * t1 + t2 * t2)``), so the same value; that
    function where a force is not finite."""
    rows, scales = local.tolist(), scale.tolist()
    normals = [abs(n) for n, _, _ in rows]
    if not all(math.isfinite(x) for row in rows for x in row):
        return _largest_ratio_numpy(local, scale)
    limit = PRESSED_RTOL * max(max(normals), ZERO_GUARD)
    largest = None
    for (n, t1, t2), s in zip(rows, scales, strict=True):
        fn = n * s
        if s > 0 and fn > limit:
            ratio = math.sqrt(t1 * t1 + t2 * t2) / fn
            if largest is None or ratio > largest:
                largest = ratio
    return 0.0 if largest is None else largest


def _largest_ratio_numpy(local: np.ndarray, scale: np.ndarray) -> float:
    """:func:`largest_ratio` with numpy."""
    fn = local[:, 0] * scale
    tangential = np.linalg.norm(local[:, 1:], axis=1)
    pressed = (scale > 0) & (fn > PRESSED_RTOL * max(float(np.abs(local[:, 0]).max()), ZERO_GUARD))
    ratios = tangential[pressed] / fn[pressed]
    return float(ratios.max()) if len(ratios) else 0.0


#: Most Newton steps of :func:`sliding_limit` per set of pressed contacts (it needs 3 to 8; 1
#: of 234 recorded cases needed 16 to 30).
NEWTON_STEPS = 16
#: Most contacts :func:`sliding_limit` lets lift off before it leaves the answer to the conic
#: search.
LIFTED = 2


def sliding_limit(
    columns: np.ndarray, wrench: np.ndarray, kept: np.ndarray, rtol: float
) -> float | None:
    """The least common coefficient ``mu`` (coefficients ``mu * kept``) at which rough
    contacts in space (``columns`` (3k, 6) as :func:`kcheck.mechanics.statics._contact_axes`)
    balance ``wrench``, where every contact pressed at that least coefficient slides there:
    without a conic solve, and certified; None where that does not hold (a pressed contact
    sticks, a support is frictionless, the steps do not converge or the certificate fails),
    and the caller's conic search decides.

    The limit is a twist ``h`` along which the load does no work while every pressed contact
    opens exactly as fast as its friction cone allows (``h . N_j = mu s_j |(h . T1_j, h .
    T2_j)|``: a separating hyperplane of the contact-wrench cone that touches it at
    ``-wrench``), with normal forces ``f_j > 0`` on those contacts, each on its cone's edge
    opposite that slip, balancing the wrench: ``a + 1 + 6`` equations in ``h``, ``mu`` and
    the ``a`` forces (:func:`_sliding_newton`), solved by Newton's method from the
    frictionless free twist at ``mu = 0``. A contact whose force comes out negative lifts
    off: it leaves the pressed set and the steps go on (at most LIFTED times).

    Checked as bisection would find it, without a conic solve, and to the standard the conic
    search meets rather than exactly. The "holds" side rests on an explicit balance: normal
    forces positive, each pressed contact on its cone's edge, the returned value their
    largest friction ratio as computed in floating point (a few ulps), and an imbalance of
    at most ``BALANCE_RTOL`` (1e-10) of the wrench (a converged solve leaves about 1e-15):
    forces within the conic solver's own tolerance (1e-8) of a balance, so the programme at
    that coefficient would find it feasible too, but not a proof that an exact balance
    exists there. The "fails" side rests on a separating twist (nudged so that the load does
    work along it) that clears every contact's cone at ``(1 - rtol)`` times the value by
    more than ``SLIDING_CERTIFICATE_MARGIN`` of the terms compared (:func:`_separates`; Farkas: no
    balance there), far above the rounding of the few products it is computed from."""
    n, k = len(wrench), len(kept)
    if n != 6 or not np.all(kept > 0):
        return None
    size = float(np.linalg.norm(wrench))
    if not size > 0:
        return None
    if k >= n:
        return None  # no free twist: the normals alone fix the body
    w = wrench / size
    parts = columns.reshape(k, 3, n)
    normals, tangents = parts[:, 0], parts[:, 1:]
    u, sv, vt = np.linalg.svd(normals)
    if not sv[-1] > 0:
        return None
    free = vt[-1]  # the frictionless free twist
    along = float(free @ w)
    if along == 0:
        return None
    start = free if along > 0 else -free
    pressed = np.arange(k)
    # The frictionless normal forces (least squares, in units of the wrench) from the same
    # decomposition: the start.
    state = (start, 0.0, u @ ((vt[:k] @ -w) / sv))
    for lifted in range(LIFTED + 1):
        if lifted == 0 and k == n - 1:
            found = _sliding_newton_all(normals, tangents, w, kept, start)
        else:
            found = _sliding_newton(
                normals[pressed], tangents[pressed], w, kept[pressed], start, state
            )
        if found is None:
            return None
        h, mu, force = found
        if np.all(force > 0):
            break
        lifts = np.arange(len(pressed)) != int(np.argmin(force))
        pressed, state = pressed[lifts], (h, mu, force[lifts])
    else:
        return None
    slip, _ = _slip(tangents[pressed], h)
    if slip is None or not mu > 0:
        return None
    local = np.zeros((k, 3))
    local[pressed, 0] = size * force
    local[pressed, 1:] = -(mu * kept[pressed] * size * force)[:, None] * slip
    if np.linalg.norm(columns.T @ local.ravel() + wrench) > BALANCE_RTOL * size:
        return None
    least = largest_ratio(local, kept)
    if not _separates(normals, tangents, w, h, (1.0 - rtol) * least * kept):
        return None
    return least


def _sliding_newton_all(
    normals: np.ndarray, tangents: np.ndarray, w: np.ndarray, kept: np.ndarray, start: np.ndarray
) -> tuple[np.ndarray, float, np.ndarray] | None:
    """:func:`_sliding_newton` with every one of ``n - 1`` contacts pressed, from the free
    twist at ``mu = 0``: the twist is then fixed by the ``n - 1`` cone conditions, the load's
    zero work and its scale, so the forces need not be among the unknowns (a 7 x 7 system
    instead of 12 x 12); they follow at the end, as the balance's least squares."""
    a, n = len(kept), len(w)
    h, mu = start, 0.0
    jacobian = np.zeros((n + 1, n + 1))
    jacobian[a, :n] = w
    jacobian[a + 1, :n] = start
    residual = np.zeros(n + 1)
    for _ in range(NEWTON_STEPS):
        velocity = tangents @ h
        speed = np.hypot(velocity[:, 0], velocity[:, 1])
        if not speed.min() > 0:
            return None
        lean = np.einsum("kc,kcn->kn", velocity / speed[:, None], tangents)  # T_j^T u_j
        edges = normals - (mu * kept)[:, None] * lean
        residual[:a] = edges @ h  # h . N_j - mu s_j |T_j h|
        residual[a] = w @ h
        residual[a + 1] = start @ h - 1.0
        jacobian[:a, :n] = edges
        jacobian[:a, n] = -kept * speed
        step = _solve_small(jacobian, -residual)
        if step is None:
            return None
        h, mu = h + step[:n], mu + float(step[n])
        if not (abs(mu) < SLIDING_NEWTON_DIVERGED and np.abs(h).max() < SLIDING_NEWTON_DIVERGED):
            return None
        if abs(step[n]) <= NEWTON_RTOL * abs(mu) and np.abs(step[:n]).max() <= NEWTON_RTOL:
            velocity = tangents @ h
            speed = np.hypot(velocity[:, 0], velocity[:, 1])
            if not speed.min() > 0:
                return None
            lean = np.einsum("kc,kcn->kn", velocity / speed[:, None], tangents)
            edges = normals - (mu * kept)[:, None] * lean
            force = _solve_small(edges @ edges.T, -(edges @ w))
            return None if force is None else (h, mu, force)
    return None


def _sliding_newton(
    normals: np.ndarray,
    tangents: np.ndarray,
    w: np.ndarray,
    kept: np.ndarray,
    start: np.ndarray,
    state: tuple[np.ndarray, float, np.ndarray],
) -> tuple[np.ndarray, float, np.ndarray] | None:
    """Newton's method for :func:`sliding_limit` on the pressed contacts (normals (a, 6),
    tangents (a, 2, 6), coefficients' scale (a,)) and the unit wrench ``w``, from ``state``
    (twist, ``mu``, normal forces (a,) in units of the wrench): the residuals
    ``h . N_j - mu s_j |T_j h|``, ``start . h - 1`` (the twist's scale) and
    ``sum_j f_j (N_j - mu s_j T_j^T u_j) + w`` with ``u_j = T_j h / |T_j h|`` (the slip),
    and their exact derivatives. The solution, or None when a contact stops sliding, the
    matrix is singular or NEWTON_STEPS do not converge."""
    h, mu, force = state
    a, n = len(kept), len(w)
    size = n + 1 + a
    jacobian = np.zeros((size, size))
    jacobian[a, :n] = start
    residual = np.zeros(size)
    # T_j^T T_j, summed with weights below: d(T_j^T u_j)/dh = (T_j^T T_j - l_j l_j^T) / |T_j h|
    # with l_j = T_j^T u_j (u_j = T_j h / |T_j h|, the slip).
    gram = np.einsum("kcn,kcm->knm", tangents, tangents).reshape(a, n * n)
    for _ in range(NEWTON_STEPS):
        velocity = tangents @ h
        speed = np.hypot(velocity[:, 0], velocity[:, 1])
        if not speed.min() > 0:
            return None
        slip = velocity / speed[:, None]
        lean = np.einsum("kc,kcn->kn", slip, tangents)  # T_j^T u_j
        friction = mu * kept
        edges = normals - friction[:, None] * lean
        residual[:a] = edges @ h  # h . N_j - mu s_j |T_j h|
        residual[a] = start @ h - 1.0
        residual[a + 1 :] = force @ edges + w
        jacobian[:a, :n] = edges
        jacobian[:a, n] = -kept * speed
        jacobian[a + 1 :, n] = -(force * kept) @ lean
        jacobian[a + 1 :, n + 1 :] = edges.T
        weight = friction * force / speed
        jacobian[a + 1 :, :n] = (weight * lean.T) @ lean - (weight @ gram).reshape(n, n)
        step = _solve_small(jacobian, -residual)
        if step is None:
            return None
        h, mu, force = h + step[:n], mu + float(step[n]), force + step[n + 1 :]
        if not (abs(mu) < SLIDING_NEWTON_DIVERGED and np.abs(h).max() < SLIDING_NEWTON_DIVERGED):
            return None  # no limit with these pressed contacts (one sticks, or lifts off)
        if abs(step[n]) <= NEWTON_RTOL * abs(mu) and np.abs(step[:n]).max() <= NEWTON_RTOL:
            return h, mu, force
        # Near the solution (the error left about the square of the step) a force clearly
        # below zero stays there: that contact lifts off, no need to converge first.
        if abs(step[n]) <= LIFT_RTOL * abs(mu) and force.min() < -LIFT_RTOL * force.max():
            return h, mu, force
    return None


def _solve_small(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    """``matrix^-1 rhs`` for a small square system (LAPACK's gesv through scipy, which the
    spatial checks have loaded for qhull: a quarter of ``np.linalg.solve``'s per-call cost
    at 7 x 7); None when it is singular."""
    from scipy.linalg.lapack import dgesv

    _, _, x, info = dgesv(matrix, rhs)
    return None if info != 0 else np.asarray(x)


def _slip(tangents: np.ndarray, h: np.ndarray) -> tuple[np.ndarray | None, np.ndarray]:
    """Each contact's tangential velocity along the twist ``h`` (in its tangent axes): unit
    directions (k, 2), None where a contact does not slide, and speeds (k,)."""
    velocity = tangents @ h
    speed = np.sqrt(np.einsum("kc,kc->k", velocity, velocity))
    if not np.all(speed > 0):
        return None, speed
    return velocity / speed[:, None], speed


def _separates(
    normals: np.ndarray, tangents: np.ndarray, w: np.ndarray, h: np.ndarray, mu: np.ndarray
) -> bool:
    """Whether the twist ``h``, nudged along the unit wrench ``w`` so that the load does
    work along it, clears every contact's cone of coefficient ``mu_j``: ``h . N_j >
    mu_j |(h . T1_j, h . T2_j)|`` with a margin of SLIDING_CERTIFICATE_MARGIN times the terms
    compared. Then no balance of the wrench lies in those cones (Farkas' lemma)."""
    lean = float(w @ h)
    h = h + (abs(lean) + SLIDING_CERTIFICATE_MARGIN * float(np.abs(h).max())) * w
    if not float(w @ h) > 0:
        return False
    velocity = tangents @ h
    speed = np.sqrt(np.einsum("kc,kc->k", velocity, velocity))
    opening = normals @ h
    scale = float(np.abs(h).sum()) * (
        np.abs(normals).max(axis=1) + mu * np.abs(tangents).max(axis=(1, 2))
    )
    return bool(np.all(opening - mu * speed > SLIDING_CERTIFICATE_MARGIN * scale))


# The last few certified sliding limits: the jamming check decides the design direction at
# the scene's friction right after the least holding friction of the same case.
_LIMITS: dict[bytes, tuple[np.ndarray, float, float]] = {}
#: How many certified limits :func:`certified_holding` remembers.
RECENT_LIMITS = 16


def _limit_key(statics: Statics, keep: np.ndarray, wrench: np.ndarray) -> bytes:
    """The kept contacts' geometry and the wrench, as bytes."""
    parts = (statics.points[keep], statics.normals[keep], wrench)
    return b"|".join(np.ascontiguousarray(x, float).tobytes() for x in parts)


def remember_limit(
    statics: Statics,
    keep: np.ndarray,
    wrench: np.ndarray,
    kept: np.ndarray,
    holds_from: float,
    fails_to: float,
) -> None:
    """Keep a certified limit: coefficients ``c * kept`` balance the wrench for ``c >=
    holds_from`` (an explicit balance there, to ``BALANCE_RTOL``: :func:`sliding_limit`) and
    do not for ``c <= fails_to`` (a separating twist)."""
    if len(_LIMITS) >= RECENT_LIMITS:
        del _LIMITS[next(iter(_LIMITS))]
    _LIMITS[_limit_key(statics, keep, wrench)] = (kept.copy(), holds_from, fails_to)


def certified_holding(
    statics: Statics, keep: np.ndarray, wrench: np.ndarray, mu: np.ndarray
) -> bool | None:
    """Whether the supports ``keep`` with coefficients ``mu`` (every support's) balance
    ``wrench``, where one of the last sliding limits
    :func:`~kcheck.mechanics.least_friction.least_friction_exactly` checked decides it
    without a conic solve: ``mu`` on the kept supports a common multiple ``c`` of that
    search's scale, and ``c`` at or above the limit (True) or at or below ``(1 - rtol)``
    times it (False). None otherwise."""
    found = _LIMITS.get(_limit_key(statics, keep, wrench))
    if found is None:
        return None
    kept, holds_from, fails_to = found
    mine = np.asarray(mu, float)[keep]
    c = float(mine[0] / kept[0])
    if not np.array_equal(mine, c * kept):
        return None
    if c >= holds_from:
        return True
    if c <= fails_to:
        return False
    return None
