"""Whether friction can hold a body, decided for many contact sets at once by certificates.

Each question is the conic programme of :func:`kcheck.mechanics.statics.holds_exactly`: do
forces ``f_j = (n_j, t_j)`` in the kept contacts' exact friction cones
``K_j = {|t_j| <= mu_j n_j}`` balance the wrench, ``sum_j C_j^T f_j = -w`` (``C_j``: the
contact's three unit wrenches, rows of :func:`~kcheck.mechanics.statics.contact_columns`)?
Either answer has a certificate that plain arithmetic checks:

* **no** (Farkas): a twist ``y`` with ``y . w > 0`` that opens every kept contact inside the
  dual of its friction cone, ``p_j >= mu_j |q_j|`` with ``(p_j, q_j) = C_j y`` (normal and
  tangential velocity). Dotting the balance with ``y`` gives ``sum_j (p_j n_j + q_j . t_j)
  >= 0`` on the left and ``-y . w < 0`` on the right.
* **yes**: forces strictly inside every cone that balance ``-w`` (put back on the balance
  exactly by a least-norm correction).

Both are searched by one method: the dual's *phase one*, maximise ``s`` with
``p_j - s >= mu_j |q_j|``, ``y . w = 1`` and ``s <= 1``, which has an obvious strictly
feasible start (``y = w``, ``s`` low enough), so a plain log-barrier method (damped Newton
on the cones' self-concordant barrier; every question's 7 unknowns stacked in one batch of
numpy calls) needs no phase one of its own. Its iterate is the twist; the barrier's gradient
at the cones lies inside them and gives the forces. A question is answered only when a
certificate passes its check with a margin, ``HOLDING_CERTIFICATE_MARGIN`` of its size, a
hundred times clarabel's tolerances: then the conic programme has the same answer. Every
other question (too near the boundary, a frictionless contact that would need forces on the
cone's edge, contacts whose wrenches are too near dependent for the balance's rounding to be
bounded, or not decided within ``HOLDING_CERTIFICATE_STEPS`` steps) is left undecided
(None), for the programme itself.

Nondimensional throughout (the wrenches of :class:`kcheck.mechanics.statics.Statics`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from kcheck.numerics.thresholds import (
    EPS,
    HOLDING_CERTIFICATE_CONDITION,
    HOLDING_CERTIFICATE_MARGIN,
    HOLDING_CERTIFICATE_STEPS,
)

__all__ = ["holding_certified"]

_J = np.array([1.0, -1.0, -1.0])  # the second-order cone's form: z^T J z = z0^2 - |z1|^2

# The barrier method's numerical choices (they change how many steps a question takes, not
# what a certificate must pass).
#: The barrier's first weight on ``s`` (from 1 it took about 1.6x the steps).
FIRST_WEIGHT = 10.0
#: The factor on the weight each time the iterate is centred (a long-step path following).
WEIGHT_GROWTH = 8.0
#: Newton decrement below which the full step is taken (damped ``1 / (1 + decrement)`` above:
#: self-concordance keeps the iterate inside the cones) and the iterate counts as close
#: enough to the central path for the "hopeless" test.
FULL_STEP_DECREMENT = 0.25
#: Newton decrement below which the iterate counts as centred and the weight grows.
CENTRED_DECREMENT = 0.5
#: Share of the margin a slack may lose to the balance's rounding and its exact correction.
ROUNDING_SHARE = 0.5


def holding_certified(
    columns: Sequence[np.ndarray], wrenches: Sequence[np.ndarray], mus: Sequence[np.ndarray]
) -> list[bool | None]:
    """Per question (kept columns (3k, 6), wrench (6,), coefficients (k,)): True where
    checked forces show friction holds the body, False where a checked twist shows it cannot
    (the conic programme answers the same), None where neither was found (ask the
    programme)."""
    holds = np.zeros(len(columns), bool)
    fails = np.zeros(len(columns), bool)
    sizes = np.array([len(m) for m in mus], dtype=np.int64)
    for k in np.unique(sizes).tolist():
        which = np.flatnonzero(sizes == k)
        index = which.tolist()
        c = np.array([columns[i] for i in index], dtype=np.float64).reshape(len(index), k, 3, 6)
        w = np.array([wrenches[i] for i in index], dtype=np.float64)
        mu = np.array([mus[i] for i in index], dtype=np.float64)
        holds[which], fails[which] = _certified(c, w, mu)
    return [True if h else False if f else None for h, f in zip(holds, fails, strict=True)]


def _certified(c: np.ndarray, w: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`holding_certified` of questions with the same number of kept contacts: columns
    (q, k, 3, 6), wrenches (q, 6), coefficients (q, k); whether each holds, whether each
    cannot (both False: undecided)."""
    q, k = mu.shape
    found, holds = np.zeros(q, bool), np.zeros(q, bool)
    norm = np.linalg.norm(w, axis=1)
    live = np.flatnonzero((norm > 0) & np.all(np.isfinite(w), axis=1) & np.all(mu >= 0, axis=1))
    if len(live) == 0 or k == 0:
        return holds, found
    c, mu, w = c[live], mu[live], w[live] / norm[live, None]
    # The dual's cones on v = (y, s): z_j = D_j v = (p_j - s, mu_j q_j).
    d = np.zeros((len(live), k, 3, 7))
    d[..., 0, :6] = c[:, :, 0]
    d[..., 0, 6] = -1.0
    d[..., 1:, :6] = mu[..., None, None] * c[:, :, 1:]
    jd = d * _J[:, None]
    forms = np.einsum("qkai,qkaj->qkij", d, jd).reshape(len(live), k, 49)  # D^T J D
    v = np.zeros((len(live), 7))
    v[:, :6] = w
    z = (d @ v[:, None, :, None])[..., 0]
    v[:, 6] = np.minimum((z[..., 0] - np.hypot(z[..., 1], z[..., 2])).min(axis=1) - 1.0, 0.0)
    t = np.full(len(live), FIRST_WEIGHT)  # the barrier's weight on s
    barrier = 2 * k + 1  # the barrier's parameter: the central path's gap is barrier / t
    flat = c.reshape(len(live), 3 * k, 6)
    gram = _inverse_each(np.einsum("qai,qaj->qij", flat, flat))  # (C^T C)^-1
    reach = np.linalg.norm(flat, axis=(1, 2)) * np.linalg.norm(gram, axis=(1, 2))
    # Forces can certify holding only inside every cone: no frictionless contact.
    gram[~np.all(mu > 0, axis=1)] = np.nan
    kkt = np.zeros((len(live), 8, 8))
    kkt[:, :6, 7] = kkt[:, 7, :6] = w
    rhs = np.zeros((len(live), 8, 1))
    active = np.arange(len(live))
    with np.errstate(all="ignore"):
        for _ in range(HOLDING_CERTIFICATE_STEPS):
            a = active
            jz = (jd[a] @ v[a, None, :, None])[..., 0]  # J z_j
            inv = 1.0 / np.einsum("qka,qka->qk", jz * _J, jz)  # 1 / (z^T J z)
            u = np.einsum("qkai,qka->qki", d[a], jz)  # D^T J z
            grad = -2.0 * np.einsum("qki,qk->qi", u, inv)
            hess = (-2.0 * inv[:, None, :] @ forms[a]).reshape(len(a), 7, 7)
            hess += 4.0 * (u * (inv**2)[..., None]).transpose(0, 2, 1) @ u
            room = 1.0 - v[a, 6]
            grad[:, 6] += 1.0 / room - t[a]
            hess[:, 6, 6] += 1.0 / room**2
            kkt[a, :7, :7] = hess
            rhs[a, :7, 0] = -grad
            step = _solve_each(kkt[a], rhs[a])[:, :7, 0]
            decrement = np.sqrt(np.maximum(np.einsum("qi,qij,qj->q", step, hess, step), 0.0))
            # Damped Newton: stays strictly inside the cones (self-concordance).
            damp = np.where(decrement < FULL_STEP_DECREMENT, 1.0, 1.0 / (1.0 + decrement))
            v[a] += damp[:, None] * step
            centred = decrement < CENTRED_DECREMENT
            t[a] = np.where(centred, WEIGHT_GROWTH * t[a], t[a])
            ok = _checks(c[a], mu[a], w[a], v[a, :6])
            found[live[a[ok]]] = True
            held = _balanced(c[a], mu[a], w[a], gram[a], reach[a], jz * inv[..., None]) & ~ok
            holds[live[a[held]]] = True
            ok |= held
            # Centred, and even twice the central path's gap (the iterate is only near the
            # path) leaves the margin s below zero: no twist certificate to find (forces, if
            # any, were tried just above).
            hopeless = (decrement < FULL_STEP_DECREMENT) & (v[a, 6] + 2.0 * barrier / t[a] < 0.0)
            keep = ~ok & ~hopeless & np.all(np.isfinite(v[a]), axis=1)
            active = a[keep]
            if len(active) == 0:
                break
    return holds, found


