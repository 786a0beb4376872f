"""Seated pose error from manufacturing errors: small-displacement kinematics of a seated
spatial coupling (docs/checks.md, `pose-error`).

Six contacts with support normals ``n_i`` (pushing the body) at points ``p_i``. When a made
coupling differs from the drawn one, each contact's surfaces end up ``delta_i`` (m) further
apart along ``n_i`` than drawn, and the body, staying in contact everywhere, moves by the small
twist ``t = (omega, v)`` (rotation rad, translation m of the seat's origin ``o``) with

    J t = delta,    J rows = ((p_i - o) x n_i, n_i)

— the contact wrench rows of :mod:`kcheck.mechanics.seat`, solved nondimensionally (positions
over the layout size) with the equilibrated solve and condition number of
:func:`kcheck.mechanics.dynamics.solve_affine`. The pose error at a body point ``q`` is
``v + omega x (q - o)``.

A part displaced rigidly by a small twist ``(w, d)`` about a reference point ``g`` moves its
surface at the contact by ``d + w x (p_i - g)``, so it changes ``delta_i`` by the sign ``s_i``
times ``n_i . (d + w x (p_i - g)) = ((p_i - g) x n_i, n_i) . (w, d)`` — the same wrench rows:
``s_i = +1`` for a part on the base (a base surface moving along ``n_i`` pushes the body away),
``-1`` for a part on the body. A ball's radius growing by ``dr`` adds ``dr`` wherever it
touches. Every error source is therefore a linear map from drawn numbers to ``delta`` (a
*sensitivity* matrix), and the pose error at ``q`` is one matrix product per source: the Monte
Carlo is a matrix product, with no loop over samples.
"""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.dynamics import ILL_CONDITIONED, solve_affine
from kcheck.mechanics.kinematics import wrenches
from kcheck.mechanics.seat import seat_layout
from kcheck.numerics.streams import chunk_bounds, chunk_generator
from kcheck.numerics.thresholds import EPS, TINY
from kcheck.records import dataclass

#: Samples drawn and mapped per chunk (2^16: about 19 MB of draws at 36 error sources). Each
#: chunk of independent draws has its own stream, so changing this changes the samples.
CHUNK = 2**16

__all__ = [
    "PoseMap",
    "part_rows",
    "radius_rows",
    "seat_pivots",
    "pose_map",
    "pose_errors",
    "draw",
    "sobol_draws",
    "PoseChunk",
    "pose_chunks",
    "pose_chunk",
    "CHUNK",
    "mean_bounds",
    "quantile_bounds",
]


def part_rows(
    points: np.ndarray,
    normals: np.ndarray,
    part: np.ndarray,
    count: int,
    sign: np.ndarray,
    reference: np.ndarray,
) -> np.ndarray:
    """Sensitivity (k, 6 count) of the contact separations (m) to small rigid twists of
    ``count`` parts, each ``(w rad, d m)`` about its contacts' ``reference`` points (k, 3) m:
    contact ``i`` belongs to part ``part[i]`` (-1: none) on the side ``sign[i]`` (+1 base,
    -1 body)."""
    p = np.asarray(points, float)
    n = np.asarray(normals, float)
    rows = wrenches(p - np.asarray(reference, float), n) * np.asarray(sign, float)[:, None]
    out = np.zeros((len(p), 6 * count))
    for i, j in enumerate(np.asarray(part, int)):
        if j >= 0:
            out[i, 6 * j : 6 * j + 6] = rows[i]
    return out


def radius_rows(ball: np.ndarray, count: int) -> np.ndarray:
    """Sensitivity (k, count) of the contact separations to the radii of ``count`` balls (each
    contact touches ball ``ball[i]``, -1: none): 1 where a ball touches."""
    b = np.asarray(ball, int)
    return (b[:, None] == np.arange(count)[None, :]).astype(float)


def seat_pivots(points: np.ndarray, normals: np.ndarray, seat: np.ndarray) -> np.ndarray:
    """Per contact (k, 3) m, the point a seat's angle error turns its surface about: the point
    nearest the contact on the intersection of the tangent planes of the seat's contacts (a
    vee's root line, a trihedral's or a cone's apex); the contact itself for a lone flat."""
    p = np.asarray(points, float)
    n = np.asarray(normals, float)
    s = np.asarray(seat, int)
    out = p.copy()
    for i in range(len(p)):
        mates = np.flatnonzero(s == s[i]) if s[i] >= 0 else np.array([i])
        planes = n[mates]
        offsets = np.einsum("ij,ij->i", planes, p[mates] - p[i])
        # the least-norm step from p_i onto every plane (least squares where they miss)
        out[i] = p[i] + np.linalg.pinv(planes) @ offsets
    return out


