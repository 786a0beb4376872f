"""Elastic contact materials: the materials of the one table (:mod:`kcheck.scene.materials`)
that contact mechanics can use (Young's modulus, Poisson's ratio, allowable contact pressure,
with their sources; docs/materials.md). Nothing is defined here: the body, its parts and the
`hertz` check share one vocabulary.
"""

from __future__ import annotations

from kcheck.scene.materials import (
    ALIASES,
    FIRST_YIELD_FACTOR,
    TABLE,
    Material,
    canonical,
    lookup,
    ring_crack,
)

__all__ = ["Material", "MATERIALS", "ALIASES", "FIRST_YIELD_FACTOR", "material", "ring_crack"]

#: The materials with elastic constants and an allowable pressure, by canonical name.
MATERIALS: dict[str, Material] = {name: m for name, m in TABLE.items() if m.elastic}


def material(name: str | int) -> Material | None:
    """A material of the table by name or alias (case and ``_``/space insensitive), or None;
    it may lack elastic constants (``Material.elastic``)."""
    return lookup(name)


def elastic_names() -> str:
    """The names contact mechanics can use, for messages."""
    return ", ".join(sorted(MATERIALS))


__all__ += ["canonical", "elastic_names"]
