"""The scene file's fields (version 1) as pydantic models: types, static ranges, and the JSON
Schema. Unit-dependent ranges (coordinates, radii) and relations between fields are checked
after conversion to SI, in :mod:`kcheck.scene.load`."""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Discriminator,
    Field,
    Tag,
    WithJsonSchema,
    field_validator,
)

from kcheck.scene.accept import COUPLING_TYPES
from kcheck.scene.accept import coefficient_kind as _coefficient_kind
from kcheck.scene.accept import friction_kind as _friction_kind
from kcheck.scene.limits import LIMITS

__all__ = [
    "UNITS",
    "COUPLING_TYPES",
    "SceneModel",
    "BodyModel",
    "PartModel",
    "SupportModel",
    "ContactModel",
    "MaterialName",
    "CouplingModel",
    "TransformModel",
    "AxisAngleModel",
    "LoadModel",
    "SweepModel",
    "PreloadModel",
    "PointMassModel",
    "FrictionRangeModel",
    "FrictionPairModel",
    "FrictionValue",
    "TolerancesModel",
]

UNITS = ("m", "cm", "mm", "um", "in")
Units = Literal["m", "cm", "mm", "um", "in"]

Vec3 = Annotated[list[float], Field(min_length=3, max_length=3)]
Matrix3 = Annotated[list[Vec3], Field(min_length=3, max_length=3)]
Name = Annotated[str, Field(min_length=1, max_length=200)]


def _material_name(value: Any) -> Any:
    # YAML reads an unquoted 52100 as a number; a material's name is text either way.
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    return value


#: A name of the material table (docs/materials.md); numbers such as 52100 may go unquoted.
MaterialName = Annotated[
    str,
    BeforeValidator(_material_name),
    Field(min_length=1, max_length=100),
    WithJsonSchema({"anyOf": [{"type": "string"}, {"type": "integer"}]}),
]


def bounded(key: str, default: Any = ..., **kwargs: Any) -> Any:
    """A pydantic Field limited to the range ``LIMITS[key]``."""
    r = LIMITS[key]
    if r.open:
        return Field(default, gt=r.low, lt=r.high, **kwargs)
    return Field(default, ge=r.low, le=r.high, **kwargs)


class _Model(BaseModel):
    # Strict: "10" is not 10. No inf/nan anywhere. Unknown keys are errors.
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)


class FrictionRangeModel(_Model):
    """An uncertain coefficient: every value from `min` to `max` may occur."""

    TAGGED: ClassVar[bool] = True  # a branch chosen by its keys (validate.py)
    min: float = bounded("friction", description="The lowest coefficient")
    max: float = bounded("friction", description="The highest coefficient")


Coefficient = Annotated[
    Annotated[float, bounded("friction"), Tag("float")]
    | Annotated[FrictionRangeModel, Tag("FrictionRangeModel")],
    Discriminator(_coefficient_kind),
]


class FrictionPairModel(_Model):
    """Static and kinetic coefficients, static at least kinetic; each a number or a range."""

    TAGGED: ClassVar[bool] = True
    static: Coefficient = Field(description="Friction before motion starts (holding, jamming)")
    kinetic: Coefficient = Field(description="Friction while sliding (the dynamics)")


#: A Coulomb coefficient: a number, a range ``{min, max}`` or ``{static, kinetic}``.
FrictionValue = Annotated[
    Annotated[float, bounded("friction"), Tag("float")]
    | Annotated[FrictionRangeModel, Tag("FrictionRangeModel")]
    | Annotated[FrictionPairModel, Tag("FrictionPairModel")],
    Discriminator(_friction_kind),
]


class AxisAngleModel(_Model):
    """A rotation by ``angle`` degrees about ``axis`` (right-hand rule)."""

    axis: Vec3 = Field(description="Rotation axis; any length")
    angle: float = bounded("angle", description="deg, counter-clockwise about the axis")


class TransformModel(_Model):
    """Places a part in the scene: rotate about the file's origin, then translate."""

    translate: Vec3 | None = Field(None, description="In the scene's units")
    rotate: AxisAngleModel | Matrix3 | None = Field(
        None,
        description="Axis-angle in degrees, or a 3x3 rotation matrix (columns: the "
        "part's axes in scene coordinates)",
    )


class PartModel(_Model):
    """One mesh of a multi-part body."""

    mesh: str = Field(
        description="Mesh file, relative to the scene file; any format trimesh "
        "loads, or STEP (.step/.stp) with the `step` extra"
    )
    material: MaterialName | None = Field(
        None, description="Name from the material table (docs/materials.md)"
    )
    density: float | None = bounded("density", None, description="kg/m^3")
    units: Units | None = Field(
        None,
        description="Length unit of the mesh file (default: the "
        "scene's); STEP files declare their own",
    )
    transform: TransformModel | None = None
    repair: bool = Field(False, description="Merge vertices, fix winding, fill small holes")


