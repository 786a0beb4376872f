"""Sanity warnings: a scene that loads and checks but is probably not what its author meant.

Each rule returns :class:`~kcheck.result.Finding` values with a stable ``code`` and the
scene ``field`` they concern; the runner adds them to the scene result's ``warnings``. The
rules look at the scene, its mass properties (when a check needed them: the body's box comes
from its meshes, or from explicit inertia as the equivalent uniform box) and the checks'
public results, never at a check's internals.

* ``support-far-from-body``: a support farther from the body's box than the box's diagonal
  (a units slip: supports in mm in a scene declared in m).
* ``supports-tiny``: every support within a hundredth of the body's size (the opposite slip).
* ``point-far-from-body``: the centre of mass, the load point or a preload point that far.
* ``body-size``: a body smaller than 0.1 mm or larger than 20 m across.
* ``supports-vs-inertia``: a planar scene with a lone I_zz (no box to compare with) whose
  supports span more than ``GYRATION_RATIO`` times its radius of gyration ``sqrt(I_zz / m)``,
  or less than its inverse.
* ``part-size-outlier``: a mesh part whose size is out of line with the others (a part in cm
  in a mm assembly).
* ``mass-units``, ``inertia-units``, ``center-of-mass-units``: explicit mass properties that
  disagree with the mesh (or the supports) by a unit factor (:mod:`kcheck.analysis.mass_units`);
  the box rules are then skipped (the box of a slipped inertia means nothing).
* ``normals-reversed``: every case opens, with every normal reversed every case closes, and
  the normals do not clearly point towards the centre of mass.
* and the mesh warnings carried by the mass properties (``mesh-repaired``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from kcheck.errors import FieldPath
from kcheck.fmt import format_length
from kcheck.records import dataclass
from kcheck.result import CheckResult, Finding
from kcheck.scene import Scene

if TYPE_CHECKING:
    from kcheck.result import MassProperties

__all__ = ["Box", "body_box", "scene_warnings", "BODY_SIZE_M", "PART_RATIO", "GYRATION_RATIO"]

#: Plausible body sizes (box diagonal, m).
BODY_SIZE_M = (1e-4, 20.0)
#: A part is an outlier when its size differs from the median of the others by this factor
#: and it does not touch them, or by the second factor regardless.
PART_RATIO = (5.0, 20.0)
#: Supports spanning less than this fraction of the body's size are suspiciously small.
TINY_LAYOUT = 1e-2
#: With I_zz alone the body's size is unknown, but a body reaches at least its radius of
#: gyration from its centre of mass, and a support layout this many times larger (or smaller)
#: than it means a body nearly all of whose mass sits in a tiny core: a units slip is likelier.
GYRATION_RATIO = 100.0
#: Density (kg/m³) given to mesh parts without one when explicit values are compared with
#: them: only ratios are read then (radius of gyration, centre of mass).
MESH_STAND_IN_DENSITY = 1000.0


@dataclass(frozen=True)
class Box:
    """An oriented box: centre (m), axes (columns, unit), half extents (m)."""

    center: np.ndarray
    axes: np.ndarray
    half: np.ndarray

    @property
    def diagonal(self) -> float:
        """Length of the box's diagonal (m)."""
        return float(2 * np.linalg.norm(self.half))

    def distance(self, point: np.ndarray) -> float:
        """Distance (m) from a point to the box; 0 inside."""
        local = self.axes.T @ (np.asarray(point, dtype=float) - self.center)
        return float(np.linalg.norm(np.maximum(np.abs(local) - self.half, 0.0)))


