"""Static equilibrium with Coulomb friction: can the remaining supports hold the body?

With support ``r`` retracted, the body stays put if the external wrench ``W`` (load, weight,
preloads, torque) is balanced by contact forces of the remaining supports, each inside its
friction cone ``|f_t| <= mu_j f_n`` (``f_n >= 0``: a support only pushes). The contact
wrenches form a convex cone ``C`` (the sum of the supports' friction cones, mapped to wrenches
by :func:`kcheck.kinematics.wrenches`); equilibrium exists iff ``-W`` lies in ``C``.

* Planar: a friction cone is exactly two rays ``n +- mu t``, so ``C`` is polyhedral and its
  facets are cross products of pairs of edge wrenches (exact).
* Spatial: a circular cone is approximated by an ``m``-sided pyramid, inscribed (edges at
  ``mu``: a lower bound of ``C``) or circumscribed (edges at ``mu / cos(pi/m)``: an upper
  bound); the true boundary lies between. Its facets come from qhull. At single wrenches the
  exact second-order cones are decided by a conic solver (:func:`holds_exactly`, clarabel).

The swept load makes ``W`` affine in the unit direction ``d``: ``W(d) = w0 + B d``. Each facet
``f`` of ``C`` gives one condition ``a + c . d >= 0`` with ``a = -f . w0``, ``c = -B^T f``: a
half circle in the sweep plane, a spherical cap on the sphere (:mod:`kcheck.arcs`). So the
directions where friction can hold the body are exact arc sets (planar) or a cap intersection.

All arrays are nondimensional (:class:`kcheck.kinematics.Frame`): lengths by the layout size,
forces by the force scale. Wrenches are ``(moment about the origin, force)``. Friction
coefficients are per support, so callers may pass a static value, a range end, or a common
factor (:func:`least_friction`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np

from kcheck.arcs import FULL, ArcSet, affine_arcs
from kcheck.arrays import unique, unique_rows
from kcheck.cones import FACET_TOL, cone_facets, essential_rows
from kcheck.dynamics import friction_directions
from kcheck.kinematics import Frame, cross3, wrenches

__all__ = [
    "PYRAMID_EDGES",
    "Statics",
    "Equilibria",
    "build_statics",
    "tangent_frames",
    "friction_edges",
    "edge_wrenches",
    "equilibria",
    "closing_condition",
    "forward_limit",
    "holds",
    "holds_exactly",
    "equilibrium_forces",
    "friction_candidates",
    "least_friction",
    "least_friction_exactly",
    "rough_supports",
]

#: Sides of the pyramid approximating a spatial friction cone. The inscribed and the
#: circumscribed pyramids differ in friction by the factor cos(pi/8) = 0.924 (option
#: `pyramid_edges`; the error it makes in degrees is measured and reported).
PYRAMID_EDGES = 8
EPS = float(np.finfo(float).eps)
#: Most Dinkelbach-type steps of :func:`least_friction_exactly` (it needs 3 to 8).
STEPS = 30
Pyramid = Literal["inscribed", "circumscribed"]


@dataclass(frozen=True)
class Statics:
    """A scene's statics, nondimensional.

    ``fixed`` (n,) is the wrench that does not depend on the swept direction (weight when the
    load is swept, preloads, torque); ``swept`` (n, dim) maps a unit direction to its wrench
    (the load at its point, or the weight at the centre of mass when gravity is swept).
    """

    frame: Frame
    names: tuple[str, ...]
    points: np.ndarray  # (k, dim)
    normals: np.ndarray  # (k, dim), unit
    friction: np.ndarray  # (k,)
    fixed: np.ndarray  # (n,)
    swept: np.ndarray  # (n, dim)

    @property
    def dim(self) -> int:
        """2 (planar) or 3 (spatial)."""
        return self.points.shape[1]

    def wrench(self, direction: np.ndarray) -> np.ndarray:
        """External wrench (n,) for a unit swept direction (dim,)."""
        return self.fixed + self.swept @ direction


def build_statics(
    *,
    points: np.ndarray,
    normals: np.ndarray,
    friction: np.ndarray,
    names: tuple[str, ...],
    dim: int,
    force: float,
    swept_point: np.ndarray,
    swept_magnitude: float,
    fixed_forces: tuple[tuple[np.ndarray, np.ndarray], ...] = (),
    torque: np.ndarray | None = None,
) -> Statics:
    """Nondimensionalise (SI inputs, 3-vectors) into :class:`Statics`.

    ``force`` (N) is the force scale; the swept force of ``swept_magnitude`` (N) acts at
    ``swept_point`` (m); ``fixed_forces`` are ``(point, force vector)`` pairs in m and N (the
    weight when the load is swept, preloads); ``torque`` (N m) is a fixed couple.
    """
    if not force > 0:
        raise ValueError("the force scale must be positive")
    frame = Frame.for_points(np.asarray(points, float), dim, force)
    nw = 1 if dim == 2 else 3
    normals = np.asarray(normals, float)[:, :dim]
    fixed = np.zeros(nw + dim)
    for point, vector in fixed_forces:
        fixed += wrenches(frame.point(point), frame.vector(vector) / force)
    if torque is not None:
        fixed[:nw] += np.asarray(torque, float)[3 - nw :] / (force * frame.length)
    q = np.broadcast_to(frame.point(swept_point), (dim, dim))
    swept = (swept_magnitude / force) * wrenches(q, np.eye(dim)).T
    return Statics(
        frame=frame,
        names=names,
        points=frame.point(np.asarray(points, float)),
        normals=normals / np.linalg.norm(normals, axis=1, keepdims=True),
        friction=np.asarray(friction, float),
        fixed=fixed,
        swept=swept,
    )


# --- friction cones and the contact-wrench cone ---------------------------------------------


def tangent_frames(normals: np.ndarray) -> np.ndarray:
    """Unit tangents of each contact: (k, 1, 2) planar (``n`` turned +90°), (k, 2, 3) spatial
    (a right-handed pair ``t1, t2 = n x t1``)."""
    if normals.shape[1] == 2:
        return np.stack([-normals[:, 1], normals[:, 0]], axis=-1)[:, None, :]
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, np.cross(normals, t1)], axis=1)


def friction_edges(
    normals: np.ndarray,
    mu: np.ndarray,
    edges: int = PYRAMID_EDGES,
    pyramid: Pyramid = "circumscribed",
) -> np.ndarray:
    """Edge directions (k, m, dim) of each contact's friction cone (per unit normal force).

    Planar: the two exact edges ``n + mu t`` and ``n - mu t`` (``m = 2``). Spatial: an
    ``edges``-sided pyramid, inscribed in the circular cone or circumscribed about it.
    """
    tangents = tangent_frames(normals)
    if normals.shape[1] == 2:
        signs = np.array([1.0, -1.0])
        return normals[:, None, :] + (mu[:, None] * signs)[:, :, None] * tangents
    angles = 2.0 * np.pi * np.arange(edges) / edges
    radius = mu / np.cos(np.pi / edges) if pyramid == "circumscribed" else mu
    ring = np.cos(angles)[None, :, None] * tangents[:, None, 0] + (
        np.sin(angles)[None, :, None] * tangents[:, None, 1]
    )
    return normals[:, None, :] + radius[:, None, None] * ring


def edge_wrenches(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Unit wrenches (g, n) of the edge forces (k, m, dim) at their contacts, duplicates
    (a frictionless contact's coinciding edges) removed."""
    k, m, _ = forces.shape
    g = wrenches(np.repeat(points, m, axis=0), forces.reshape(k * m, -1))
    g = g / np.linalg.norm(g, axis=1, keepdims=True)
    return unique_rows(np.round(g, 14)) if len(g) > 1 else g


