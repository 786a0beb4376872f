"""A scene's dynamics in nondimensional form: the problem every retracted case is solved in.

Lengths are divided by the layout size ``L`` (:class:`kcheck.mechanics.kinematics.Frame`), forces by
the force scale ``F`` — the largest of the load, the weight and the preloads, compared as
logarithms so that no magnitude overflows or vanishes — and masses by ``m`` (so the
nondimensional mass is 1 and inertia is ``I / (m L^2)``). Wrenches are ordered
``[moment about the centre of mass; force]``, like those of :mod:`kcheck.mechanics.kinematics`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from kcheck.mechanics.kinematics import Frame, row_norms, unit_rows, wrenches
from kcheck.records import dataclass

__all__ = ["Problem", "build_problem", "log_size", "relative"]


@dataclass(frozen=True)
class Problem:
    """A scene's dynamics, nondimensional. ``dim`` is 2 (planar) or 3 (spatial)."""

    frame: Frame
    names: tuple[str, ...]
    points: np.ndarray  # (k, dim)
    normals: np.ndarray  # (k, dim) unit
    friction: np.ndarray  # (k,)
    com: np.ndarray  # (dim,)
    inertia: np.ndarray  # (nw, nw), I / (m L^2) about the centre of mass
    gravity: np.ndarray  # (dim,), m g / F
    torque: np.ndarray  # (nw,), M / (F L)
    load_point: np.ndarray  # (dim,)
    load_scale: float  # load magnitude / F (0 without a load)
    mass: float  # kg, for converting back
    preload: np.ndarray | None = None  # (n,), wrench of the preloads about the centre of mass
    log_force: float | None = None  # log of the force scale F (N); None: log(frame.force)

    @property
    def dim(self) -> int:
        """2 or 3."""
        return self.points.shape[1]

    def fixed_wrench(self) -> np.ndarray:
        """The wrench that does not depend on the load direction: torque, weight, preloads."""
        b0 = np.concatenate([self.torque, self.gravity])
        return b0 if self.preload is None else b0 + self.preload

    def load_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """External wrench about the centre of mass as ``b0 + B d``: returns ``(b0, B)``."""
        r = self.load_point - self.com
        eye = np.eye(self.dim)
        lever = wrenches(np.broadcast_to(r, (self.dim, self.dim)), eye).T  # (n, dim)
        return self.fixed_wrench(), self.load_scale * lever

    @property
    def swept(self) -> Literal["load", "gravity"]:
        """What a direction sweeps: the load's when it has a magnitude, else gravity's."""
        return "load" if self.load_scale > 0 else "gravity"

    def gravity_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """External wrench about the centre of mass as ``b0 + B d`` for gravity's direction
        ``d`` swept with its magnitude kept (the tilt of the body): returns ``(b0, B)``; the
        torque and the preloads stay fixed to the body."""
        nw = len(self.torque)
        weight = float(row_norms(self.gravity))
        b0 = np.concatenate([self.torque, np.zeros(self.dim)])
        if self.preload is not None:
            b0 = b0 + self.preload
        return b0, np.vstack([np.zeros((nw, self.dim)), weight * np.eye(self.dim)])

    def swept_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """``(b0, B)`` of the swept direction (:attr:`swept`): the load's or gravity's."""
        return self.load_basis() if self.swept == "load" else self.gravity_basis()

    def wrench(self, direction: np.ndarray | None) -> np.ndarray:
        """External wrench for a unit force direction (dim,), or the fixed wrench alone."""
        b0, big_b = self.load_basis()
        return b0 if direction is None else b0 + big_b @ direction

    def _log_force(self) -> float:
        return float(np.log(self.frame.force)) if self.log_force is None else self.log_force

    def acceleration_scale(self) -> float:
        """m/s^2 per unit of nondimensional lambda (``inf`` beyond the largest float)."""
        with np.errstate(all="ignore"):
            return float(np.exp(self._log_force() - np.log(self.mass)))

    def newtons(self, values: np.ndarray) -> np.ndarray:
        """Nondimensional forces in N (``+-inf`` beyond the largest float)."""
        v = np.asarray(values, float)
        with np.errstate(all="ignore"):
            return np.sign(v) * np.exp(np.log(np.abs(v)) + self._log_force())

    def friction_pattern(self) -> tuple[np.ndarray, float]:
        """Friction as ``mu * pattern``: the pattern (k,) and the scene's ``mu``.

        ``mu`` is the largest coefficient of the scene and the pattern every support's share
        of it, so equal coefficients give a common ``mu`` and supports the scene makes
        frictionless stay frictionless. A frictionless scene gets the pattern 1 everywhere.
        """
        mu = float(self.friction.max()) if len(self.friction) else 0.0
        if mu > 0:
            return self.friction / mu, mu
        return np.ones(len(self.friction)), 0.0