def body_box(mass: MassProperties | None) -> Box | None:
    """The body's box: its meshes' bounds, or the uniform box with the same explicit inertia
    (half extents ``sqrt(3 (I_j + I_k - I_i) / (2 m))`` in principal axes); None without
    mass properties or with a planar I_zz alone."""
    if mass is None:
        return None
    if mass.bounds is not None:
        lo, hi = mass.bounds
        return Box((lo + hi) / 2, np.eye(3), (hi - lo) / 2)
    if not np.all(np.isfinite(mass.inertia)):
        return None
    moments, axes = np.linalg.eigh(mass.inertia)
    total = moments.sum()
    # Uniform box of sides a_i: I_i = m (a_j^2 + a_k^2) / 12, so a_i^2 = 6 (I_j + I_k - I_i) / m.
    sides_sq = np.maximum(6 * (total - 2 * moments) / mass.mass, 0.0)
    return Box(mass.center_of_mass, axes, np.sqrt(sides_sq) / 2)


def _length(scene: Scene, value_m: float) -> str:
    return format_length(value_m, scene.scale, scene.units)


def _supports_far(scene: Scene, box: Box) -> list[Finding]:
    out = []
    for s in scene.supports:
        d = box.distance(s.position)
        if d > box.diagonal:
            out.append(
                Finding(
                    f"support `{s.name}` is {_length(scene, d)} from the body's bounding box, "
                    f"more than the box's diagonal ({_length(scene, box.diagonal)})",
                    code="support-far-from-body",
                    field=s.field or None,
                    hint=f"are its coordinates in the scene's units ({scene.units})?",
                )
            )
    return out


def _supports_tiny(scene: Scene, box: Box) -> list[Finding]:
    positions = np.array([s.position for s in scene.supports])
    span = float(np.linalg.norm(np.ptp(positions, axis=0)))
    if box.diagonal > 0 and span < TINY_LAYOUT * box.diagonal:
        field: FieldPath = ("supports",) if scene.supports[0].geometry is None else ("couplings",)
        return [
            Finding(
                f"the supports span only {_length(scene, span)} while the body is "
                f"{_length(scene, box.diagonal)} across",
                code="supports-tiny",
                field=field,
                hint=f"are their coordinates in the scene's units ({scene.units})?",
            )
        ]
    return []


def _points_far(scene: Scene, box: Box, mass: MassProperties) -> list[Finding]:
    points: list[tuple[str, np.ndarray, FieldPath]] = []
    if mass.bounds is not None:  # an equivalent box is centred on the centre of mass
        where: FieldPath = ("body", "center_of_mass") if mass.source == "explicit" else ("body",)
        points.append(("the centre of mass", mass.center_of_mass, where))
    if scene.load is not None and scene.load.point is not None:
        points.append(("the load point", scene.load.point, ("load", "point")))
    for i, p in enumerate(scene.preloads):
        points.append((f"preload `{p.name}`'s point", p.point, ("preloads", i, "point")))
    out = []
    for what, point, where in points:
        d = box.distance(point)
        if d > box.diagonal:
            out.append(
                Finding(
                    f"{what} is {_length(scene, d)} outside the body's bounding box (whose "
                    f"diagonal is {_length(scene, box.diagonal)})",
                    code="point-far-from-body",
                    field=where,
                    hint=f"are its coordinates in the scene's units ({scene.units})?",
                )
            )
    return out


def _body_size(scene: Scene, box: Box, mass: MassProperties) -> list[Finding]:
    low, high = BODY_SIZE_M
    if low <= box.diagonal <= high:
        return []
    explicit = mass.source == "explicit"
    return [
        Finding(
            f"the body is {box.diagonal:.3g} m across"
            + (" (the uniform box with its explicit inertia)" if explicit else "")
            + f", outside the plausible {low:g}–{high:g} m for a kinematic coupling",
            code="body-size",
            field=("body", "inertia") if explicit else ("body",),
            hint="are `inertia` in kg·m² and `mass` in kg?"
            if explicit
            else f"is the mesh's unit right? The scene says {scene.units}",
        )
    ]