# --- equilibrium sets over the swept direction ------------------------------------------------


@dataclass(frozen=True)
class Equilibria:
    """Swept directions ``d`` for which friction can hold the body: ``a + c . d >= 0`` for
    every row, or ``everywhere`` / ``flat`` (nowhere but a measure-zero set)."""

    kind: Literal["cone", "everywhere", "flat"]
    a: np.ndarray  # (f,)
    c: np.ndarray  # (f, dim)

    def contains(self, directions: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Whether each unit direction (m, dim) is held (boundary included within ``tol``)."""
        if self.kind != "cone":
            return np.full(len(directions), self.kind == "everywhere")
        return np.all(self.a + directions @ self.c.T >= -tol, axis=1)

    def arcs(self, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, float]:
        """Held directions in the sweep plane (rad from ``e1`` towards ``e2``) and the error
        of the arc ends (rad) from rounding of the facet coefficients (0 without ends)."""
        if self.kind != "cone":
            return (FULL if self.kind == "everywhere" else ()), 0.0
        scale = np.abs(self.a) + np.linalg.norm(self.c, axis=1)
        arcs, error = affine_arcs(self.a, self.c, e1, e2, 64 * EPS * scale)
        return arcs, 0.0 if error is None else error


def equilibria(
    statics: Statics,
    keep: np.ndarray,
    mu: np.ndarray | None = None,
    *,
    edges: int = PYRAMID_EDGES,
    pyramid: Pyramid = "circumscribed",
) -> Equilibria:
    """Directions of the swept force for which the supports ``keep`` can hold the body.

    ``mu`` (k,) overrides the scene's coefficients (per support, all supports indexed).
    """
    mu = statics.friction if mu is None else np.asarray(mu, float)
    forces = friction_edges(statics.normals[keep], mu[keep], edges, pyramid)
    facets = cone_facets(edge_wrenches(statics.points[keep], forces))
    dim = statics.dim
    if isinstance(facets, str):
        return Equilibria(facets, np.zeros(0), np.zeros((0, dim)))  # type: ignore[arg-type]
    a, c = -(facets @ statics.fixed), -(facets @ statics.swept)
    if dim == 3:
        # Most facets of the six-dimensional cone never bound the three-dimensional set of
        # swept directions; keep those that do (same set, far fewer caps to evaluate).
        rows = essential_rows(np.column_stack([c, a]))
        if rows is None:
            return Equilibria("flat", np.zeros(0), np.zeros((0, dim)))
        a, c = a[rows], c[rows]
    return Equilibria("cone", a, c)


def closing_condition(statics: Statics, twist: np.ndarray) -> tuple[float, np.ndarray]:
    """Virtual power ``xi . W(d) = a + c . d`` of the external wrench on a free twist:
    positive where, without friction, the body would move along ``xi`` (close the gap)."""
    return float(twist @ statics.fixed), statics.swept.T @ twist


def forward_limit(
    statics: Statics, keep: np.ndarray, twist: np.ndarray, mu: np.ndarray | None = None
) -> tuple[float, np.ndarray] | None:
    """Planar: the condition ``a + c . d >= 0`` that ``-W`` lies on the cone's side of the
    plane through both forward-limit edges ``n_j + mu_j t_j`` (``t_j`` opposing sliding along
    ``twist``), when that plane carries a facet of the contact-wrench cone whose inward normal
    ``f`` has ``f . xi > 0``; None otherwise.

    This is Koster's friction-pole condition (``f`` is the friction twist ``xi'``): it ignores
    the sign of the normal forces, so it admits loads that only a pulling support could hold.
    The facet fails to exist when the rotation about the friction pole presses into a
    remaining contact; the graphical construction then does not describe the equilibria.
    """
    mu = statics.friction if mu is None else np.asarray(mu, float)
    points, normals = statics.points[keep], statics.normals[keep]
    t, _ = friction_directions(twist, points, +1)
    limit = wrenches(points, normals + mu[keep, None] * t)
    normal = np.cross(limit[0], limit[1])
    size = float(np.linalg.norm(normal))
    if normals.shape[1] != 2 or not size > FACET_TOL:
        return None
    normal /= size
    if normal @ twist < 0:
        normal = -normal
    facets = cone_facets(edge_wrenches(points, friction_edges(normals, mu[keep])))
    if isinstance(facets, str):
        return None
    match = facets @ normal
    if not match.max() > 1.0 - 1e-11:
        return None
    # The cone's own facet row, so that its arc ends are bit-identical to the held set's.
    normal = facets[int(np.argmax(match))]
    return float(-(normal @ statics.fixed)), -(statics.swept.T @ normal)


# --- single wrenches: exact decisions and the least friction --------------------------------


def holds(
    statics: Statics,
    keep: np.ndarray,
    wrench: np.ndarray,
    mu: np.ndarray | None = None,
    *,
    edges: int = PYRAMID_EDGES,
    pyramid: Pyramid = "circumscribed",
) -> bool:
    """Whether the supports ``keep`` balance ``wrench`` with forces in the (polyhedral)
    friction cones; exact for planar scenes."""
    mu = statics.friction if mu is None else np.asarray(mu, float)
    forces = friction_edges(statics.normals[keep], mu[keep], edges, pyramid)
    facets = cone_facets(edge_wrenches(statics.points[keep], forces))
    if isinstance(facets, str):
        return facets == "everywhere"
    scale = float(np.linalg.norm(wrench)) or 1.0
    return bool(np.all(facets @ -wrench >= -FACET_TOL * scale))


def holds_exactly(
    statics: Statics, keep: np.ndarray, wrench: np.ndarray, mu: np.ndarray | None = None
) -> bool:
    """Whether ``wrench`` is balanced with forces in the exact circular friction cones.

    Spatial: :func:`equilibrium_forces` (clarabel); planar cones are polyhedral and decided
    exactly by :func:`holds`.
    """
    mu = statics.friction if mu is None else np.asarray(mu, float)
    if statics.dim == 2:
        return holds(statics, keep, wrench, mu)
    return equilibrium_forces(statics, keep, wrench, mu) is not None


def equilibrium_forces(
    statics: Statics, keep: np.ndarray, wrench: np.ndarray, mu: np.ndarray | None = None
) -> np.ndarray | None:
    """Contact forces (k, 3) of the supports ``keep`` balancing ``wrench`` inside the exact
    circular friction cones, or None when there are none (spatial, nondimensional).

    A second-order-cone feasibility problem solved by clarabel (interior point, default
    tolerances 1e-8): unknowns per support are the normal force and two tangential
    components, with ``|f_t| <= mu f_n``.
    """
    mu = statics.friction if mu is None else np.asarray(mu, float)
    axes, columns = _contact_axes(statics, keep)
    local = _solve_conic(columns, wrench, mu[keep], None)
    return None if local is None else np.einsum("ki,kij->kj", local[0], axes)


def _contact_axes(statics: Statics, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each kept contact's axes (k, 3, 3: normal, two tangents) and their unit wrenches as
    the columns (3k, 6) of the equilibrium equations."""
    frames = tangent_frames(statics.normals[keep])
    axes = np.stack([statics.normals[keep], frames[:, 0], frames[:, 1]], axis=1)
    columns = wrenches(statics.points[keep][:, None, :], axes).reshape(3 * len(keep), -1)
    return axes, columns


