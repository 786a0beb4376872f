"""PyYAML, imported without compiling its patterns (issue 24).

PyYAML compiles ten patterns when it is imported, about 5 ms: the pure-Python reader's
character class ``yaml.reader.Reader.NON_PRINTABLE`` (a class over most of Unicode, 3.5 ms
alone), the resolver's implicit tags and the constructor's timestamp. kcheck reads scene files
from libyaml's event stream (:mod:`kcheck.scene.yamlio`) and resolves plain scalars itself,
so a check uses none of them; writing YAML (the resolver deciding what to quote) and the
pure-Python reader (where libyaml is missing) do. While PyYAML is imported here, each pattern
its modules compile is a stand-in that compiles it on first use and then answers as the
compiled pattern; any other module's ``re.compile`` is untouched, and ``re.compile`` is
restored after. Import ``yaml`` from here.
"""

from __future__ import annotations

import re
import sys
from typing import Any

__all__ = ["yaml"]

#: The pure-Python reader's pattern as PyYAML 3.x-6.x writes it.
NON_PRINTABLE = "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"


class _OnFirstUse:
    """A compiled pattern's stand-in: compiles it the first time it is used. Copied or
    pickled, it is the compiled pattern (``re.compile`` of the same arguments)."""

    __slots__ = ("_args", "_pattern")

    def __init__(self, pattern: str, flags: int) -> None:
        self._args = (pattern, flags)
        self._pattern: re.Pattern[str] | None = None

    def __getattr__(self, name: str) -> Any:
        # Only a pattern's public names are passed on: a special name or one of its own slots
        # missing (an object made without __init__, by copy or pickle) is not looked for in
        # the pattern, which would read the missing slot again, without end.
        if name in _OnFirstUse.__slots__ or (name.startswith("__") and name.endswith("__")):
            raise AttributeError(name)
        if self._pattern is None:
            self._pattern = re.compile(*self._args)
        return getattr(self._pattern, name)

    def __reduce__(self) -> tuple[Any, tuple[str, int]]:
        return re.compile, self._args


def _import() -> None:
    if "yaml" in sys.modules:
        return
    compile_ = re.compile

    def deferred(pattern: Any, flags: int = 0) -> Any:
        if str(sys._getframe(1).f_globals.get("__name__")).startswith("yaml."):
            return _OnFirstUse(pattern, flags)
        return compile_(pattern, flags)

    re.compile = deferred
    try:
        import yaml  # noqa: F401
    finally:
        re.compile = compile_


_import()

import yaml  # noqa: E402
