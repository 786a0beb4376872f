"""The scene format's JSON Schema (``docs/kcheck-scene.schema.json``, the same as ``kcheck
schema``), walked along a scene's data: whether a field path is a field of the format in the
branch the data takes (a `ball-vee` coupling has `groove.up`, not `up`). Written here, not
taken from kcheck: the oracle of "errors sit at real fields" (issue 25)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

__all__ = ["SCHEMA", "MISSING", "in_schema", "parse_path"]

SCHEMA = json.loads(
    (Path(__file__).resolve().parents[2] / "docs" / "kcheck-scene.schema.json").read_text()
)

MISSING = object()


def _resolve(node: dict) -> dict:
    while "$ref" in node:
        name = node["$ref"].split("/")[-1]
        node = {**SCHEMA["definitions"][name], **{k: v for k, v in node.items() if k != "$ref"}}
    return node


_TYPES = {"object": dict, "array": list, "string": str, "null": type(None), "boolean": bool}


def _fits(node: dict, data: Any) -> bool:
    """Whether ``data`` can be an instance of this branch (its type, its `type` tag, its keys)."""
    if data is MISSING:
        return True
    kind = node.get("type")
    if kind in ("number", "integer"):
        return isinstance(data, (int, float)) and not isinstance(data, bool)
    if kind in _TYPES and not isinstance(data, _TYPES[kind]):
        return False
    if isinstance(data, dict) and node.get("type") == "object":
        props = node.get("properties", {})
        tags = {}
        for key, sub in props.items():
            sub = _resolve(sub)
            if "const" in sub:
                tags[key] = sub["const"]
            elif sub.get("enum") and len(sub["enum"]) == 1:
                tags[key] = sub["enum"][0]
        given = {k: v for k, v in tags.items() if k in data}
        if given:  # a tagged branch (a coupling's `type`): the tag decides
            return all(data[k] == v for k, v in given.items())
        if node.get("additionalProperties") is False and not set(data) <= set(props):
            return False
    return True


def _branches(node: dict, data: Any) -> list[dict]:
    node = _resolve(node)
    for key in ("anyOf", "oneOf"):
        if key in node:
            out = []
            for b in node[key]:
                b = _resolve(b)
                if any(k in b for k in ("anyOf", "oneOf")) or _fits(b, data):
                    out.extend(_branches(b, data))
            if not out:  # the data fits no branch (an unknown tag): any may be meant
                return [b for b in node[key] for b in _branches(b, MISSING)]
            return out
    if "allOf" in node:
        merged: dict = {}
        for b in node["allOf"]:
            merged.update(_resolve(b))
        return [merged]
    return [node]


def _child(data: Any, part: Any) -> Any:
    if isinstance(part, int):
        return data[part] if isinstance(data, list) and part < len(data) else MISSING
    return data.get(part, MISSING) if isinstance(data, dict) else MISSING


def in_schema(path: tuple, data: Any) -> bool:
    """Whether the field ``path`` exists in the schema, along the branches ``data`` takes."""
    frontier = [(SCHEMA, data)]
    for part in path:
        nxt = []
        for node, here in frontier:
            for b in _branches(node, here):
                if isinstance(part, int):
                    if "items" in b:
                        nxt.append((b["items"], _child(here, part)))
                elif part in b.get("properties", {}):
                    nxt.append((b["properties"][part], _child(here, part)))
                elif isinstance(b.get("additionalProperties"), dict):
                    nxt.append((b["additionalProperties"], _child(here, part)))
                elif b.get("additionalProperties") is True:
                    nxt.append(({}, _child(here, part)))
        if not nxt:
            return False
        frontier = nxt
    return True


def parse_path(text: str) -> tuple[Any, ...]:
    """A field path as kcheck writes it (``couplings[0].groove.up``) as a tuple."""
    return tuple(
        int(index) if index else name for name, index in re.findall(r"([^.\[\]]+)|\[(\d+)\]", text)
    )