def _supports_vs_inertia(scene: Scene, mass: MassProperties) -> list[Finding]:
    izz = float(mass.inertia[2, 2])
    if not (izz > 0 and np.isfinite(izz)):
        return []
    gyration = float(np.sqrt(izz / mass.mass))
    positions = np.array([s.position for s in scene.supports])
    span = float(np.linalg.norm(np.ptp(positions, axis=0)))
    if GYRATION_RATIO * gyration >= span >= gyration / GYRATION_RATIO:
        return []
    field: FieldPath = ("supports",) if scene.supports[0].geometry is None else ("couplings",)
    return [
        Finding(
            f"the supports span {_length(scene, span)}, but the body's radius of gyration "
            f"sqrt(I_zz / m) is only {_length(scene, gyration)}"
            if span > gyration
            else f"the supports span only {_length(scene, span)}, but the body's radius of "
            f"gyration sqrt(I_zz / m) is {_length(scene, gyration)}",
            code="supports-vs-inertia",
            field=field,
            hint=f"are the coordinates in the scene's units ({scene.units}) and I_zz in kg·m²?",
        )
    ]


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    """Distance (m) between two axis-aligned boxes (rows min, max); 0 if they overlap."""
    return float(np.linalg.norm(np.maximum(np.maximum(a[0] - b[1], b[0] - a[1]), 0.0)))


def _part_outliers(scene: Scene, mass: MassProperties) -> list[Finding]:
    """Parts whose size is out of line with the others'. With two parts only the smaller one
    can be named (a file in cm or m read as mm comes out small)."""
    if scene.body is None or len(mass.part_bounds) < 2:
        return []
    boxes = list(mass.part_bounds)
    sizes = np.array([np.linalg.norm(b[1] - b[0]) for b in boxes])
    candidates = range(len(boxes)) if len(boxes) > 2 else [int(np.argmin(sizes))]
    out = []
    for i in candidates:
        part = scene.body.parts[i]
        others = float(np.median(np.delete(sizes, i)))
        ratio = sizes[i] / others
        factor = max(ratio, 1 / ratio)
        gap = min(_gap(boxes[i], b) for j, b in enumerate(boxes) if j != i)
        detached = gap > 0.02 * float(sizes.max())
        if factor >= PART_RATIO[1] or (factor >= PART_RATIO[0] and detached):
            scaled = "smaller" if ratio < 1 else "larger"
            out.append(
                Finding(
                    f"part {i + 1} ({part.mesh.name}) is {factor:.3g} times {scaled} than the "
                    f"other parts ({_length(scene, sizes[i])} across against "
                    f"{_length(scene, others)})"
                    + (" and touches none of them" if detached else ""),
                    code="part-size-outlier",
                    field=part.field or None,
                    hint=f"is its mesh in another unit than {part.units}? Give the part its own "
                    "`units`",
                )
            )
    return out


def _every_case_opens(checks: Sequence[CheckResult]) -> bool:
    """Whether some check evaluated cases and none of them closes anywhere."""
    for check in checks:
        if not check.cases:
            continue
        outcomes = {c.outcome for c in check.cases}
        if outcomes and outcomes <= {"opens", "opens_loses_contact"}:
            return True
        if outcomes == {"swept"} and all(not c.safe_ranges_deg for c in check.cases):
            return True
    return False


