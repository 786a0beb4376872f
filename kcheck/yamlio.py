"""Safe YAML reading with YAML 1.2 numbers, no duplicate keys, and line numbers per field.

PyYAML speaks YAML 1.1: ``1e3`` would be a string and ``yes``/``on`` booleans, and a repeated
key silently wins. Scene files are engineering input, so this loader reads ``1e3`` as a number,
only ``true``/``false`` as booleans, and rejects duplicate keys with both line numbers.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from kcheck.errors import FieldPath, SceneError, format_path

__all__ = ["FieldPath", "LineMap", "load_yaml", "format_path"]

LineMap = Mapping[FieldPath, int]

_FLOAT_TAG = "tag:yaml.org,2002:float"
_BOOL_TAG = "tag:yaml.org,2002:bool"
# YAML 1.2 core-schema floats: a dot is optional when an exponent is present.
_FLOAT_12 = re.compile(
    r"""^(?:[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?(?:[eE][-+]?[0-9]+)?
    |[-+]?\.[0-9_]+(?:[eE][-+]?[0-9]+)?
    |[-+]?\.(?:inf|Inf|INF)
    |\.(?:nan|NaN|NAN))$""",
    re.X,
)
_BOOL_12 = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")


class _Loader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 floats and booleans."""


_Loader.yaml_implicit_resolvers = {
    first: [(tag, rx) for tag, rx in resolvers if tag not in (_FLOAT_TAG, _BOOL_TAG)]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_Loader.add_implicit_resolver(_FLOAT_TAG, _FLOAT_12, list("-+0123456789."))
_Loader.add_implicit_resolver(_BOOL_TAG, _BOOL_12, list("tTfF"))
# An int-looking scalar must stay an int: the int resolver was registered first and wins.


def _convert(
    loader: _Loader, node: yaml.Node, path: FieldPath, lines: dict[FieldPath, int], file: Path
) -> Any:
    lines.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        out: dict[Any, Any] = {}
        key_lines: dict[Any, int] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                raise SceneError(
                    file,
                    "mapping keys must be plain names",
                    field=format_path(path) or None,
                    line=key_node.start_mark.line + 1,
                )
            key = loader.construct_object(key_node)
            key_line = key_node.start_mark.line + 1
            if key in out:
                raise SceneError(
                    file,
                    f"duplicate key `{key}` (first given on line {key_lines[key]})",
                    field=format_path((*path, key)),
                    line=key_line,
                )
            key_lines[key] = key_line
            lines[(*path, key)] = key_line
            out[key] = _convert(loader, value_node, (*path, key), lines, file)
        return out
    if isinstance(node, yaml.SequenceNode):
        return [
            _convert(loader, item, (*path, i), lines, file) for i, item in enumerate(node.value)
        ]
    return loader.construct_object(node)


def load_yaml(path: Path) -> tuple[Any, dict[FieldPath, int]]:
    """Read a YAML file safely; return its data and the 1-based line of every field path."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(path, f"cannot read the file ({exc})") from exc
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            raise SceneError(path, "the file is empty; expected a scene mapping")
        lines: dict[FieldPath, int] = {}
        data = _convert(loader, node, (), lines, path)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = None if mark is None else mark.line + 1
        problem = exc.problem or exc.context or "invalid YAML"
        raise SceneError(path, f"YAML syntax error: {problem}", line=line) from exc
    except yaml.YAMLError as exc:
        raise SceneError(path, f"YAML error: {exc}") from exc
    finally:
        loader.dispose()
    return data, lines
