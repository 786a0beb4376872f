"""Static equilibrium with Coulomb friction: can the remaining supports hold the body?

With support ``r`` retracted, the body stays put if the external wrench ``W`` (load, weight,
preloads, torque) is balanced by contact forces of the remaining supports, each inside its
friction cone ``|f_t| <= mu_j f_n`` (``f_n >= 0``: a support only pushes). The contact
wrenches form a convex cone ``C`` (the sum of the supports' friction cones, mapped to wrenches
by :func:`kcheck.mechanics.kinematics.wrenches`); equilibrium exists iff ``-W`` lies in ``C``.

* Planar: a friction cone is exactly two rays ``n +- mu t``, so ``C`` is polyhedral and its
  facets are cross products of pairs of edge wrenches (exact).
* Spatial: a circular cone is approximated by an ``m``-sided pyramid, inscribed (edges at
  ``mu``: a lower bound of ``C``) or circumscribed (edges at ``mu / cos(pi/m)``: an upper
  bound); the true boundary lies between. Its facets come from qhull. At single wrenches the
  exact second-order cones are decided by a conic solver (:func:`holds_exactly`, clarabel).

The swept load makes ``W`` affine in the unit direction ``d``: ``W(d) = w0 + B d``. Each facet
``f`` of ``C`` gives one condition ``a + c . d >= 0`` with ``a = -f . w0``, ``c = -B^T f``: a
half circle in the sweep plane, a spherical cap on the sphere (:mod:`kcheck.mechanics.arcs`). So the
directions where friction can hold the body are exact arc sets (planar) or a cap intersection.

All arrays are nondimensional (:class:`kcheck.mechanics.kinematics.Frame`): lengths by the layout
size, forces by the force scale. Wrenches are ``(moment about the origin, force)``. Friction
coefficients are per support, so callers may pass a static value, a range end, or a common
factor (:mod:`kcheck.mechanics.least_friction`).
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from typing import Literal

import numpy as np

from kcheck.mechanics.arcs import FULL, ArcSet, affine_arcs
from kcheck.mechanics.cones import (
    FACET_TOL,
    balanced_image,
    cone_facets,
    essential_rows,
    inside_image,
    planar_cone_holds,
)
from kcheck.mechanics.csc import Csc
from kcheck.mechanics.dynamics import friction_directions
from kcheck.mechanics.kinematics import Frame, cross3, wrenches
from kcheck.numerics.arrays import round3_like_numpy, unique_rows
from kcheck.numerics.thresholds import EDGE_WRENCH_DECIMALS, EPS, PRODUCT_ROUNDING, SAME_FACET
from kcheck.records import dataclass

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
    "contact_columns",
    "kept_columns",
]

#: Sides of the pyramid approximating a spatial friction cone. The inscribed and the
#: circumscribed pyramids differ in friction by the factor cos(pi/8) = 0.924 (option
#: `pyramid_edges`; the error it makes in degrees is measured and reported).
PYRAMID_EDGES = 8
# Directions times facets evaluated at once by Equilibria.contains (16 MB of float64).
CONTAINS_CHUNK = 2_000_000
# Facets Equilibria.contains tests every direction against (chosen on CONTAINS_SAMPLE of
# them); the other facets meet only the directions inside these.
CONTAINS_FIRST = 12
CONTAINS_SAMPLE = 400
# Directions times facets below which every facet meets every direction at once: choosing
# the screening facets would cost more (the jamming map's undecided cells: 60-1100).
CONTAINS_DIRECT = 100_000
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
    t1 = cross3(normals, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, cross3(normals, t1)], axis=1)


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
    unit = _unit_edge_wrenches(points, forces)
    return unique_rows(_rounded(unit)) if len(unit) > 1 else unit


def _unit_edge_wrenches(points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Unit wrenches (k m, n) of the edge forces (k, m, dim) at their contacts ``points``
    (k, dim), row by row (a subset of rows is the same bits computed alone)."""
    k, m, _ = forces.shape
    g = wrenches(np.repeat(points, m, axis=0), forces.reshape(k * m, -1))
    return g / np.linalg.norm(g, axis=1, keepdims=True)


