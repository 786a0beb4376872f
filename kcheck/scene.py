"""Scene files (``*.kcheck.yaml``, version 1): validation, and the scene model in SI units.

Loading a scene reads YAML and checks fields only; it never touches a mesh (that is
:mod:`kcheck.mass`, called only when a check needs mass properties).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from kcheck.errors import SceneError
from kcheck.units import LENGTH_TO_M, MATERIALS, density_of
from kcheck.yamlio import FieldPath, LineMap, format_path, load_yaml

__all__ = [
    "SCENE_GLOB",
    "Surface",
    "ContactGeometry",
    "Support",
    "Preload",
    "Load",
    "Sweep",
    "Part",
    "ExplicitMass",
    "Body",
    "Scene",
    "load_scene",
    "scene_json_schema",
]

SCENE_GLOB = "*.kcheck.yaml"

# Relative tolerance for "lies in the plane" tests, on unit normals and on positions / L.
PLANAR_TOL = 1e-9

Vec3 = Annotated[list[float], Field(min_length=3, max_length=3)]
Matrix3 = Annotated[list[Vec3], Field(min_length=3, max_length=3)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)


class PartModel(_Model):
    """One mesh of a multi-part body."""

    mesh: str = Field(description="Mesh file, relative to the scene file; any format trimesh loads")
    material: str | None = Field(None, description="Name from the built-in material table")
    density: float | None = Field(None, gt=0, description="Density in kg/m^3")


class BodyModel(_Model):
    """The moving body: a mesh (or parts) with a material, or explicit mass properties."""

    mesh: str | None = Field(None, description="Mesh file, relative to the scene file")
    material: str | None = Field(None, description="Name from the built-in material table")
    density: float | None = Field(None, gt=0, description="Density in kg/m^3")
    parts: list[PartModel] | None = Field(None, min_length=1, description="Instead of `mesh`")
    mass: float | None = Field(None, gt=0, description="kg; with center_of_mass and inertia")
    center_of_mass: Vec3 | None = Field(None, description="In the scene's units")
    inertia: Matrix3 | float | None = Field(
        None,
        description="kg m^2 about the centre of mass, 3x3; a planar scene may give I_zz alone",
    )


class SupportModel(_Model):
    """One point support."""

    name: str = Field(min_length=1)
    position: Vec3 = Field(description="Contact point on the body, scene units")
    normal: Vec3 = Field(description="Direction the support pushes the body; any length")
    friction: float | None = Field(None, ge=0, description="Coulomb coefficient override")


class LoadModel(_Model):
    """The closing force (and optional torque)."""

    point: Vec3 | None = Field(None, description="Attachment point; default the centre of mass")
    magnitude: float = Field(ge=0, description="N")
    direction: Vec3 | None = Field(None, description="The design's direction; any length")
    angle: float | None = Field(None, description="The design's direction, deg in the sweep plane")
    torque: Vec3 | None = Field(None, description="N m")


class SweepModel(_Model):
    """The plane in which force angles are swept and reported."""

    normal: Vec3 = Field(default_factory=lambda: [0.0, 0.0, 1.0])
    zero: Vec3 = Field(default_factory=lambda: [1.0, 0.0, 0.0], description="Angle 0")


class SceneModel(_Model):
    """A kcheck scene, version 1."""

    version: Literal[1]
    name: str | None = None
    units: Literal["m", "cm", "mm", "um", "in"] = "m"
    body: BodyModel | None = None
    supports: list[SupportModel]
    friction: float = Field(0.0, ge=0, description="Coulomb coefficient for every support")
    gravity: Vec3 | None = Field(None, description="m/s^2")
    load: LoadModel | None = None
    sweep: SweepModel = Field(default_factory=SweepModel)
    checks: dict[str, dict[str, Any] | None] = Field(
        default_factory=dict, description="Per-check options, keyed by check id"
    )


@dataclass(frozen=True)
class Surface:
    """Local shape of one of the two surfaces touching at a contact, for contact mechanics.

    ``radii``: the two principal radii of curvature in m; positive for a convex surface (a
    ball, a pin), negative for a concave one (a conformal groove), ``inf`` where it is flat in
    that direction. ``direction``: unit 3-vector in the contact's tangent plane along which
    the first radius is measured (None when both radii are equal).
    """

    radii: tuple[float, float]
    direction: np.ndarray | None = None


@dataclass(frozen=True)
class ContactGeometry:
    """Where a support came from and the shapes that touch there (coupling shorthands).

    ``coupling`` is the coupling entry's name and ``kind`` its type (``ball-vee``, ...);
    ``index`` the contact's number ``k`` in the support name ``<coupling>.<k>``. ``ball_center``
    (m) and ``ball_radius`` (m) describe the ball; ``ball_on`` says which side carries it.
    ``body`` and ``base`` are the body's and the base's surfaces at the contact.
    ``line_contact`` marks a line contact modelled by points (``ball-cone``).
    """

    coupling: str
    kind: str
    index: int
    ball_center: np.ndarray
    ball_radius: float
    ball_on: Literal["body", "base"]
    body: Surface
    base: Surface
    line_contact: bool = False


@dataclass(frozen=True)
class Support:
    """A point support: contact point (m), unit normal into the body, Coulomb coefficient,
    and the contact's geometry when a coupling shorthand made it (None for explicit ones)."""

    name: str
    position: np.ndarray
    normal: np.ndarray
    friction: float
    geometry: ContactGeometry | None = None


