"""Scene files (``*.kcheck.yaml``, version 1): validation, and the scene model in SI units.

Loading a scene reads YAML and checks fields only; it never reads a mesh (that is
:mod:`kcheck.body.mass`, called only when a check needs mass properties). The package is split by
concept: :mod:`.types` (the validated scene), :mod:`.models` (the file's fields),
:mod:`.limits` (accepted ranges), :mod:`.validate` (error collection and wording),
:mod:`.load` (reading: supports, forces, frames), :mod:`.body` (meshes, parts, mass),
:mod:`.shorthands` (coupling entries, expanded through :mod:`kcheck.scene.couplings`),
:mod:`.schema` (JSON Schema).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from kcheck.scene.load import SCENE_GLOB, load_scene
    from kcheck.scene.schema import scene_json_schema
    from kcheck.scene.types import (
        PLANAR_TOL,
        Body,
        ContactGeometry,
        ExplicitMass,
        Friction,
        Load,
        Part,
        PointMass,
        Preload,
        Scene,
        Support,
        Surface,
        Sweep,
        Tolerances,
    )
    from kcheck.scene.validate import describe_pydantic

# The names below are read from their modules on first use (PEP 562): the package also holds
# the YAML reader, which `kcheck config` and path discovery use without numpy or pydantic.
_HOME = {
    "SCENE_GLOB": "load",
    "load_scene": "load",
    "scene_json_schema": "schema",
    "describe_pydantic": "validate",
    **dict.fromkeys(
        (
            "PLANAR_TOL Body ContactGeometry ExplicitMass Friction Load Part PointMass Preload "
            "Scene Support Surface Sweep Tolerances"
        ).split(),
        "types",
    ),
}


def __getattr__(name: str) -> Any:
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{home}"), name)
    globals()[name] = value
    return value


__all__ = [
    "PLANAR_TOL",
    "SCENE_GLOB",
    "Surface",
    "ContactGeometry",
    "Support",
    "Friction",
    "Tolerances",
    "Preload",
    "Load",
    "Sweep",
    "Part",
    "PointMass",
    "ExplicitMass",
    "Body",
    "Scene",
    "load_scene",
    "scene_json_schema",
    "describe_pydantic",
]
