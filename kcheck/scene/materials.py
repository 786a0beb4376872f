"""The one material table: every name a scene's `material`, a coupling's or support's
`ball_material`/`seat_material` and the `hertz` options may use, with density, elastic
constants, allowable contact pressure, yield strength and thermal expansion (SI), each with its
source (the table with sources in docs/materials.md).

It lives with the scene because scene files are validated against it; the body layer
(:mod:`kcheck.body.elastic`) and the checks read it from here.

Two layers:

* **grades** (``52100``, ``6061-t6``, ``ti-6al-4v``, ...): one alloy in one condition, with
  every property its datasheet gives;
* **families** (``steel``, ``aluminium``, ``stainless-steel``, ``titanium``, ...): a generic
  name with a nominal density of its own (used for mass) whose contact and thermal properties
  are those of a named representative grade (``grade``), the weakest common one, so a check
  that uses them errs on the safe side; every result that uses them names the grade.
  Materials that only have a density (granite, brass, ...) have no contact properties.

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
  2 nu)``; conservative (real ceramic balls carry more: the strength has a size effect), and
  never above the compressive strength where the datasheet gives one.
"""

from __future__ import annotations

from dataclasses import replace

from kcheck.records import dataclass

__all__ = [
    "Material",
    "TABLE",
    "MATERIALS",
    "ALIASES",
    "FIRST_YIELD_FACTOR",
    "ring_crack",
    "canonical",
    "lookup",
    "density_of",
    "known_names",
]

#: Peak Hertz pressure over tensile yield strength at first yield (Johnson 1985, §6.2).
FIRST_YIELD_FACTOR = 1.60


def ring_crack(flexural_strength: float, poisson: float) -> float:
    """Peak pressure (Pa) at which the edge tension ``(1 - 2 nu) p0 / 3`` reaches a strength."""
    return 3.0 * flexural_strength / (1.0 - 2.0 * poisson)


@dataclass(frozen=True)
class Material:
    """A material of the table, SI units; None where the table has no value.

    ``density`` kg/m^3; ``youngs_modulus``, ``allowable_pressure`` (Hertz peak pressure) and
    ``yield_strength`` Pa; ``thermal_expansion`` 1/K (20-100 °C); ``basis`` says how the
    allowable pressure was found, ``source`` where every value comes from; ``grade`` is the
    representative grade whose contact properties a family uses ("" for a grade itself);
    ``typical``: every value is a typical datasheet value; False: the allowable pressure rests
    on a standard (ISO 76) or a specification minimum of the yield strength (the rest typical).
    """

    name: str
    density: float | None
    youngs_modulus: float | None = None
    poisson: float | None = None
    allowable_pressure: float | None = None
    yield_strength: float | None = None
    thermal_expansion: float | None = None
    basis: str = ""
    source: str = ""
    grade: str = ""
    typical: bool = True

    @property
    def elastic(self) -> bool:
        """Whether contact mechanics can use it (E, nu and an allowable pressure known)."""
        return None not in (self.youngs_modulus, self.poisson, self.allowable_pressure)

    @property
    def label(self) -> str:
        """Its name for people: a family names its grade (``aluminium (as 6061-t6)``)."""
        return f"{self.name} (as {self.grade})" if self.grade else self.name


_GPA, _MPA, _UM = 1e9, 1e6, 1e-6


def _yield(y_mpa: float) -> tuple[float, float, str]:
    return FIRST_YIELD_FACTOR * y_mpa * _MPA, y_mpa * _MPA, f"first yield, Y = {y_mpa:g} MPa"


