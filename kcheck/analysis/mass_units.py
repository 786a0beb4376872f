"""Explicit mass properties in the wrong unit: the scene's ``mass`` (kg), ``center_of_mass``
(scene units) and ``inertia`` (kg·m²) against what the body's mesh implies or, without a mesh,
what the supports' span and the values' own consistency imply.

A finding is made only where the disagreement matches a unit mix-up (a ratio within a factor
:data:`MATCH` of 10³, 10⁶, ...: g or mg typed where kg is read, kg·mm² where kg·m² is read, a
centre of mass in m in a scene in mm), and it names the field and the unit it was probably
typed in. A mere disagreement (a hollow part, a mesh without its inserts) is no unit slip.

* With a mesh: the explicit mass against the mesh's (when the parts have a density), the
  inertia against the mesh's (its radius of gyration ``sqrt(tr I / m)`` when they have none),
  the centre of mass against the mesh's.
* Without one: the radius of gyration against the supports' span (a body carried on its
  supports is of their size: :data:`GYRATION_BAND`) and the density of the uniform box with the
  same inertia (:data:`DENSITY_BAND`); a mass slip scales the density by ``f^2.5`` and the
  gyration by ``f^-0.5``, an inertia slip by ``g^-1.5`` and ``g^0.5``, so the two are told
  apart, and the simplest pair of unit factors that makes both plausible is named. The centre
  of mass against the supports' centroid.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np

from kcheck.errors import FieldPath
from kcheck.result import Finding, MassProperties
from kcheck.scene import Scene
from kcheck.scene.units import LENGTH_TO_M

__all__ = [
    "MASS_UNITS",
    "INERTIA_UNITS",
    "MATCH",
    "GYRATION_BAND",
    "DENSITY_BAND",
    "explicit_unit_slips",
]

#: Units a mass may have been typed in, by how many of them make a kilogram.
MASS_UNITS: Mapping[float, str] = {1e3: "g", 1e6: "mg"}
#: Units an inertia may have been typed in, by how many of them make a kg·m².
INERTIA_UNITS: Mapping[float, str] = {
    1e3: "g·m²",
    1e4: "kg·cm²",
    1e6: "kg·mm²",
    1e7: "g·cm²",
    1e9: "g·mm²",
}
#: A ratio within this factor of a unit factor matches it: a density or a mesh off by less
#: (a hollow part, a missing insert) is not mistaken for a unit, and neighbouring factors
#: (10³ and 10⁴) stay apart.
MATCH = 2.0
#: Radius of gyration over the supports' span of a body carried on them: 0.01 to 10 (the
#: bundled fixtures lie in 0.03–6.6; a unit slip of the inertia moves it by 31.6 at least).
GYRATION_BAND = (0.01, 10.0)
#: Density (kg/m³) of the uniform box with the explicit inertia: from foams to tungsten, with
#: room for hollow bodies (which look lighter) and compact cores (heavier).
DENSITY_BAND = (30.0, 50_000.0)
#: A centre of mass farther than this fraction of the body's size from the mesh's (or, without
#: a mesh, this many supports' spans from their centroid) is looked at for a unit slip ...
COM_FAR = 0.1
COM_FAR_SPANS = 10.0
#: ... and one that lands within this fraction (span) of it when rescaled is named.
COM_NEAR = 0.05
COM_NEAR_SPANS = 1.0


def _unit_of(ratio: float, units: Mapping[float, str]) -> tuple[float, str] | None:
    """The unit whose factor the ratio matches (within :data:`MATCH`), if any."""
    for factor, name in units.items():
        if factor / MATCH <= ratio <= factor * MATCH:
            return factor, name
    return None


def _moments(inertia: np.ndarray) -> np.ndarray:
    """Principal moments, or a planar scene's lone I_zz."""
    if np.all(np.isfinite(inertia)):
        return np.asarray(np.linalg.eigvalsh((inertia + inertia.T) / 2))
    return np.array([float(inertia[2, 2])])


def _mass_finding(value: float, ratio: float, against: str) -> Finding | None:
    unit = _unit_of(ratio, MASS_UNITS)
    if unit is None:
        return None
    factor, name = unit
    return Finding(
        f"the explicit mass {value:.4g} kg is {ratio:.3g} times {against}",
        code="mass-units",
        field=("body", "mass"),
        hint=f"was it typed in {name}? kcheck reads kg: {value / factor:.4g}",
    )


def _inertia_finding(ratio: float, against: str, planar: bool) -> Finding | None:
    unit = _unit_of(ratio, INERTIA_UNITS)
    if unit is None:
        return None
    factor, name = unit
    what = "I_zz" if planar else "inertia"
    return Finding(
        f"the explicit {what} is {ratio:.3g} times {against}",
        code="inertia-units",
        field=("body", "inertia"),
        hint=f"was it typed in {name}? kcheck reads kg·m²: divide it by {factor:g}",
    )


