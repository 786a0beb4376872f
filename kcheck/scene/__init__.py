"""Scene files (``*.kcheck.yaml``, version 1): validation, and the scene model in SI units.

Loading a scene reads YAML and checks fields only; it never reads a mesh (that is
:mod:`kcheck.mass`, called only when a check needs mass properties). The package is split by
concept: :mod:`.types` (the validated scene), :mod:`.models` (the file's fields),
:mod:`.limits` (accepted ranges), :mod:`.validate` (error collection and wording),
:mod:`.load` (reading: supports, forces, frames), :mod:`.body` (meshes, parts, mass),
:mod:`.shorthands` (coupling entries, expanded through :mod:`kcheck.couplings`),
:mod:`.schema` (JSON Schema).
"""

from __future__ import annotations

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

#: Kept for the runner (options of checks): one pydantic error in words.
_describe_pydantic = describe_pydantic

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