def _solve_conic(
    columns: np.ndarray, wrench: np.ndarray, mu: np.ndarray, shrink: np.ndarray | None
) -> tuple[np.ndarray, float] | None:
    """Forces in the contacts' axes (k, 3) balancing ``wrench`` with ``|f_t| <= mu f_n``; or,
    with ``shrink`` (k,), those minimising ``s >= -1`` subject to
    ``|f_t| <= mu f_n + s shrink`` (a step of :func:`least_friction_exactly`), and ``s``.
    None unless clarabel solves it."""
    import clarabel
    from scipy import sparse

    k, n = len(mu), len(wrench)
    extra = 0 if shrink is None else 1
    size = 3 * k + extra
    equal = np.zeros((n, size))
    equal[:, : 3 * k] = columns.T
    cone_rows = np.zeros((3 * k + extra, size))
    cone_rows[np.arange(3 * k), np.arange(3 * k)] = -1.0
    cone_rows[0 : 3 * k : 3, 0 : 3 * k : 3] *= mu[:, None] * np.eye(k)
    rhs = np.concatenate([-wrench, np.zeros(3 * k)])
    cones = [clarabel.ZeroConeT(n)] + [clarabel.SecondOrderConeT(3)] * k
    cost = np.zeros(size)
    if shrink is not None:
        cone_rows[0 : 3 * k : 3, -1] = -shrink
        cone_rows[-1, -1] = -1.0  # s >= -1: the step stays bounded
        rhs = np.append(rhs, 1.0)
        cones.append(clarabel.NonnegativeConeT(1))
        cost[-1] = 1.0
    # A support only pushes: f_n >= 0 (the cone implies it only where mu > 0).
    pushes = np.zeros((k, size))
    pushes[np.arange(k), 3 * np.arange(k)] = -1.0
    cone_rows = np.vstack([cone_rows, pushes])
    rhs = np.append(rhs, np.zeros(k))
    cones.append(clarabel.NonnegativeConeT(k))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solver = clarabel.DefaultSolver(
        sparse.csc_matrix((size, size)),
        cost,
        sparse.csc_matrix(np.vstack([equal, cone_rows])),
        rhs,
        cones,
        settings,
    )
    solution = solver.solve()
    if str(solution.status) not in ("Solved", "AlmostSolved"):
        return None
    x = np.asarray(solution.x)
    return x[: 3 * k].reshape(k, 3), float(x[-1]) if extra else 0.0


