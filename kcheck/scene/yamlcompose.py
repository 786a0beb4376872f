"""Composing plain data from YAML parser events, with YAML 1.2 core-schema scalars and limits
enforced as the events arrive (the reading half of :mod:`kcheck.scene.yamlio`).

Works the same on libyaml's and PyYAML's event streams. Only plain data is built: mappings with
string keys, lists, strings, numbers, booleans and null; a tag that would construct anything
else is an error, and so are merge keys, recursive aliases and alias expansions beyond the
limit. Errors are :class:`Located` (0-based line and column), turned into SceneErrors by
:func:`kcheck.scene.yamlio.read_yaml`.
"""

from __future__ import annotations

import math
import re
from typing import Any, Protocol

from kcheck.errors import FieldPath, format_path
from kcheck.records import dataclass
from kcheck.scene.yamllib import yaml

__all__ = [
    "Located",
    "TooDeep",
    "Composer",
    "NOTHING",
    "plain_scalar",
    "YamlLimits",
    "DEFAULT_LIMITS",
]

# YAML 1.2 core schema (https://yaml.org/spec/1.2.2/#1032-tag-resolution).
_NULL = re.compile(r"^(?:~|null|Null|NULL|)$")
_BOOL = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
_INT10 = re.compile(r"^[-+]?[0-9]+$")
_INT8 = re.compile(r"^0o[0-7]+$")
_INT16 = re.compile(r"^0x[0-9a-fA-F]+$")
_FLOAT = re.compile(r"^[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?$")
_INF = re.compile(r"^[-+]?\.(?:inf|Inf|INF)$")
_NAN = re.compile(r"^\.(?:nan|NaN|NAN)$")
# Longest decimal integer accepted (Python refuses to convert longer ones by default).
_MAX_INT_DIGITS = 4000

_TAG = "tag:yaml.org,2002:"
_SCALAR_TAGS = {f"{_TAG}{t}" for t in ("str", "int", "float", "bool", "null")}
_COLLECTION_TAGS = {f"{_TAG}map", f"{_TAG}seq"}


@dataclass(frozen=True)
class YamlLimits:
    """Resource limits of one YAML file (configuration may change them).

    ``max_bytes``: file size; ``max_depth``: nesting of mappings and lists; ``max_values``:
    values (scalars, mappings, lists) in the document after expanding aliases;
    ``max_alias_values``: values that aliases may add in total (an alias counts the whole
    value it refers to each time it is used).
    """

    max_bytes: int = 5 * 1024 * 1024
    max_depth: int = 64
    max_values: int = 200_000
    max_alias_values: int = 10_000


DEFAULT_LIMITS = YamlLimits()


