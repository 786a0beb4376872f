"""The built-in material table: names a scene's `material` may use, and their densities (SI).

It lives with the scene because scene files are validated against it. Elastic constants and
allowable contact pressures of contact materials are :mod:`kcheck.body.elastic`.
"""

from __future__ import annotations

__all__ = ["MATERIALS", "density_of"]

#: Nominal densities in kg/m^3 (room temperature, typical engineering grades).
MATERIALS: dict[str, float] = {
    "aluminium": 2700.0,
    "aluminum": 2700.0,
    "steel": 7850.0,
    "stainless-steel": 8000.0,
    "cast-iron": 7200.0,
    "invar": 8050.0,
    "brass": 8500.0,
    "bronze": 8800.0,
    "copper": 8960.0,
    "titanium": 4430.0,
    "granite": 2700.0,
    "zerodur": 2530.0,
    "fused-silica": 2200.0,
    "glass": 2500.0,
    "ceramic-alumina": 3950.0,
    "silicon-carbide": 3100.0,
    "tungsten-carbide": 15600.0,
    "pom": 1410.0,
    "peek": 1320.0,
    "nylon": 1150.0,
    "abs": 1040.0,
    "pla": 1240.0,
}


def density_of(material: str) -> float | None:
    """Density in kg/m^3 of a named material, or None if the table does not have it."""
    return MATERIALS.get(material.strip().lower().replace("_", "-").replace(" ", "-"))