def _largest_ratio(local: np.ndarray, scale: np.ndarray) -> float:
    """The largest ``|f_t| / (scale f_n)`` over the contacts with a share of the normal
    force (forces in the contacts' axes, (k, 3))."""
    fn = local[:, 0] * scale
    tangential = np.linalg.norm(local[:, 1:], axis=1)
    pressed = (scale > 0) & (fn > 1e-9 * max(float(np.abs(local[:, 0]).max()), 1e-300))
    ratios = tangential[pressed] / fn[pressed]
    return float(ratios.max()) if len(ratios) else 0.0


def least_friction_exactly(
    statics: Statics,
    keep: np.ndarray,
    wrench: np.ndarray,
    scale: np.ndarray,
    upper: float = 1.0,
    *,
    largest: float = 100.0,
    rtol: float = 1e-6,
) -> float | None:
    """Spatial: the smallest common coefficient ``mu`` for which the supports ``keep``, with
    coefficients ``mu * scale`` and exact circular cones, balance ``wrench``; None when not
    even ``largest`` does.

    The least coefficient is ``min over balancing forces of max_j |f_t,j| / (scale_j f_n,j)``,
    a generalised fractional programme. From a balance found at a feasible coefficient
    (doubling ``upper``), Dinkelbach-type steps (Crouzeix, Ferland & Schaible 1985), each a
    conic programme (:func:`_solve_conic`), lower the largest ratio of actual balancing
    forces; they stop when a step gains less than ``rtol / 1000``. The result is then checked
    as bisection would have found it: it holds, and ``(1 - rtol)`` times it does not (else
    bisection below it decides). About 7 conic solves instead of bisection's 17.
    """
    scale = np.asarray(scale, float)

    def feasible(mu: float) -> bool:
        return equilibrium_forces(statics, keep, wrench, mu * scale) is not None

    if feasible(0.0):
        return 0.0
    axes, columns = _contact_axes(statics, keep)
    mu = max(upper, 1e-3)
    while (found := _solve_conic(columns, wrench, mu * scale[keep], None)) is None:
        if mu >= largest:
            return None
        mu = min(2.0 * mu, largest)
    local, kept = found[0], scale[keep]
    ratio = _largest_ratio(local, kept)
    for _ in range(STEPS):
        step = _solve_conic(columns, wrench, ratio * kept, np.maximum(local[:, 0] * kept, 0.0))
        if step is None:
            break
        lower = _largest_ratio(step[0], kept)
        if not lower < ratio:
            break
        gain = ratio - lower
        local, ratio = step[0], lower
        if gain <= 1e-3 * rtol * ratio:
            break
    if feasible(ratio * (1.0 - rtol)):  # not converged (degenerate): bisection below it
        return least_friction(feasible, ratio, largest=largest, rtol=rtol)
    return ratio