@dataclass(frozen=True)
class Preload:
    """A fixed force on the body (a spring, a magnet): point (m) and force vector (N). It acts
    with gravity, beside the swept closing load."""

    name: str
    point: np.ndarray
    force: np.ndarray


@dataclass(frozen=True)
class Load:
    """The closing load: force magnitude (N), attachment point (m, None = centre of mass),
    design direction (unit vector or None) and torque (N m)."""

    magnitude: float
    point: np.ndarray | None
    direction: np.ndarray | None
    torque: np.ndarray


@dataclass(frozen=True)
class Sweep:
    """Orthonormal frame of the sweep plane: angle alpha is the direction cos a e1 + sin a e2."""

    normal: np.ndarray
    e1: np.ndarray
    e2: np.ndarray

    def direction(self, angle_deg: np.ndarray | float) -> np.ndarray:
        """Unit force directions (..., 3) for angles in degrees."""
        a = np.radians(np.asarray(angle_deg, dtype=float))[..., None]
        return np.cos(a) * self.e1 + np.sin(a) * self.e2

    def angle_of(self, direction: np.ndarray) -> float:
        """Angle in degrees [0, 360) of a direction's projection onto the sweep plane."""
        return float(np.degrees(np.arctan2(direction @ self.e2, direction @ self.e1)) % 360.0)


@dataclass(frozen=True)
class Part:
    """One mesh file of the body and its density (kg/m^3)."""

    mesh: Path
    density: float
    field: FieldPath


@dataclass(frozen=True)
class ExplicitMass:
    """Mass properties given in the scene: kg, m, kg m^2 about the centre of mass."""

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray


@dataclass(frozen=True)
class Body:
    """The moving body: mesh parts, explicit mass properties, or both (explicit wins)."""

    parts: tuple[Part, ...]
    explicit: ExplicitMass | None


@dataclass(frozen=True)
class Scene:
    """A validated scene in SI units."""

    path: Path
    name: str
    units: str
    scale: float
    kind: Literal["planar", "spatial"]
    supports: tuple[Support, ...]
    gravity: np.ndarray
    load: Load | None
    sweep: Sweep
    body: Body | None
    check_options: Mapping[str, Mapping[str, Any]]
    lines: LineMap = field(repr=False)
    notes: tuple[str, ...] = ()
    preloads: tuple[Preload, ...] = ()

    @property
    def dim(self) -> int:
        """2 for a planar scene (motion in the xy-plane), 3 for a spatial one."""
        return 2 if self.kind == "planar" else 3

    @property
    def design_angle_deg(self) -> float | None:
        """The design force direction as an angle in the sweep plane, if the scene gives one."""
        if self.load is None or self.load.direction is None:
            return None
        return self.sweep.angle_of(self.load.direction)

    def line_of(self, path: FieldPath) -> int | None:
        """Line of a field (or of its nearest enclosing field) in the scene file."""
        return _line_of(self.lines, path)

    def error(self, path: FieldPath, message: str) -> SceneError:
        """A SceneError pointing at a field of this scene."""
        return _Fields(self.path, self.lines).error(path, message)


