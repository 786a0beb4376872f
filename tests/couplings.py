"""Coupling scenes for tests: supports with contact geometry, as the `couplings:` shorthands give.

The contact formulas are those of the shorthands (issue 7): for a ball of centre ``c`` and
radius ``r`` and a unit vector ``n`` from the mating surface towards the ball centre, the
contact point is ``c - r n`` and the support normal is ``n`` (the ball on the body) or ``-n``
(the ball on the base: the groove is on the body). The scene is written as real YAML with the
explicit supports, read by the real parser, and the supports then get their geometry.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import yaml

from kcheck.scene import ContactGeometry, Scene, Support, Surface, load_scene

UP = np.array([0.0, 0.0, 1.0])
BALL_FLAT = Surface((np.inf, np.inf))


def _unit(v: Sequence[float]) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def ball_contacts(
    name: str,
    kind: str,
    center: Sequence[float],
    radius: float,
    directions: Sequence[np.ndarray],
    seats: Sequence[Surface],
    ball_on: str = "body",
) -> list[tuple[np.ndarray, np.ndarray, ContactGeometry]]:
    """Contacts of one ball (SI): (point, support normal, geometry) per mating surface."""
    c = np.asarray(center, float)
    ball = Surface((radius, radius))
    out = []
    for k, (n, seat) in enumerate(zip(directions, seats, strict=True)):
        n = _unit(n)
        body, base = (ball, seat) if ball_on == "body" else (seat, ball)
        geometry = ContactGeometry(name, kind, k + 1, c, radius, ball_on, body, base)  # type: ignore[arg-type]
        out.append((c - radius * n, n if ball_on == "body" else -n, geometry))
    return out


def ball_vee(name: str, center, radius, axis, half_angle_deg, ball_on="body"):
    """A ball in a V-groove along ``axis`` (horizontal); flank normals ``half_angle`` from up."""
    b = np.radians(half_angle_deg)
    side = _unit(np.cross(UP, _unit(axis)))
    normals = [np.cos(b) * UP + np.sin(b) * side, np.cos(b) * UP - np.sin(b) * side]
    return ball_contacts(name, "ball-vee", center, radius, normals, [BALL_FLAT] * 2, ball_on)


def ball_trihedral(name: str, center, radius, half_angle_deg, reference=(1.0, 0.0, 0.0)):
    """A ball in a trihedral socket: three flat flanks, normals ``half_angle`` from up."""
    b = np.radians(half_angle_deg)
    e1 = _unit(reference)
    e2 = np.cross(UP, e1)
    normals = []
    for k in range(3):
        phi = 2 * np.pi * k / 3
        normals.append(np.cos(b) * UP + np.sin(b) * (np.cos(phi) * e1 + np.sin(phi) * e2))
    return ball_contacts(name, "ball-trihedral", center, radius, normals, [BALL_FLAT] * 3)


def ball_flat(name: str, center, radius):
    """A ball on a horizontal flat."""
    return ball_contacts(name, "ball-flat", center, radius, [UP], [BALL_FLAT])


def ball_cylinders(name: str, center, radius, axis, pin_radius, half_angle_deg):
    """A ball on two parallel pins along ``axis`` (a tool changer's dowels): the contact
    normals point from each pin's axis to the ball centre, ``half_angle`` from up."""
    b = np.radians(half_angle_deg)
    axis = _unit(axis)
    side = _unit(np.cross(UP, axis))
    normals = [np.cos(b) * UP + np.sin(b) * side, np.cos(b) * UP - np.sin(b) * side]
    pin = Surface((np.inf, pin_radius), axis)
    return ball_contacts(name, "ball-cylinders", center, radius, normals, [pin, pin])


def three_vee(ball_circle: float, radius: float, half_angle_deg: float, azimuth0: float = 90.0):
    """A Maxwell three-vee coupling: balls at 120° on a circle, grooves radial."""
    contacts = []
    for k in range(3):
        phi = np.radians(azimuth0 + 120.0 * k)
        center = ball_circle * np.array([np.cos(phi), np.sin(phi), 0.0])
        contacts += ball_vee(f"g{k + 1}", center, radius, center, half_angle_deg)
    return contacts


def kelvin(ball_circle: float, radius: float, half_angle_deg: float):
    """A Kelvin coupling: trihedral socket, a vee pointing at it, a flat."""
    centers = [
        ball_circle * np.array([np.cos(p), np.sin(p), 0.0]) for p in np.radians([90, 210, 330])
    ]
    return (
        ball_trihedral("cone", centers[0], radius, half_angle_deg)
        + ball_vee("vee", centers[1], radius, centers[1] - centers[0], half_angle_deg)
        + ball_flat("flat", centers[2], radius)
    )


def coupling_scene(
    folder: Path,
    contacts: list[tuple[np.ndarray, np.ndarray, ContactGeometry]],
    extra: dict | None = None,
    units: str = "mm",
) -> Scene:
    """Write the contacts as a real scene file (explicit supports, ``units``), load it with
    the real parser, then give each support its contact geometry (SI)."""
    scale = {"mm": 1e-3, "m": 1.0}[units]
    supports = [
        {
            "name": f"{g.coupling}.{g.index}",
            "position": [float(x) for x in p / scale],
            "normal": [float(x) for x in n],
        }
        for p, n, g in contacts
    ]
    doc = {"version": 1, "units": units, "supports": supports, **(extra or {})}
    path = folder / "coupling.kcheck.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    scene = load_scene(path)
    with_geometry = tuple(
        dataclasses.replace(s, geometry=g)
        for s, (_, _, g) in zip(scene.supports, contacts, strict=True)
    )
    return dataclasses.replace(scene, supports=with_geometry)


def with_preloads(scene: Scene, preloads) -> Scene:
    """The scene with fixed forces (``kcheck.scene.Preload``) added."""
    return dataclasses.replace(scene, preloads=tuple(preloads))


def supports_of(scene: Scene) -> tuple[Support, ...]:
    """The scene's supports (for readability in tests)."""
    return scene.supports


def tilted_kelvin(folder: Path, friction: float, sweep: dict | None = None) -> Path:
    """fixtures/kelvin (real mesh) with gravity as the only swept force: its `load:` and
    `sweep:` dropped, a 20 N spring pressing the plate down, ``friction`` and, if given, a
    ``sweep`` of its own. Returns the scene file (written next to a copy of the mesh)."""
    import shutil

    source = Path(__file__).resolve().parents[1] / "fixtures" / "kelvin"
    shutil.copy(source / "top-plate.stl", folder / "top-plate.stl")
    lines = (source / "coupling.kcheck.yaml").read_text(encoding="utf-8").splitlines()
    kept = [ln for ln in lines if not ln.startswith(("load:", "sweep:", "friction:"))]
    kept += [
        f"friction: {friction}",
        "preloads: [{name: spring, point: [0, 0, 20], force: [0, 0, -20]}]",
    ]
    if sweep is not None:
        kept.append(f"sweep: {yaml.safe_dump(sweep, default_flow_style=True).strip()}")
    path = folder / "tilted.kcheck.yaml"
    path.write_text("\n".join(kept) + "\n", encoding="utf-8")
    return path


USER_KELVIN = """\
version: 1
name: kelvin clamp plate (cone, vee, flat)
units: mm
body:
  mesh: plate.stl                  # 100 x 100 x 10 mm, z 0..10
  material: aluminium
  point_masses:                    # three 10 mm steel balls glued under the plate
    - {{name: ball-A, mass: 0.00411, point: [0, 35, -5]}}
    - {{name: ball-B, mass: 0.00411, point: [-30.311, -17.5, -5]}}
    - {{name: ball-C, mass: 0.00411, point: [30.311, -17.5, -5]}}
couplings:
  - {{name: A, type: ball-cone, ball: {{center: [0, 35, -5], radius: 5}},
     up: [0, 0, 1], half_angle: 45}}
  - {{name: B, type: ball-vee, ball: {{center: [-30.311, -17.5, -5], radius: 5}},
     groove: {{axis: [-0.5, -0.866, 0], up: [0, 0, 1], half_angle: 45}}}}
  - {{name: C, type: ball-flat, ball: {{center: [30.311, -17.5, -5], radius: 5}},
     normal: [0, 0, 1]}}
friction: {friction}
gravity: [0, 0, -9.81]
preloads:
  - {{name: spring, point: [0, 0, 10], force: [0, 0, -20]}}
"""


def user_kelvin(folder: Path, friction: float = 0.15) -> Path:
    """A new user's Kelvin clamp, as reported: a 100 x 100 x 10 mm aluminium plate (a real
    STL written by trimesh) on a cone, a vee and a flat, gravity and a 20 N spring the only
    closing forces (no `load:`, no `sweep:`). Returns the scene file."""
    import trimesh

    plate = trimesh.creation.box(extents=(100.0, 100.0, 10.0))
    plate.apply_translation((0.0, 0.0, 5.0))
    plate.export(folder / "plate.stl")
    path = folder / "kelvin.kcheck.yaml"
    path.write_text(USER_KELVIN.format(friction=friction), encoding="utf-8")
    return path