@dataclass(frozen=True)
class PoseMap:
    """Linear maps from contact separations (k,) m to the pose error at the point of
    interest: ``translation`` (3, k) m/m and ``rotation`` (3, k) rad/m; ``condition``: the
    equilibrated condition number of the nondimensional contact matrix."""

    translation: np.ndarray
    rotation: np.ndarray
    condition: float


def pose_map(points: np.ndarray, normals: np.ndarray, point: np.ndarray) -> PoseMap | None:
    """The seated body's pose error at ``point`` (3,) m per unit separation of each of six
    contacts (points, normals (6, 3), SI); None when the layout does not fix the body."""
    seat = seat_layout(np.asarray(points, float), np.asarray(normals, float), 3, 1.0)
    k = len(seat.rows)
    if seat.rows.shape != (6, 6):
        return None
    sol = solve_affine(seat.rows, np.zeros(k), np.eye(k))
    if not sol.condition < ILL_CONDITIONED:
        return None
    length, origin = seat.frame.length, seat.frame.origin
    rotation = sol.c[:3] / length  # the solve's unknowns are (L omega, v)
    r = np.asarray(point, float) - origin
    translation = sol.c[3:] - np.cross(r, rotation.T).T  # v + omega x r
    return PoseMap(translation, rotation, float(sol.condition))


