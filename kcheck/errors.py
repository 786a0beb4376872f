"""The one exception tree of kcheck; only the CLI turns these into output and exit codes."""

from __future__ import annotations

from pathlib import Path

__all__ = ["FieldPath", "KcheckError", "SceneError", "MeshError", "PluginError", "format_path"]

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
    ) -> None:
        self.path = str(path)
        self.where: FieldPath | None = field if isinstance(field, tuple) else None
        self.field = format_path(field) if isinstance(field, tuple) else field
        self.line = line
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        where = self.path if self.line is None else f"{self.path}:{self.line}"
        what = f"field `{self.field}`: " if self.field else ""
        return f"{where}: {what}{self.message}"


class MeshError(SceneError):
    """A mesh that cannot give meaningful mass properties (open, inverted, empty, ...)."""


class PluginError(KcheckError):
    """A check plugin that cannot be loaded or declares itself wrongly."""