def _rounded(unit: np.ndarray) -> np.ndarray:
    """Unit edge wrenches rounded to EDGE_WRENCH_DECIMALS, as duplicates are compared."""
    return np.round(unit, EDGE_WRENCH_DECIMALS)


def cone_generators(
    statics: Statics,
    keep: np.ndarray,
    mu: np.ndarray,
    edges: int = PYRAMID_EDGES,
    pyramid: Pyramid = "circumscribed",
) -> np.ndarray:
    """``edge_wrenches`` of the kept supports' friction edges at coefficients ``mu`` (k,):
    the generators of the contact-wrench cone (:func:`cone_facets`)."""
    if statics.dim == 2:
        fast = _planar_generators(statics.points[keep], statics.normals[keep], mu[keep])
        if fast is not None:
            return fast
    if statics.dim == 2 or not len(statics.points) or not np.all(np.isfinite(mu)):
        forces = friction_edges(statics.normals[keep], mu[keep], edges, pyramid)
        return edge_wrenches(statics.points[keep], forces)
    unit, rounded = _every_edge_wrench(statics, mu, edges, pyramid)
    m = len(unit) // len(statics.points)
    kept = np.arange(len(statics.points))[keep]  # indices, also of a boolean mask
    rows = (m * kept[:, None] + np.arange(m)).ravel()
    # edge_wrenches of the kept supports: every step is row by row, so the same bits.
    return unique_rows(rounded[rows]) if len(rows) > 1 else unit[rows]


def _every_edge_wrench(
    statics: Statics, mu: np.ndarray, edges: int, pyramid: Pyramid
) -> tuple[np.ndarray, np.ndarray]:
    """Unit edge wrenches (k m, n) of every support's friction edges, as :func:`edge_wrenches`
    makes them before removing duplicates, and rounded as it rounds them: a spatial jamming
    check asks for the cones of six cases (each all supports but one) at two pyramids, and
    the edges of a support are the same in each. The last few are kept (read-only)."""
    key = b"|".join(
        [
            repr((edges, pyramid, statics.points.shape)).encode(),
            np.ascontiguousarray(statics.points, float).tobytes(),
            np.ascontiguousarray(statics.normals, float).tobytes(),
            np.ascontiguousarray(mu, float).tobytes(),
        ]
    )
    known = _EDGE_WRENCHES.get(key)
    if known is None:
        forces = friction_edges(statics.normals, mu, edges, pyramid)
        unit = _unit_edge_wrenches(statics.points, forces)
        rounded = _rounded(unit)
        unit.setflags(write=False)
        rounded.setflags(write=False)
        # Threads (the gate's) may share the cache: evict and insert under one lock.
        with _EDGE_WRENCHES_LOCK:
            while len(_EDGE_WRENCHES) >= RECENT_EDGE_WRENCHES:
                _EDGE_WRENCHES.pop(next(iter(_EDGE_WRENCHES)), None)
            known = _EDGE_WRENCHES.setdefault(key, (unit, rounded))
    return known


#: Every support's edge wrenches recently computed (:func:`_every_edge_wrench`), oldest first.
_EDGE_WRENCHES: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
_EDGE_WRENCHES_LOCK = threading.Lock()
RECENT_EDGE_WRENCHES = 8


def _planar_generators(
    points: np.ndarray, normals: np.ndarray, mu: np.ndarray
) -> np.ndarray | None:
    """Planar ``edge_wrenches(points, friction_edges(normals, mu))`` in plain float arithmetic
    (numpy's per-call overhead on 2-vectors was most of a planar jamming check's time): the
    same operations in numpy's order (``n + (mu s) t`` with ``t`` = ``n`` turned +90°, the
    moment ``p_x f_y - p_y f_x``, the norm's squares summed left to right, ``np.round``'s
    ``rint(x 10^14) / 10^14`` with the sign of zero kept, rows sorted and deduplicated as
    ``unique_rows``), so the same bits. None (numpy's path) for fewer than one support or a
    non-finite or zero edge."""
    if not len(points):
        return None
    return _planar_generators_of(points.tolist(), normals.tolist(), mu.tolist())


