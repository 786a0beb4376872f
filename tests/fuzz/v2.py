"""Generated scenes of today's format (kinds ``v2`` and ``v2mutation``): not rewrites of the
fixtures but designs built from every feature the scene format has grown since its first
fixtures (issue 25) — every coupling shorthand (on the body or on the base), explicit supports
beside them, friction as a number, a range and a static/kinetic pair (scene-wide, per support,
per coupling), preloads, tolerances, meshes in their own units, parts with transforms
(axis-angle and matrix), point masses, explicit mass properties (a planar I_zz alone too), a
sweep plane, torques, every length unit.

Each design is valid by construction — within every documented limit, balls touching their
pins and spheres, planar layouts in the plane — so a ``v2`` scene must get a verdict (any
verdict: there is no fixture to compare with), and a ``v2mutation`` is one to three of the
fuzzer's structural mutations of such a scene, judged by the documented contract
(:mod:`tests.fuzz.contract`) like a mutated fixture.
"""

from __future__ import annotations

import copy
import math
import random
from typing import Any

import numpy as np

from tests.fuzz.contract import UNIT_SCALE
from tests.fuzz.model import ACCEPTED, Case
from tests.fuzz.scenes import dump, encode

__all__ = ["v2_design", "v2_case", "v2_mutation_case", "MATERIALS"]

#: A few names of the material table (docs/scene-format.md).
MATERIALS = ("aluminium", "steel", "brass", "titanium", "pom", "invar", "granite")
SCENE = "design.kcheck.yaml"


def _round(x: float) -> float:
    return float(f"{x:.10g}")


def _vec(v: Any) -> list[float]:
    return [_round(float(x)) + 0.0 for x in v]


def _box_stl(lo: np.ndarray, hi: np.ndarray, transform: Any = None) -> bytes:
    """A closed box from ``lo`` to ``hi`` (file units), as binary STL; ``transform`` maps the
    box's corners into the file's coordinates."""
    import trimesh

    box = trimesh.creation.box(extents=hi - lo)
    box.apply_translation((lo + hi) / 2)
    if transform is not None:
        box.vertices = transform(np.asarray(box.vertices))
    return box.export(file_type="stl")


def _balls_stl(centres: list[np.ndarray], radius: float) -> bytes:
    import trimesh

    meshes = []
    for c in centres:
        ball = trimesh.creation.icosphere(subdivisions=2, radius=radius)
        ball.apply_translation(c)
        meshes.append(ball)
    return trimesh.util.concatenate(meshes).export(file_type="stl")


