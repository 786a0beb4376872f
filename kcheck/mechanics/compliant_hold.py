"""Whether a body friction can hold stays held on compliant contacts: the elastic response of
the seat to the loss of one support.

The rigid model leaves a held body's friction forces statically indeterminate (5 spatial
contacts: 15 force components, 6 equations); "friction can hold" means some distribution lies
in the cones, not that the one a compliant seat reaches does. This module computes the one
linear contact springs reach. From the frictionless seat (each contact pressed by its seated
normal force ``N0_i``, no tangential force: the body slid into its seat without friction, as
the `reseat` simulation settles it) the retracted support's force ``N0_r`` is removed; the
body's small displacement twist ``u`` on the remaining contacts' springs (normal ``k_n,i``,
tangential ``k_t,i = ratio k_n,i``, isotropic in the tangent plane) balances the lost force:

    K u = -N0_r w_r,    K = sum_i sum_e k_e,i w_e,i w_e,i^T

over each remaining contact's unit directions ``e`` (normal, one or two tangents) with
wrenches ``w = (p x e, e)``. Contact ``i``'s force is then ``N0_i n_i - sum_e k_e,i (w_e,i .
u) e``. A contact whose normal force would pull lets go (its seated force is lost too, and the
response is solved again without it); a contact whose tangential force exceeds ``mu N`` slips: the compliant seat does not
hold the body there, whatever the rigid model's equilibrium. Quasi-static (no overshoot of the
sudden release), small displacements, and the forces depend on the stiffnesses only through
their ratios. Mindlin's no-slip tangential stiffness of a sphere on a flat of the same material
is ``2 (1 - nu) / (2 - nu)`` of the normal one: 0.67 (nu = 0.5) to 1 (nu = 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kcheck.mechanics.kinematics import wrenches

__all__ = [
    "CompliantHold",
    "compliant_hold",
    "hertz_stiffness",
    "mindlin_ratio",
    "seat_forces",
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


def seat_forces(points: np.ndarray, normals: np.ndarray, wrench: np.ndarray) -> np.ndarray:
    """Frictionless seated normal forces (c,) N of ``c = 3`` (planar) or 6 contacts balancing
    ``wrench`` (n,: moment about the origin of ``points``, force): ``sum N_i w_i = -wrench``."""
    return np.linalg.solve(wrenches(points, normals).T, -np.asarray(wrench, float))


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