class PointMassModel(_Model):
    """A bought part that is in no mesh (a ball, a magnet, a motor), as a point."""

    name: Name
    mass: float = Field(gt=0, description="kg")
    point: Vec3 = Field(description="Its centre of mass, scene units")


class BodyModel(_Model):
    """The moving body: a mesh (or parts) with a material, or explicit mass properties."""

    mesh: str | None = Field(None, description="Mesh file, relative to the scene file")
    material: MaterialName | None = Field(
        None, description="Name from the material table (docs/materials.md)"
    )
    density: float | None = bounded("density", None, description="kg/m^3")
    repair: bool = Field(False, description="Merge vertices, fix winding, fill small holes")
    parts: list[PartModel] | None = Field(
        None, min_length=1, max_length=1000, description="Instead of `mesh`"
    )
    point_masses: list[PointMassModel] = Field(default_factory=list, max_length=1000)
    mass: float | None = Field(None, gt=0, description="kg; with center_of_mass and inertia")
    center_of_mass: Vec3 | None = Field(None, description="In the scene's units")
    inertia: Matrix3 | float | None = Field(
        None,
        description="kg m^2 about the centre of mass, 3x3; a planar scene may give I_zz alone",
    )


class ContactModel(_Model):
    """The local shape at an explicit support, for `hertz`: a ball (any convex sphere: a
    ball-ended pin, a ball) on a seat (a flat face, a pin, a groove of radius)."""

    ball_radius: float = Field(gt=0, description="Scene units")
    ball_radii: Annotated[list[float], Field(min_length=2, max_length=2)] | None = Field(
        None, description="A canoe ball's two principal radii (default: ball_radius both ways)"
    )
    ball_direction: Vec3 | None = Field(
        None, description="Along the first ball radius (needed when the two differ)"
    )
    seat_radii: Annotated[list[float | None], Field(min_length=2, max_length=2)] | None = Field(
        None,
        description="The seat's two principal radii, scene units: positive convex (a pin), "
        "negative concave (a groove), null flat; default: flat",
    )
    seat_direction: Vec3 | None = Field(
        None, description="Along the seat's first radius (needed when the two differ)"
    )
    ball_on: Literal["body", "base"] = Field(
        "base", description="Which side carries the ball; the seat is on the other"
    )
    ball_material: MaterialName | None = Field(None, description="The ball's material")
    seat_material: MaterialName | None = Field(
        None, description="The seat's material (default: the body's, for a seat on the body)"
    )


class SupportModel(_Model):
    """One point support."""

    name: Name
    position: Vec3 = Field(description="Contact point on the body, scene units")
    normal: Vec3 = Field(description="Direction the support pushes the body; any length")
    friction: FrictionValue | None = Field(
        None, description="Coulomb coefficient: a number, {min, max} or {static, kinetic}"
    )
    contact: ContactModel | None = Field(
        None, description="Local contact radii and materials, for the `hertz` check"
    )


class BallModel(_Model):
    """A ball (or the spherical end of a pin): centre and radius in scene units; a canoe ball
    also gives its contact surface's two principal radii."""

    center: Vec3
    radius: float = Field(gt=0)
    surface_radii: Annotated[list[float], Field(min_length=2, max_length=2)] | None = Field(
        None,
        description="A canoe ball: the contact surface's principal radii, scene units "
        "(default: `radius` both ways); `radius` still places the contacts",
    )
    surface_direction: Vec3 | None = Field(
        None, description="Along the first surface radius (needed when the two differ)"
    )


class GrooveModel(_Model):
    """A V-groove: its axis, the direction out of it, and the flank normals' angle to `up`."""

    axis: Vec3 = Field(description="Along the groove; any length")
    up: Vec3 = Field(description="Out of the groove, towards the ball; any length")
    half_angle: float = bounded("half_angle", description="deg between each flank normal and up")
    radius: float | None = Field(
        None,
        gt=0,
        description="Flanks of this radius across the groove (a gothic arch or a conformal "
        "groove; larger than the ball's), scene units; default flat flanks",
    )


class CylinderModel(_Model):
    """A cylinder (dowel pin, rod, screw shank): a point on its axis, the axis, radius."""

    point: Vec3
    axis: Vec3
    radius: float = Field(gt=0)


class SphereModel(_Model):
    """A sphere (a ball, a screw head) the ball rests on."""

    center: Vec3
    radius: float = Field(gt=0)


class _Coupling(_Model):
    name: Name = Field(description="Its contacts are named `<name>.1`, `<name>.2`, ...")
    ball: BallModel
    ball_on: Literal["body", "base"] = Field(
        "body", description="Which side carries the ball; `base` flips every normal"
    )
    friction: FrictionValue | None = Field(
        None, description="For its contacts: a number, {min, max} or {static, kinetic}"
    )
    ball_material: MaterialName | None = Field(None, description="The ball's material")
    seat_material: MaterialName | None = Field(
        None,
        description="The groove's, flat's, cylinders' or spheres' material (default: the "
        "body's, when they are cut into the body: `ball_on: base`)",
    )


