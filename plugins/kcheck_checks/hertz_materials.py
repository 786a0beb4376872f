"""Options of the ``hertz`` check and the contacts of a scene with their materials.

Every ball and every seat (groove flank, flat, pin, ...) gets a material: the defaults
``ball_material`` and ``seat_material``, overridden per coupling name, from the built-in table
(:mod:`kcheck.body.elastic`) or from materials defined in the options themselves.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydantic import Field, model_validator

from kcheck.body.elastic import MATERIALS, Material, material
from kcheck.numerics.margins import MARGINAL_UTILISATION
from kcheck.plugin import Options
from kcheck.scene import Scene

__all__ = ["MaterialModel", "CouplingMaterials", "HertzOptions", "Contacts", "contacts_of"]

Vec3 = list[float]


class MaterialModel(Options):
    """A material given in the options (supplier data)."""

    youngs_modulus_gpa: float = Field(gt=0, description="Young's modulus, GPa")
    poisson: float = Field(ge=0, lt=0.5, description="Poisson's ratio")
    allowable_pressure_mpa: float = Field(gt=0, description="Allowable Hertz peak pressure, MPa")


class CouplingMaterials(Options):
    """Materials of one coupling's ball and seat (groove, flat, pins, ...)."""

    ball: str | None = None
    seat: str | None = None


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
    ball_material: str = Field("52100", description="Material of every ball (see docs)")
    seat_material: str = Field("52100", description="Material of every seat (groove, flat, ...)")
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
    error_point: Vec3 | None = Field(
        None,
        min_length=3,
        max_length=3,
        description="Body point whose error motion is reported, scene units (default: the "
        "supports' centroid)",
    )

    @model_validator(mode="after")
    def _known_materials(self) -> HertzOptions:
        names = [self.ball_material, self.seat_material]
        names += [n for c in self.couplings.values() for n in (c.ball, c.seat) if n is not None]
        unknown = sorted({n for n in names if n not in self.materials and material(n) is None})
        if unknown:
            raise ValueError(
                f"unknown material(s) {', '.join(unknown)}; known: {', '.join(MATERIALS)} "
                "(or define them under `materials`)"
            )
        return self

    def lookup(self, name: str) -> Material:
        """A material by name: the options' own first, then the built-in table."""
        if name in self.materials:
            m = self.materials[name]
            return Material(
                name,
                m.youngs_modulus_gpa * 1e9,
                m.poisson,
                m.allowable_pressure_mpa * 1e6,
                "given in the check options",
                "scene file",
            )
        found = material(name)
        assert found is not None  # validated
        return found

    @property
    def disturbed(self) -> bool:
        """Whether a disturbing load is given."""
        return any(self.disturbing_force) or any(self.disturbing_torque)


@dataclass(frozen=True)
class Contacts:
    """Per contact: the curvature sums, the major axis and both materials."""

    sum_a: np.ndarray
    sum_b: np.ndarray
    major_axis: np.ndarray
    ball: tuple[Material, ...]
    seat: tuple[Material, ...]
    modulus: np.ndarray

    @property
    def allowable(self) -> np.ndarray:
        """Allowable peak pressure (Pa) of each contact: the weaker of its two materials."""
        pairs = zip(self.ball, self.seat, strict=True)
        return np.array([min(b.allowable_pressure, s.allowable_pressure) for b, s in pairs])

    def weaker(self, i: int) -> Material:
        """The material of contact ``i`` with the lower allowable pressure."""
        b, s = self.ball[i], self.seat[i]
        return b if b.allowable_pressure <= s.allowable_pressure else s


def contacts_of(scene: Scene, options: HertzOptions) -> Contacts:
    """Curvature sums, major axes and materials of every contact (supports with geometry)."""
    from kcheck.mechanics.hertz import contact_modulus, curvature_sums, curvature_tensor

    normals = np.array([s.normal for s in scene.supports])
    tensors = np.zeros((len(normals), 3, 3))
    balls, seats = [], []
    for i, s in enumerate(scene.supports):
        g = s.geometry
        assert g is not None
        for surface in (g.body, g.base):
            radii = np.asarray(surface.radii, float)
            tensors[i] += curvature_tensor(radii, surface.direction, normals[i])
        chosen = options.couplings.get(g.coupling, CouplingMaterials())
        balls.append(options.lookup(chosen.ball or options.ball_material))
        seats.append(options.lookup(chosen.seat or options.seat_material))
    sum_a, sum_b, axis = curvature_sums(tensors, normals)
    modulus = contact_modulus(
        [m.youngs_modulus for m in balls],
        [m.poisson for m in balls],
        [m.youngs_modulus for m in seats],
        [m.poisson for m in seats],
    )
    return Contacts(sum_a, sum_b, axis, tuple(balls), tuple(seats), modulus)
