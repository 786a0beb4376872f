"""Safe, bounded YAML reading with YAML 1.2 scalars, no duplicate keys, and the line and
column of every field.

PyYAML speaks YAML 1.1: ``1e3`` would be a string, ``yes``/``on`` booleans, ``010`` the octal
8 and ``1:20`` the sexagesimal 80, and a repeated key silently wins. Scene files are
engineering input, so this reader resolves plain scalars by the YAML 1.2 core schema, rejects
duplicate keys with both line numbers, and builds the data itself from the parser's event
stream (libyaml's C parser when PyYAML has it, else PyYAML's pure-Python parser), which lets it
enforce limits while reading: file size, nesting depth, the number of values, and how much
aliases may expand (alias bombs and recursive aliases are refused early, in bounded time and
memory). Only plain data comes out: mappings with string keys, lists, strings, numbers,
booleans and null. No tag can construct an object, and no code runs.
"""

from __future__ import annotations

import codecs
import math
import re
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, NamedTuple

import yaml

from kcheck.errors import FieldPath, SceneError, format_path

__all__ = [
    "FieldPath",
    "LineMap",
    "YamlLimits",
    "YamlDocument",
    "DEFAULT_LIMITS",
    "load_yaml",
    "read_yaml",
    "format_path",
    "HAVE_LIBYAML",
    "dump_yaml",
]

LineMap = Mapping[FieldPath, int]

#: Whether PyYAML was built with libyaml (the C parser is then used by default).
HAVE_LIBYAML = bool(getattr(yaml, "__with_libyaml__", False))


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


class YamlDocument(NamedTuple):
    """Plain data of one YAML document, and the 1-based line and column of every field
    (a mapping key's position for a mapping value, the item's for a list item)."""

    data: Any
    lines: dict[FieldPath, int]
    columns: dict[FieldPath, int]


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


class _Located(Exception):
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


def _plain(value: str, line: int, column: int) -> Any:
    """A plain (unquoted, untagged) scalar by the YAML 1.2 core schema."""
    if _NULL.match(value):
        return None
    if _BOOL.match(value):
        return value[0] in "tT"
    if _INT10.match(value):
        if len(value) > _MAX_INT_DIGITS:
            raise _Located(f"the number `{value[:20]}...` has too many digits", line, column)
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


def _scalar(event: yaml.ScalarEvent) -> Any:
    mark = event.start_mark
    tag, value = event.tag, event.value
    plain = event.implicit[0] and tag in (None, "!")
    if plain:
        return _plain(value, mark.line, mark.column)
    if tag in (None, "!", f"{_TAG}str"):
        return value
    if tag not in _SCALAR_TAGS:
        raise _Located(
            f"the tag `{tag}` is not allowed (scene files hold plain data only)",
            mark.line,
            mark.column,
        )
    result = _plain(value, mark.line, mark.column)
    kind = tag.removeprefix(_TAG)
    expected = {"int": int, "float": (int, float), "bool": bool, "null": type(None)}[kind]
    if not isinstance(result, expected) or (kind != "bool" and isinstance(result, bool)):
        raise _Located(f"`{value}` is not a valid !!{kind}", mark.line, mark.column)
    return float(result) if kind == "float" else result


_NO_KEY = object()
_KEY_KINDS: dict[type, str] = {type(None): "null (no value)", bool: "a boolean", int: "an integer"}


class _Frame:
    """An open mapping or list while its events arrive."""

    __slots__ = ("value", "path", "anchor", "size", "key", "key_line", "key_lines")

    def __init__(self, value: dict | list, path: FieldPath, anchor: str | None) -> None:
        self.value = value
        self.path = path
        self.anchor = anchor
        self.size = 1
        self.key: Any = _NO_KEY
        self.key_line = 0
        self.key_lines: dict[str, int] = {}