def rough_supports(friction: np.ndarray) -> np.ndarray:
    """Which supports a common friction coefficient applies to: those with friction in the
    scene, or all of them when the scene is frictionless (as for the limiting friction)."""
    rough = friction > 0
    return rough if np.any(rough) else np.ones_like(rough)


def friction_candidates(
    statics: Statics, keep: np.ndarray, wrench: np.ndarray, scale: np.ndarray
) -> np.ndarray:
    """Planar: every common coefficient ``mu > 0`` at which the supports ``keep``, with the
    coefficients ``mu * scale``, can start to balance ``wrench`` (sorted).

    Each edge wrench is affine in ``mu``, ``g(mu) = a + mu b`` (``a`` the normal's wrench,
    ``b`` the tangent's). By Carathéodory ``x = -wrench`` is balanced iff it is a non-negative
    combination of at most three independent edges, whose coefficients are ratios of
    determinants (Cramer): ``det[x, g_v, g_w] / det[g_u, g_v, g_w]``. Their signs change only
    where a numerator (``x`` on the plane of two edges: a quadratic in ``mu``) or a
    denominator (three edges in one plane, the cone turning into a half-space or the whole
    space: a cubic) vanishes; the positive real roots of these polynomials are the
    candidates (exact up to rounding).
    """
    points, normals = statics.points[keep], statics.normals[keep]
    tangents = tangent_frames(normals)[:, 0]
    a = wrenches(points, normals)
    b = scale[keep, None] * wrenches(points, tangents)
    # Both edges of each cone, n + mu t and n - mu t; an edge that does not move with mu
    # (a frictionless support) once.
    moving = np.any(b != 0, axis=1)
    a, b = np.concatenate([a, a[moving]]), np.concatenate([b, -b[moving]])
    x = -np.asarray(wrench, float)
    i, j = np.triu_indices(len(a), 1)
    # det[x, a_i + mu b_i, a_j + mu b_j]: coefficients of mu^2, mu, 1 (a leading 0: cubics)
    ax, bx = cross3(a, x), cross3(b, x)  # det[x, p, q] = -(p x x) . q
    pairs = -np.column_stack(
        [
            np.zeros(len(i)),
            np.sum(bx[i] * b[j], axis=1),
            np.sum(ax[i] * b[j] + bx[i] * a[j], axis=1),
            np.sum(ax[i] * a[j], axis=1),
        ]
    )
    u, v, w = _triples(len(a))
    # det[g_u, g_v, g_w] = (g_u x g_v) . g_w: coefficients of mu^3 ... 1
    aa, ab, ba, bb = (cross3(p[u], q[v]) for p, q in ((a, a), (a, b), (b, a), (b, b)))
    triples = np.column_stack(
        [
            np.sum(bb * b[w], axis=1),
            np.sum(bb * a[w] + (ab + ba) * b[w], axis=1),
            np.sum((ab + ba) * a[w] + aa * b[w], axis=1),
            np.sum(aa * a[w], axis=1),
        ]
    )
    return unique(_positive_roots(np.vstack([pairs, triples])))