def _checks(c: np.ndarray, mu: np.ndarray, w: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Whether each twist ``y`` is a certificate with the margin: every contact opened
    inside the dual cone and the wrench doing work, by HOLDING_CERTIFICATE_MARGIN of |y|."""
    g = (c @ y[:, None, :, None])[..., 0]
    size = np.linalg.norm(y, axis=1)
    opened = g[..., 0] - mu * np.hypot(g[..., 1], g[..., 2])
    floor = HOLDING_CERTIFICATE_MARGIN * size
    with np.errstate(invalid="ignore"):
        return np.all(opened >= floor[:, None], axis=1) & (np.einsum("qj,qj->q", y, w) >= floor)


def _balanced(
    c: np.ndarray,
    mu: np.ndarray,
    w: np.ndarray,
    gram: np.ndarray,
    reach: np.ndarray,
    cones: np.ndarray,
) -> np.ndarray:
    """Whether the forces the barrier's iterate implies hold the body with the margin.

    The barrier's gradient at the cones ``J z_j / (z_j^T J z_j)`` (q, k, 3) is inside each
    second-order cone, so ``(n_j, t_j) = (g_0, mu_j g_1, mu_j g_2)`` is inside each friction
    cone; near the central path the forces balance a multiple of ``-w``. Scaled to balance
    ``-w`` best and put back on the balance exactly (least-norm correction), they certify an
    equilibrium when every normal force and every cone's slack clears
    HOLDING_CERTIFICATE_MARGIN of their size, and the balance's rounding is far inside that:
    the exact correction of what is left, at most ``reach`` (``|C| |(C^T C)^-1|``, Frobenius
    norms) times the residual, moves no slack by more than half the margin. The residual
    counts its own rounding too: computed as ``left``, it is at most ``left + (3k + 1) eps
    (|C| |f| + |w|)`` (Higham's bound for a sum of ``3k + 1`` terms). And ``reach`` times the
    unit roundoff stays below HOLDING_CERTIFICATE_CONDITION, so that ``(C^T C)^-1`` is itself
    computed to far better than the margin: a nearly dependent contact set, whose computed
    residual can round to zero while its reach is 1e16, certifies nothing."""
    q, k = mu.shape
    f = np.concatenate([cones[..., :1], mu[..., None] * cones[..., 1:]], axis=2)
    flat = c.reshape(q, 3 * k, 6)
    b = np.einsum("qai,qa->qi", flat, f.reshape(q, 3 * k))
    scale = -np.einsum("qi,qi->q", b, w) / np.einsum("qi,qi->q", b, b)
    f = f.reshape(q, 3 * k) * scale[:, None]
    residual = np.einsum("qai,qa->qi", flat, f) + w
    f = f - np.einsum("qai,qij,qj->qa", flat, gram, residual)
    left = np.linalg.norm(np.einsum("qai,qa->qi", flat, f) + w, axis=1)
    size = np.linalg.norm(flat, axis=(1, 2)) * np.linalg.norm(f, axis=1)
    left += (3 * k + 1) * EPS * (size + np.linalg.norm(w, axis=1))
    f = f.reshape(q, k, 3)
    floor = HOLDING_CERTIFICATE_MARGIN * np.abs(f).max(axis=(1, 2))
    slack = np.minimum(f[..., 0], mu * f[..., 0] - np.hypot(f[..., 1], f[..., 2]))
    with np.errstate(invalid="ignore"):
        exact = (1.0 + mu.max(axis=1)) * reach * left <= ROUNDING_SHARE * floor
        exact &= reach * EPS <= HOLDING_CERTIFICATE_CONDITION
        return (scale > 0) & exact & np.all(slack >= floor[:, None], axis=1)


def _inverse_each(matrix: np.ndarray) -> np.ndarray:
    """Each matrix's inverse; NaN where one is singular."""
    eye = np.broadcast_to(np.eye(matrix.shape[-1]), matrix.shape)
    return _solve_each(matrix, eye.copy())


def _solve_each(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``matrix^-1 rhs`` per question; NaN where one is singular (that question stops)."""
    try:
        return np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError:
        out = np.full_like(rhs, np.nan)
        for i, (m, r) in enumerate(zip(matrix, rhs, strict=True)):
            try:
                out[i] = np.linalg.solve(m, r)
            except np.linalg.LinAlgError:
                pass
        return out
