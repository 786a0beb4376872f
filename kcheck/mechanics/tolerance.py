"""Manufacturing tolerances: how the closing behaviour varies over a box of made couplings.

A sample is a coupling as it may be made: every support position moved by up to ``±δ`` in
each coordinate (uniform), every normal tilted by up to ``δn`` (uniform over the spherical cap
of directions within ``δn``; in a plane, a turn uniform in ``±δn``), the kinetic coefficients
uniform along their ranges (together, as the analytical checks take a range, or each support
on its own). For each sample the analytical equations of
every retracted case are set up and solved at once, in batches of numpy calls (free twists by
one SVD per case, the systems by one solve): nothing is looped over samples. A run is cut into
chunks of ``CHUNK`` samples, each drawn from its own stream (:mod:`kcheck.numerics.streams`)
and solved by :func:`chunk_margins`, a pure function of its :class:`MarginChunk`: any process
may solve any chunk, and the margins are the same.

The result per sample is the **design margin**: the least, over the cases and their closing
conditions ``a_k + c_k . d > 0``, of the angular distance of the design direction ``d`` to the
condition's boundary, ``arccos(-a_k / |c_k|) - arccos(c_k . d / |c_k|)`` — exact where the
design direction closes every case (then it is the distance to the nearest boundary of the safe
set, as analytical-2d/3d report it), and minus the largest violation of one condition where it
does not. A load direction tolerance ``δd`` is exact on top: every load direction within ``δd``
closes iff the margin is at least ``δd``. Painlevé-type, undetermined and ill-conditioned
samples fail (margin ``-pi``).
"""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.dynamics import (
    ILL_CONDITIONED,
    UNDETERMINED,
    Problem,
    _equilibrate,
    contact_matrices,
)
from kcheck.mechanics.kinematics import free_twist_arrays, wrenches
from kcheck.numerics.streams import chunk_bounds, chunk_generator
from kcheck.records import dataclass

__all__ = [
    "Perturbed",
    "perturb",
    "unit_dimensions",
    "sample_margins",
    "Box",
    "MarginChunk",
    "margin_chunks",
    "chunk_layouts",
    "chunk_margins",
    "CHUNK",
]

#: Samples drawn, set up and solved per chunk (bounds the memory: about 3 MB per 1000 spatial
#: samples). Each chunk draws from its own stream, so changing this changes the samples.
CHUNK = 4096


@dataclass(frozen=True)
class Perturbed:
    """Sampled layouts (nondimensional, in the nominal problem's frame): ``points`` and unit
    ``normals`` (s, k, dim), coefficients ``friction`` (s, k)."""

    points: np.ndarray
    normals: np.ndarray
    friction: np.ndarray


