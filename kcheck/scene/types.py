"""The validated scene in SI units: immutable values the checks read."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from kcheck.errors import FieldPath, SceneError
from kcheck.numerics.thresholds import PLANAR_TOL
from kcheck.records import dataclass
from kcheck.scene.yamlio import LineMap

__all__ = [
    "PLANAR_TOL",
    "Surface",
    "ContactGeometry",
    "Friction",
    "Support",
    "Preload",
    "Load",
    "Sweep",
    "Part",
    "PointMass",
    "ExplicitMass",
    "Body",
    "Tolerances",
    "Scene",
    "line_of",
    "position_of",
]


def line_of(lines: LineMap, path: FieldPath) -> int | None:
    """Line of a field, or of its nearest enclosing field, or None."""
    return position_of(lines, {}, path)[0]


def position_of(lines: LineMap, columns: LineMap, path: FieldPath) -> tuple[int | None, int | None]:
    """Line and column of a field as written (its key, or its item in a list), or of its
    nearest enclosing field written in the file (a required field that is missing: the
    mapping it belongs in); (None, None) when nothing is known."""
    for n in range(len(path), -1, -1):
        if path[:n] in lines:
            return lines[path[:n]], columns.get(path[:n])
    return None, None


@dataclass(frozen=True)
class Surface:
    """Local shape of one of the two surfaces touching at a contact, for contact mechanics.

    ``radii``: the two principal radii of curvature in m; positive for a convex surface (a
    ball, a pin), negative for a concave one (a conformal groove, a conical seat across),
    ``inf`` where it is flat in that direction. ``direction``: unit 3-vector in the contact's
    tangent plane along which the *first* radius is measured (None when both radii are equal);
    the second is measured across it (``normal × direction``).
    """

    radii: tuple[float, float]
    direction: np.ndarray | None = None


@dataclass(frozen=True)
class ContactGeometry:
    """Where a support came from and the shapes that touch there (coupling shorthands).

    ``coupling`` is the coupling entry's name and ``kind`` its type (``ball-vee``, ...);
    ``index`` the contact's number ``k`` (from 1) in the support name ``<coupling>.<k>``.
    ``ball_center`` (m) and ``ball_radius`` (m) describe the ball; ``ball_on`` says which side
    carries it. ``body`` and ``base`` are the body's and the base's surfaces at the contact.
    ``line_contact`` marks a line contact modelled by points (``ball-cone``).
    ``ball_material`` and ``seat_material``: the table's names given in the scene for the ball
    and the mating surface (None: not given there). An explicit support's contact has its
    support's name as ``coupling`` and ``kind`` ``explicit``.
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
    ball_material: str | None = None
    seat_material: str | None = None

    @property
    def seat_on(self) -> Literal["body", "base"]:
        """Which side carries the seat (the mating surface): the other one than the ball."""
        return "base" if self.ball_on == "body" else "body"


FrictionKind = Literal["static", "kinetic"]


@dataclass(frozen=True)
class Friction:
    """A contact's Coulomb coefficients: ``static`` (what friction can hold before motion
    starts) and ``kinetic`` (while sliding), each a closed range ``(low, high)`` of values that
    may occur. A plain coefficient has all four equal; ``{min, max}`` gives both the same range.
    """

    static: tuple[float, float]
    kinetic: tuple[float, float]

    @classmethod
    def of(cls, mu: float) -> Friction:
        """One coefficient for everything."""
        return cls((mu, mu), (mu, mu))

    @property
    def largest(self) -> float:
        """The largest coefficient the contact may have."""
        return max(self.static[1], self.kinetic[1])

    @property
    def plain(self) -> bool:
        """Whether it is one number (no range, static = kinetic)."""
        return self.static[0] == self.static[1] == self.kinetic[0] == self.kinetic[1]

    @property
    def two_valued(self) -> bool:
        """Whether static and kinetic differ."""
        return self.static != self.kinetic

    def of_kind(self, kind: FrictionKind) -> tuple[float, float]:
        """The range of the static or the kinetic coefficient."""
        return self.static if kind == "static" else self.kinetic

    def to_yaml(self) -> float | dict[str, Any]:
        """The scene-file form: a number, ``{min, max}`` or ``{static, kinetic}``."""

        def one(r: tuple[float, float]) -> float | dict[str, float]:
            return r[0] if r[0] == r[1] else {"min": r[0], "max": r[1]}

        if not self.two_valued:
            return one(self.kinetic)
        return {"static": one(self.static), "kinetic": one(self.kinetic)}


