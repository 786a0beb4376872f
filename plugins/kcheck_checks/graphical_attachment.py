"""Where the swept force of Koster's construction acts (graphical-2d): its attachment point,
torque arm and design direction, and the fixed forces that act with it (the weight, preloads),
scaled by the swept force. Scene level: no construction, no mesh read.
"""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.dynamics import log_size, relative
from kcheck.mechanics.kinematics import unit_rows
from kcheck.plugin import Inputs
from kcheck.records import dataclass
from kcheck.scene import Scene

__all__ = [
    "Attachment",
    "attachment",
    "attachment_of",
    "missing_force",
    "needs_centre_of_mass",
]


@dataclass(frozen=True)
class Attachment:
    """Where and how the swept force acts: point (m, 3), ``arm = M_z / F`` (m), design
    direction (unit 3-vector or None), and notes for the result. ``fixed`` are the forces that
    act with it — the weight, preloads — as ``(point m, force / F)`` (3-vectors)."""

    point: np.ndarray
    arm: float
    design: np.ndarray | None
    source: str
    notes: tuple[str, ...]
    fixed: tuple[tuple[np.ndarray, np.ndarray], ...] = ()


def missing_force(scene: Scene) -> str | None:
    """Why a planar scene gives the construction no force to sweep, or None (no mesh read)."""
    load = scene.load
    has_load = load is not None and load.magnitude > 0
    if not has_load and not np.any(scene.gravity[:2]):
        return "needs a closing force: a load with a magnitude, or gravity in the plane"
    if not has_load and load is not None and load.torque[2] != 0:
        return "a torque without a load magnitude needs the weight; give `load.magnitude`"
    if (not has_load or load is None or load.point is None) and scene.body is None:
        return (
            "the force acts at the centre of mass, but the scene has no `body` to find it; "
            "give `load.point` or a body"
        )
    return None


def attachment_of(inputs: Inputs) -> Attachment | str:
    """:func:`attachment` of a check's inputs (the centre of mass and mass when known)."""
    mass = inputs.mass
    return attachment(
        inputs.scene,
        com=None if mass is None else mass.center_of_mass,
        mass=None if mass is None else mass.mass,
    )


def _weight_in_plane(scene: Scene) -> bool:
    return bool(np.any(scene.gravity[:2]))


def needs_centre_of_mass(scene: Scene) -> bool:
    """Whether the construction needs the mass properties: the swept force acts at the centre
    of mass (no load point, or the weight), or the weight acts with the load."""
    load = scene.load
    if load is None or load.magnitude <= 0 or load.point is None:
        return True
    return _weight_in_plane(scene) and scene.body is not None


def _plane_point(scene: Scene, point: np.ndarray) -> np.ndarray:
    point = np.asarray(point, float)
    if point.shape == (2,):
        point = np.append(point, scene.supports[0].position[2])
    return point


def attachment(
    scene: Scene,
    point: np.ndarray | None = None,
    com: np.ndarray | None = None,
    mass: float | None = None,
) -> Attachment | str:
    """The swept force's attachment, or the reason the construction has none.

    ``point`` (m) overrides the attachment point, e.g. one already found in a result; ``com``
    (m) and ``mass`` (kg) are the centre of mass and mass, used when the force acts there and
    for the weight.
    """
    reason = missing_force(scene)
    if reason is not None:
        return reason
    load = scene.load
    gravity = np.append(scene.gravity[:2], 0.0)
    log_weight = log_size(gravity) + (log_size(mass) if mass is not None else -np.inf)
    notes: list[str] = []
    fixed: list[tuple[np.ndarray, np.ndarray]] = []
    if load is not None and load.magnitude > 0:
        point = load.point if point is None else point
        log_swept = log_size(load.magnitude)
        arm = float(load.torque[2]) / load.magnitude
        design, source = load.direction, "load"
        if _weight_in_plane(scene):
            if com is None or mass is None:
                notes.append("gravity left out: the scene has no `body` for the weight")
            else:
                weight = relative(gravity, log_swept, log_weight)
                fixed.append((np.asarray(com, float), weight))
                notes.append("the weight acts with the load (their resultant is swept)")
    else:
        arm, source = 0.0, "weight"
        design = unit_rows(gravity)
        log_swept = log_weight
    if point is None:
        if com is None:
            return "the force acts at the centre of mass, which is not known"
        point = com
        notes.append("force at the centre of mass")
    pushing = [p for p in scene.preloads if np.any(p.force[:2] != 0)]
    if pushing and np.isfinite(log_swept):
        for p in pushing:
            force = relative(np.append(p.force[:2], 0.0), log_swept)
            fixed.append((_plane_point(scene, p.point), force))
        notes.append("preloads act with the swept force")
    return Attachment(_plane_point(scene, point), arm, design, source, tuple(notes), tuple(fixed))