def pose_errors(pose: PoseMap, separations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Translation (s, 3) m and rotation (s, 3) rad at the point for separations (s, k) m."""
    d = np.asarray(separations, float)
    # einsum, not matmul: for skinny products it beats a threaded BLAS call on a busy machine
    return np.einsum("sk,ak->sa", d, pose.translation), np.einsum("sk,ak->sa", d, pose.rotation)


def draw(rng: np.random.Generator, count: int, scale: np.ndarray, distribution: str) -> np.ndarray:
    """``count`` draws (count, m) of independent errors: normal with standard deviations
    ``scale`` (m,), or uniform within ``+-scale``."""
    s = np.asarray(scale, float)
    if distribution == "normal":
        return rng.standard_normal((count, len(s))) * s
    if distribution == "uniform":
        return rng.uniform(-1.0, 1.0, (count, len(s))) * s
    raise ValueError(f"unknown distribution {distribution!r}")


def sobol_draws(
    seed: int, count: int, scale: np.ndarray, distribution: str
) -> tuple[np.ndarray, int]:
    """Quasi-random draws like :func:`draw` from one scrambled Sobol sequence over all
    ``len(scale)`` dimensions (seeded): ``count`` rounded up to a power of two (Sobol's
    balance), returned with the count used."""
    from scipy.stats import qmc

    s = np.asarray(scale, float)
    m = max(int(np.ceil(np.log2(max(count, 2)))), 1)
    u = qmc.Sobol(len(s), scramble=True, seed=seed).random_base2(m)
    return _unit_draws(u, s, distribution), len(u)


def _unit_draws(u: np.ndarray, scale: np.ndarray, distribution: str) -> np.ndarray:
    """Points ``u`` of ``[0, 1)^m`` as errors: normal with standard deviations ``scale``
    (m,) through the normal quantile, or uniform within ``+-scale``."""
    if distribution == "normal":
        from scipy.stats import norm

        # scrambled points are never exactly 0 or 1, but keep ppf finite regardless
        return np.asarray(norm.ppf(np.clip(u, TINY, 1.0 - EPS))) * scale
    if distribution == "uniform":
        return (2.0 * u - 1.0) * scale
    raise ValueError(f"unknown distribution {distribution!r}")


def mean_bounds(values: np.ndarray, z: float) -> tuple[float, float, float, float]:
    """Sample mean, sample standard deviation and the central-limit bounds
    ``mean -+ z s / sqrt(n)`` of the mean of ``values`` (n,)."""
    v = np.asarray(values, float)
    mean = float(v.mean())
    std = float(v.std(ddof=1)) if len(v) > 1 else 0.0
    half = z * std / np.sqrt(len(v))
    return mean, std, mean - half, mean + half


def quantile_bounds(values: np.ndarray, q: float, confidence: float) -> tuple[float, float, float]:
    """The ``q`` sample quantile of ``values`` (n,) and distribution-free bounds on the true
    quantile at ``confidence``: order statistics ``X_(l) <= xi_q <= X_(u)`` with ``l``, ``u``
    from the binomial(n, q) distribution of how many draws fall below ``xi_q`` (central
    interval; the ends clipped to the smallest and largest draw)."""
    from scipy.stats import binom

    v = np.sort(np.asarray(values, float))
    n = len(v)
    tail = (1.0 - confidence) / 2.0
    lo = int(binom.ppf(tail, n, q))  # X_(lo) (1-based) <= xi_q with probability >= 1 - tail
    hi = int(binom.ppf(1.0 - tail, n, q)) + 1
    lo = min(max(lo, 1), n)
    hi = min(max(hi, 1), n)
    return float(np.quantile(v, q)), float(v[lo - 1]), float(v[hi - 1])


def _sobol_points(seed: int, dimensions: int, start: int, count: int) -> np.ndarray:
    """Points ``start`` to ``start + count`` of the scrambled Sobol sequence seeded by
    ``seed``: those of one sequence drawn from its start, whichever chunk asks."""
    import warnings

    from scipy.stats import qmc

    engine = qmc.Sobol(dimensions, scramble=True, seed=seed)
    if start:
        engine.fast_forward(start)
    with warnings.catch_warnings():  # a chunk past the first need not start at a power of 2
        warnings.simplefilter("ignore", UserWarning)
        return np.asarray(engine.random(count))


@dataclass(frozen=True)
class PoseChunk:
    """One chunk of a pose-error Monte Carlo, as sent to whichever process maps it: samples
    ``start`` to ``start + count`` of a run seeded by ``seed`` (chunk ``index``), drawn from
    ``sampler`` (``random`` or ``sobol``) and ``distribution`` at the tolerances ``scale``
    (m,), through the sensitivities ``matrix`` (k, m) and the ``pose`` map."""

    pose: PoseMap
    matrix: np.ndarray
    scale: np.ndarray
    distribution: str
    sampler: str
    seed: int
    index: int
    start: int
    count: int


def pose_chunks(
    pose: PoseMap,
    matrix: np.ndarray,
    scale: np.ndarray,
    distribution: str,
    sampler: str,
    seed: int,
    samples: int,
) -> tuple[list[PoseChunk], int]:
    """The chunks of ``CHUNK`` samples of a run, and its sample count (Sobol: ``samples``
    rounded up to a power of two, for Sobol's balance)."""
    if sampler == "sobol":
        samples = 2 ** max(int(np.ceil(np.log2(max(samples, 2)))), 1)
    elif sampler != "random":
        raise ValueError(f"unknown sampler {sampler!r}")
    chunks = [
        PoseChunk(pose, matrix, scale, distribution, sampler, seed, i, start, stop - start)
        for i, (start, stop) in enumerate(chunk_bounds(samples, CHUNK))
    ]
    return chunks, samples


def pose_chunk(chunk: PoseChunk) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One chunk's pose errors at the point: translation (count,) m and rotation (count,)
    rad magnitudes, and the sums (3,) of the translation and rotation vectors (for the mean
    vector). Random draws come from the chunk's own stream
    (:func:`kcheck.numerics.streams.chunk_generator`), Sobol points from the one sequence:
    a pure function of the chunk, so any process may map it."""
    s = np.asarray(chunk.scale, float)
    if chunk.sampler == "sobol":
        u = _sobol_points(chunk.seed, len(s), chunk.start, chunk.count)
        x = _unit_draws(u, s, chunk.distribution)
    else:
        x = draw(chunk_generator(chunk.seed, chunk.index), chunk.count, s, chunk.distribution)
    separations = np.einsum("sm,km->sk", x, chunk.matrix)
    trans, rot = pose_errors(chunk.pose, separations)
    return (
        np.linalg.norm(trans, axis=1),
        np.linalg.norm(rot, axis=1),
        trans.sum(axis=0),
        rot.sum(axis=0),
    )
