"""The one exception tree of kcheck; only the CLI turns these into output and exit codes."""

from __future__ import annotations

import errno
from pathlib import Path

__all__ = [
    "FieldPath",
    "KcheckError",
    "SceneError",
    "SceneErrors",
    "MeshError",
    "PluginError",
    "UsageError",
    "format_path",
]

FieldPath = tuple[str | int, ...]


def format_path(path: FieldPath) -> str:
    """Render a field path like ``supports[1].normal``."""
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out


class KcheckError(Exception):
    """Root of every error kcheck raises on purpose."""


class SceneError(KcheckError):
    """Bad input in a scene file: names the file, the field, the line and what was expected."""

    def __init__(
        self,
        path: Path | str,
        message: str,
        *,
        field: str | FieldPath | None = None,
        line: int | None = None,
        column: int | None = None,
    ) -> None:
        self.path = str(path)
        self.where: FieldPath | None = field if isinstance(field, tuple) else None
        self.field = format_path(field) if isinstance(field, tuple) else field
        self.line = line
        self.column = column
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        where = self.path if self.line is None else f"{self.path}:{self.line}"
        if self.line is not None and self.column is not None:
            where += f":{self.column}"
        what = f"field `{self.field}`: " if self.field else ""
        return f"{where}: {what}{self.message}"

    def all(self) -> tuple[SceneError, ...]:
        """Every error this one stands for (itself; :class:`SceneErrors` holds several)."""
        return (self,)


class SceneErrors(SceneError):
    """Several input errors of one file, reported together (the first one leads)."""

    def __init__(self, errors: list[SceneError]) -> None:
        if not errors:
            raise ValueError("SceneErrors needs at least one error")
        self.errors = tuple(e for err in errors for e in err.all())
        first = self.errors[0]
        super().__init__(
            first.path,
            first.message,
            field=first.where or first.field,
            line=first.line,
            column=first.column,
        )

    def __str__(self) -> str:
        return "\n".join(SceneError.__str__(e) for e in self.errors)

    def all(self) -> tuple[SceneError, ...]:
        """Every error of the file, in file order."""
        return self.errors


class MeshError(SceneError):
    """A mesh that cannot give meaningful mass properties (open, inverted, empty, ...)."""


class PluginError(KcheckError):
    """A check plugin that cannot be loaded or declares itself wrongly."""


class UsageError(KcheckError):
    """A bad command line or configuration (exit code 2, no scene involved)."""


def describe_os_error(exc: OSError) -> str:
    """A short reason for an OS error, without the repeated file name."""
    reasons = {
        errno.ENAMETOOLONG: "the path is too long for the operating system",
        errno.ELOOP: "too many levels of symbolic links (a symlink loop)",
        errno.EACCES: "permission denied",
        errno.EPERM: "operation not permitted",
        errno.ENOTDIR: "a part of the path is a file, not a folder",
        errno.EISDIR: "it is a folder, not a file",
        errno.ENOSPC: "no space left on the device",
        errno.EROFS: "the file system is read-only",
        errno.ENOENT: "no such file or folder",
        errno.ENXIO: "a pipe that nobody reads",
    }
    return reasons.get(exc.errno or 0, exc.strerror or str(exc))