class Located(Exception):
    """An error at a position of the text (0-based line and column)."""

    def __init__(
        self,
        message: str,
        line: int | None,
        column: int | None = None,
        field: FieldPath | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column
        self.field = field


class TooDeep(Located):
    """Mappings and lists nested past the depth limit (the one limit libyaml has too)."""


#: First characters of every text the patterns below can match (the empty text aside): null
#: ``~ n N``, booleans ``t T f F``, numbers ``- + . 0-9``. Any other text is a string.
_NOT_PLAIN_TEXT = frozenset("~nNtTfF-+.0123456789")


def plain_scalar(value: str, line: int, column: int) -> Any:
    """A plain (unquoted, untagged) scalar by the YAML 1.2 core schema."""
    if value and value[0] not in _NOT_PLAIN_TEXT:
        return value  # no pattern can match: a name, most keys (one test, not eight)
    if _NULL.match(value):
        return None
    if _BOOL.match(value):
        return value[0] in "tT"
    if _INT10.match(value):
        if len(value) > _MAX_INT_DIGITS:
            raise Located(f"the number `{value[:20]}...` has too many digits", line, column)
        return int(value)
    if _INT8.match(value):
        return int(value[2:], 8)
    if _INT16.match(value):
        return int(value[2:], 16)
    if _FLOAT.match(value):
        return float(value)
    if _INF.match(value):
        return -math.inf if value[0] == "-" else math.inf
    if _NAN.match(value):
        return math.nan
    return value


class _Mark(Protocol):
    """Where an event starts: PyYAML's ``yaml.Mark`` or libyaml's (0-based)."""

    @property
    def line(self) -> int: ...

    @property
    def column(self) -> int: ...


def _scalar(event: yaml.ScalarEvent) -> Any:
    mark = event.start_mark
    assert mark is not None  # both parsers mark every event
    tag, value = event.tag, event.value
    plain = event.implicit[0] and tag in (None, "!")
    if plain:
        return plain_scalar(value, mark.line, mark.column)
    if tag in (None, "!", f"{_TAG}str"):
        return value
    if tag not in _SCALAR_TAGS:
        raise Located(
            f"the tag `{tag}` is not allowed (scene files hold plain data only)",
            mark.line,
            mark.column,
        )
    result = plain_scalar(value, mark.line, mark.column)
    kind = tag.removeprefix(_TAG)
    kinds: dict[str, type[Any] | tuple[type[Any], ...]]
    kinds = {"int": int, "float": (int, float), "bool": bool, "null": type(None)}
    expected = kinds[kind]
    if not isinstance(result, expected) or (kind != "bool" and isinstance(result, bool)):
        raise Located(f"`{value}` is not a valid !!{kind}", mark.line, mark.column)
    return float(result) if kind == "float" else result


#: The absence of a value (no pending key; no document root yet).
NOTHING = object()
_KEY_KINDS: dict[type, str] = {type(None): "null (no value)", bool: "a boolean", int: "an integer"}


class _Frame:
    """An open mapping or list while its events arrive."""

    __slots__ = ("value", "path", "anchor", "size", "key", "key_line", "key_lines")

    def __init__(self, value: dict | list, path: FieldPath, anchor: str | None) -> None:
        self.value = value
        self.path = path
        self.anchor = anchor
        self.size = 1
        self.key: Any = NOTHING
        self.key_line = 0
        self.key_lines: dict[str, int] = {}


class Composer:
    """Builds plain data from parser events, enforcing the limits as it goes."""

    def __init__(self, limits: YamlLimits) -> None:
        self.limits = limits
        self.stack: list[_Frame] = []
        self.anchors: dict[str, tuple[Any, int]] = {}
        self.open_anchors: set[str] = set()
        self.values = 0
        self.alias_values = 0
        self.lines: dict[FieldPath, int] = {}
        self.columns: dict[FieldPath, int] = {}
        self.root: Any = NOTHING

    def _count(self, size: int, mark: _Mark) -> None:
        self.values += size
        if self.values > self.limits.max_values:
            raise Located(
                f"the document holds more than {self.limits.max_values} values "
                "(after expanding aliases); a scene file needs far fewer",
                mark.line,
                mark.column,
            )

    def _child_path(self, mark: _Mark) -> FieldPath:
        """Path of the value about to be added (a collection starting), after checks."""
        if not self.stack:
            return ()
        top = self.stack[-1]
        if isinstance(top.value, list):
            return (*top.path, len(top.value))
        if top.key is NOTHING:
            raise Located("mapping keys must be plain names, not lists or mappings", mark.line)
        return (*top.path, top.key)

    def _add(self, value: Any, size: int, mark: _Mark, scalar: bool) -> None:
        if not self.stack:
            self.root = value
            self.lines[()] = mark.line + 1
            self.columns[()] = mark.column + 1
            return
        top = self.stack[-1]
        if isinstance(top.value, list):
            path = (*top.path, len(top.value))
            self.lines.setdefault(path, mark.line + 1)
            self.columns.setdefault(path, mark.column + 1)
            top.value.append(value)
        elif top.key is NOTHING:
            self._key(top, value, mark, scalar)
            return
        else:
            top.value[top.key] = value
            top.key = NOTHING
        top.size += size

    def _key(self, top: _Frame, key: Any, mark: _Mark, scalar: bool) -> None:
        line, column = mark.line, mark.column
        if not scalar or isinstance(key, (dict, list)):
            raise Located("mapping keys must be plain names, not lists or mappings", line, column)
        if not isinstance(key, str):
            where = format_path(top.path) or "the top level"
            shown = "null" if key is None else str(key).lower() if isinstance(key, bool) else key
            kind = _KEY_KINDS.get(type(key), "a number")
            raise Located(
                f"mapping keys must be names; `{shown}` (in {where}) is read as "
                f"{kind}: quote it if you mean the text",
                line,
                column,
                top.path,
            )
        if key in top.key_lines:
            raise Located(
                f"duplicate key `{key}` (first given on line {top.key_lines[key]})",
                line,
                column,
                (*top.path, key),
            )
        top.key_lines[key] = line + 1
        top.key = key
        path = (*top.path, key)
        self.lines[path] = line + 1
        self.columns[path] = column + 1

    def event(self, event: yaml.Event) -> None:
        mark = event.start_mark
        assert mark is not None  # both parsers mark every event
        if isinstance(event, yaml.ScalarEvent):
            top = self.stack[-1] if self.stack else None
            awaiting_key = top is not None and isinstance(top.value, dict) and top.key is NOTHING
            if (
                awaiting_key
                and event.value == "<<"
                and event.implicit[0]
                and event.tag in (None, "!")
            ):
                raise Located(
                    "merge keys (`<<`) are not supported: write the fields out in full "
                    "(a scene file is read literally)",
                    mark.line,
                    mark.column,
                )
            self.values += 1  # _count(1, mark), written out: most events are scalars
            if self.values > self.limits.max_values:
                self._count(0, mark)  # raises
            value = _scalar(event)
            if event.anchor is not None:
                self.anchors[event.anchor] = (value, 1)
            self._add(value, 1, mark, scalar=True)
        elif isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
            if event.tag not in (None, "!", *_COLLECTION_TAGS):
                raise Located(
                    f"the tag `{event.tag}` is not allowed (scene files hold plain data only)",
                    mark.line,
                    mark.column,
                )
            if len(self.stack) >= self.limits.max_depth:
                raise TooDeep(
                    f"mappings and lists nest deeper than {self.limits.max_depth} levels",
                    mark.line,
                    mark.column,
                )
            self._count(1, mark)
            path = self._child_path(mark)
            if not self.stack or isinstance(self.stack[-1].value, list):
                # a list item, or the document itself: where it starts (its first key)
                self.lines.setdefault(path, mark.line + 1)
                self.columns.setdefault(path, mark.column + 1)
            container: dict | list = {} if isinstance(event, yaml.MappingStartEvent) else []
            if event.anchor is not None:
                self.open_anchors.add(event.anchor)
            self.stack.append(_Frame(container, path, event.anchor))
        elif isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
            frame = self.stack.pop()
            if frame.anchor is not None:
                self.open_anchors.discard(frame.anchor)
                self.anchors[frame.anchor] = (frame.value, frame.size)
            if self.stack:
                top = self.stack[-1]
                if isinstance(top.value, list):
                    top.value.append(frame.value)
                else:
                    top.value[top.key] = frame.value
                    top.key = NOTHING
                top.size += frame.size
            else:
                self.root = frame.value
                self.lines.setdefault((), 1)
        elif isinstance(event, yaml.AliasEvent):
            self._alias(event)

    def _alias(self, event: yaml.AliasEvent) -> None:
        mark, name = event.start_mark, event.anchor
        assert mark is not None  # both parsers mark every event
        if name in self.open_anchors:
            raise Located(
                f"the alias `*{name}` refers to a mapping or list that contains it "
                "(a recursive structure)",
                mark.line,
                mark.column,
            )
        if name not in self.anchors:
            raise Located(f"the alias `*{name}` has no anchor `&{name}` before it", mark.line)
        value, size = self.anchors[name]
        self.alias_values += size
        if self.alias_values > self.limits.max_alias_values:
            raise Located(
                f"aliases expand to more than {self.limits.max_alias_values} values "
                f"(`*{name}` alone stands for {size}); exponentially nested aliases "
                "(an alias bomb) are refused",
                mark.line,
                mark.column,
            )
        self._count(size, mark)
        top = self.stack[-1] if self.stack else None
        scalar = not isinstance(value, (dict, list))
        if top is not None and isinstance(top.value, dict) and top.key is not NOTHING:
            path = (*top.path, top.key)
            self.lines.setdefault(path, mark.line + 1)
        self._add(value, size, mark, scalar=scalar)