def _planar_generators_of(
    points: list[list[float]], normals: list[list[float]], mu: list[float]
) -> np.ndarray | None:
    """:func:`_planar_generators` of at least one support given as lists."""
    rows = _planar_generator_rows(points, normals, mu)
    return None if rows is None else np.array(rows, dtype=float)


def _planar_generator_rows(
    points: list[list[float]], normals: list[list[float]], mu: list[float]
) -> list[tuple[float, ...]] | None:
    """The rows of :func:`_planar_generators_of` as tuples (sorted, distinct); None also
    for no support."""
    if not points:
        return None
    # np.round(g, EDGE_WRENCH_DECIMALS)'s factor; unit wrenches: |part scale| is far inside
    # RINT_SHIFT's bound
    scale = 10.0**EDGE_WRENCH_DECIMALS
    rows: list[tuple[float, ...]] = []
    for (px, py), (nx, ny), m in zip(points, normals, mu, strict=True):
        tx, ty = -ny, nx
        for s in (m * 1.0, m * -1.0):
            fx = nx + s * tx
            fy = ny + s * ty
            w = px * fy - py * fx
            size = math.sqrt(w * w + fx * fx + fy * fy)
            if not (0.0 < size < math.inf):
                return None
            # A finite positive size bounds each part's size (the squares are summed rounding
            # to nearest, which keeps order): the parts are finite, their rounding defined.
            rows.append(round3_like_numpy(w / size, fx / size, fy / size, scale))
    rows.sort()  # sorted_unique_tuples' order and duplicates
    out = [rows[0]]
    for row in rows[1:]:
        if row != out[-1]:
            out.append(row)
    return out


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
        return self.least_slack(directions, -tol) >= -tol

    def least_slack(self, directions: np.ndarray, floor: float) -> np.ndarray:
        """The least ``a + c . d`` over the facets for each unit direction (m, dim), where it is
        at least ``floor``; elsewhere some value below ``floor``. ``inf`` everywhere for a set
        held everywhere, ``-inf`` for a flat one (held nowhere but a measure-zero set)."""
        if self.kind != "cone" or not len(self.a):
            held = self.kind == "everywhere" or (self.kind == "cone" and not len(self.a))
            return np.full(len(directions), np.inf if held else -np.inf)
        if len(directions) * len(self.a) <= CONTAINS_DIRECT:
            return _least(self.a, directions @ self.c.T)
        # A few facets that, on a sample of the directions, leave the fewest above the floor;
        # only the directions above it there meet the other facets (the least of the same
        # values a + c . d as with every facet at once). In chunks: a picture's 58,000
        # directions against hundreds of facets at once took 180 MB.
        first = self._screening_facets(directions, floor)
        rest = np.setdiff1d(np.arange(len(self.a)), first, assume_unique=True)
        slack = np.empty(len(directions))
        step = max(1, CONTAINS_CHUNK // max(1, len(first)))
        for i in range(0, len(directions), step):
            chunk = directions[i : i + step]
            slack[i : i + step] = _least(self.a[first], chunk @ self.c[first].T)
        if len(rest):
            alive = np.flatnonzero(slack >= floor)
            step = max(1, CONTAINS_CHUNK // len(rest))
            for i in range(0, len(alive), step):
                which = alive[i : i + step]
                slack[which] = np.minimum(
                    slack[which],
                    _least(self.a[rest], directions[which] @ self.c[rest].T),
                )
        return slack

    def _screening_facets(self, directions: np.ndarray, floor: float) -> np.ndarray:
        """Up to CONTAINS_FIRST facet indices chosen greedily on a sample of ``directions``:
        each the one putting most of the sample still above ``floor`` below it."""
        sample = directions[:: max(1, len(directions) // CONTAINS_SAMPLE)]
        slack = sample @ self.c.T
        slack += self.a  # in place: the same sums, one (s, f) temporary fewer
        above = slack >= floor  # (s, f)
        alive = np.ones(len(sample), bool)
        chosen: list[int] = []
        for _ in range(min(CONTAINS_FIRST, len(self.a))):
            out = np.count_nonzero(~above[alive], axis=0)
            best = int(np.argmax(out))
            if out[best] == 0:
                break
            chosen.append(best)
            alive &= above[:, best]
        return np.array(chosen or [0], dtype=int)

    def arcs(self, e1: np.ndarray, e2: np.ndarray) -> tuple[ArcSet, float]:
        """Held directions in the sweep plane (rad from ``e1`` towards ``e2``) and the error
        of the arc ends (rad) from rounding of the facet coefficients (0 without ends)."""
        if self.kind != "cone":
            return (FULL if self.kind == "everywhere" else ()), 0.0
        scale = np.abs(self.a) + np.linalg.norm(self.c, axis=1)
        arcs, error = affine_arcs(self.a, self.c, e1, e2, 64 * EPS * scale)
        return arcs, 0.0 if error is None else error


def _least(a: np.ndarray, products: np.ndarray) -> np.ndarray:
    """``np.min(a + products, axis=1)`` for products (m, f) it may overwrite: ``a`` added in
    place (the same sums; a second temporary of this size cost more than the product and the
    minimum together, its pages fresh each time)."""
    products += a
    return products.min(axis=1)


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
    generators = cone_generators(statics, keep, mu, edges, pyramid)
    facets = cone_facets(generators)
    dim = statics.dim
    if isinstance(facets, str):
        return Equilibria(facets, np.zeros(0), np.zeros((0, dim)))
    a, c = -(facets @ statics.fixed), -(facets @ statics.swept)
    if dim == 3:
        # Most facets of the six-dimensional cone never bound the three-dimensional set of
        # swept directions; keep those that do (same set, far fewer caps to evaluate).
        # A direction inside the held set, where perceptron steps find none: a balance by
        # every edge at once (a programme over the edges, not over the facets' rows).
        image = -np.column_stack([statics.swept, statics.fixed])
        rows = essential_rows(
            np.column_stack([c, a]),
            lambda: balanced_image(generators, image),
            lambda: inside_image(generators, image),
        )
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
    normal = cross3(limit[0], limit[1])  # np.cross's arithmetic without its overhead
    size = float(np.linalg.norm(normal))
    if normals.shape[1] != 2 or not size > FACET_TOL:
        return None
    normal /= size
    if normal @ twist < 0:
        normal = -normal
    facets = cone_facets(cone_generators(statics, keep, mu))
    if isinstance(facets, str):
        return None
    match = facets @ normal
    if not match.max() > 1.0 - SAME_FACET:
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
    if statics.dim == 2:
        held = _planar_holds(statics.points[keep], statics.normals[keep], mu[keep], wrench)
        if held is not None:
            return held
    facets = cone_facets(cone_generators(statics, keep, mu, edges, pyramid))
    if isinstance(facets, str):
        return facets == "everywhere"
    scale = float(np.linalg.norm(wrench)) or 1.0
    return bool(np.all(facets @ -wrench >= -FACET_TOL * scale))


def _planar_holds(
    points: np.ndarray, normals: np.ndarray, mu: np.ndarray, wrench: np.ndarray
) -> bool | None:
    """:func:`holds` of a planar scene's kept supports by :func:`planar_cone_holds` (the same
    answer where it decides), None where it does not (or the inputs are not finite)."""
    against = (-wrench).tolist()
    if not len(points) or not all(map(math.isfinite, against)):
        return None
    rows = _planar_generator_rows(points.tolist(), normals.tolist(), mu.tolist())
    if rows is None:
        return None
    scale = float(np.linalg.norm(wrench)) or 1.0
    return planar_cone_holds(rows, against, -FACET_TOL * scale, PRODUCT_ROUNDING * EPS * scale)


def planar_holding(
    statics: Statics, keep: np.ndarray, wrench: np.ndarray, scale: np.ndarray
) -> Callable[[float], bool]:
    """``lambda mu: holds(statics, keep, wrench, mu * scale)`` of a planar scene, the same
    answers: the kept supports' rows, the wrench's size and the plain lists built once,
    not at each of the 5-10 coefficients a least-friction search asks about."""
    points, normals, rows = statics.points[keep], statics.normals[keep], scale[keep]
    plain = (points.tolist(), normals.tolist()) if len(points) else None
    against = -wrench
    size = float(np.linalg.norm(wrench)) or 1.0
    limit = -FACET_TOL * size
    # planar_cone_holds decides without numpy where every facet's product is farther than
    # this from the limit: numpy's product of a unit facet and ``against`` differs from the
    # plain one by at most a few roundings of |against| (fused multiply-adds).
    margin = PRODUCT_ROUNDING * EPS * size
    quick = tuple(against.tolist()) if np.all(np.isfinite(against)) else None

    def decide(mu: float) -> bool:
        kept = mu * rows  # (mu * scale)[keep], elementwise: the same bits
        found = None if plain is None else _planar_generator_rows(*plain, kept.tolist())
        if found is not None and quick is not None:
            held = planar_cone_holds(found, quick, limit, margin)
            if held is not None:
                return held
        generators = None if found is None else np.array(found, dtype=float)
        if generators is None:
            generators = edge_wrenches(
                points, friction_edges(normals, kept, PYRAMID_EDGES, "circumscribed")
            )
        facets = cone_facets(generators)
        if isinstance(facets, str):
            return facets == "everywhere"
        return bool(np.all(facets @ against >= limit))

    return decide


def holds_exactly(
    statics: Statics,
    keep: np.ndarray,
    wrench: np.ndarray,
    mu: np.ndarray | None = None,
    columns: np.ndarray | None = None,
) -> bool:
    """Whether ``wrench`` is balanced with forces in the exact circular friction cones.

    Spatial: :func:`equilibrium_forces` (clarabel); planar cones are polyhedral and decided
    exactly by :func:`holds`. ``columns``: :func:`contact_columns` of every support, for a
    caller asking about several ``keep`` of one statics (the kept rows are the same numbers).
    """
    mu = statics.friction if mu is None else np.asarray(mu, float)
    if statics.dim == 2:
        return holds(statics, keep, wrench, mu)
    if columns is None:
        return equilibrium_forces(statics, keep, wrench, mu) is not None
    return _solve_conic(kept_columns(columns, keep), wrench, mu[keep], None) is not None


def contact_columns(statics: Statics) -> np.ndarray:
    """The equilibrium columns (3k, 6) of every support (:func:`_contact_axes`): three per
    support, its normal's and its two tangents' unit wrenches."""
    return _contact_axes(statics, np.arange(len(statics.points)))[1]


def kept_columns(columns: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """The rows of :func:`contact_columns` (3k, 6) that belong to the supports ``keep``
    (3 len(keep), 6), in ``keep``'s order."""
    return columns.reshape(len(columns) // 3, 3, -1)[keep].reshape(3 * len(keep), -1)


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


# The last few conic programmes and their answers: the jamming check decides the design
# direction at the scene's friction after the least holding friction solved the same one.
_RECENT: dict[bytes, tuple[np.ndarray, float] | None] = {}
RECENT_SOLVES = 16


def _solve_conic(
    columns: np.ndarray, wrench: np.ndarray, mu: np.ndarray, shrink: np.ndarray | None
) -> tuple[np.ndarray, float] | None:
    """:func:`_solve_conic_anew`, or its answer to the same programme when that is one of the
    last RECENT_SOLVES (the solver is deterministic: the same answer)."""
    parts = [np.ascontiguousarray(x, float) for x in (columns, wrench, mu)]
    if shrink is not None:
        parts.append(np.ascontiguousarray(shrink, float))
    key = b"|".join([repr(columns.shape).encode(), *(x.tobytes() for x in parts)])
    if key in _RECENT:
        found = _RECENT[key]
        return None if found is None else (found[0].copy(), found[1])
    found = _solve_conic_anew(columns, wrench, mu, shrink)
    if len(_RECENT) >= RECENT_SOLVES:
        del _RECENT[next(iter(_RECENT))]
    _RECENT[key] = None if found is None else (found[0].copy(), found[1])
    return found


def _solve_conic_anew(
    columns: np.ndarray, wrench: np.ndarray, mu: np.ndarray, shrink: np.ndarray | None
) -> tuple[np.ndarray, float] | None:
    """Forces in the contacts' axes (k, 3) balancing ``wrench`` with ``|f_t| <= mu f_n``; or,
    with ``shrink`` (k,), those minimising ``s >= -1`` subject to
    ``|f_t| <= mu f_n + s shrink`` (a step of
    :func:`kcheck.mechanics.least_friction.least_friction_exactly`), and ``s``. None unless clarabel
    solves it."""
    import clarabel

    k = len(mu)
    extra = 0 if shrink is None else 1
    form = _conic_form(columns, wrench, extra)
    n = len(wrench)
    # Rows: equilibrium (n), the cones (3k, then s >= -1), f_n >= 0 (k); -mu_j at each
    # cone's normal-force entry, -shrink_j in s's column.
    matrix = form.matrix.copy()
    matrix[n + 3 * np.arange(k), 3 * np.arange(k)] = -1.0 * mu
    if shrink is not None:
        matrix[n : n + 3 * k : 3, -1] = -shrink
    solver = clarabel.DefaultSolver(
        form.quadratic, form.cost, Csc.of(matrix), form.rhs, form.cones, form.settings
    )
    solution = solver.solve()
    if str(solution.status) not in ("Solved", "AlmostSolved"):
        return None
    x = np.asarray(solution.x)
    return x[: 3 * k].reshape(k, 3), float(x[-1]) if extra else 0.0


@dataclass(frozen=True)
class _ConicForm:
    """What the conic programmes of one set of contacts and one wrench share: the constraint
    matrix without the coefficients (dense), right-hand side, cones, cost and settings."""

    matrix: np.ndarray
    rhs: np.ndarray
    cones: list[object]
    cost: np.ndarray
    quadratic: Csc
    settings: object


_FORMS: dict[bytes, _ConicForm] = {}


def _conic_form(columns: np.ndarray, wrench: np.ndarray, extra: int) -> _ConicForm:
    """The :class:`_ConicForm` for these columns (3k, n), wrench (n,) and ``extra`` (1: the
    step's variable ``s``), built once for the last few (a least-friction search solves a
    dozen programmes that differ only in the coefficients)."""
    import clarabel

    key = b"|".join(
        [repr((columns.shape, extra)).encode(), np.ascontiguousarray(columns, float).tobytes()]
        + [np.ascontiguousarray(wrench, float).tobytes()]
    )
    form = _FORMS.get(key)
    if form is not None:
        return form
    k, n = len(columns) // 3, len(wrench)
    size = 3 * k + extra
    matrix = np.zeros((n + 4 * k + extra, size))
    matrix[:n, : 3 * k] = columns.T
    matrix[n + np.arange(3 * k), np.arange(3 * k)] = -1.0
    rhs = np.concatenate([-wrench, np.zeros(3 * k)])
    cones = [clarabel.ZeroConeT(n)] + [clarabel.SecondOrderConeT(3)] * k
    cost = np.zeros(size)
    if extra:
        matrix[n + 3 * k, -1] = -1.0  # s >= -1: the step stays bounded
        rhs = np.append(rhs, 1.0)
        cones.append(clarabel.NonnegativeConeT(1))
        cost[-1] = 1.0
    # A support only pushes: f_n >= 0 (the cone implies it only where mu > 0).
    matrix[n + 3 * k + extra + np.arange(k), 3 * np.arange(k)] = -1.0
    rhs = np.append(rhs, np.zeros(k))
    cones.append(clarabel.NonnegativeConeT(k))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    form = _ConicForm(matrix, rhs, cones, cost, Csc.empty(size), settings)
    if len(_FORMS) >= RECENT_SOLVES:
        del _FORMS[next(iter(_FORMS))]
    _FORMS[key] = form
    return form
