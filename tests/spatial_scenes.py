"""Generated spatial scenes (three balls in three grooves, perturbed), for the speed work of
issue 24: the reference values recorded before optimising (``tests/golden/speed_reference.json``)
and the paired benchmarks in ``benchmarks/`` use the same scenes.

Scene ``i`` is determined by ``i`` alone (``numpy.random.default_rng(i)``): three balls of
radius 6 mm on a circle of radius 30–80 mm at roughly 120° spacing (±15°), each in a V-groove
of flank angle 25–65° from the horizontal, every normal tilted by up to 3° more, explicit mass
properties of a solid box (no mesh), gravity, a load within 35° of straight down, one friction
coefficient 0.05–0.3. Contacts are on the ball surfaces.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

BALL_RADIUS_MM = 6.0


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _tilt(n: np.ndarray, rng: np.random.Generator, deg: float) -> np.ndarray:
    """``n`` tilted by up to ``deg`` degrees in a random direction."""
    side = _unit(np.cross(n, rng.normal(size=3)))
    angle = np.radians(rng.uniform(0.0, deg))
    return _unit(np.cos(angle) * n + np.sin(angle) * side)


def spatial_scene(i: int) -> str:
    """The YAML text of generated spatial scene ``i``."""
    rng = np.random.default_rng(i)
    radius = rng.uniform(30.0, 80.0)
    base = rng.uniform(0.0, 360.0)
    lines = []
    for b in range(3):
        theta = np.radians(base + 120.0 * b + rng.uniform(-15.0, 15.0))
        beta = np.radians(rng.uniform(25.0, 65.0))
        radial = np.array([np.cos(theta), np.sin(theta), 0.0])
        tangent = np.array([-np.sin(theta), np.cos(theta), 0.0])
        centre = radius * radial
        for side, sign in (("a", 1.0), ("b", -1.0)):
            normal = _tilt(sign * np.cos(beta) * tangent + np.sin(beta) * np.array([0, 0, 1.0]),
                           rng, 3.0)  # fmt: skip
            point = centre - BALL_RADIUS_MM * normal
            lines.append(
                f"  - {{name: g{b + 1}{side}, position: [{point[0]:.6f}, {point[1]:.6f}, "
                f"{point[2]:.6f}], normal: [{normal[0]:.9f}, {normal[1]:.9f}, {normal[2]:.9f}]}}"
            )
    com = [rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(5, 30)]
    mass = rng.uniform(0.5, 5.0)
    sides = rng.uniform(0.05, 0.25, size=3)  # m: a solid box's inertia (a rigid body's)
    inertia = mass / 12 * (np.sum(sides**2) - sides**2)
    direction = _tilt(np.array([0, 0, -1.0]), rng, 35.0)
    point = [rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(0, 40)]
    return (
        f"version: 1\nname: generated spatial {i}\nunits: mm\nbody:\n"
        f"  mass: {mass:.6f}\n"
        f"  center_of_mass: [{com[0]:.6f}, {com[1]:.6f}, {com[2]:.6f}]\n"
        f"  inertia: [[{inertia[0]:.6e}, 0, 0], [0, {inertia[1]:.6e}, 0], "
        f"[0, 0, {inertia[2]:.6e}]]\n"
        "supports:\n" + "\n".join(lines) + "\n"
        f"friction: {rng.uniform(0.05, 0.3):.6f}\n"
        "gravity: [0, 0, -9.81]\n"
        f"load:\n  point: [{point[0]:.6f}, {point[1]:.6f}, {point[2]:.6f}]\n"
        f"  magnitude: {rng.uniform(10, 200):.6f}\n"
        f"  direction: [{direction[0]:.9f}, {direction[1]:.9f}, {direction[2]:.9f}]\n"
        "sweep: {normal: [0, -1, 0], zero: [0, 0, -1]}\n"
    )


def write_spatial_scenes(folder: Path, indices: range) -> list[Path]:
    """Write scenes ``indices`` into ``folder`` (one file each); their paths."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for i in indices:
        path = folder / f"s{i:04d}.kcheck.yaml"
        path.write_text(spatial_scene(i))
        paths.append(path)
    return paths


#: The result fields the speed work must keep (issue 24): safe-range ends, limiting and least
#: holding friction, sphere shares, margins, and every error estimate. Words are left out
#: (other work changes them); the status is kept.
KEPT = (
    "status",
    "error_estimate",
    "safe_ranges_deg",
    "jam_free_deg",
    "held_deg",
    "closing_deg",
    "jamming_deg",
    "holds_opening_deg",
    "limiting_friction",
    "friction_intervals",
    "holding_friction",
    "design_margin_deg",
    "robust_margin_deg",
    "most_robust_direction",
    "polyhedral_error_deg",
    "sphere_points",
)


def kept_values(check: dict) -> dict:
    """The fields of one check's JSON result (and its cases') that the speed work keeps:
    those named in KEPT and every ``*solid_angle_fraction*``."""

    def keep(d: dict) -> dict:
        return {k: v for k, v in d.items() if k in KEPT or "solid_angle_fraction" in k}

    out = keep(check)
    if check.get("cases"):
        out["cases"] = [keep(c) for c in check["cases"]]
    return out