def _line_of(lines: LineMap, path: FieldPath) -> int | None:
    """Line of a field, or of its nearest enclosing field, or None."""
    for n in range(len(path), -1, -1):
        if path[:n] in lines:
            return lines[path[:n]]
    return None


class _Fields:
    """Raise field errors for one file."""

    def __init__(self, path: Path, lines: LineMap) -> None:
        self.path = path
        self.lines = lines

    def error(self, where: FieldPath, message: str) -> SceneError:
        return SceneError(
            self.path, message, field=format_path(where) or None, line=_line_of(self.lines, where)
        )

    def unit(self, where: FieldPath, vector: list[float], what: str) -> np.ndarray:
        v = np.asarray(vector, dtype=float)
        if not np.all(np.isfinite(v)):
            raise self.error(where, f"expected finite numbers for {what}, got {vector}")
        norm = float(np.linalg.norm(v))
        if norm == 0.0:
            raise self.error(where, f"expected a non-zero vector for {what}, got {vector}")
        return v / norm

    def finite(self, where: FieldPath, vector: Any, what: str) -> np.ndarray:
        v = np.asarray(vector, dtype=float)
        if not np.all(np.isfinite(v)):
            raise self.error(where, f"expected finite numbers for {what}, got {vector}")
        return v


def _describe_pydantic(err: Mapping[str, Any]) -> str:
    kind = err["type"]
    got = err.get("input")
    shown = repr(got)
    if len(shown) > 60:
        shown = shown[:57] + "..."
    if kind == "missing":
        return "required field is missing"
    if kind == "extra_forbidden":
        return "unknown field (check the spelling; see `kcheck schema`)"
    if kind in ("too_short", "too_long") and isinstance(got, list):
        return f"expected a list of 3 numbers, got {len(got)} item(s)"
    if kind == "literal_error":
        return f"{err['msg'].replace('Input should be', 'expected')}, got {shown}"
    msg = err["msg"].replace("Input should be", "expected")
    return f"{msg}, got {shown}"


def _first_error(errors: list[Mapping[str, Any]]) -> Mapping[str, Any]:
    # With unions pydantic reports one error per branch; the deepest path is the most specific.
    return max(errors, key=lambda e: len(e["loc"]))


def _resolve_mesh(f: _Fields, where: FieldPath, name: str, allow_outside: bool) -> Path:
    folder = f.path.parent.resolve()
    mesh = (folder / name).resolve()
    if not allow_outside and not mesh.is_relative_to(folder):
        raise f.error(
            where,
            f"mesh path `{name}` leaves the scene's folder {folder}; "
            "pass --allow-outside-paths to permit it",
        )
    if not mesh.is_file():
        raise f.error(where, f"mesh file `{name}` not found (looked for {mesh})")
    return mesh


def _density(
    f: _Fields, where: FieldPath, material: str | None, density: float | None
) -> float | None:
    if material is not None and density is not None:
        raise f.error(where, "give either `material` or `density`, not both")
    if density is not None:
        return density
    if material is None:
        return None
    value = density_of(material)
    if value is None:
        known = ", ".join(sorted(MATERIALS))
        raise f.error((*where, "material"), f"unknown material `{material}`; known: {known}")
    return value


