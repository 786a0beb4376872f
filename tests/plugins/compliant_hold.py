"""Whether a body friction can hold stays held on compliant contacts: the elastic response of
the seat to the loss of one support. Evidence for issue 26, kept with the tests: no check
uses it (docs/validation.md, "Compliant contacts").

The rigid model leaves a held body's friction forces statically indeterminate (5 spatial
contacts: 15 force components, 6 equations); "friction can hold" means some distribution lies
in the cones, not that the one a compliant seat reaches does. This module computes the one
linear contact springs reach. From the frictionless seat (each contact pressed by its seated
normal force ``N0_i``, no tangential force: the body slid into its seat without friction, as
the `reseat` simulation settles it; :func:`kcheck.mechanics.seat.contact_forces`) the retracted
support's force ``N0_r`` is removed; the body's small displacement twist ``u`` on the remaining
contacts' springs (normal ``k_n,i``, tangential ``k_t,i = ratio k_n,i``, isotropic in the
tangent plane) balances the lost force:

    K u = -N0_r w_r,    K = sum_i sum_e k_e,i w_e,i w_e,i^T

over each remaining contact's unit directions ``e`` (normal, one or two tangents) with
wrenches ``w = (p x e, e)``. Contact ``i``'s force is then ``N0_i n_i - sum_e k_e,i (w_e,i . u)
e``. A contact whose normal force would pull lets go (its seated force is lost too, and the
response is solved again without it); a contact whose tangential force exceeds ``mu N`` slips:
the compliant seat does not hold the body there, whatever the rigid model's equilibrium.
Quasi-static (no overshoot of the sudden release), small displacements, and the forces depend on the
stiffnesses only through their ratios. Mindlin's no-slip tangential stiffness of a sphere on a
flat of the same material is ``2 (1 - nu) / (2 - nu)`` of the normal one: 0.67 (nu = 0.5) to
1 (nu = 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kcheck.mechanics.kinematics import wrenches

__all__ = [
    "CompliantHold",
    "SlipHold",
    "compliant_hold",
    "slip_hold",
    "hertz_stiffness",
    "mindlin_ratio",
]


def mindlin_ratio(poisson: np.ndarray | float) -> np.ndarray:
    """Mindlin's tangential over normal stiffness of an elastic sphere on a flat of the same
    material, ``2 (1 - nu) / (2 - nu)`` (Johnson, Contact Mechanics, eq. 7.42)."""
    nu = np.asarray(poisson, float)
    return 2 * (1 - nu) / (2 - nu)


def hertz_stiffness(forces: np.ndarray) -> np.ndarray:
    """Relative normal stiffness of identical Hertzian contacts pressed by ``forces`` (c,) N:
    ``dN / d delta`` grows as ``N^(1/3)`` (delta ~ N^(2/3))."""
    return np.cbrt(np.maximum(np.asarray(forces, float), 0.0))


def _tangents(normals: np.ndarray) -> np.ndarray:
    """Unit tangent directions (c, dim - 1, dim) of each contact."""
    if normals.shape[1] == 2:
        return np.stack([-normals[:, 1], normals[:, 0]], axis=-1)[:, None]
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, np.cross(normals, t1)], axis=1)


@dataclass(frozen=True)
class CompliantHold:
    """The remaining contacts' forces on the body after the release, one row per stiffness
    ratio: ``forces`` (r, c, dim) N, ``normal`` and ``tangential`` magnitude (r, c) N,
    ``separated`` (the contact let go), and the friction each needs, ``usage = tangential /
    (mu normal)`` (0 where separated; inf where the contacts left cannot hold the body)."""

    forces: np.ndarray
    normal: np.ndarray
    tangential: np.ndarray
    separated: np.ndarray
    usage: np.ndarray

    @property
    def slips(self) -> np.ndarray:
        """Contacts (r, c) whose force leaves the friction cone: the seat slips there."""
        return self.usage > 1.0

    @property
    def holds(self) -> np.ndarray:
        """Whether every remaining contact sticks, per ratio (r,)."""
        return ~np.any(self.slips, axis=-1)


def compliant_hold(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    seated: np.ndarray,
    retracted: int,
    stiffness: np.ndarray,
    ratios: np.ndarray,
) -> CompliantHold:
    """The elastic response of the seat at ``points`` (c, dim) m with unit ``normals`` (into
    the body), coefficients ``mu`` (c,) and frictionless seated normal forces ``seated`` (c,)
    N to removing support ``retracted``'s force; contact normal stiffnesses ``stiffness`` (c,)
    (relative), tangential ones ``ratios`` (r,) times those. Columns follow the contacts; the
    retracted one is reported separated."""
    points = np.asarray(points, float)
    normals = np.asarray(normals, float)
    seated = np.asarray(seated, float)
    c, dim = points.shape
    ratios = np.atleast_1d(np.asarray(ratios, float))
    # Levers about the centroid over the layout size keep K well scaled (forces do not depend
    # on the origin or the length unit).
    centre = points.mean(axis=0)
    size = float(np.max(np.linalg.norm(points - centre, axis=1))) or 1.0
    lever = (points - centre) / size
    tangents = _tangents(normals)
    rows_n = wrenches(lever, normals)  # (c, n)
    rows_t = wrenches(lever[:, None], tangents)  # (c, dim - 1, n)
    k_n = np.einsum("i,ia,ib->iab", np.asarray(stiffness, float), rows_n, rows_n)
    k_t = np.einsum("i,ija,ijb->iab", np.asarray(stiffness, float), rows_t, rows_t)
    active = np.ones((len(ratios), c), dtype=bool)
    active[:, retracted] = False
    normal = np.zeros((len(ratios), c))
    tangential = np.zeros((len(ratios), c))
    forces = np.zeros((len(ratios), c, dim))
    for _ in range(c):
        mask = active.astype(float)
        matrix = np.einsum("rc,cab->rab", mask, k_n) + ratios[:, None, None] * np.einsum(
            "rc,cab->rab", mask, k_t
        )
        try:
            # every contact not pressing any more (the retracted one, those let go) loses its
            # seated force
            lost = -((1 - mask) * seated) @ rows_n
            twist = np.linalg.solve(matrix, lost[..., None])[..., 0]
        except np.linalg.LinAlgError:  # too few contacts left to hold the body elastically
            inf = np.where(active, np.inf, 0.0)
            return CompliantHold(forces, normal, tangential, ~active, inf)
        normal = (seated - np.asarray(stiffness, float) * (twist @ rows_n.T)) * mask
        t_parts = -(ratios[:, None, None] * np.asarray(stiffness, float)[None, :, None]) * (
            np.einsum("cja,ra->rcj", rows_t, twist)
        )
        tangential = np.linalg.norm(t_parts, axis=-1) * mask
        forces = (normal[..., None] * normals + np.einsum("rcj,cjd->rcd", t_parts, tangents)) * (
            mask[..., None]
        )
        pulling = active & (normal < 0)
        if not pulling.any():
            break
        # The most pulling contact of each ratio lets go; solve again without it.
        worst = np.argmin(np.where(pulling, normal, np.inf), axis=1)
        rows = np.flatnonzero(pulling.any(axis=1))
        active[rows, worst[rows]] = False
    mu = np.asarray(mu, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        usage = np.where(active, tangential / (mu * normal), 0.0)
    usage = np.where(active & (mu * normal <= 0) & (tangential > 0), np.inf, usage)
    return CompliantHold(forces, normal, tangential, ~active, np.nan_to_num(usage, nan=0.0))


#: A slipping contact's friction direction is settled when it turns less than this (rad) in a
#: step; the slip is followed for at most SLIP_STEPS solves.
SLIP_TURN = 1e-6
SLIP_STEPS = 200


@dataclass(frozen=True)
class SlipHold:
    """The compliant seat after local slip: ``holds`` whether a state is reached where every
    sticking contact's force is in its cone and every slipping one carries ``mu N`` against
    its slip (False: the slip does not stop, the body moves); ``slipping`` and ``separated``
    (c,) the contacts that slipped or let go on the way."""

    holds: bool
    slipping: np.ndarray
    separated: np.ndarray
    why: str = ""  # "held", "unstable" (the slip does not stop) or "unsettled" (no fixed point)


def slip_hold(
    points: np.ndarray,
    normals: np.ndarray,
    mu: np.ndarray,
    seated: np.ndarray,
    retracted: int,
    stiffness: np.ndarray,
    ratio: float,
) -> SlipHold:
    """:func:`compliant_hold` at one ratio, followed through local slip: a contact whose
    force leaves its cone slips, carrying ``mu N`` (N still from its normal spring) against
    the direction its point moves, without a tangential spring; the response is solved
    again until no contact leaves its cone (held) or the remaining sticking contacts cannot
    stop the slip (the stiffness matrix singular or not positive: moves). One quasi-static
    step from the seat, not the path the release follows."""
    points = np.asarray(points, float)
    normals = np.asarray(normals, float)
    seated = np.asarray(seated, float)
    k = np.asarray(stiffness, float)
    mu = np.asarray(mu, float)
    c, dim = points.shape
    centre = points.mean(axis=0)
    size = float(np.max(np.linalg.norm(points - centre, axis=1))) or 1.0
    lever = (points - centre) / size
    tangents = _tangents(normals)
    rows_n = wrenches(lever, normals)
    rows_t = wrenches(lever[:, None], tangents)  # (c, dim - 1, n)
    active = np.ones(c, dtype=bool)
    active[retracted] = False
    slipping = np.zeros(c, dtype=bool)
    friction = np.zeros((c, dim))  # unit direction of a slipping contact's friction force
    for _ in range(SLIP_STEPS):
        matrix = np.zeros((rows_n.shape[1],) * 2)
        rhs = -((~active) * seated) @ rows_n
        for i in np.flatnonzero(active):
            if slipping[i]:
                w_slip = wrenches(lever[i], normals[i] + mu[i] * friction[i])
                matrix += k[i] * np.outer(w_slip, rows_n[i])
                rhs += seated[i] * mu[i] * wrenches(lever[i], friction[i])
            else:
                matrix += k[i] * (np.outer(rows_n[i], rows_n[i]) + ratio * rows_t[i].T @ rows_t[i])
        eig = np.linalg.eigvals(matrix)
        if np.min(eig.real) <= 1e-12 * np.max(np.abs(eig)):
            return SlipHold(False, slipping, ~active, "unstable")
        twist = np.linalg.solve(matrix, rhs)
        normal = np.where(active, seated - k * (rows_n @ twist), 0.0)
        if np.any(normal < 0):
            worst = int(np.argmin(normal))
            active[worst] = slipping[worst] = False
            continue
        moved = np.einsum("cja,a->cj", rows_t, twist)  # tangential displacement, tangent basis
        force_t = -ratio * k[:, None] * moved
        # slipping contacts: friction against the slip
        along = np.einsum("cj,cjd->cd", -moved, tangents)
        length = np.linalg.norm(along, axis=1)
        turned = False
        for i in np.flatnonzero(active & slipping):
            if length[i] > 0:
                new = along[i] / length[i]
                if np.linalg.norm(new - friction[i]) > SLIP_TURN:
                    turned = True
                    # half a step towards the slip's direction: a full step can cycle
                    half = friction[i] + new
                    friction[i] = half / np.linalg.norm(half) if np.any(half) else new
        if turned:
            continue
        usage = np.where(
            active & ~slipping,
            np.linalg.norm(force_t, axis=1) / np.maximum(mu * normal, 1e-300),
            0.0,
        )
        if np.max(usage) <= 1.0:
            return SlipHold(True, slipping, ~active, "held")
        worst = int(np.argmax(usage))
        slipping[worst] = True
        trial = np.einsum("j,jd->d", force_t[worst], tangents[worst])
        friction[worst] = trial / np.linalg.norm(trial)
    return SlipHold(False, slipping, ~active, "unsettled")
