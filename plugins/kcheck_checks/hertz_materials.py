"""Options of the ``hertz`` check and the contacts of a scene with their materials.

Every ball and every seat (groove flank, flat, pin, ...) takes its material from the scene:
the coupling's (or explicit support's ``contact``) ``ball_material``/``seat_material``, then the
options per coupling name, then the body's ``material`` for a seat cut into the body, then the
options' global ``ball_material``/``seat_material``. Names come from the one table
(:mod:`kcheck.scene.materials`) or from materials defined in the options. A side with no
material, or one without elastic constants, is reported, never assumed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from kcheck.body.elastic import Material, elastic_names, material
from kcheck.numerics.margins import MARGINAL_UTILISATION
from kcheck.plugin import Field, Options, model_validator
from kcheck.records import dataclass
from kcheck.scene import Scene
from kcheck.scene.yamlio import format_path

if TYPE_CHECKING:  # read by the options' pydantic model when options are given
    from kcheck.scene.models import MaterialName

__all__ = [
    "MaterialModel",
    "CouplingMaterials",
    "HertzOptions",
    "Contacts",
    "Unknown",
    "contacts_of",
    "unknown_hint",
]

Vec3 = list[float]


class MaterialModel(Options):
    """A material given in the options (supplier data)."""

    youngs_modulus_gpa: float = Field(gt=0, description="Young's modulus, GPa")
    poisson: float = Field(ge=0, lt=0.5, description="Poisson's ratio")
    allowable_pressure_mpa: float = Field(gt=0, description="Allowable Hertz peak pressure, MPa")
    thermal_expansion_per_k: float | None = Field(
        None, description="Thermal expansion coefficient, 1/K (for the thermal pose shift)"
    )


class CouplingMaterials(Options):
    """Materials of one coupling's ball and seat (groove, flat, pins, ...)."""

    ball: MaterialName | None = None
    seat: MaterialName | None = None


class HertzOptions(Options):
    """Options of the ``hertz`` check."""

    safety_factor: float = Field(
        1.0, gt=0, description="Every peak pressure must stay below allowable / safety_factor"
    )
    marginal_utilisation: float = Field(
        MARGINAL_UTILISATION,
        gt=0,
        le=1,
        description="A pass whose largest utilisation (peak pressure over allowable / "
        "safety_factor) is above this is marginal (1: no marginal band)",
    )
    ball_material: MaterialName | None = Field(
        None, description="Material of every ball the scene gives none for (docs/materials.md)"
    )
    seat_material: MaterialName | None = Field(
        None,
        description="Material of every seat (groove, flat, ...) the scene gives none for and "
        "that is not cut into the body",
    )
    # pydantic copies mutable defaults per instance
    couplings: dict[str, CouplingMaterials] = Field(
        {}, description="Materials per coupling name, overriding the above"
    )
    materials: dict[str, MaterialModel] = Field({}, description="Custom materials by name")
    disturbing_force: Vec3 = Field([0.0, 0.0, 0.0], min_length=3, max_length=3, description="N")
    disturbing_torque: Vec3 = Field([0.0, 0.0, 0.0], min_length=3, max_length=3, description="N m")
    disturbing_point: Vec3 | None = Field(
        None,
        min_length=3,
        max_length=3,
        description="Where it acts, scene units (default: error_point)",
    )
    temperature_change: float = Field(
        0.0,
        description="Uniform temperature change, K, for the thermal pose shift (0: none)",
    )
    base_material: MaterialName | None = Field(
        None, description="The base's material, for its thermal expansion"
    )
    body_material: MaterialName | None = Field(
        None,
        description="The body's material for its thermal expansion (default: the body's "
        "`material`)",
    )
    error_point: Vec3 | None = Field(
        None,
        min_length=3,
        max_length=3,
        description="Body point whose error motion is reported, scene units (default: the "
        "supports' centroid)",
    )

    @model_validator(mode="after")
    def _known_materials(self) -> HertzOptions:
        names = [self.ball_material, self.seat_material, self.base_material, self.body_material]
        names += [n for c in self.couplings.values() for n in (c.ball, c.seat)]
        unknown = sorted(
            {n for n in names if n is not None and n not in self.materials and material(n) is None}
        )
        if unknown:
            raise ValueError(
                f"unknown material(s) {', '.join(unknown)}; known: {elastic_names()} "
                "(or define them under `materials`)"
            )
        return self

    def lookup(self, name: str) -> Material:
        """A material by name: the options' own first, then the table (which may give one
        without elastic constants: ``Material.elastic``)."""
        if name in self.materials:
            m = self.materials[name]
            return Material(
                name,
                None,
                m.youngs_modulus_gpa * 1e9,
                m.poisson,
                m.allowable_pressure_mpa * 1e6,
                thermal_expansion=m.thermal_expansion_per_k,
                basis="given in the check options",
                source="scene file (checks: hertz: materials)",
            )
        found = material(name)
        assert found is not None  # validated
        return found

    @property
    def disturbed(self) -> bool:
        """Whether a disturbing load is given."""
        return any(self.disturbing_force) or any(self.disturbing_torque)


