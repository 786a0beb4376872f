"""What one fuzz input is: the files to lay out, how kcheck is called, what must come out."""

from __future__ import annotations

import os
import socket
import stat
from dataclasses import dataclass, field
from pathlib import Path

__all__ = [
    "Symlink",
    "Fifo",
    "Socket",
    "Folder",
    "Blob",
    "Sparse",
    "Entry",
    "Claim",
    "Expect",
    "Case",
    "materialize",
    "VALID",
    "ANY",
    "ACCEPTED",
    "invalid",
]


@dataclass(frozen=True)
class Symlink:
    """A symbolic link to ``target`` (as written, relative to the link's folder or absolute)."""

    target: str


@dataclass(frozen=True)
class Fifo:
    """A named pipe (opening it for reading blocks until a writer comes)."""


@dataclass(frozen=True)
class Socket:
    """A Unix socket file."""


@dataclass(frozen=True)
class Folder:
    """A folder, with a mode set after its contents are written (0: unreadable)."""

    mode: int | None = None


@dataclass(frozen=True)
class Blob:
    """A file's bytes with a mode (e.g. 0: unreadable for anyone but root)."""

    data: bytes
    mode: int


@dataclass(frozen=True)
class Sparse:
    """A file of ``size`` zero bytes that takes no disk space (a hole), after ``head``."""

    size: int
    head: bytes = b""


Entry = bytes | Symlink | Fifo | Socket | Folder | Blob | Sparse


@dataclass(frozen=True)
class Claim:
    """An input error the documented contract says must be reported: at ``field`` (a path as
    kcheck writes it, ``supports[1].normal``) or, with None, about the file as a whole."""

    field: str | None
    why: str
    numeric: bool = False  # from a number's range (judged afresh on the final data)


@dataclass(frozen=True)
class Expect:
    """What a scene's result must be.

    ``valid``: accepted with the verdict of the fixture ``baseline`` (status and every
    check's status); ``accepted``: accepted, any verdict; ``invalid``: an input error, at one
    of ``claims`` (with ``exact``; else, when other changes may have caused errors of their
    own, anywhere); ``any``: accepted or an input error (either way kept to the promise).
    """

    outcome: str
    claims: tuple[Claim, ...] = ()
    baseline: str | None = None
    exact: bool = True


VALID = "valid"
ACCEPTED = Expect("accepted")
ANY = Expect("any")


def invalid(field: str | None, why: str) -> Expect:
    """An input that must be refused, at ``field``."""
    return Expect("invalid", (Claim(field, why),))


@dataclass
class Case:
    """One fuzz input.

    ``files`` are laid out in the case's own folder (paths relative to it); ``targets`` are the
    paths given to ``kcheck check`` (relative to the case folder, or absolute); ``results``
    maps every scene path the run must report (relative to the case folder) to what it must
    be. ``unprivileged``: file permissions must apply (the run drops root). ``argv``: a whole
    command line run on its own (``cli`` cases; ``{case}`` is replaced by the case folder),
    with ``exit_codes`` allowed. ``absent``: files that must not exist after the run (a
    payload's canary). ``other_results``: results under the case folder besides ``results``
    are allowed (paths whose reported form cannot be foreseen, past PATH_MAX), but there
    must be at least one. ``outputs``: report files a ``cli`` case writes, by format, which
    must read back in that format.
    """

    kind: str
    seed: int
    index: int
    what: str
    files: dict[str, Entry] = field(default_factory=dict)
    targets: tuple[str, ...] = ()
    results: dict[str, Expect] = field(default_factory=dict)
    unprivileged: bool = False
    argv: tuple[str, ...] | None = None
    exit_codes: frozenset[int] = frozenset()
    env: dict[str, str] = field(default_factory=dict)
    stdin: bytes | None = None
    absent: tuple[str, ...] = ()
    other_results: bool = False
    outputs: dict[str, str] = field(default_factory=dict)

    @property
    def ident(self) -> str:
        """``kind-seed-index``: enough to regenerate the input."""
        return f"{self.kind}-{self.seed}-{self.index}"


def _write(path: Path, entry: Entry) -> None:
    if isinstance(entry, bytes):
        path.write_bytes(entry)
    elif isinstance(entry, Symlink):
        os.symlink(entry.target, path)
    elif isinstance(entry, Fifo):
        os.mkfifo(path)
    elif isinstance(entry, Socket):
        sock = socket.socket(socket.AF_UNIX)
        try:
            sock.bind(str(path))
        except OSError:  # a path too long for a socket address: a plain file instead
            path.write_bytes(b"")
        finally:
            sock.close()
    elif isinstance(entry, Folder):
        path.mkdir(exist_ok=True)
    elif isinstance(entry, Blob):
        path.write_bytes(entry.data)
    elif isinstance(entry, Sparse):
        with open(path, "wb") as handle:
            handle.write(entry.head)
            handle.truncate(entry.size)


def _makedirs(folder: Path, root: Path) -> None:
    """Create ``folder`` below ``root`` one level at a time (works past PATH_MAX)."""
    fd = os.open(root, os.O_RDONLY | os.O_DIRECTORY)
    try:
        for part in folder.relative_to(root).parts:
            try:
                os.mkdir(part, dir_fd=fd)
            except FileExistsError:
                pass
            nxt = os.open(part, os.O_RDONLY | os.O_DIRECTORY, dir_fd=fd)
            os.close(fd)
            fd = nxt
    finally:
        os.close(fd)


def materialize(case: Case, folder: Path) -> None:
    """Lay out a case's files in ``folder`` (created; everything readable to anyone, then the
    modes the case asks for)."""
    folder.mkdir(parents=True, exist_ok=True)
    os.chmod(folder, 0o777)
    modes: list[tuple[Path, int]] = []
    for rel, entry in case.files.items():
        path = folder / rel
        if len(str(path)) >= 4000:  # past PATH_MAX: write through a folder descriptor
            _long_write(path, folder, entry)
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        _write(path, entry)
        if isinstance(entry, Folder) and entry.mode is not None:
            modes.append((path, entry.mode))
        elif isinstance(entry, Blob):
            modes.append((path, entry.mode))
        elif not isinstance(entry, (Symlink, Socket)) and path.exists():
            path.chmod(0o777 if path.is_dir() else 0o666)
    for d, _, _ in os.walk(folder):
        try:
            os.chmod(d, 0o777)
        except OSError:  # past PATH_MAX: left as made (searchable by anyone)
            pass
    for path, mode in reversed(modes):  # deepest first
        os.chmod(path, mode)


def _long_write(path: Path, root: Path, entry: Entry) -> None:
    _makedirs(path.parent, root)
    fd = os.open(root, os.O_RDONLY | os.O_DIRECTORY)
    try:
        for part in path.parent.relative_to(root).parts:
            nxt = os.open(part, os.O_RDONLY | os.O_DIRECTORY, dir_fd=fd)
            os.close(fd)
            fd = nxt
        if isinstance(entry, Symlink):
            os.symlink(entry.target, path.name, dir_fd=fd)
        else:
            data = entry if isinstance(entry, bytes) else b""
            out = os.open(path.name, os.O_WRONLY | os.O_CREAT, 0o666, dir_fd=fd)
            os.write(out, data)
            os.close(out)
    finally:
        os.close(fd)


def make_removable(folder: Path) -> None:
    """Give every folder below ``folder`` its permissions back, so it can be deleted."""
    for d, dirs, _ in os.walk(folder):
        for name in dirs:
            p = os.path.join(d, name)
            try:
                if not os.path.islink(p):
                    os.chmod(p, stat.S_IRWXU)
            except OSError:
                pass
