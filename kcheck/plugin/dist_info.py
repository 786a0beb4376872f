"""Installed distributions read straight from their metadata folders, for start-up.

Importing :mod:`importlib.metadata` costs about 30 ms (it pulls in ``email``, ``zipfile``,
``csv`` and ``socket``), paid by every run only to find kcheck's entry points and one
version. This reads the ``*.dist-info`` / ``*.egg-info`` folders on ``sys.path`` itself (in
``sys.path`` order, as :func:`importlib.metadata.distributions` does), and answers None
wherever it cannot be sure to see what importlib.metadata sees — a zip archive on
``sys.path``, or a meta-path finder of its own that can list distributions — so that callers
fall back to :mod:`importlib.metadata`.
"""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path
from typing import Any, NamedTuple

__all__ = ["EntryPoint", "Distribution", "distributions", "version"]

SUFFIXES = (".dist-info", ".egg-info")


class EntryPoint(NamedTuple):
    """An entry point (the fields and ``load`` of :class:`importlib.metadata.EntryPoint`)."""

    name: str
    value: str
    group: str

    def load(self) -> Any:
        """The object named by ``module:attribute.path``."""
        module, _, attrs = self.value.partition(":")
        obj = importlib.import_module(module.strip())
        for attr in filter(None, attrs.split("[")[0].strip().split(".")):
            obj = getattr(obj, attr)
        return obj


def _read(path: str, errors: str = "strict") -> str | None:
    """A file's text (UTF-8, ``errors`` as for :meth:`bytes.decode`); None when it cannot be
    read. One ``open`` and ``read`` of the descriptor, no file object: most folders have no
    ``entry_points.txt``, and with 90 folders a file object and a raised error each were most
    of the scan (about 1.5 ms of every start, issue 24)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None
    try:
        chunks = []
        while chunk := os.read(fd, 1 << 16):
            chunks.append(chunk)
    except OSError:
        return None
    finally:
        os.close(fd)
    return b"".join(chunks).decode("utf-8", errors)


class Distribution(NamedTuple):
    """A distribution's metadata folder (``folder``, its path as given on ``sys.path``)."""

    folder: str

    @property
    def path(self) -> Path:
        """The metadata folder."""
        return Path(self.folder)

    def _headers(self) -> dict[str, str]:
        for name in ("METADATA", "PKG-INFO"):
            text = _read(self.folder + os.sep + name, errors="replace")
            if text is None:
                continue
            headers: dict[str, str] = {}
            for line in text.splitlines():
                if not line.strip():
                    break  # the body (description) follows the headers
                key, sep, value = line.partition(":")
                if sep and not line[0].isspace():
                    headers.setdefault(key.strip(), value.strip())
            return headers
        return {}

    @property
    def name(self) -> str | None:
        """The ``Name`` of its metadata."""
        return self._headers().get("Name")

    @property
    def version(self) -> str:
        """The ``Version`` of its metadata."""
        return self._headers().get("Version", "")

    def entry_points(self, group: str) -> list[EntryPoint]:
        """Its entry points of ``group`` (``entry_points.txt``, an INI file)."""
        text = _read(self.folder + os.sep + "entry_points.txt")
        if text is None:
            return []
        found, section = [], None
        for raw in text.splitlines():
            line = raw.strip()
            if not line or line.startswith(("#", ";")):
                continue
            if line.startswith("[") and line.endswith("]"):
                section = line[1:-1].strip()
            elif section == group:
                name, sep, value = line.partition("=")
                if sep:
                    found.append(EntryPoint(name.strip(), value.strip(), group))
        return found


def _trustworthy() -> bool:
    """Whether reading the folders on sys.path sees every distribution importlib would."""
    from importlib.machinery import PathFinder

    def plain(method: Any) -> Any:
        return getattr(method, "__func__", method)

    # Some hosts (a Dask worker) run with a PathFinder that has no find_distributions: then
    # only importlib.metadata can say.
    reference = getattr(PathFinder, "find_distributions", None)
    if reference is None:
        return False
    for finder in sys.meta_path:
        own = getattr(finder, "find_distributions", None)
        if own is not None and plain(own) is not plain(reference):
            return False  # a finder of its own that can list distributions
    return not any(os.path.isfile(entry or ".") for entry in sys.path)  # zip archives


def distributions() -> list[Distribution] | None:
    """Every distribution's metadata folder on ``sys.path``, in path order; None when only
    :func:`importlib.metadata.distributions` can say (see the module text)."""
    if not _trustworthy():
        return None
    found = []
    for entry in sys.path:
        try:
            names = sorted(os.listdir(entry or "."))
        except OSError:
            continue
        base = os.path.join(entry or ".", "")  # with its separator: joined to each name below
        found += [Distribution(base + n) for n in names if n.endswith(SUFFIXES)]
    return found


def _normalise(name: str) -> str:
    return "".join("_" if c in "-_." else c for c in name.lower())


def version(name: str) -> str | None:
    """The version of the first installed distribution called ``name`` (None: not found);
    falls back to :mod:`importlib.metadata` where the folders cannot be trusted."""
    dists = distributions()
    if dists is None:
        import importlib.metadata

        try:
            return importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            return None
    wanted = _normalise(name)
    for dist in dists:
        stem = os.path.basename(dist.folder).rsplit(".", 1)[0].split("-")[0]
        if _normalise(stem) == wanted:
            return dist.version
    return None
