"""The most robust direction in a plane: the angle deepest inside every arc ``a_k + c_k . d > 0``.

Each condition's signed margin at angle ``t`` is a tent, ``w_k - |t - phi_k|`` (wrapped), with
``phi_k`` the arc's middle and ``w_k`` its half-width (:func:`kcheck.mechanics.arcs.cap_geometry`,
in the plane). Their minimum is piecewise linear, so its maximum lies at a tent's peak or where
a falling tent meets a rising one: every such angle is tried, exactly.
"""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.arcs import cap_geometry, cap_margins

__all__ = ["most_robust_angle"]


def most_robust_angle(a: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, float]:
    """Unit direction (2,) deepest inside every arc ``a_k + c_k . d > 0`` (``c`` (k, 2)) and its
    margin (rad; negative when no direction satisfies every condition: the best of the
    smallest margins). Without a bounding condition: ``+x`` and ``pi``."""
    a, c = np.asarray(a, float), np.asarray(c, float)
    ratio, axes, radius = cap_geometry(a, c)
    if np.any(ratio >= 1.0):  # a condition that holds nowhere
        return np.array([1.0, 0.0]), -float(np.pi)
    bounded = ratio > -1.0
    if not np.any(bounded):
        return np.array([1.0, 0.0]), float(np.pi)
    phi = np.arctan2(axes[bounded, 1], axes[bounded, 0])
    w = radius[bounded]
    crossing = 0.5 * (w[:, None] - w[None, :] + phi[:, None] + phi[None, :])
    angles = np.concatenate([phi, crossing.ravel(), crossing.ravel() + np.pi])
    directions = np.column_stack([np.cos(angles), np.sin(angles)])
    margins = cap_margins(a, c, directions)
    best = int(np.argmax(margins))
    return directions[best], float(margins[best])