class _Composer:
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
        self.root: Any = _NO_KEY

    def _count(self, size: int, mark: yaml.Mark) -> None:
        self.values += size
        if self.values > self.limits.max_values:
            raise _Located(
                f"the document holds more than {self.limits.max_values} values "
                "(after expanding aliases); a scene file needs far fewer",
                mark.line,
                mark.column,
            )

    def _child_path(self, mark: yaml.Mark) -> FieldPath:
        """Path of the value about to be added (a collection starting), after checks."""
        if not self.stack:
            return ()
        top = self.stack[-1]
        if isinstance(top.value, list):
            return (*top.path, len(top.value))
        if top.key is _NO_KEY:
            raise _Located("mapping keys must be plain names, not lists or mappings", mark.line)
        return (*top.path, top.key)

    def _add(self, value: Any, size: int, mark: yaml.Mark, scalar: bool) -> None:
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
        elif top.key is _NO_KEY:
            self._key(top, value, mark, scalar)
            return
        else:
            top.value[top.key] = value
            top.key = _NO_KEY
        top.size += size

    def _key(self, top: _Frame, key: Any, mark: yaml.Mark, scalar: bool) -> None:
        line, column = mark.line, mark.column
        where = format_path(top.path) or "the top level"
        if not scalar or isinstance(key, (dict, list)):
            raise _Located("mapping keys must be plain names, not lists or mappings", line, column)
        if not isinstance(key, str):
            shown = "null" if key is None else str(key).lower() if isinstance(key, bool) else key
            kind = _KEY_KINDS.get(type(key), "a number")
            raise _Located(
                f"mapping keys must be names; `{shown}` (in {where}) is read as "
                f"{kind}: quote it if you mean the text",
                line,
                column,
                top.path,
            )
        if key in top.key_lines:
            raise _Located(
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
        if isinstance(event, yaml.ScalarEvent):
            top = self.stack[-1] if self.stack else None
            awaiting_key = top is not None and isinstance(top.value, dict) and top.key is _NO_KEY
            if (
                awaiting_key
                and event.value == "<<"
                and event.implicit[0]
                and event.tag in (None, "!")
            ):
                raise _Located(
                    "merge keys (`<<`) are not supported: write the fields out in full "
                    "(a scene file is read literally)",
                    mark.line,
                    mark.column,
                )
            self._count(1, mark)
            value = _scalar(event)
            if event.anchor is not None:
                self.anchors[event.anchor] = (value, 1)
            self._add(value, 1, mark, scalar=True)
        elif isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
            if event.tag not in (None, "!", *_COLLECTION_TAGS):
                raise _Located(
                    f"the tag `{event.tag}` is not allowed (scene files hold plain data only)",
                    mark.line,
                    mark.column,
                )
            if len(self.stack) >= self.limits.max_depth:
                raise _Located(
                    f"mappings and lists nest deeper than {self.limits.max_depth} levels",
                    mark.line,
                    mark.column,
                )
            self._count(1, mark)
            path = self._child_path(mark)
            if self.stack and isinstance(self.stack[-1].value, list):
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
                    top.key = _NO_KEY
                top.size += frame.size
            else:
                self.root = frame.value
                self.lines.setdefault((), 1)
        elif isinstance(event, yaml.AliasEvent):
            self._alias(event)

    def _alias(self, event: yaml.AliasEvent) -> None:
        mark, name = event.start_mark, event.anchor
        if name in self.open_anchors:
            raise _Located(
                f"the alias `*{name}` refers to a mapping or list that contains it "
                "(a recursive structure)",
                mark.line,
                mark.column,
            )
        if name not in self.anchors:
            raise _Located(f"the alias `*{name}` has no anchor `&{name}` before it", mark.line)
        value, size = self.anchors[name]
        self.alias_values += size
        if self.alias_values > self.limits.max_alias_values:
            raise _Located(
                f"aliases expand to more than {self.limits.max_alias_values} values "
                f"(`*{name}` alone stands for {size}); exponentially nested aliases "
                "(an alias bomb) are refused",
                mark.line,
                mark.column,
            )
        self._count(size, mark)
        top = self.stack[-1] if self.stack else None
        scalar = not isinstance(value, (dict, list))
        if top is not None and isinstance(top.value, dict) and top.key is not _NO_KEY:
            path = (*top.path, top.key)
            self.lines.setdefault(path, mark.line + 1)
        self._add(value, size, mark, scalar=scalar)


def _events(text: str, backend: str) -> Iterator[yaml.Event]:
    loader_class = yaml.CSafeLoader if backend == "c" else yaml.SafeLoader
    loader = loader_class(text)
    try:
        while True:
            event = loader.get_event()
            yield event
            if isinstance(event, yaml.StreamEndEvent):
                return
    finally:
        dispose: Callable[[], None] | None = getattr(loader, "dispose", None)
        if dispose is not None:
            dispose()


def _line_col(text: str, offset: int) -> tuple[int, int]:
    """1-based line and column of a character offset."""
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


_BOMS = (
    (codecs.BOM_UTF32_LE, "utf-32"),
    (codecs.BOM_UTF32_BE, "utf-32"),
    (codecs.BOM_UTF8, "utf-8-sig"),
    (codecs.BOM_UTF16_LE, "utf-16"),
    (codecs.BOM_UTF16_BE, "utf-16"),
)


def _read_text(path: Path, limits: YamlLimits) -> str:
    chunks: list[bytes] = []
    size = 0
    try:
        with open(path, "rb") as handle:
            # In pieces, so that neither a huge file nor an endless device is read whole.
            while size <= limits.max_bytes:
                chunk = handle.read(min(1 << 16, limits.max_bytes + 1 - size))
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
    except (OSError, ValueError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise SceneError(path, f"cannot read the file: {reason}") from None
    raw = b"".join(chunks)
    if len(raw) > limits.max_bytes:
        raise SceneError(
            path,
            f"the file is larger than {limits.max_bytes / 2**20:g} MiB; a scene file is a few "
            "kB (the limit is configurable)",
        )
    encoding = next((enc for bom, enc in _BOMS if raw.startswith(bom)), "utf-8")
    try:
        text = raw.decode(encoding)
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise SceneError(
            path,
            f"the file is not {encoding.upper()} text (byte 0x{raw[exc.start]:02x}); save it "
            "as UTF-8",
            line=line,
        ) from None
    nul = text.find("\x00")
    if nul >= 0:
        line, column = _line_col(text, nul)
        raise SceneError(
            path,
            "the file contains a NUL character (is it a binary file?)",
            line=line,
            column=column,
        )
    return text


def read_yaml(
    path: Path,
    *,
    limits: YamlLimits = DEFAULT_LIMITS,
    backend: Literal["auto", "c", "python"] = "auto",
) -> YamlDocument:
    """Read one YAML document safely within ``limits``; SceneError (located) otherwise.

    ``backend`` chooses the parser: libyaml's (``c``, the default when available) or
    PyYAML's pure-Python one; both give the same data, lines and columns.
    """
    path = Path(path)
    text = _read_text(path, limits)
    if backend == "auto":
        backend = "c" if HAVE_LIBYAML else "python"
    composer = _Composer(limits)
    documents = 0
    try:
        for event in _events(text, backend):
            if isinstance(event, yaml.DocumentStartEvent):
                documents += 1
                if documents > 1:
                    raise _Located(
                        "the file holds more than one YAML document (`---`); a scene file "
                        "is one mapping",
                        event.start_mark.line,
                    )
            elif not isinstance(
                event, (yaml.StreamStartEvent, yaml.StreamEndEvent, yaml.DocumentEndEvent)
            ):
                composer.event(event)
    except _Located as exc:
        raise SceneError(
            path,
            exc.message,
            field=exc.field or None,
            line=None if exc.line is None else exc.line + 1,
            column=None if exc.column is None else exc.column + 1,
        ) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        problem = exc.problem or exc.context or "invalid YAML"
        raise SceneError(
            path,
            f"YAML syntax error: {problem}",
            line=None if mark is None else mark.line + 1,
            column=None if mark is None else mark.column + 1,
        ) from None
    except yaml.YAMLError as exc:
        raise SceneError(path, f"YAML error: {exc}") from None
    if composer.root is _NO_KEY:
        raise SceneError(path, "the file is empty; expected a scene mapping")
    return YamlDocument(composer.root, composer.lines, composer.columns)


def load_yaml(
    path: Path, *, limits: YamlLimits = DEFAULT_LIMITS
) -> tuple[Any, dict[FieldPath, int]]:
    """Read a YAML file safely; return its data and the 1-based line of every field path."""
    document = read_yaml(path, limits=limits)
    return document.data, document.lines


class _Flow(dict):
    """A mapping written on one line."""


class _Dumper(yaml.SafeDumper):
    """Writes what :func:`read_yaml` reads back identically: strings that YAML 1.2 would
    read as something else are quoted, floats keep every digit (``repr``)."""

    def represent_str(self, data: str) -> yaml.ScalarNode:  # type: ignore[override]
        if not isinstance(_plain(data, 0, 0), str) or data in ("<<", "="):
            return self.represent_scalar("tag:yaml.org,2002:str", data, style="'")
        return super().represent_str(data)


_Dumper.add_representer(str, _Dumper.represent_str)
_Dumper.add_representer(
    _Flow, lambda d, data: d.represent_mapping("tag:yaml.org,2002:map", data, flow_style=True)
)


def dump_yaml(data: Any, flow_items: tuple[str, ...] = ()) -> str:
    """YAML text of plain data (keys in their order, lists of numbers on one line); items of
    the top-level lists named in ``flow_items`` are written one per line."""
    if isinstance(data, dict):
        data = {
            k: [_Flow(i) if isinstance(i, dict) else i for i in v]
            if k in flow_items and isinstance(v, list)
            else v
            for k, v in data.items()
        }
    return yaml.dump(
        data,
        Dumper=_Dumper,
        sort_keys=False,
        default_flow_style=None,
        allow_unicode=True,
        width=100,
    )
