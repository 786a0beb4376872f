"""Length units of scene files and the built-in material table (SI densities)."""

from __future__ import annotations

__all__ = ["LENGTH_TO_M", "MATERIALS", "density_of"]

#: Metres per scene length unit.
LENGTH_TO_M: dict[str, float] = {
    "m": 1.0,
    "cm": 1e-2,
    "mm": 1e-3,
    "um": 1e-6,
    "in": 0.0254,
}

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
