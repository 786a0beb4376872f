"""Length units of scene files (metres per unit)."""

from __future__ import annotations

__all__ = ["LENGTH_TO_M"]

#: Metres per scene length unit.
LENGTH_TO_M: dict[str, float] = {
    "m": 1.0,
    "cm": 1e-2,
    "mm": 1e-3,
    "um": 1e-6,
    "in": 0.0254,
}
