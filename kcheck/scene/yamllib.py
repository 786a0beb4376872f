"""PyYAML, imported without compiling its pure-Python reader's character class (issue 24).

``yaml.reader.Reader.NON_PRINTABLE``, a pattern over most of Unicode, costs about 3.5 ms to
compile at every import of PyYAML, yet only the pure-Python reader uses it; kcheck reads
through libyaml's parser when PyYAML has it (:mod:`kcheck.scene.yamlio`). While PyYAML is
imported here, that one pattern is made a stand-in compiled on its first use (so the
pure-Python reader, where libyaml is missing, still gets it); every other pattern is
compiled as usual. Import ``yaml`` from here.
"""

from __future__ import annotations

import re
import sys
from typing import Any

__all__ = ["yaml"]

#: The pattern as PyYAML 3.x-6.x writes it (any other text is compiled as usual).
NON_PRINTABLE = "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"


class _OnFirstUse:
    """A compiled pattern's stand-in: compiles it the first time it is used."""

    def __init__(self, pattern: str, flags: int) -> None:
        self._args = (pattern, flags)
        self._pattern: re.Pattern[str] | None = None

    def __getattr__(self, name: str) -> Any:
        if self._pattern is None:
            self._pattern = re.compile(*self._args)
        return getattr(self._pattern, name)


def _import() -> None:
    if "yaml" in sys.modules:
        return
    compile_ = re.compile

    def deferred(pattern: Any, flags: int = 0) -> Any:
        if pattern == NON_PRINTABLE:
            return _OnFirstUse(pattern, flags)
        return compile_(pattern, flags)

    re.compile = deferred
    try:
        import yaml  # noqa: F401
    finally:
        re.compile = compile_


_import()

import yaml  # noqa: E402