def _normals_reversed(
    scene: Scene, mass: MassProperties, checks: Sequence[CheckResult]
) -> list[Finding]:
    """Every case opens (or no direction closes any case), the same scene with every normal
    reversed closes every case (re-evaluated with :func:`kcheck.analysis.analyse`), and the
    normals do not clearly point towards the centre of mass.

    The dynamics alone cannot tell reversed normals from a reversed load: without friction
    and gravity both give the same equations. Geometry can veto: a support pushes the body, so
    when most normals point within 60° of the centre of mass they are probably right and the
    load is what is wrong (the checks' findings say where to turn it).
    """
    if not _every_case_opens(checks):
        return []
    points = np.array([s.position for s in scene.supports])
    normals = np.array([s.normal for s in scene.supports])
    towards = mass.center_of_mass - points
    distance = np.linalg.norm(towards, axis=1)
    cosine = np.einsum("ij,ij->i", normals, towards) / np.where(distance > 0, distance, 1.0)
    if np.count_nonzero(cosine > 0.5) > len(cosine) / 2:
        return []
    from kcheck.analysis import analyse
    from kcheck.analysis.cases import closing_force_reason

    if closing_force_reason(scene) is not None:
        return []
    flipped = dataclasses.replace(
        scene,
        supports=tuple(dataclasses.replace(s, normal=-s.normal) for s in scene.supports),
    )
    analysis = analyse(flipped, mass)
    if analysis.combined is not None and analysis.design is None:
        closes = bool(analysis.combined)
    else:
        closes = analysis.every_case_closes
    if not closes:
        return []
    explicit = scene.supports[0].geometry is None
    field: FieldPath = ("supports",) if explicit else ("couplings",)
    # `ball_on` is a coupling shorthand's: explicit supports have no balls to move.
    hint = (
        "reverse the normals (each points from its support into the body)"
        if explicit
        else "reverse the normals, or put the balls on the other side (`ball_on`)"
    )
    return [
        Finding(
            "every case opens, but with every support normal reversed every case closes: "
            "the support normals may be reversed (they point from the support into the body)",
            code="normals-reversed",
            field=field,
            hint=hint,
        )
    ]


def scene_warnings(
    scene: Scene, mass: MassProperties | None, checks: Sequence[CheckResult] = ()
) -> tuple[Finding, ...]:
    """Every sanity warning of a checked scene (see the module's list). A rule that crashes
    (a bug) gives a finding saying so instead of taking the scene down."""
    out: list[Finding] = []
    if mass is not None:
        out.extend(mass.warnings)
    try:
        slips = _unit_slips(scene) if mass is not None else []
    except Exception as exc:  # a bug in a rule must not lose the scene's result
        slips = [_crashed(exc)]
    out += slips
    # A box from an explicit inertia in the wrong unit says nothing more: the slip is named.
    slipped = {("body", "mass"), ("body", "inertia")} & {f.field for f in slips}
    box = None if slipped else body_box(mass)
    rules: list[Callable[[], list[Finding]]] = []
    if box is not None and mass is not None:
        rules += [
            lambda: _body_size(scene, box, mass),
            lambda: _supports_far(scene, box),
            lambda: _supports_tiny(scene, box),
            lambda: _points_far(scene, box, mass),
            lambda: _part_outliers(scene, mass),
        ]
    if mass is not None:
        rules.append(lambda: _normals_reversed(scene, mass, checks))
    if box is None and not slipped and mass is not None and mass.bounds is None:
        rules.append(lambda: _supports_vs_inertia(scene, mass))
    for rule in rules:
        try:
            out += rule()
        except Exception as exc:  # a bug in a rule must not lose the scene's result
            out.append(_crashed(exc))
    return tuple(out)


def _crashed(exc: Exception) -> Finding:
    return Finding(
        f"a sanity rule crashed ({type(exc).__name__}: {exc}); please report it",
        code="sanity-rule-crashed",
    )


def _unit_slips(scene: Scene) -> list[Finding]:
    """Explicit mass properties in the wrong unit (:mod:`kcheck.analysis.mass_units`),
    against the mesh parts' own mass properties when the body has meshes (read again: the
    explicit values won over them). A mesh that cannot give mass properties is no reference."""
    from kcheck.analysis.mass_units import explicit_unit_slips

    body = scene.body
    if body is None or body.explicit is None:
        return []
    mesh = None
    has_density = bool(body.parts) and all(p.density > 0 for p in body.parts)
    if body.parts:
        from kcheck.body.mass import body_mass_properties
        from kcheck.errors import SceneError
        from kcheck.scene import Body

        # Without a density only ratios (radius of gyration, centre) are read: any will do.
        parts = tuple(
            p if p.density > 0 else dataclasses.replace(p, density=MESH_STAND_IN_DENSITY)
            for p in body.parts
        )
        try:
            mesh = body_mass_properties(Body(parts, None))
        except SceneError:
            return []
    return explicit_unit_slips(scene, mesh, has_density)