class BallVeeModel(_Coupling):
    """A ball in a V-groove: 2 contacts."""

    type: Literal["ball-vee"]
    groove: GrooveModel


class BallCylindersModel(_Coupling):
    """A ball on cylinders (a pair of dowel pins): 1 contact per cylinder."""

    type: Literal["ball-cylinders"]
    cylinders: list[CylinderModel] = Field(min_length=1, max_length=3)


class BallSphereModel(_Coupling):
    """A ball on spheres (balls, screw heads): 1 contact per sphere."""

    type: Literal["ball-sphere"]
    spheres: list[SphereModel] = Field(min_length=1, max_length=3)


class BallTrihedralModel(_Coupling):
    """A ball in a trihedral socket (three flat flanks): 3 contacts."""

    type: Literal["ball-trihedral"]
    up: Vec3
    half_angle: float = bounded("half_angle", description="deg between each flank normal and up")
    reference: Vec3 = Field(description="Direction from the ball centre to the first flank")


class BallConeModel(_Coupling):
    """A ball in a conical seat: a line contact, modelled as 3 points 120 deg apart."""

    type: Literal["ball-cone"]
    up: Vec3
    half_angle: float = bounded("half_angle", description="deg between the cone's normal and up")
    reference: Vec3 | None = Field(None, description="Direction to the first point")


class BallFlatModel(_Coupling):
    """A ball on a flat: 1 contact."""

    type: Literal["ball-flat"]
    normal: Vec3 = Field(description="The flat's normal, towards the ball centre")


CouplingModel = Annotated[
    BallVeeModel
    | BallCylindersModel
    | BallSphereModel
    | BallTrihedralModel
    | BallConeModel
    | BallFlatModel,
    Field(discriminator="type"),
]


class LoadModel(_Model):
    """The closing force (and optional torque)."""

    point: Vec3 | None = Field(None, description="Attachment point; default the centre of mass")
    magnitude: float = bounded("force", description="N")
    direction: Vec3 | None = Field(None, description="The design's direction; any length")
    angle: float | None = bounded(
        "angle", None, description="The design's direction, deg in the sweep plane"
    )
    torque: Vec3 | None = Field(None, description="N m")


class PreloadModel(_Model):
    """A fixed force on the body (spring, magnet), acting like gravity."""

    name: Name
    point: Vec3 = Field(description="Where it acts, scene units")
    force: Vec3 = Field(description="N")


class SweepModel(_Model):
    """The plane in which force angles are swept and reported."""

    normal: Vec3 = Field(default_factory=lambda: [0.0, 0.0, 1.0])
    zero: Vec3 = Field(default_factory=lambda: [1.0, 0.0, 0.0], description="Angle 0")


class TolerancesModel(_Model):
    """How far the made coupling may differ from the scene (the `tolerances` check)."""

    position: float = Field(
        0.0, ge=0, description="± every coordinate of every support position, scene units"
    )
    normal: float = bounded(
        "tolerance_angle", 0.0, description="± tilt of every support normal, deg"
    )
    load_direction: float = bounded(
        "tolerance_angle", 0.0, description="± tilt of the load's design direction, deg"
    )


class SceneModel(_Model):
    """A kcheck scene, version 1."""

    version: Literal[1]
    name: str | None = Field(None, max_length=200)
    units: Units = "m"
    body: BodyModel | None = None
    supports: list[SupportModel] = Field(default_factory=list, max_length=6)
    couplings: list[CouplingModel] = Field(
        default_factory=list, max_length=6, description="Shorthands expanded into supports"
    )
    friction: FrictionValue = Field(
        0.0,
        description="Coulomb coefficient of every support: a number, a range {min, max}, or "
        "{static, kinetic} (each a number or a range)",
    )
    gravity: Vec3 | None = Field(None, description="m/s^2")
    load: LoadModel | None = None
    preloads: list[PreloadModel] = Field(default_factory=list, max_length=100)
    sweep: SweepModel = Field(default_factory=SweepModel)
    tolerances: TolerancesModel | None = Field(
        None, description="Manufacturing tolerances, for the `tolerances` check"
    )
    checks: dict[str, dict[str, Any] | None] = Field(
        default_factory=dict, description="Per-check options, keyed by check id"
    )

    @field_validator("version", mode="before")
    @classmethod
    def _integer_version(cls, value: Any) -> Any:
        # `true` and `1.0` compare equal to 1 in Python; the format version is the integer 1.
        if type(value) is not int:
            raise ValueError(f"expected the integer 1, got {value!r}")
        return value
