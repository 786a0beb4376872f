"""The JSON Schema of scene files (draft-07, the dialect editors' YAML plugins support)."""

from __future__ import annotations

from typing import Any

from kcheck.scene.models import SceneModel

__all__ = ["scene_json_schema"]


def scene_json_schema() -> dict[str, Any]:
    """JSON Schema (draft-07 compatible) of the scene file format, version 1."""
    # draft-07 names shared definitions `definitions`, not 2020-12's `$defs`.
    schema = SceneModel.model_json_schema(ref_template="#/definitions/{model}")
    schema["definitions"] = schema.pop("$defs", {})
    schema["$schema"] = "http://json-schema.org/draft-07/schema#"
    schema["title"] = "kcheck scene, version 1 (*.kcheck.yaml)"
    return schema