@dataclass(frozen=True)
class Support:
    """A point support: contact point (m), unit normal into the body, Coulomb coefficient
    (the largest it may have), the contact's geometry when a coupling shorthand made it (None
    for explicit ones), the field that gave it, and its coefficients when they are a range
    or a static/kinetic pair (:attr:`coefficients`)."""

    name: str
    position: np.ndarray
    normal: np.ndarray
    friction: float
    geometry: ContactGeometry | None = None
    #: Where the support is written in the scene file (a support, or the coupling entry).
    field: FieldPath = dataclasses.field(default=(), compare=False)
    #: Static and kinetic ranges; None: exactly ``friction`` for both.
    friction_spec: Friction | None = None
    #: An explicit support's local contact shape and materials (its `contact` field).
    contact: ContactGeometry | None = None

    @property
    def contact_geometry(self) -> ContactGeometry | None:
        """The contact's shape: from the coupling shorthand, or an explicit `contact`."""
        return self.geometry if self.geometry is not None else self.contact

    @property
    def coefficients(self) -> Friction:
        """Static and kinetic coefficient ranges (one number: all equal to ``friction``)."""
        return Friction.of(self.friction) if self.friction_spec is None else self.friction_spec

    def to_json(self) -> dict[str, Any]:
        """JSON form (SI): name, position, normal, friction (the largest coefficient), its
        static and kinetic ranges when they are not one number, coupling (or None), kind."""
        g = self.geometry
        out: dict[str, Any] = {
            "name": self.name,
            "position": self.position.tolist(),
            "normal": self.normal.tolist(),
            "friction": self.friction,
        }
        mu = self.coefficients
        if not mu.plain:
            out["friction_static"] = list(mu.static)
            out["friction_kinetic"] = list(mu.kinetic)
        out["coupling"] = None if g is None else g.coupling
        out["kind"] = "explicit" if g is None else g.kind
        return out


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
    """Orthonormal frame of the sweep plane: angle alpha is the direction cos a e1 + sin a e2.

    ``given``: whether the scene file chose it (a ``sweep:`` entry); otherwise it is the
    xy-plane, and a spatial check may choose a plane of its own (and says which).
    """

    normal: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    given: bool = False

    def direction(self, angle_deg: np.ndarray | float) -> np.ndarray:
        """Unit force directions (..., 3) for angles in degrees."""
        a = np.radians(np.asarray(angle_deg, dtype=float))[..., None]
        return np.cos(a) * self.e1 + np.sin(a) * self.e2

    def angle_of(self, direction: np.ndarray) -> float:
        """Angle in degrees [0, 360) of a direction's projection onto the sweep plane."""
        return float(np.degrees(np.arctan2(direction @ self.e2, direction @ self.e1)) % 360.0)


Matrix = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]


@dataclass(frozen=True)
class Part:
    """One mesh file of the body, and everything its mass properties depend on.

    ``density`` in kg/m^3; ``scale`` metres per file unit (``units`` names that unit, for
    messages; a STEP file is read in metres, its own unit converted by the importer);
    ``rotation`` (rows of a proper rotation matrix, or None) and ``translation`` (m) place the
    file's coordinates in the scene: ``x_scene = R (scale x_file) + t``; ``repair`` allows
    merging, re-winding and hole filling. ``field`` locates the part in the scene file and
    takes no part in comparisons (equal parts give equal mass properties: a cache key).
    """

    mesh: Path
    density: float
    field: FieldPath = dataclasses.field(default=(), compare=False)
    scale: float = 1.0
    units: str = "m"
    rotation: Matrix | None = None
    translation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    repair: bool = False

    @property
    def is_step(self) -> bool:
        """Whether the mesh is a STEP file (read through the `step` extra)."""
        return self.mesh.suffix.lower() in (".step", ".stp")


@dataclass(frozen=True)
class PointMass:
    """A part in no mesh, as a point: name, mass (kg), position (m)."""

    name: str
    mass: float
    point: np.ndarray


@dataclass(frozen=True)
class ExplicitMass:
    """Mass properties given in the scene: kg, m, kg m^2 about the centre of mass."""

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray


@dataclass(frozen=True)
class Body:
    """The moving body: mesh parts, explicit mass properties, or both (explicit wins over the
    meshes), plus point masses added to either. ``materials``: the table's names of the
    body's (or its parts') `material`, each once, in order (seats cut into the body are of
    it)."""

    parts: tuple[Part, ...]
    explicit: ExplicitMass | None
    point_masses: tuple[PointMass, ...] = ()
    materials: tuple[str, ...] = ()


@dataclass(frozen=True)
class Tolerances:
    """How far the made coupling may differ from the scene: every coordinate of every support
    position by up to ``position`` (m), every support normal tilted by up to ``normal_deg``,
    the load direction by up to ``load_direction_deg`` (degrees). Friction's uncertainty is
    the scene's ``friction`` ranges."""

    position: float = 0.0
    normal_deg: float = 0.0
    load_direction_deg: float = 0.0


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
    columns: LineMap = field(default_factory=dict, repr=False)
    tolerances: Tolerances | None = None

    @property
    def dim(self) -> int:
        """2 for a planar scene (motion in the xy-plane), 3 for a spatial one."""
        return 2 if self.kind == "planar" else 3

    def friction_range(self, kind: FrictionKind) -> tuple[np.ndarray, np.ndarray]:
        """Per support, the lowest and the highest static or kinetic coefficient: (k,) each."""
        ranges = np.array([s.coefficients.of_kind(kind) for s in self.supports], dtype=float)
        ranges = ranges.reshape(len(self.supports), 2)
        return ranges[:, 0], ranges[:, 1]

    @property
    def design_angle_deg(self) -> float | None:
        """The design force direction as an angle in the sweep plane, if the scene gives one."""
        if self.load is None or self.load.direction is None:
            return None
        return self.sweep.angle_of(self.load.direction)

    def support_field(self, index: int) -> FieldPath:
        """Where support ``index`` is written: its item under `supports`, or the coupling
        entry that made it (findings about a support point there). A support built in code
        has no recorded field: couplings then count in the order their names first appear,
        explicit supports in their own order (as a file lists them)."""
        support = self.supports[index]
        if support.field:
            return support.field
        if support.geometry is not None:
            names = list(dict.fromkeys(s.geometry.coupling for s in self.supports if s.geometry))
            return ("couplings", names.index(support.geometry.coupling))
        explicit = [i for i, s in enumerate(self.supports) if s.geometry is None]
        return ("supports", explicit.index(index))

    def line_of(self, path: FieldPath) -> int | None:
        """Line of a field (or of its nearest enclosing field) in the scene file."""
        return line_of(self.lines, path)

    def error(self, path: FieldPath, message: str) -> SceneError:
        """A SceneError pointing at a field of this scene (its line and column, or those of
        its nearest enclosing field written in the file)."""
        line, column = position_of(self.lines, self.columns, path)
        return SceneError(self.path, message, field=path or None, line=line, column=column)