def _tilts(normals: np.ndarray, angle: float, rng: np.random.Generator, count: int) -> np.ndarray:
    """Unit normals (count, k, dim) tilted from ``normals`` (k, dim) by at most ``angle`` rad:
    uniformly over the cap of directions (3D: ``cos`` of the tilt uniform), uniformly in the
    turn (2D)."""
    k, dim = normals.shape
    if angle <= 0:
        return np.broadcast_to(normals, (count, k, dim)).copy()
    if dim == 2:
        turn = rng.uniform(-angle, angle, (count, k))
        c, s = np.cos(turn), np.sin(turn)
        x, y = normals[:, 0], normals[:, 1]
        return np.stack([c * x - s * y, s * x + c * y], axis=-1)
    cos_tilt = rng.uniform(np.cos(angle), 1.0, (count, k))
    sin_tilt = np.sqrt(np.maximum(1.0 - cos_tilt**2, 0.0))
    azimuth = rng.uniform(0.0, 2.0 * np.pi, (count, k))
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = np.cross(normals, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(normals, e1)
    side = np.cos(azimuth)[..., None] * e1 + np.sin(azimuth)[..., None] * e2
    return cos_tilt[..., None] * normals + sin_tilt[..., None] * side


def perturb(
    problem: Problem,
    *,
    position: float,
    normal: float,
    friction_low: np.ndarray,
    friction_high: np.ndarray,
    count: int,
    rng: np.random.Generator,
    independent: bool = False,
    unit: np.ndarray | None = None,
) -> Perturbed:
    """``count`` made couplings around the problem's: positions within ``±position`` (m) per
    coordinate, normals within ``normal`` (rad), coefficients uniform along their ranges —
    together, as the analytical checks take a range (``low + t (high - low)``, one ``t`` per
    sample), or each support on its own (``independent``). Drawn from ``rng``, or mapped
    from ``unit`` points of ``[0, 1)^d`` (count, :func:`unit_dimensions`), e.g. a Latin
    hypercube or Sobol design of :mod:`kcheck.numerics.design`."""
    k, dim = problem.points.shape
    if unit is not None:
        return _from_unit(problem, position, normal, friction_low, friction_high, unit)
    shift = rng.uniform(-1.0, 1.0, (count, k, dim)) * (position / problem.frame.length)
    normals = _tilts(problem.normals, normal, rng, count)
    span = np.asarray(friction_high, float) - np.asarray(friction_low, float)
    t = rng.uniform(0.0, 1.0, (count, k) if independent else (count, 1))
    mu = np.asarray(friction_low, float) + t * span
    return Perturbed(problem.points + shift, normals, mu)


def unit_dimensions(k: int, dim: int, independent: bool) -> int:
    """Columns of the unit points one sample of ``k`` supports takes: its shifts (k dim),
    its tilts (3D: cosine and azimuth per support; 2D: the turn) and its coefficients (one
    shared, or one per support)."""
    return k * dim + (k if dim == 2 else 2 * k) + (k if independent else 1)


def _from_unit(
    problem: Problem,
    position: float,
    normal: float,
    friction_low: np.ndarray,
    friction_high: np.ndarray,
    unit: np.ndarray,
) -> Perturbed:
    """The made couplings of :func:`perturb` at the given unit points (count, d): each
    uniform quantity is its range's ``low + u (high - low)``."""
    k, dim = problem.points.shape
    count = len(unit)
    u_shift = unit[:, : k * dim].reshape(count, k, dim)
    shift = (2.0 * u_shift - 1.0) * (position / problem.frame.length)
    tilt_cols = k if dim == 2 else 2 * k
    u_tilt = unit[:, k * dim : k * dim + tilt_cols]
    nominal = problem.normals
    if normal <= 0:
        normals = np.broadcast_to(nominal, (count, k, dim)).copy()
    elif dim == 2:
        turn = normal * (2.0 * u_tilt - 1.0)
        c, s = np.cos(turn), np.sin(turn)
        x, y = nominal[:, 0], nominal[:, 1]
        normals = np.stack([c * x - s * y, s * x + c * y], axis=-1)
    else:
        cos_tilt = np.cos(normal) + u_tilt[:, :k] * (1.0 - np.cos(normal))
        sin_tilt = np.sqrt(np.maximum(1.0 - cos_tilt**2, 0.0))
        azimuth = 2.0 * np.pi * u_tilt[:, k:]
        helper = np.where(np.abs(nominal[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        e1 = np.cross(nominal, helper)
        e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
        e2 = np.cross(nominal, e1)
        side = np.cos(azimuth)[..., None] * e1 + np.sin(azimuth)[..., None] * e2
        normals = cos_tilt[..., None] * nominal + sin_tilt[..., None] * side
    t = unit[:, k * dim + tilt_cols :]
    span = np.asarray(friction_high, float) - np.asarray(friction_low, float)
    mu = np.asarray(friction_low, float) + t * span
    return Perturbed(problem.points + shift, normals, mu)


def _sample_twists(
    points: np.ndarray, normals: np.ndarray, pivot: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Free twists (s, c, n) of sampled layouts (s, k, dim), with a determinacy measure and
    the closing rate (s, c), from one square solve per case instead of an SVD: the twist's
    component ``pivot`` (c,) — the nominal twist's largest — is set to 1 and the constraint
    rows give the rest. Determinacy is the Hadamard ratio of that square system (0: singular)."""
    count, k, _ = points.shape
    rows = wrenches(points, normals)  # (s, k, n)
    n = rows.shape[-1]
    keep = np.array([np.flatnonzero(np.arange(k) != r) for r in range(k)])  # (c, k-1)
    kept = rows[:, keep]  # (s, c, k-1, n)
    others = np.array([np.flatnonzero(np.arange(n) != j) for j in pivot])  # (c, n-1)
    square = np.take_along_axis(kept, others[None, :, None, :], axis=-1)  # (s, c, n-1, n-1)
    rhs = -np.take_along_axis(kept, pivot[None, :, None, None], axis=-1)  # (s, c, n-1, 1)
    with np.errstate(all="ignore"):
        sign, logdet = np.linalg.slogdet(square)
        norms = np.sum(np.log(np.sqrt(np.sum(square * square, axis=-1))), axis=-1)
        determinacy = np.where(sign != 0, np.exp(logdet - norms), 0.0)
    usable = determinacy > 0
    safe = np.where(usable[..., None, None], square, np.eye(n - 1))
    rest = np.linalg.solve(safe, rhs)[..., 0]  # (s, c, n-1)
    twist = np.ones((count, k, n))
    np.put_along_axis(twist, np.broadcast_to(others[None], rest.shape), rest, axis=-1)
    twist /= np.linalg.norm(twist, axis=-1, keepdims=True)
    gap = np.sum(rows * twist, axis=-1)  # n_r . u(p_r) of each retracted support
    sense = np.where(gap > 0, -1.0, 1.0)
    return sense[..., None] * twist, np.where(usable, determinacy, 0.0), -sense * gap


def _margins_chunk(
    problem: Problem, layouts: Perturbed, design: np.ndarray | None, pivot: np.ndarray
) -> np.ndarray:
    """Design margins (s,) of one batch of sampled layouts (see the module text)."""
    points, normals, mu = layouts.points, layouts.normals, layouts.friction
    count, k, _ = points.shape
    twists, determinacy, closing = _sample_twists(points, normals, pivot)  # (s, c, n), (s, c)
    keep = np.array([np.flatnonzero(np.arange(k) != r) for r in range(k)])  # (c, k-1)
    k0, big_f, _ = contact_matrices(
        twists, points[:, keep], normals[:, keep], mu[:, keep], problem.com, problem.inertia
    )
    forward, backward = k0 + big_f, k0 - big_f
    rows, cols = _equilibrate(forward)
    scaled = forward * rows[..., :, None] * cols[..., None, :]
    b0, big_b = problem.load_basis()
    rhs_w = np.column_stack([b0, big_b])  # (n, 1 + dim)
    with np.errstate(all="ignore"):
        sign0, _ = np.linalg.slogdet(k0)
        sign_f, log_f = np.linalg.slogdet(scaled)
        sign_b, _ = np.linalg.slogdet(backward)
        row_norms = np.sum(np.log(np.sqrt(np.sum(scaled * scaled, axis=-1))), axis=-1)
        hadamard = np.where(sign_f != 0, np.exp(log_f - row_norms), 0.0)
    ok = (
        (determinacy > UNDETERMINED)
        & (closing > UNDETERMINED)
        & (hadamard > 1.0 / ILL_CONDITIONED)
        & (sign_f == sign0)
        & (sign_b == sign0)
        & (sign0 != 0)
    )
    safe = np.where(ok[..., None, None], scaled, np.eye(scaled.shape[-1]))
    x = np.linalg.solve(safe, rhs_w[None, None] * rows[..., :, None]) * cols[..., :, None]
    a, c = x[..., 0], x[..., 1:]  # (s, c, n), (s, c, n, dim)
    if design is None:
        # the fixed wrench alone: closing or not (a sign, not an angle)
        value = np.where(np.all(a > 0, axis=-1), np.pi, -np.pi)
    else:
        size = np.linalg.norm(c, axis=-1)
        with np.errstate(all="ignore"):
            radius = np.arccos(np.clip(-a / size, -1.0, 1.0))
            off = np.arccos(np.clip((c @ design) / size, -1.0, 1.0))
        value = np.where(size > 0, radius - off, np.where(a > 0, np.pi, -np.pi)).min(axis=-1)
    value = np.where(ok & np.isfinite(value), value, -np.pi)
    return value.min(axis=-1)


def sample_margins(problem: Problem, layouts: Perturbed, design: np.ndarray | None) -> np.ndarray:
    """Design margins (rad, (s,)) of sampled layouts, in batches of ``CHUNK``; ``pi`` /
    ``-pi`` for closing / not closing under the fixed wrench when there is no design
    direction."""
    count = len(layouts.points)
    out = np.empty(count)
    pivot = _pivot(problem)
    for start in range(0, count, CHUNK):
        part = slice(start, start + CHUNK)
        batch = Perturbed(layouts.points[part], layouts.normals[part], layouts.friction[part])
        out[part] = _margins_chunk(problem, batch, design, pivot)
    return out


def _pivot(problem: Problem) -> np.ndarray:
    """Per case, the nominal free twist's largest component (the sampled twists' pivot)."""
    nominal, _, _ = free_twist_arrays(problem.points, problem.normals)
    return np.argmax(np.abs(nominal), axis=-1)


@dataclass(frozen=True)
class Box:
    """The tolerance box of :func:`perturb`: positions within ``±position`` (m) per
    coordinate, normals within ``normal`` (rad), coefficients from ``friction_low`` to
    ``friction_high`` (k,), together or each on its own (``independent``)."""

    position: float
    normal: float
    friction_low: np.ndarray
    friction_high: np.ndarray
    independent: bool = False


@dataclass(frozen=True)
class MarginChunk:
    """One chunk of a tolerance Monte Carlo, as sent to whichever process solves it: chunk
    ``index`` of a run seeded by ``seed``, ``count`` samples (its unit points ``unit`` when a
    design gives them), the box and the problem with its design direction."""

    problem: Problem
    box: Box
    design: np.ndarray | None
    pivot: np.ndarray
    seed: int
    index: int
    count: int
    unit: np.ndarray | None = None


def margin_chunks(
    problem: Problem,
    box: Box,
    design: np.ndarray | None,
    count: int,
    seed: int,
    unit: np.ndarray | None = None,
) -> list[MarginChunk]:
    """The chunks of ``CHUNK`` samples of a run of ``count`` samples seeded by ``seed`` (or at
    the rows of ``unit``, (count, :func:`unit_dimensions`), a design's points)."""
    pivot = _pivot(problem)
    return [
        MarginChunk(
            problem,
            box,
            design,
            pivot,
            seed,
            i,
            stop - start,
            None if unit is None else unit[start:stop],
        )
        for i, (start, stop) in enumerate(chunk_bounds(count, CHUNK))
    ]


def chunk_layouts(chunk: MarginChunk) -> Perturbed:
    """The made couplings of one chunk: drawn from the chunk's own stream
    (:func:`kcheck.numerics.streams.chunk_generator`) or mapped from its unit points."""
    b = chunk.box
    return perturb(
        chunk.problem,
        position=b.position,
        normal=b.normal,
        friction_low=b.friction_low,
        friction_high=b.friction_high,
        count=chunk.count,
        rng=chunk_generator(chunk.seed, chunk.index),
        independent=b.independent,
        unit=chunk.unit,
    )


def chunk_margins(chunk: MarginChunk) -> np.ndarray:
    """Design margins (rad, (count,)) of one chunk's made couplings: a pure function of the
    chunk, so any process may solve it."""
    return _margins_chunk(chunk.problem, chunk_layouts(chunk), chunk.design, chunk.pivot)