@dataclass(frozen=True)
class Unknown:
    """A contact side whose material is not known well enough: support index, ``side``
    (``ball`` or ``seat``), and why (the name without elastic constants, or None: not given)."""

    index: int
    side: str
    name: str | None


@dataclass(frozen=True)
class Contacts:
    """Per contact: the curvature sums, the major axis, both materials and where each came
    from (``ball_from``, ``seat_from``: the scene field or option that named it)."""

    sum_a: np.ndarray
    sum_b: np.ndarray
    major_axis: np.ndarray
    ball: tuple[Material, ...]
    seat: tuple[Material, ...]
    modulus: np.ndarray
    ball_from: tuple[str, ...] = ()
    seat_from: tuple[str, ...] = ()

    @property
    def allowable(self) -> np.ndarray:
        """Allowable peak pressure (Pa) of each contact: the weaker of its two materials."""
        return np.array([self.weaker(i).allowable_pressure for i in range(len(self.ball))])

    def weaker(self, i: int) -> Material:
        """The material of contact ``i`` with the lower allowable pressure."""
        b, s = self.ball[i], self.seat[i]
        assert b.allowable_pressure is not None and s.allowable_pressure is not None
        return b if b.allowable_pressure <= s.allowable_pressure else s


def _name(scene: Scene, i: int) -> str:
    g = scene.supports[i].contact_geometry
    assert g is not None
    return g.coupling


def _choose(scene: Scene, options: HertzOptions, i: int, side: str) -> tuple[str | None, str]:
    """The material name of one side of contact ``i`` and where it came from; the scene's
    own field first, then the options per coupling, the body's material for a seat cut into
    the body, and the options' global default."""
    s = scene.supports[i]
    g = s.contact_geometry
    assert g is not None
    own = g.ball_material if side == "ball" else g.seat_material
    field = format_path((*scene.support_field(i), *(("contact",) if s.geometry is None else ())))
    if own is not None:
        return own, f"{field}.{side}_material"
    chosen = options.couplings.get(g.coupling, CouplingMaterials())
    per = chosen.ball if side == "ball" else chosen.seat
    if per is not None:
        return per, f"checks.hertz.couplings.{g.coupling}.{side}"
    if side == "seat" and g.seat_on == "body" and scene.body is not None:
        if len(scene.body.materials) == 1:
            return scene.body.materials[0], "the body's material"
    default = options.ball_material if side == "ball" else options.seat_material
    if default is not None:
        return default, f"checks.hertz.{side}_material"
    return None, ""


def unknown_hint(scene: Scene, u: Unknown) -> str:
    """How to give the material of an unknown contact side."""
    s = scene.supports[u.index]
    g = s.contact_geometry
    assert g is not None
    if u.name is not None:
        return (
            f"{u.name} has no elastic constants in kcheck's table: name a grade (one of "
            f"{elastic_names()}) or define `{u.name}` under checks: hertz: materials"
        )
    where = format_path(scene.support_field(u.index))
    if s.geometry is None:
        own = f"`{u.side}_material` in {where}.contact"
    else:
        own = f"`{u.side}_material` on coupling {g.coupling} ({where})"
    body = ""
    if u.side == "seat" and g.seat_on == "body":
        several = scene.body is not None and len(scene.body.materials) > 1
        body = (
            ", the body's `material` (its parts are of several materials, so say which)"
            if several
            else ", the body's `material` (the seat is cut into the body)"
        )
    return f"set {own}{body}, or `{u.side}_material` under checks: hertz for every {u.side}"


def contacts_of(scene: Scene, options: HertzOptions) -> Contacts | list[Unknown]:
    """Curvature sums, major axes and materials of every contact (supports with geometry),
    or the contact sides whose material is unknown."""
    from kcheck.mechanics.hertz import contact_modulus, curvature_sums, curvature_tensor

    normals = np.array([s.normal for s in scene.supports])
    tensors = np.zeros((len(normals), 3, 3))
    balls: list[Material] = []
    seats: list[Material] = []
    ball_from: list[str] = []
    seat_from: list[str] = []
    unknown: list[Unknown] = []
    for i, s in enumerate(scene.supports):
        g = s.contact_geometry
        assert g is not None
        for surface in (g.body, g.base):
            radii = np.asarray(surface.radii, float)
            tensors[i] += curvature_tensor(radii, surface.direction, normals[i])
        for side, found, origin in (("ball", balls, ball_from), ("seat", seats, seat_from)):
            name, where = _choose(scene, options, i, side)
            m = None if name is None else options.lookup(name)
            if m is None or not m.elastic:
                unknown.append(Unknown(i, side, name))
            else:
                found.append(m)
                origin.append(where)
    if unknown:
        return unknown
    sum_a, sum_b, axis = curvature_sums(tensors, normals)
    # every material here is elastic (checked above): no None among the values
    modulus = contact_modulus(
        np.array([m.youngs_modulus for m in balls], float),
        np.array([m.poisson for m in balls], float),
        np.array([m.youngs_modulus for m in seats], float),
        np.array([m.poisson for m in seats], float),
    )
    return Contacts(
        sum_a, sum_b, axis, tuple(balls), tuple(seats), modulus, tuple(ball_from), tuple(seat_from)
    )