def _body(f: _Fields, model: BodyModel, scale: float, planar: bool, allow_outside: bool) -> Body:
    where: FieldPath = ("body",)
    parts: list[Part] = []
    if model.mesh is not None and model.parts is not None:
        raise f.error(where, "give either `mesh` or `parts`, not both")
    if model.mesh is not None:
        rho = _density(f, where, model.material, model.density)
        parts.append(
            Part(_resolve_mesh(f, (*where, "mesh"), model.mesh, allow_outside), rho or 0.0, where)
        )
    elif model.parts is not None:
        if model.material is not None or model.density is not None:
            raise f.error(where, "with `parts`, give `material`/`density` per part")
        for i, part in enumerate(model.parts):
            pw = (*where, "parts", i)
            parts.append(
                Part(
                    _resolve_mesh(f, (*pw, "mesh"), part.mesh, allow_outside),
                    _density(f, pw, part.material, part.density) or 0.0,
                    pw,
                )
            )
    explicit_fields = (model.mass, model.center_of_mass, model.inertia)
    explicit: ExplicitMass | None = None
    if any(v is not None for v in explicit_fields):
        missing = [
            n
            for n, v in zip(("mass", "center_of_mass", "inertia"), explicit_fields, strict=True)
            if v is None
        ]
        if missing:
            raise f.error(
                (*where, missing[0]),
                "explicit mass properties need `mass`, `center_of_mass` and `inertia` together",
            )
        inertia = _inertia(f, (*where, "inertia"), model.inertia, planar)
        com = f.finite((*where, "center_of_mass"), model.center_of_mass, "the centre of mass")
        explicit = ExplicitMass(float(model.mass), com * scale, inertia)  # type: ignore[arg-type]
    elif not parts:
        raise f.error(where, "expected `mesh`, `parts`, or explicit mass properties")
    for part in parts:
        if part.density == 0.0 and explicit is None:
            raise f.error(
                (*where, "parts") if model.parts else where,
                "expected `material` or `density` for the mesh (trimesh would assume 1 kg/m^3)",
            )
    return Body(tuple(parts), explicit)


def _inertia(f: _Fields, where: FieldPath, value: Any, planar: bool) -> np.ndarray:
    if isinstance(value, (int, float)):
        if not planar:
            raise f.error(where, "a spatial scene needs the full 3x3 inertia tensor")
        if value <= 0:
            raise f.error(where, f"expected a positive moment of inertia, got {value}")
        # Only I_zz matters for motion in the xy-plane; the rest is never read.
        return np.diag([np.nan, np.nan, float(value)])
    tensor = f.finite(where, value, "the inertia tensor")
    if not np.allclose(tensor, tensor.T, rtol=1e-6, atol=1e-12 * np.abs(tensor).max()):
        raise f.error(where, "expected a symmetric inertia tensor")
    eig = np.linalg.eigvalsh(tensor)
    if eig.min() <= 0:
        raise f.error(where, f"expected a positive definite inertia tensor, eigenvalues {eig}")
    a, b, c = np.sort(eig)
    if a + b < c * (1 - 1e-6):
        raise f.error(
            where, f"principal moments {eig} violate the triangle inequality (not a rigid body)"
        )
    return tensor


def _kind(f: _Fields, supports: tuple[Support, ...], length: float) -> Literal["planar", "spatial"]:
    n = len(supports)
    if n == 6:
        return "spatial"
    if n == 3:
        normals = np.array([s.normal for s in supports])
        z = np.array([s.position[2] for s in supports])
        for i, s in enumerate(supports):
            if abs(s.normal[2]) > PLANAR_TOL:
                raise f.error(
                    ("supports", i, "normal"),
                    "a 3-support (planar) scene needs normals in the xy-plane (z = 0), "
                    f"got {np.round(normals[i], 12).tolist()}",
                )
        if np.ptp(z) > PLANAR_TOL * max(length, 1e-300):
            raise f.error(
                ("supports",),
                "a 3-support (planar) scene needs every support at the same z, "
                f"got z = {z.tolist()} m",
            )
        return "planar"
    raise f.error(("supports",), f"expected 3 supports (planar) or 6 (spatial), got {n}")


def _sweep(f: _Fields, model: SweepModel, planar: bool) -> Sweep:
    normal = f.unit(("sweep", "normal"), model.normal, "the sweep plane normal")
    zero = f.finite(("sweep", "zero"), model.zero, "the sweep zero direction")
    e1 = zero - (zero @ normal) * normal
    if np.linalg.norm(e1) < 1e-9 * max(np.linalg.norm(zero), 1e-300):
        raise f.error(("sweep", "zero"), "expected a direction not parallel to the sweep normal")
    e1 = e1 / np.linalg.norm(e1)
    if planar and abs(abs(normal[2]) - 1) > PLANAR_TOL:
        raise f.error(("sweep", "normal"), "a planar scene sweeps in the xy-plane: use [0, 0, 1]")
    return Sweep(normal, e1, np.cross(normal, e1))