class _Design:
    """One generated scene: its data (scene units) and its files."""

    def __init__(self, rng: random.Random) -> None:
        self.rng = rng
        self.units = rng.choice(("m", "cm", "mm", "mm", "um", "in"))
        self.s = UNIT_SCALE[self.units]  # metres per scene unit
        self.files: dict[str, bytes] = {}
        self.data: dict[str, Any] = {"version": 1, "units": self.units}
        if rng.random() < 0.5:
            self.data["name"] = f"design {rng.randrange(1000)}"

    def length(self, metres: float) -> float:
        return _round(metres / self.s)

    def point(self, metres: Any) -> list[float]:
        return _vec(np.asarray(metres, dtype=float) / self.s)

    # --- friction -----------------------------------------------------------------------

    def coefficient(self) -> Any:
        rng = self.rng
        form = rng.randrange(5)
        low = _round(rng.uniform(0.0, 0.25))
        high = _round(low + rng.uniform(0.01, 0.15))
        if form == 0:
            return low
        if form == 1:
            return {"min": low, "max": high}
        kinetic = low
        static = _round(kinetic + rng.uniform(0.0, 0.1))
        if form == 2:
            return {"static": static, "kinetic": kinetic}
        if form == 3:
            return {"static": {"min": static, "max": _round(static + 0.05)}, "kinetic": kinetic}
        return {
            "static": {"min": static, "max": _round(static + 0.05)},
            "kinetic": {"min": kinetic, "max": _round(kinetic + rng.uniform(0.0, 0.05))},
        }

    # --- supports -------------------------------------------------------------------------

    def spatial(self) -> None:
        """Three balls on a circle of radius ``R``, six contacts among every shorthand."""
        rng = self.rng
        self.R = R = rng.uniform(0.01, 0.2)
        self.r = r = R * rng.uniform(0.08, 0.2)
        turn = rng.uniform(0, 2 * math.pi)
        split = rng.choice(((2, 2, 2), (3, 2, 1), (3, 2, 1), (1, 2, 3), (3, 3, 0)))
        on_base = rng.random() < 0.25  # the balls on the base, the grooves in the body
        self.data["couplings"] = []
        self.data["supports"] = []
        names = iter("abcdefghi")
        self.ball_centres = []
        for k, count in enumerate(split):
            if count == 0:
                continue
            theta = turn + 2 * math.pi * k / 3
            radial = np.array([math.cos(theta), math.sin(theta), 0.0])
            tangent = np.array([-math.sin(theta), math.cos(theta), 0.0])
            centre = R * radial
            self.ball_centres.append(centre)
            name = next(names)
            entry = self.coupling(name, count, centre, r, radial, tangent)
            if entry is None:  # one contact as an explicit support instead
                normal = np.array([0.0, 0.0, -1.0 if on_base else 1.0])
                support = {
                    "name": f"s{name}",
                    # on the body's face, where the ball touches it (kcheck checks
                    # supports against the mesh, which may leave the ball out)
                    "position": self.point(centre + (-r if on_base else r) * np.array([0, 0, 1.0])),
                    "normal": _vec(normal * rng.choice((1.0, 3.0, 0.25))),
                }
                if rng.random() < 0.3:
                    support["friction"] = self.coefficient()
                self.data["supports"].append(support)
                continue
            if on_base:
                entry["ball_on"] = "base"
            elif rng.random() < 0.2:
                entry["ball_on"] = "body"
            if rng.random() < 0.25:
                entry["friction"] = self.coefficient()
            self.data["couplings"].append(entry)
        if not self.data["supports"]:
            del self.data["supports"]
        self.top = r if not on_base else -r  # the body's side of the balls
        self.up = -1.0 if on_base else 1.0

    def coupling(
        self,
        name: str,
        count: int,
        centre: np.ndarray,
        r: float,
        radial: np.ndarray,
        tangent: np.ndarray,
    ) -> dict[str, Any] | None:
        rng = self.rng
        z = np.array([0.0, 0.0, 1.0])
        ball = {"center": self.point(centre), "radius": self.length(r)}
        base: dict[str, Any] = {"name": name, "ball": ball}
        if count == 3:
            if rng.random() < 0.5:
                entry = {
                    **base,
                    "type": "ball-trihedral",
                    "up": _vec(z * rng.choice((1.0, 2.0))),
                    "half_angle": _round(rng.uniform(40, 60)),
                    "reference": _vec(radial + 0.3 * z),
                }
            else:
                entry = {
                    **base,
                    "type": "ball-cone",
                    "up": _vec(z),
                    "half_angle": _round(rng.uniform(30, 60)),
                }
                if rng.random() < 0.5:
                    entry["reference"] = _vec(tangent)
            return entry
        if count == 2:
            kind = rng.choice(("ball-vee", "ball-cylinders", "ball-sphere"))
            phi = math.radians(rng.uniform(30, 60))  # contact angle from vertical
            if kind == "ball-vee":
                axis = radial if rng.random() < 0.7 else tangent
                return {
                    **base,
                    "type": kind,
                    "groove": {
                        "axis": _vec(axis * rng.choice((1.0, -1.0, 5.0))),
                        "up": _vec(z + rng.uniform(-0.2, 0.2) * axis),  # need not be square
                        "half_angle": _round(90 - math.degrees(phi)),
                    },
                }
            other = r * rng.uniform(0.2, 0.8)
            d = r + other
            mates = [
                centre + d * (s * math.sin(phi) * tangent - math.cos(phi) * z) for s in (1, -1)
            ]
            if kind == "ball-cylinders":
                cylinders = []
                for m in mates:
                    along = rng.uniform(-2, 2) * r
                    cylinders.append(
                        {
                            "point": self.point(m + along * radial),
                            "axis": _vec(radial),
                            "radius": self.length(other),
                        }
                    )
                return {**base, "type": kind, "cylinders": cylinders}
            return {
                **base,
                "type": kind,
                "spheres": [{"center": self.point(m), "radius": self.length(other)} for m in mates],
            }
        kind = rng.choice(("ball-flat", "ball-cylinders", "ball-sphere", "support"))
        other = r * rng.uniform(0.2, 0.8)
        if kind == "support":
            return None
        if kind == "ball-flat":
            return {**base, "type": kind, "normal": _vec(z)}
        below = centre - (r + other) * z
        if kind == "ball-cylinders":
            cylinder = {
                "point": self.point(below),
                "axis": _vec(tangent),
                "radius": self.length(other),
            }
            return {**base, "type": kind, "cylinders": [cylinder]}
        return {
            **base,
            "type": kind,
            "spheres": [{"center": self.point(below), "radius": self.length(other)}],
        }

    def planar(self) -> None:
        """A 3-2-1 style layout in the xy-plane, as supports or in-plane shorthands."""
        rng = self.rng
        W, H = rng.uniform(0.02, 0.3), rng.uniform(0.02, 0.3)
        self.R = max(W, H) / 2
        self.r = r = min(W, H) * 0.05
        contacts = [
            (np.array([W * rng.uniform(0.1, 0.4), 0, 0]), np.array([0.0, 1, 0])),
            (np.array([W * rng.uniform(0.6, 0.9), 0, 0]), np.array([0.0, 1, 0])),
            (np.array([0, H * rng.uniform(0.2, 0.8), 0]), np.array([1.0, 0, 0])),
        ]
        self.data["supports"] = []
        self.data["couplings"] = []
        for i, (point, normal) in enumerate(contacts):
            form = rng.randrange(3)
            name = f"p{i}"
            centre = point + r * normal
            if form == 0:
                support = {"name": name, "position": self.point(point), "normal": _vec(normal)}
                if rng.random() < 0.3:
                    support["friction"] = self.coefficient()
                self.data["supports"].append(support)
            elif form == 1:
                self.data["couplings"].append(
                    {
                        "name": name,
                        "type": "ball-flat",
                        "ball": {"center": self.point(centre), "radius": self.length(r)},
                        "normal": _vec(normal),
                    }
                )
            else:  # a vertical pin: its normal lies in the plane
                pin = r * rng.uniform(0.5, 2)
                self.data["couplings"].append(
                    {
                        "name": name,
                        "type": "ball-cylinders",
                        "ball": {"center": self.point(centre), "radius": self.length(r)},
                        "cylinders": [
                            {
                                "point": self.point(centre - (r + pin) * normal + [0, 0, 0.01]),
                                "axis": [0.0, 0.0, 1.0],
                                "radius": self.length(pin),
                            }
                        ],
                    }
                )
        for key in ("supports", "couplings"):
            if not self.data[key]:
                del self.data[key]
        self.W, self.H = W, H
        self.top, self.up = 0.0, 1.0
        self.ball_centres = []

    # --- the body -------------------------------------------------------------------------

    def body(self, planar: bool) -> None:
        rng = self.rng
        R = self.R
        if planar:
            lo = np.array([0.0, 0.0, -0.01])
            hi = np.array([self.W, self.H, 0.01])
        else:
            t = R * rng.uniform(0.1, 0.4)
            z0 = self.top if self.up > 0 else self.top - t
            lo = np.array([-1.2 * R, -1.2 * R, z0])
            hi = np.array([1.2 * R, 1.2 * R, z0 + t])
        self.lo, self.hi = lo, hi
        kind = rng.choice(("mesh", "parts", "parts", "explicit"))
        body: dict[str, Any] = {}
        if kind == "mesh":
            unit = rng.choice((self.units, self.units, "mm", "m"))
            if unit != self.units:  # a mesh in another unit than the scene: give it as a part
                kind = "parts"
            else:
                self.files["body.stl"] = _box_stl(lo / self.s, hi / self.s)
                body = {"mesh": "body.stl", **self.matter()}
                if rng.random() < 0.2:
                    body["repair"] = False
        if kind == "parts":
            body = {"parts": self.parts(lo, hi, planar)}
        if kind == "explicit" or rng.random() < 0.1:  # explicit values (winning over meshes)
            mass = rng.uniform(0.05, 20)
            size = hi - lo
            moments = (
                mass
                * np.array(
                    [
                        size[1] ** 2 + size[2] ** 2,
                        size[0] ** 2 + size[2] ** 2,
                        size[0] ** 2 + size[1] ** 2,
                    ]
                )
                / 12
            )
            body["mass"] = _round(mass)
            body["center_of_mass"] = self.point((lo + hi) / 2)
            if planar and rng.random() < 0.5:
                body["inertia"] = _round(moments[2])
            else:
                body["inertia"] = [_vec(row) for row in np.diag(moments)]
            if rng.random() < 0.2 and "parts" not in body and "mesh" not in body:
                body["material"] = rng.choice(MATERIALS)  # unused without a mesh, but valid
        if rng.random() < 0.4:
            body["point_masses"] = [
                {
                    "name": f"m{i}",
                    "mass": _round(rng.uniform(0.001, 0.5)),
                    "point": self.point(
                        lo + (hi - lo) * np.array([rng.random() for _ in range(3)])
                    ),
                }
                for i in range(rng.randint(1, 2))
            ]
        self.data["body"] = body

    def matter(self) -> dict[str, Any]:
        if self.rng.random() < 0.6:
            return {"material": self.rng.choice(MATERIALS)}
        return {"density": _round(self.rng.uniform(800, 9000))}

    def parts(self, lo: np.ndarray, hi: np.ndarray, planar: bool) -> list[dict[str, Any]]:
        """The plate (maybe turned over in its file, maybe in its own unit) and, for a
        spatial design whose balls are on the body, the balls as a second part."""
        rng = self.rng
        unit = rng.choice(("m", "cm", "mm", "in", self.units))
        scale = UNIT_SCALE[unit]
        part: dict[str, Any] = {"mesh": "plate.stl", **self.matter()}
        if unit != self.units or rng.random() < 0.3:
            part["units"] = unit
        form = rng.randrange(4)
        rotation = np.eye(3)
        translation = np.zeros(3)
        if form == 1:  # drawn upside down: turned over about x
            rotation = np.diag([1.0, -1.0, -1.0])
            part["transform"] = {"rotate": {"axis": [1.0, 0.0, 0.0], "angle": 180.0}}
        elif form == 2:  # a matrix, a quarter turn about z, and drawn 5 mm off
            rotation = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
            translation = np.array([0.0, 0.0, 0.005])
            part["transform"] = {
                "rotate": [_vec(row) for row in rotation],
                "translate": self.point(translation),
            }
        elif form == 3:
            angle = rng.uniform(-180, 180)
            axis = np.array([rng.uniform(-1, 1) for _ in range(3)]) + [0, 0, 2]
            a = axis / np.linalg.norm(axis)
            k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
            t = math.radians(angle)
            rotation = np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)
            part["transform"] = {"rotate": {"axis": _vec(axis), "angle": _round(angle)}}
        # the file holds the box where the transform brings it to lo..hi: x = R (s x_f) + t
        self.files["plate.stl"] = _box_stl(lo, hi, lambda v: (v - translation) @ rotation / scale)
        parts = [part]
        if self.ball_centres and self.up > 0 and rng.random() < 0.6:
            ball_unit = rng.choice(("mm", "m", self.units))
            self.files["balls.stl"] = _balls_stl(
                [c / UNIT_SCALE[ball_unit] for c in self.ball_centres],
                self.r / UNIT_SCALE[ball_unit],
            )
            balls: dict[str, Any] = {"mesh": "balls.stl", "material": "steel"}
            if ball_unit != self.units:
                balls["units"] = ball_unit
            parts.append(balls)
        return parts

    # --- forces and the rest ----------------------------------------------------------------

    def forces(self, planar: bool) -> None:
        rng = self.rng
        data = self.data
        centre = (self.lo + self.hi) / 2
        if rng.random() < 0.7:
            data["friction"] = self.coefficient()
        if rng.random() < 0.8:
            g = np.array([0.0, -9.81, 0.0]) if planar else np.array([0.0, 0.0, -9.81 * self.up])
            if rng.random() < 0.2:
                g = g + np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), 0.0 if planar else 0.0])
            data["gravity"] = _vec(g)
        if rng.random() < 0.8 or "gravity" not in data:
            load: dict[str, Any] = {"magnitude": _round(rng.uniform(0.5, 100))}
            if rng.random() < 0.7:  # the body's centre, or above (below) its middle
                load["point"] = self.point(centre if planar else [0.0, 0.0, centre[2]])
            if planar:
                if rng.random() < 0.5:
                    load["angle"] = _round(rng.uniform(180, 270))
                elif rng.random() < 0.5:
                    load["direction"] = _vec([-rng.random(), -rng.random() - 0.1, 0])
                if rng.random() < 0.2:
                    load["torque"] = [0.0, 0.0, _round(rng.uniform(-0.01, 0.01))]
            else:
                if rng.random() < 0.6:
                    load["direction"] = _vec(
                        [rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), -self.up]
                    )
                if rng.random() < 0.2:
                    load["torque"] = _vec([rng.uniform(-0.01, 0.01) for _ in range(3)])
            data["load"] = load
        if rng.random() < 0.5:
            data["preloads"] = []
            for i in range(rng.randint(1, 3)):
                force = (
                    [-rng.uniform(0.1, 20), -rng.uniform(0.1, 20), rng.uniform(-5, 5)]
                    if planar
                    else [rng.uniform(-1, 1), rng.uniform(-1, 1), -self.up * rng.uniform(1, 40)]
                )
                spot = self.lo + (self.hi - self.lo) * np.array([rng.random() for _ in range(3)])
                data["preloads"].append(
                    {"name": f"spring {i}", "point": self.point(spot), "force": _vec(force)}
                )
        if not planar and rng.random() < 0.3:
            data["sweep"] = {"normal": [0.0, -1.0, 0.0], "zero": [0.0, 0.0, -self.up]}
        elif planar and rng.random() < 0.2:
            data["sweep"] = {"normal": [0.0, 0.0, 1.0], "zero": _vec([0.0, -1.0, 0.0])}
        if rng.random() < 0.4:
            data["tolerances"] = {
                "position": self.length(rng.uniform(0, 1e-4) * self.R / 0.05),
                "normal": _round(rng.uniform(0, 1)),
                "load_direction": _round(rng.uniform(0, 3)),
            }
            if rng.random() < 0.5:
                del data["tolerances"][rng.choice(("position", "normal", "load_direction"))]
            data.setdefault("checks", {})["tolerances"] = {
                "samples": rng.choice((200, 500, 1000)),
                "seed": rng.randrange(100),
            }
        if rng.random() < 0.2:
            data.setdefault("checks", {})["maxwell"] = {"min_cos": _round(rng.uniform(0.3, 0.9))}
        if rng.random() < 0.1:
            data.setdefault("checks", {})["jamming"] = {"severity": "warning"}


