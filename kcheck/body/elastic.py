"""Elastic materials for contact mechanics: Young's modulus, Poisson's ratio and an allowable
contact pressure, each with where it comes from (the table in docs/checks.md, `hertz`).

The allowable pressure is the largest Hertz peak pressure ``p0`` the material takes under a
static load. Three bases are used, named per material:

* ``static rating``: ISO 76:2006 defines the basic static load rating of ball bearings by a
  peak contact pressure of 4200 MPa, at which hardened bearing steel takes a permanent set of
  about 1e-4 of the ball diameter;
* ``first yield``: ``p0 = 1.60 Y`` (Johnson, *Contact Mechanics*, 1985, §6.2: a ball pressed on
  a flat first yields below the surface at ``p0 = 1.60 Y`` for nu = 0.3, Tresca and von Mises
  alike), with ``Y`` the tensile yield strength of the datasheet;
* ``ring crack``: a brittle ceramic cracks where the radial tension at the edge of the contact,
  ``(1 - 2 nu) p0 / 3`` (Johnson §4.2), reaches its flexural strength: ``p0 = 3 sigma_f / (1 -
  2 nu)``; conservative (real ceramic balls carry more: the strength has a size effect).

Values are nominal; a coupling's own supplier data belong in the check's ``materials`` option.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Material", "MATERIALS", "ALIASES", "FIRST_YIELD_FACTOR", "material", "ring_crack"]

#: Peak Hertz pressure over tensile yield strength at first yield (Johnson 1985, §6.2).
FIRST_YIELD_FACTOR = 1.60


def ring_crack(flexural_strength: float, poisson: float) -> float:
    """Peak pressure (Pa) at which the edge tension ``(1 - 2 nu) p0 / 3`` reaches a strength."""
    return 3.0 * flexural_strength / (1.0 - 2.0 * poisson)


@dataclass(frozen=True)
class Material:
    """An elastic material: ``youngs_modulus`` and ``allowable_pressure`` in Pa."""

    name: str
    youngs_modulus: float
    poisson: float
    allowable_pressure: float
    basis: str
    source: str


_GPA, _MPA = 1e9, 1e6

MATERIALS: dict[str, Material] = {
    m.name: m
    for m in (
        Material(
            "52100",
            210 * _GPA,
            0.30,
            4200 * _MPA,
            "static rating (ISO 76)",
            "E, nu: SKF super-precision bearings catalogue, 'Materials for bearing rings and "
            "rolling elements', table 1 (100Cr6 = AISI 52100, 58-65 HRC); p: ISO 76:2006 §3.1",
        ),
        Material(
            "440c",
            200 * _GPA,
            0.28,
            FIRST_YIELD_FACTOR * 1900 * _MPA,
            "first yield, Y = 1900 MPa",
            "AK Steel 440C product data bulletin (hardened 1010 °C, tempered 316 °C: "
            "Y = 1900 MPa; E = 200 GPa); nu typical for martensitic stainless steel",
        ),
        Material(
            "stainless-304",
            193 * _GPA,
            0.29,
            FIRST_YIELD_FACTOR * 205 * _MPA,
            "first yield, Y = 205 MPa",
            "ASTM A240 (annealed 304, minimum Y = 205 MPa); E, nu: AK Steel 304 bulletin",
        ),
        Material(
            "17-4ph",
            197 * _GPA,
            0.27,
            FIRST_YIELD_FACTOR * 1170 * _MPA,
            "first yield, Y = 1170 MPa",
            "ASTM A564 (17-4PH, H900, minimum Y = 1170 MPa); E, nu: AK Steel 17-4PH bulletin",
        ),
        Material(
            "si3n4",
            310 * _GPA,
            0.26,
            ring_crack(800 * _MPA, 0.26),
            "ring crack, flexural strength 800 MPa",
            "E, nu: SKF super-precision bearings catalogue, table 1 (bearing-grade silicon "
            "nitride); flexural strength: a typical datasheet value of hot-isostatically pressed "
            "bearing-grade Si3N4 (not a specification minimum)",
        ),
        Material(
            "alumina",
            370 * _GPA,
            0.22,
            ring_crack(379 * _MPA, 0.22),
            "ring crack, flexural strength 379 MPa",
            "CoorsTek AD-995 (99.5 % Al2O3) datasheet: E = 370 GPa, nu = 0.22, "
            "flexural strength 379 MPa",
        ),
        Material(
            "aluminium-6061-t6",
            68.9 * _GPA,
            0.33,
            FIRST_YIELD_FACTOR * 276 * _MPA,
            "first yield, Y = 276 MPa",
            "ASM Aerospace Specification Metals, Aluminum 6061-T6 (E = 68.9 GPa, nu = 0.33, "
            "Y = 276 MPa)",
        ),
        Material(
            "aluminium-7075-t6",
            71.7 * _GPA,
            0.33,
            FIRST_YIELD_FACTOR * 503 * _MPA,
            "first yield, Y = 503 MPa",
            "ASM Aerospace Specification Metals, Aluminum 7075-T6 (E = 71.7 GPa, nu = 0.33, "
            "Y = 503 MPa)",
        ),
        Material(
            "pla",
            2.35 * _GPA,
            0.36,
            FIRST_YIELD_FACTOR * 49.5 * _MPA,
            "first yield, Y = 49.5 MPa (printed)",
            "Ultimaker PLA technical data sheet (printed ISO 527 bars: E = 2346.5 MPa, "
            "Y = 49.5 MPa); nu typical for PLA",
        ),
        Material(
            "petg",
            2.0 * _GPA,
            0.38,
            FIRST_YIELD_FACTOR * 44 * _MPA,
            "first yield, Y = 44 MPa (printed)",
            "additive.tools PETG, FDM as-built XY: E 2-3 GPa, tensile strength 44-56 MPa "
            "(lower ends taken); nu typical for amorphous polyesters",
        ),
    )
}

#: Other names for table entries (AISI/DIN designations, generic names).
ALIASES: dict[str, str] = {
    "100cr6": "52100",
    "bearing-steel": "52100",
    "aisi-52100": "52100",
    "aisi-440c": "440c",
    "x105crmo17": "440c",
    "silicon-nitride": "si3n4",
    "ceramic-alumina": "alumina",
    "al2o3": "alumina",
    "6061-t6": "aluminium-6061-t6",
    "aluminum-6061-t6": "aluminium-6061-t6",
    "7075-t6": "aluminium-7075-t6",
    "aluminum-7075-t6": "aluminium-7075-t6",
    "304": "stainless-304",
}


def _key(name: str) -> str:
    return name.strip().lower().replace("_", "-").replace(" ", "-")


def material(name: str) -> Material | None:
    """A material of the table by name or alias (case and ``_``/space insensitive), or None."""
    key = _key(name)
    return MATERIALS.get(ALIASES.get(key, key))
