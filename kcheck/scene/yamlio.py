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
import errno
import os
import stat
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any, BinaryIO, Literal, NamedTuple

from kcheck.errors import FieldPath, SceneError, describe_os_error, format_path
from kcheck.scene.yamlcompose import (
    DEFAULT_LIMITS,
    NOTHING,
    Composer,
    Located,
    TooDeep,
    YamlLimits,
    plain_scalar,
)
from kcheck.scene.yamllib import yaml

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
    "open_regular",
    "NotRegularFile",
]

LineMap = Mapping[FieldPath, int]

#: Whether PyYAML was built with libyaml (the C parser is then used by default).
HAVE_LIBYAML = bool(getattr(yaml, "__with_libyaml__", False))


class YamlDocument(NamedTuple):
    """Plain data of one YAML document, and the 1-based line and column of every field
    (a mapping key's position for a mapping value, the item's for a list item)."""

    data: Any
    lines: dict[FieldPath, int]
    columns: dict[FieldPath, int]


def _events(text: str, backend: str) -> Iterator[yaml.Event]:
    loader_class = yaml.CSafeLoader if backend == "c" else yaml.SafeLoader
    loader = loader_class(text)
    try:
        while True:
            event = loader.get_event()
            assert event is not None  # None only after the StreamEndEvent
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


class NotRegularFile(OSError):
    """A path that is a pipe, socket or device, not a file to read."""


def open_regular(path: Path) -> BinaryIO:
    """Open a regular file for reading in binary; NotRegularFile (an OSError) for a FIFO,
    socket or device. Opened without blocking, so that a FIFO with no writer cannot hang
    the caller (the flag does nothing on regular files)."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise NotRegularFile(
                errno.EINVAL, "not a regular file (a pipe, socket or device)", str(path)
            )
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _read_text(path: Path, limits: YamlLimits) -> str:
    chunks: list[bytes] = []
    size = 0
    try:
        with open_regular(path) as handle:
            # In pieces, so that neither a huge file nor an endless device is read whole.
            while size <= limits.max_bytes:
                chunk = handle.read(min(1 << 16, limits.max_bytes + 1 - size))
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
    except (OSError, ValueError) as exc:
        reason = describe_os_error(exc) if isinstance(exc, OSError) else str(exc)
        raise SceneError(path, f"cannot read the file: {reason}") from None
    raw = b"".join(chunks)
    if len(raw) > limits.max_bytes:
        raise SceneError(
            path,
            f"the file is larger than {limits.max_bytes / 2**20:g} MiB; a scene file is a few "
            "kB (the limit is configuration `max_file_size`)",
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
    try:
        try:
            composer = _compose(text, backend, limits)
        except yaml.YAMLError as exc:
            if backend != "c":
                raise
            # libyaml has limits of its own (a nesting depth, in PyYAML 6.0.4's wheels) and
            # its own wording. The pure-Python parser with kcheck's composer is the reference
            # for every error, so both parsers give kcheck's message at the same place. It
            # first reads only the text up to libyaml's error (its mark counts bytes, never
            # fewer than characters): kcheck's depth limit met there is the answer (nesting
            # does not depend on what follows), found in milliseconds even for 50,000 nested
            # lists; anything else is decided on the whole text.
            mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
            if mark is not None and mark.index + 1 < len(text):
                try:
                    _compose(text[: mark.index + 1], "python", limits)
                except (yaml.YAMLError, Located) as prefix_error:
                    if isinstance(prefix_error, TooDeep):
                        raise
            composer = _compose(text, "python", limits)
    except Located as exc:
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
    except yaml.reader.ReaderError as exc:
        raise _forbidden_character(path, text, exc) from None
    except yaml.YAMLError as exc:
        raise SceneError(path, f"YAML error: {exc}") from None
    if composer.root is NOTHING:
        raise SceneError(path, "the file is empty; expected a scene mapping")
    return YamlDocument(composer.root, composer.lines, composer.columns)


def _compose(text: str, backend: str, limits: YamlLimits) -> Composer:
    """Plain data of ``text`` from the chosen parser's events; Located for kcheck's own
    limits and rules, the parser's YAMLError for invalid YAML."""
    composer = Composer(limits)
    documents = 0
    scalar = yaml.ScalarEvent
    for event in _events(text, backend):
        if isinstance(event, scalar):  # most events: straight to the composer
            composer.event(event)
        elif isinstance(event, yaml.DocumentStartEvent):
            documents += 1
            if documents > 1:
                assert event.start_mark is not None  # both parsers mark every event
                raise Located(
                    "the file holds more than one YAML document (`---`); a scene file "
                    "is one mapping",
                    event.start_mark.line,
                )
        elif not isinstance(
            event, (yaml.StreamStartEvent, yaml.StreamEndEvent, yaml.DocumentEndEvent)
        ):
            composer.event(event)
    return composer


def _forbidden_character(path: Path, text: str, exc: yaml.reader.ReaderError) -> SceneError:
    """A character YAML does not allow (a control character), at its line and column.

    The parsers give its position in bytes (libyaml) or characters (PyYAML); the character
    itself is the same in both, so it is looked up in the text."""
    char = chr(exc.character) if isinstance(exc.character, int) else str(exc.character)
    offset = text.find(char)
    line, column = _line_col(text, offset) if offset >= 0 else (None, None)
    return SceneError(
        path,
        f"the file contains the character U+{ord(char):04X}, which YAML does not "
        "allow (a control character); remove it",
        line=line,
        column=column,
    )


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

    def represent_str(self, data: str) -> yaml.ScalarNode:
        if not isinstance(plain_scalar(data, 0, 0), str) or data in ("<<", "="):
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