def _load(
    f: _Fields, model: LoadModel, scale: float, sweep: Sweep, planar: bool
) -> tuple[Load, tuple[str, ...]]:
    notes: list[str] = []
    where: FieldPath = ("load",)
    if model.direction is not None and model.angle is not None:
        raise f.error(where, "give either `direction` or `angle`, not both")
    direction = None
    if model.direction is not None:
        direction = f.unit((*where, "direction"), model.direction, "the load direction")
    elif model.angle is not None:
        direction = sweep.direction(model.angle)
    if planar and direction is not None and abs(direction[2]) > PLANAR_TOL:
        raise f.error((*where, "direction"), "a planar scene needs a load direction with z = 0")
    torque = np.zeros(3)
    if model.torque is not None:
        torque = f.finite((*where, "torque"), model.torque, "the torque")
        if planar and np.any(torque[:2] != 0):
            notes.append("torque x/y components act out of the plane and are ignored")
    point = None
    if model.point is not None:
        point = f.finite((*where, "point"), model.point, "the load point") * scale
    return Load(float(model.magnitude), point, direction, torque), tuple(notes)


def load_scene(path: Path | str, *, allow_outside: bool = False) -> Scene:
    """Read and validate a scene file; raise SceneError naming file, field and line."""
    path = Path(path)
    data, lines = load_yaml(path)
    f = _Fields(path, lines)
    if not isinstance(data, dict):
        raise f.error((), f"expected a mapping of scene fields, got {type(data).__name__}")
    try:
        model = SceneModel.model_validate(data)
    except ValidationError as exc:
        err = _first_error(exc.errors(include_url=False))
        loc: FieldPath = tuple(p for p in err["loc"] if not (isinstance(p, str) and "[" in p))
        raise f.error(loc, _describe_pydantic(err)) from None

    scale = LENGTH_TO_M[model.units]
    supports_list: list[Support] = []
    names: dict[str, int] = {}
    for i, s in enumerate(model.supports):
        if s.name in names:
            raise f.error(
                ("supports", i, "name"),
                f"support name `{s.name}` used twice (also item {names[s.name]})",
            )
        names[s.name] = i
        position = f.finite(("supports", i, "position"), s.position, "the position") * scale
        normal = f.unit(("supports", i, "normal"), s.normal, "the normal")
        mu = model.friction if s.friction is None else s.friction
        supports_list.append(Support(s.name, position, normal, float(mu)))
    supports = tuple(supports_list)
    positions = np.array([s.position for s in supports]) if supports else np.zeros((0, 3))
    length = float(np.ptp(positions, axis=0).max()) if len(supports) else 0.0
    kind = _kind(f, supports, length)
    planar = kind == "planar"
    sweep = _sweep(f, model.sweep, planar)

    notes: list[str] = []
    gravity = np.zeros(3)
    if model.gravity is not None:
        gravity = f.finite(("gravity",), model.gravity, "gravity")
        if planar and gravity[2] != 0:
            notes.append("gravity's z component is carried by the plane of motion and is ignored")
    load = None
    if model.load is not None:
        load, load_notes = _load(f, model.load, scale, sweep, planar)
        notes.extend(load_notes)
    body = None
    if model.body is not None:
        body = _body(f, model.body, scale, planar, allow_outside)
    options = {k: dict(v or {}) for k, v in model.checks.items()}
    return Scene(
        path=path,
        name=model.name or path.name.removesuffix(".kcheck.yaml"),
        units=model.units,
        scale=scale,
        kind=kind,
        supports=supports,
        gravity=gravity,
        load=load,
        sweep=sweep,
        body=body,
        check_options=options,
        lines=lines,
        notes=tuple(notes),
    )


def scene_json_schema() -> dict[str, Any]:
    """JSON Schema (draft-07 compatible) of the scene file format, version 1."""
    # draft-07 names shared definitions `definitions`, not 2020-12's `$defs`.
    schema = SceneModel.model_json_schema(ref_template="#/definitions/{model}")
    schema["definitions"] = schema.pop("$defs", {})
    schema["$schema"] = "http://json-schema.org/draft-07/schema#"
    schema["title"] = "kcheck scene, version 1 (*.kcheck.yaml)"
    return schema