_GRADES = (
    Material(
        "52100",
        7810.0,
        210 * _GPA,
        0.30,
        4200 * _MPA,
        2030 * _MPA,
        11.9 * _UM,
        "static rating (ISO 76)",
        "E, nu: SKF super-precision bearings catalogue, 'Materials for bearing rings and "
        "rolling elements', table 1 (100Cr6 = AISI 52100, 58-65 HRC); p: ISO 76:2006 §3.1 "
        "(the ISO 281/ISO 76 bearing-steel basis); density, Y, alpha: MatWeb AISI 52100 "
        "(hardened, typical)",
        typical=False,
    ),
    Material(
        "440c",
        7800.0,
        200 * _GPA,
        0.28,
        *_yield(1900)[:2],
        10.2 * _UM,
        _yield(1900)[2],
        "AK Steel 440C product data bulletin (hardened 1010 °C, tempered 316 °C: Y = 1900 MPa; "
        "E = 200 GPa; density 7.80 g/cm3; alpha 10.2 µm/m/K, 20-100 °C); nu typical for "
        "martensitic stainless steel",
    ),
    Material(
        "17-4ph-h900",
        7780.0,
        197 * _GPA,
        0.27,
        *_yield(1170)[:2],
        10.8 * _UM,
        _yield(1170)[2],
        "ASTM A564 (17-4PH, H900, minimum Y = 1170 MPa); E, nu, density, alpha (10.8 µm/m/K, "
        "21-93 °C): AK Steel 17-4PH bulletin (typical)",
        typical=False,
    ),
    Material(
        "stainless-304",
        8000.0,
        193 * _GPA,
        0.29,
        *_yield(205)[:2],
        17.3 * _UM,
        _yield(205)[2],
        "ASTM A240 (annealed 304, minimum Y = 205 MPa); E, nu, density, alpha: AK Steel 304 "
        "bulletin (typical)",
        typical=False,
    ),
    Material(
        "aisi-1018",
        7870.0,
        205 * _GPA,
        0.29,
        *_yield(370)[:2],
        11.5 * _UM,
        _yield(370)[2],
        "MatWeb / ASM Metals Handbook vol. 1, AISI 1018 cold drawn: Y = 370 MPa, E = 205 GPa, "
        "nu = 0.29, alpha 11.5 µm/m/K (typical)",
    ),
    Material(
        "6061-t6",
        2700.0,
        68.9 * _GPA,
        0.33,
        *_yield(276)[:2],
        23.6 * _UM,
        _yield(276)[2],
        "ASM Aerospace Specification Metals, Aluminum 6061-T6 (E = 68.9 GPa, nu = 0.33, "
        "Y = 276 MPa, density 2.70 g/cm3, alpha 23.6 µm/m/K 20-100 °C; typical)",
    ),
    Material(
        "7075-t6",
        2810.0,
        71.7 * _GPA,
        0.33,
        *_yield(503)[:2],
        23.6 * _UM,
        _yield(503)[2],
        "ASM Aerospace Specification Metals, Aluminum 7075-T6 (E = 71.7 GPa, nu = 0.33, "
        "Y = 503 MPa, density 2.81 g/cm3, alpha 23.6 µm/m/K 20-100 °C; typical)",
    ),
    Material(
        "ti-6al-4v",
        4430.0,
        113.8 * _GPA,
        0.342,
        *_yield(880)[:2],
        8.6 * _UM,
        _yield(880)[2],
        "ASM Aerospace Specification Metals, Titanium Ti-6Al-4V (Grade 5), annealed "
        "(E = 113.8 GPa, nu = 0.342, Y = 880 MPa, density 4.43 g/cm3, alpha 8.6 µm/m/K "
        "20-100 °C; typical)",
    ),
    Material(
        "silicon-nitride",
        3200.0,
        310 * _GPA,
        0.26,
        ring_crack(800 * _MPA, 0.26),
        None,
        3.2 * _UM,
        "ring crack, flexural strength 800 MPa",
        "E, nu, density, alpha: SKF super-precision bearings catalogue, table 1 "
        "(bearing-grade Si3N4); flexural strength: a typical datasheet value of hot-"
        "isostatically pressed bearing-grade Si3N4 (not a specification minimum)",
    ),
    Material(
        "zirconia",
        6050.0,
        205 * _GPA,
        0.31,
        min(ring_crack(900 * _MPA, 0.31), 2500 * _MPA),
        None,
        10.3 * _UM,
        "compressive strength 2500 MPa (below the ring-crack value of flexural strength 900 MPa)",
        "typical datasheet values of yttria-stabilised tetragonal zirconia (3Y-TZP), e.g. "
        "CoorsTek YTZP: E = 205 GPa, nu = 0.31, flexural 900 MPa, compressive 2500 MPa, "
        "density 6.05 g/cm3, alpha 10.3 µm/m/K",
    ),
    Material(
        "tungsten-carbide",
        14950.0,
        620 * _GPA,
        0.22,
        min(ring_crack(2000 * _MPA, 0.22), 5300 * _MPA),
        None,
        5.5 * _UM,
        "compressive strength 5300 MPa (below the ring-crack value of transverse rupture "
        "strength 2000 MPa)",
        "typical datasheet values of cemented carbide WC-6Co (e.g. Sandvik/Kennametal grade "
        "sheets): E = 620 GPa, nu = 0.22, TRS 2000 MPa, compressive 5300 MPa, density "
        "14.95 g/cm3, alpha 5.5 µm/m/K",
    ),
    Material(
        "alumina",
        3890.0,
        370 * _GPA,
        0.22,
        ring_crack(379 * _MPA, 0.22),
        None,
        8.2 * _UM,
        "ring crack, flexural strength 379 MPa",
        "CoorsTek AD-995 (99.5 % Al2O3) datasheet: E = 370 GPa, nu = 0.22, flexural strength "
        "379 MPa, density 3.89 g/cm3, alpha 8.2 µm/m/K (typical)",
    ),
    Material(
        "pla",
        1240.0,
        2.35 * _GPA,
        0.36,
        *_yield(49.5)[:2],
        68 * _UM,
        _yield(49.5)[2] + " (printed)",
        "Ultimaker PLA technical data sheet (printed ISO 527 bars: E = 2346.5 MPa, "
        "Y = 49.5 MPa, density 1.24 g/cm3); nu and alpha typical for PLA",
    ),
    Material(
        "petg",
        1270.0,
        2.0 * _GPA,
        0.38,
        *_yield(44)[:2],
        68 * _UM,
        _yield(44)[2] + " (printed)",
        "additive.tools PETG, FDM as-built XY: E 2-3 GPa, tensile strength 44-56 MPa "
        "(lower ends taken), density 1.27 g/cm3; nu, alpha typical for amorphous polyesters",
    ),
)