def v2_design(seed: int, index: int, kind: str = "v2") -> tuple[dict[str, Any], dict[str, bytes]]:
    """A valid design of today's format: its data and its files (meshes)."""
    rng = random.Random(f"{seed}:{kind}:{index}")
    design = _Design(rng)
    planar = rng.random() < 0.2
    if planar:
        design.planar()
    else:
        design.spatial()
    design.body(planar)
    design.forces(planar)
    return design.data, design.files


def v2_case(seed: int, index: int) -> Case:
    """A generated design that must get a verdict (any: nothing to compare it with)."""
    data, files = v2_design(seed, index)
    rng = random.Random(f"{seed}:v2-text:{index}")
    raw, encoding = (
        encode(dump(data, rng), rng) if rng.random() < 0.3 else (dump(data).encode(), "")
    )
    what = f"{len(data.get('couplings', []))} couplings, body {sorted(data['body'])}"
    return Case(
        "v2",
        seed,
        index,
        what + (f"; {encoding}" if encoding else ""),
        {**files, SCENE: raw},
        (SCENE,),
        {SCENE: ACCEPTED},
    )


def v2_mutation_case(seed: int, index: int) -> Case:
    """A generated design with one to three structural mutations (mutate.py's), judged by
    the documented contract."""
    from tests.fuzz.mutate import mutate

    data, files = v2_design(seed, index, "v2mutation")
    rng = random.Random(f"{seed}:v2mutation-ops:{index}")
    data = copy.deepcopy(data)
    done, expect = mutate(data, rng)
    return Case(
        "v2mutation",
        seed,
        index,
        "; ".join(done),
        {**files, SCENE: dump(data).encode("utf-8", "surrogatepass")},
        (SCENE,),
        {SCENE: expect},
    )