def log_size(vector: np.ndarray | float) -> float:
    """Natural logarithm of a magnitude or a vector's norm (``-inf`` for zero), without
    overflow (:func:`kcheck.mechanics.kinematics.row_norms`)."""
    size = float(row_norms(np.atleast_1d(np.asarray(vector, float))))
    with np.errstate(divide="ignore"):
        return float(np.log(size)) if np.isfinite(size) else float("inf")


def relative(vector: np.ndarray, log_scale: float, log_size_: float | None = None) -> np.ndarray:
    """``vector / exp(log_scale)`` computed as its direction times ``exp(log|v| - log_scale)``,
    so neither the vector's norm nor the scale need be representable; ``log_size_`` overrides
    ``log|v|`` (e.g. the weight ``log m + log |g|``)."""
    v = np.asarray(vector, float)
    size = log_size(v) if log_size_ is None else log_size_
    if size == -np.inf:
        return np.zeros_like(v)
    with np.errstate(over="ignore", under="ignore"):
        return unit_rows(v) * float(np.exp(size - log_scale))


def _preload_wrench(
    frame: Frame,
    com: np.ndarray,
    preloads: Sequence[tuple[np.ndarray, np.ndarray]],
    log_force: float,
) -> np.ndarray | None:
    """Nondimensional wrench (n,) of fixed forces ``(point m, force N)`` about the centre of
    mass (nondimensional), or None without preloads."""
    if not preloads:
        return None
    points = frame.point(np.array([p for p, _ in preloads], dtype=float))
    forces = np.array([relative(np.asarray(f, float)[: frame.dim], log_force) for _, f in preloads])
    return wrenches(points - com, forces).sum(axis=0)


def build_problem(
    *,
    points: np.ndarray,
    normals: np.ndarray,
    friction: np.ndarray,
    names: tuple[str, ...],
    dim: int,
    mass: float,
    com: np.ndarray,
    inertia: np.ndarray,
    gravity: np.ndarray,
    load_magnitude: float,
    load_point: np.ndarray | None,
    torque: np.ndarray,
    preloads: Sequence[tuple[np.ndarray, np.ndarray]] = (),
) -> Problem:
    """Nondimensionalise a scene (SI inputs, 3-vectors) into a :class:`Problem`.

    The force scale is the largest of the load magnitude, the weight and the preloads, so every
    nondimensional force is at most 1. Magnitudes are compared as logarithms, so a mass of
    1e308 kg or 1e-320 kg, or a load of 1e-300 N, neither overflows nor vanishes; the force
    scale itself (only used to convert results back to newtons) may then be ``inf`` or 0.
    ``preloads`` are fixed forces ``(point m, force N)`` acting with gravity.
    """
    g = np.asarray(gravity, float)[:dim]
    log_weight = log_size(mass) + log_size(g)
    log_load = log_size(load_magnitude)
    log_force = max([log_load, log_weight, *(log_size(np.asarray(f)[:dim]) for _, f in preloads)])
    if log_force == -np.inf:
        raise ValueError("no closing force: the load, gravity and preloads are all zero")
    with np.errstate(over="ignore", under="ignore"):
        force = float(np.exp(log_force))
    frame = Frame.for_points(points, dim, force)
    nw = 1 if dim == 2 else 3
    moments = np.asarray(inertia, float)
    moments = moments[2:, 2:] if dim == 2 else moments
    q = com if load_point is None else load_point
    c = frame.point(com)
    log_length = float(np.log(frame.length))
    with np.errstate(all="ignore"):
        inertia_nd = moments / mass / frame.length / frame.length
        t = np.asarray(torque, float)[3 - nw :]
        torque_nd = relative(t, log_force + log_length) if np.any(t) else np.zeros(nw)
        load_scale = float(np.exp(log_load - log_force))
    return Problem(
        frame=frame,
        names=names,
        points=frame.point(points),
        normals=unit_rows(np.asarray(normals, float)[:, :dim]),
        friction=np.asarray(friction, float),
        com=c,
        inertia=inertia_nd,
        gravity=relative(g, log_force, log_weight),
        torque=torque_nd,
        load_point=frame.point(q),
        load_scale=load_scale,
        mass=mass,
        preload=_preload_wrench(frame, c, preloads, log_force),
        log_force=log_force,
    )