def _triples(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Indices (u < v < w) of every triple of ``n`` items."""
    u, v, w = (
        np.array(
            [(u, v, w) for u in range(n) for v in range(u + 1, n) for w in range(v + 1, n)], int
        )
        .reshape(-1, 3)
        .T
    )
    return u, v, w


def _positive_roots(coefficients: np.ndarray) -> np.ndarray:
    """Positive real roots of polynomials of degree up to three (rows, highest power first),
    all at once; none of a polynomial that does not depend on ``mu`` (relative to its size).
    The companion matrices' eigenvalues, then Newton steps on each polynomial (the
    eigenvalues are accurate relative to the largest root, not each one)."""
    size = np.abs(coefficients).sum(axis=1, keepdims=True)
    c = np.where(np.abs(coefficients) > 1e-14 * size, coefficients, 0.0)
    found = []
    for degree in (3, 2, 1):
        lead = 3 - degree
        rows = c[(c[:, lead] != 0) & np.all(c[:, :lead] == 0, axis=1)]
        if not len(rows):
            continue
        monic = rows[:, lead + 1 :] / rows[:, lead : lead + 1]  # (r, degree)
        companion = np.zeros((len(rows), degree, degree))
        companion[:, 0, :] = -monic
        companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
        roots = np.linalg.eigvals(companion)  # (r, degree)
        real = np.abs(roots.imag) <= 1e-9 * np.maximum(np.abs(roots), 1.0)
        owner = np.broadcast_to(np.arange(len(rows))[:, None], roots.shape)[real]
        x, poly = roots.real[real], rows[owner]
        for _ in range(3):
            value = ((poly[:, 0] * x + poly[:, 1]) * x + poly[:, 2]) * x + poly[:, 3]
            slope = (3 * poly[:, 0] * x + 2 * poly[:, 1]) * x + poly[:, 2]
            x = x - np.divide(value, slope, out=np.zeros_like(x), where=slope != 0)
        found.append(x[x > 0])
    return np.concatenate(found) if found else np.zeros(0)


def least_friction(
    feasible: Callable[[float], bool],
    upper: float = 1.0,
    *,
    largest: float = 100.0,
    rtol: float = 1e-6,
    candidates: np.ndarray | None = None,
) -> float | None:
    """Smallest common coefficient ``mu`` with ``feasible(mu)``.

    Feasibility is monotone in ``mu`` (every friction cone grows with it). With
    ``candidates`` (sorted values among which feasibility can change,
    :func:`friction_candidates`) the least feasible candidate, found by bisection over them:
    the exact value. Otherwise, and should the candidates miss the change (degenerate
    geometry), by bisection: ``upper`` is a first guess, doubled up to ``largest``; the
    result is within ``rtol`` (relative) above the true value. None when not even
    ``largest`` holds the body (the load would need a pulling support).
    """
    if feasible(0.0):
        return 0.0
    if candidates is not None:
        found = _least_candidate(feasible, candidates, largest, rtol)
        if found is not None:
            return found
    hi = max(upper, 1e-3)
    while not feasible(hi):
        if hi >= largest:
            return None
        hi = min(2.0 * hi, largest)
    lo = 0.0
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
    return hi


def _least_candidate(
    feasible: Callable[[float], bool], candidates: np.ndarray, largest: float, rtol: float
) -> float | None:
    """The least feasible coefficient, given that feasibility is constant between
    consecutive candidates: bisection over the candidates interleaved with a point inside
    each interval after one. None if nothing up to ``largest`` is feasible. When the least is
    an infimum (feasible just above a candidate, not at it: the cone turning into a
    half-space or the whole space there), a value within ``rtol`` above it, as bisection
    gives."""
    ends = [float(c) for c in candidates if 0 < c < largest]
    if not ends:
        return None
    upper = [*ends[1:], largest]
    sequence: list[tuple[float, bool]] = []
    for c, above in zip(ends, upper, strict=True):
        sequence += [(c, True), (0.5 * (c + above), False)]
    lo, hi = 0, len(sequence)
    while lo < hi:
        mid = (lo + hi) // 2
        if feasible(sequence[mid][0]):
            hi = mid
        else:
            lo = mid + 1
    if lo == len(sequence):
        return None
    value, attained = sequence[lo]
    if attained:
        return value
    # Not attained at the candidate below (or that candidate is rounded below the change):
    # bisection from it, as without candidates, mostly one step.
    low = sequence[lo - 1][0]
    probe = low * (1.0 + rtol)
    if probe < value and feasible(probe):
        return probe
    while value - low > rtol * value:
        mid = 0.5 * (low + value)
        low, value = (low, mid) if feasible(mid) else (mid, value)
    return value