def _com_finding(
    scene: Scene, com: np.ndarray, target: np.ndarray, far: float, near: float, against: str
) -> Finding | None:
    axes = 2 if scene.kind == "planar" else 3
    if np.linalg.norm((com - target)[:axes]) <= far:
        return None
    for unit, metres in LENGTH_TO_M.items():
        f = metres / scene.scale
        if unit != scene.units and np.linalg.norm((com * f - target)[:axes]) <= near:
            return Finding(
                f"the explicit centre of mass is {np.linalg.norm((com - target)[:axes]):.3g} m "
                f"from {against}; read in {unit}, it would lie at it",
                code="center-of-mass-units",
                field=("body", "center_of_mass"),
                hint=f"was it typed in {unit}? The scene reads it in {scene.units} (`units`)",
            )
    return None


def _with_mesh(
    scene: Scene, mesh: MassProperties, has_density: bool, planar: bool
) -> list[Finding]:
    assert scene.body is not None and scene.body.explicit is not None
    e = scene.body.explicit
    out: list[Finding | None] = []
    if has_density:
        out.append(_mass_finding(e.mass, e.mass / mesh.mass, f"the mesh's ({mesh.mass:.4g} kg)"))
    explicit, meshed = _moments(e.inertia), _moments(mesh.inertia)
    if planar:
        meshed = meshed if len(meshed) == 1 else np.array([float(mesh.inertia[2, 2])])
    if has_density:
        ratio = float(explicit.sum() / meshed.sum())
        out.append(_inertia_finding(ratio, "the mesh's", planar))
    else:
        ratio = float((explicit.sum() / e.mass) / (meshed.sum() / mesh.mass))
        out.append(
            _inertia_finding(ratio, "what the mesh gives for its mass (sqrt(I / m))²", planar)
        )
    if mesh.bounds is not None:
        size = float(np.linalg.norm(np.ptp(mesh.bounds, axis=0)))
        out.append(
            _com_finding(
                scene,
                e.center_of_mass,
                mesh.center_of_mass,
                COM_FAR * size,
                COM_NEAR * size,
                "the mesh's",
            )
        )
    return [f for f in out if f is not None]


def _without_mesh(scene: Scene, planar: bool) -> list[Finding]:
    assert scene.body is not None and scene.body.explicit is not None
    e = scene.body.explicit
    points = np.array([s.position for s in scene.supports])
    span = float(np.linalg.norm(np.ptp(points, axis=0)))
    out: list[Finding | None] = []
    moments = _moments(e.inertia)
    if span > 0 and np.all(moments >= 0) and moments.max() > 0:
        gyration = float(np.sqrt(moments.max() / e.mass)) / span
        density = None
        if not planar:
            sides = np.sqrt(np.maximum(6 * (moments.sum() - 2 * moments) / e.mass, 0.0))
            volume = float(np.prod(sides))
            density = e.mass / volume if volume > 0 else None
        out.extend(_explain(gyration, density, e.mass, planar))
    out.append(
        _com_finding(
            scene,
            e.center_of_mass,
            points.mean(axis=0),
            COM_FAR_SPANS * span,
            COM_NEAR_SPANS * span,
            "the supports' centroid",
        )
    )
    return [f for f in out if f is not None]


def _plausible(gyration: float, density: float | None) -> bool:
    ok = GYRATION_BAND[0] <= gyration <= GYRATION_BAND[1]
    return ok and (density is None or DENSITY_BAND[0] <= density <= DENSITY_BAND[1])


def _explain(
    gyration: float, density: float | None, mass: float, planar: bool
) -> list[Finding | None]:
    """The simplest mass and inertia unit factors that make the radius of gyration over the
    span, and the equivalent box's density, plausible; findings for those that are not 1."""
    if _plausible(gyration, density):
        return []
    masses = [1.0, *MASS_UNITS] if density is not None else [1.0]
    best: tuple[float, float, float] | None = None
    for f, g in itertools.product(masses, [1.0, *INERTIA_UNITS]):
        k = gyration * np.sqrt(f / g)  # k² = I / m: both divided by their factors
        rho = None if density is None else density / f**2.5 * g**1.5
        if not _plausible(k, rho):
            continue
        # fewest changed fields, then the one nearest the middle of the bands (in logs)
        cost = (f != 1.0) + (g != 1.0) + 0.01 * abs(np.log10(k / 0.3))
        if best is None or cost < best[0]:
            best = (cost, f, g)
    if best is None:
        return []
    _, f, g = best
    out: list[Finding | None] = []
    if f != 1.0:
        out.append(
            _mass_finding(
                mass, f, "what the explicit inertia and the supports' span make plausible"
            )
        )
    if g != 1.0:
        out.append(
            _inertia_finding(
                g, "what the supports' span (and the explicit mass) make plausible", planar
            )
        )
    return out


def explicit_unit_slips(
    scene: Scene, mesh: MassProperties | None, has_density: bool
) -> list[Finding]:
    """Findings for explicit mass properties that disagree with the mesh's (``mesh``: the
    mesh parts' own mass properties, computed with their density when ``has_density``, else
    with any density: only ratios are read) or, without a mesh, with the supports, by a unit
    factor (module docstring)."""
    if scene.body is None or scene.body.explicit is None:
        return []
    planar = not np.all(np.isfinite(scene.body.explicit.inertia))
    if mesh is not None:
        return _with_mesh(scene, mesh, has_density, planar)
    return _without_mesh(scene, planar)


def fields_of(findings: list[Finding]) -> set[FieldPath]:
    """The fields these findings blame (the sanity rules skip what follows from them)."""
    return {f.field for f in findings if f.field is not None}
