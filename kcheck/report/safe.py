"""Text that any output stream can take: a report never dies on a character.

A scene's text can hold what a terminal cannot show: '°', '±', 'μ', '→' on an ASCII
terminal (``LANG=C``, ``PYTHONIOENCODING=ascii``), or a lone surrogate such as ``"\\ud800"``
that no encoding accepts. :class:`SafeStream` wraps a text stream: characters its encoding
cannot take get a readable fallback ('°' → ' deg', 'μ' → 'mu'), and anything else is
escaped (``\\ud800``) instead of raising.
"""

from __future__ import annotations

import codecs
import sys
from collections.abc import Callable
from typing import TextIO

__all__ = ["FALLBACKS", "SafeStream", "printable", "can_encode", "stdout", "stderr"]

#: Readable ASCII stand-ins for the characters kcheck's reports use.
FALLBACKS: dict[str, str] = {
    "°": " deg",
    "±": "+/-",
    "μ": "mu",
    "θ": "theta",
    "α": "alpha",
    "σ": "sigma",
    "→": "->",
    "←": "<-",
    "–": "-",
    "—": "--",
    "−": "-",
    "…": "...",
    "·": "*",
    "×": "x",
    "²": "^2",
    "³": "^3",
    "≤": "<=",
    "≥": ">=",
    "≈": "~",
    "∞": "inf",
    "✗": "x",
    "✓": "v",
    "↺": "(ccw)",
    "↻": "(cw)",
    "′": "'",
    "\u00a0": " ",
    "“": '"',
    "”": '"',
    "‘": "'",
    "’": "'",
}
_TABLE = str.maketrans(FALLBACKS)


def can_encode(text: str, encoding: str) -> bool:
    """Whether ``text`` encodes in ``encoding`` without an error."""
    try:
        text.encode(encoding)
    except (UnicodeEncodeError, LookupError):
        return False
    return True


def printable(text: str, encoding: str = "utf-8") -> str:
    """``text`` as ``encoding`` can write it: fallbacks for known symbols, then escapes."""
    if can_encode(text, encoding):
        return text
    if not can_encode("°", encoding):
        text = text.translate(_TABLE)
    return text.encode(encoding, "backslashreplace").decode(encoding)


class SafeStream:
    """A text stream that never raises on a character (see :func:`printable`).

    ``target`` is the stream, or a callable returning it at each write, so a wrapped
    ``sys.stdout`` follows a replaced ``sys.stdout`` (test capture, redirection).
    """

    def __init__(self, target: TextIO | Callable[[], TextIO]) -> None:
        self._target = target

    @property
    def stream(self) -> TextIO:
        """The wrapped stream."""
        return self._target() if callable(self._target) else self._target

    @property
    def encoding(self) -> str:
        """The wrapped stream's encoding (``utf-8`` when it does not say)."""
        name = getattr(self.stream, "encoding", None) or "utf-8"
        try:
            return codecs.lookup(name).name
        except LookupError:
            return "utf-8"

    def write(self, text: str) -> int:
        """Write ``text``, falling back and escaping what the encoding cannot take."""
        self.stream.write(printable(text, self.encoding))
        return len(text)

    def flush(self) -> None:
        """Flush the wrapped stream."""
        self.stream.flush()

    def isatty(self) -> bool:
        """Whether the wrapped stream is a terminal."""
        isatty = getattr(self.stream, "isatty", None)
        return bool(isatty and isatty())

    def fileno(self) -> int:
        """The wrapped stream's file descriptor (rich asks for the terminal size)."""
        return self.stream.fileno()


def stdout() -> SafeStream:
    """``sys.stdout``, whatever it is at each write, made safe."""
    return SafeStream(lambda: sys.stdout)


def stderr() -> SafeStream:
    """``sys.stderr``, whatever it is at each write, made safe."""
    return SafeStream(lambda: sys.stderr)