#: Generic names: their own nominal density, everything else from ``grade`` (the weakest
#: common grade of the family). Densities: room temperature, typical engineering grades.
_FAMILIES = (
    ("aluminium", 2700.0, "6061-t6"),
    ("steel", 7850.0, "aisi-1018"),
    ("stainless-steel", 8000.0, "stainless-304"),
    ("titanium", 4430.0, "ti-6al-4v"),
    ("ceramic-alumina", 3950.0, "alumina"),
)

#: Materials with a density only (mass properties); hertz cannot use them.
_DENSITY_ONLY = (
    Material("cast-iron", 7200.0, thermal_expansion=10.8 * _UM),
    Material("invar", 8050.0, thermal_expansion=1.2 * _UM),
    Material("brass", 8500.0, thermal_expansion=20.5 * _UM),
    Material("bronze", 8800.0, thermal_expansion=18.0 * _UM),
    Material("copper", 8960.0, thermal_expansion=17.0 * _UM),
    Material("granite", 2700.0, thermal_expansion=6.0 * _UM),
    Material("zerodur", 2530.0, thermal_expansion=0.0),
    Material("fused-silica", 2200.0, thermal_expansion=0.55 * _UM),
    Material("glass", 2500.0, thermal_expansion=9.0 * _UM),
    Material("silicon-carbide", 3100.0, thermal_expansion=4.0 * _UM),
    Material("pom", 1410.0),
    Material("peek", 1320.0),
    Material("nylon", 1150.0),
    Material("abs", 1040.0),
)


def _family(name: str, density: float, grade: str) -> Material:
    base = next(m for m in _GRADES if m.name == grade)
    return replace(base, name=name, density=density, grade=grade)


#: Every material by its canonical name.
TABLE: dict[str, Material] = {
    m.name: m
    for m in (
        *_GRADES,
        *(_family(*f) for f in _FAMILIES),
        *(replace(m, source="nominal handbook values, typical") for m in _DENSITY_ONLY),
    )
}

#: Other names for table entries (AISI/DIN designations, spellings).
ALIASES: dict[str, str] = {
    "aluminum": "aluminium",
    "100cr6": "52100",
    "aisi-52100": "52100",
    "bearing-steel": "52100",
    "chrome-steel": "52100",
    "aisi-440c": "440c",
    "x105crmo17": "440c",
    "17-4ph": "17-4ph-h900",
    "17-4-ph-h900": "17-4ph-h900",
    "630-h900": "17-4ph-h900",
    "304": "stainless-304",
    "aisi-304": "stainless-304",
    "1018": "aisi-1018",
    "6061": "6061-t6",
    "aluminium-6061-t6": "6061-t6",
    "aluminum-6061-t6": "6061-t6",
    "7075": "7075-t6",
    "aluminium-7075-t6": "7075-t6",
    "aluminum-7075-t6": "7075-t6",
    "ti64": "ti-6al-4v",
    "ti-6-4": "ti-6al-4v",
    "grade-5-titanium": "ti-6al-4v",
    "si3n4": "silicon-nitride",
    "zro2": "zirconia",
    "y-tzp": "zirconia",
    "wc": "tungsten-carbide",
    "wc-co": "tungsten-carbide",
    "carbide": "tungsten-carbide",
    "al2o3": "alumina",
}

#: Density by every accepted name (canonical and alias), for messages and old callers.
MATERIALS: dict[str, float] = {
    name: d
    for name, d in (
        *((n, m.density) for n, m in TABLE.items()),
        *((a, TABLE[c].density) for a, c in ALIASES.items()),
    )
    if d is not None
}


def canonical(name: str | int) -> str | None:
    """The table's name for a material name or alias (case, ``_``, spaces ignored; a number
    such as 52100 written unquoted in YAML accepted), or None if unknown."""
    key = str(name).strip().lower().replace("_", "-").replace(" ", "-")
    key = ALIASES.get(key, key)
    return key if key in TABLE else None


def lookup(name: str | int) -> Material | None:
    """The material of a name or alias, or None if the table does not have it."""
    key = canonical(name)
    return None if key is None else TABLE[key]


def density_of(material: str | int) -> float | None:
    """Density in kg/m^3 of a named material, or None if the table does not have it."""
    found = lookup(material)
    return None if found is None else found.density


def known_names() -> str:
    """The table's canonical names, for error messages."""
    return ", ".join(sorted(TABLE))
