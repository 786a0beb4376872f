"""The peer method: Patti & Vogels' eigenvalue computation of the limiting coefficient of
friction of a kinematic coupling, written from the paper's description for the paired
benchmark ``benchmarks/bench_peer.py`` (not part of kcheck).

Reference: A. Patti and J. Vogels, *Self-alignment of kinematic couplings: effects of
deformations*, Precision Engineering 60 (2019). For each removed contact ``r`` the body's
free motion is the twist ``xi`` reciprocal to the five remaining contact normals (their
wrenches' null space), oriented so that the removed contact moves towards its support. Each
remaining contact ``j`` slides with velocity ``u_j`` and pushes with ``N_j (n_j - mu u_j/|u_j|)``
(Coulomb friction opposing the sliding). The body can stand still — the coupling jams — when
these five forces balance the external wrench ``w``:

    [W(n) - mu W(t) | w] [N; 1] = 0,    W(.)  the 6 x 5 wrenches of the contact directions,

a generalised eigenproblem ``A0 x = mu B x`` with ``A0 = [W(n) | w]``, ``B = [W(t) | 0]``.
The limiting coefficient of the case is its smallest real positive eigenvalue whose
eigenvector has positive normal forces; the coupling's is the smallest over the cases.
Like the published script, one case at a time: a null space by SVD and one generalised
eigenproblem (``scipy.linalg.eig(A, B)``, MATLAB's ``eig(A, B)``) per removed contact.

Inputs are in any consistent units (the eigenvalues are dimensionless): contact points
``p`` (6, 3), unit normals ``n`` (6, 3) pointing from the support into the body, and the
external wrench about the origin ``w = [f, p_f x f]`` (force first).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg


def wrench(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Wrenches ``[f; p x f]`` (6, m) of forces (m, 3) at points (m, 3)."""
    return np.vstack([forces.T, np.cross(points, forces).T])


def free_twist(points: np.ndarray, normals: np.ndarray, removed: int) -> np.ndarray:
    """Twist ``[v; w]`` (6,) reciprocal to every normal but the removed one, moving the removed
    contact towards its support (against its normal)."""
    keep = np.arange(len(points)) != removed
    # Reciprocal product of a wrench [f; m] and a twist [v; w]: f.v + m.w.
    _, _, vt = np.linalg.svd(wrench(points[keep], normals[keep]).T)
    twist = vt[-1]
    u = twist[:3] + np.cross(twist[3:], points[removed])
    return twist if u @ normals[removed] < 0 else -twist


def case_friction(points: np.ndarray, normals: np.ndarray, w: np.ndarray, removed: int) -> float:
    """The limiting coefficient of one removed contact (``inf`` when no friction jams it)."""
    twist = free_twist(points, normals, removed)
    keep = np.arange(len(points)) != removed
    p, n = points[keep], normals[keep]
    u = twist[:3] + np.cross(twist[3:], p)
    t = u / np.linalg.norm(u, axis=1)[:, None]
    a0 = np.column_stack([wrench(p, n), w])
    b = np.column_stack([wrench(p, t), np.zeros(6)])
    values, vectors = scipy.linalg.eig(a0, b)
    best = np.inf
    for mu, x in zip(values, vectors.T, strict=True):
        if not np.isfinite(mu) or abs(mu.imag) > 1e-9 * max(1.0, abs(mu)) or mu.real <= 0:
            continue
        if abs(x[-1]) == 0:
            continue
        forces = (x[:-1] / x[-1]).real
        if np.all(forces > 0) and mu.real < best:
            best = mu.real
    return best


def limiting_friction(points: np.ndarray, normals: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Per removed contact, the limiting coefficient of friction (6,)."""
    return np.array([case_friction(points, normals, w, r) for r in range(len(points))])
