"""What every command shares: exit codes, the argument parser class, writing output."""

from __future__ import annotations

import argparse
import enum
import errno
import os
import sys
from pathlib import Path
from typing import Any, TextIO

__all__ = [
    "ExitCode",
    "Parser",
    "write_text",
    "fail",
    "discard_stdout",
    "open_closed_streams",
    "open_replacing",
    "close_replacing",
]


class ExitCode(enum.IntEnum):
    """Process exit status (ruff, mypy and sqlfluff use the same three)."""

    OK = 0
    CHECKS_FAILED = 1
    USAGE_OR_INPUT = 2


class Parser(argparse.ArgumentParser):
    """argparse with kcheck's usage-error exit code."""

    #: True while the parser is being built (:meth:`add_argument`, :meth:`add_subparsers`)
    _building = False

    def add_argument(self, *args: Any, **kwargs: Any) -> argparse.Action:
        self._building = True
        try:
            return super().add_argument(*args, **kwargs)
        finally:
            self._building = False

    def add_subparsers(self, **kwargs: Any) -> Any:
        self._building = True
        try:
            return super().add_subparsers(**kwargs)
        finally:
            self._building = False

    def _get_formatter(self) -> argparse.HelpFormatter:
        # While it is built, argparse formats with a formatter that asks for the terminal's
        # width (importing shutil: about 2 ms of every start, issue 24): to check an
        # argument's metavar against its nargs, and for the subcommands' program name (the
        # program's name and positionals, never wrapped). Neither depends on the width, so
        # they get a fixed one; help, usage and errors are formatted at the terminal's width.
        if self._building:
            return self.formatter_class(prog=self.prog, width=80)  # type: ignore[call-arg]
        return super()._get_formatter()

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        print(f"kcheck: error: {message}", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE_OR_INPUT)


def fail(message: str) -> int:
    """Print a usage or input error on stderr; return exit code 2."""
    print(f"kcheck: error: {message}", file=sys.stderr)
    return ExitCode.USAGE_OR_INPUT


def write_text(text: str, output: Path | None, what: str = "--output") -> None:
    """Write a document to stdout, or to a file (its folder created); a file that cannot be
    written is a UsageError naming it (and the option ``what``)."""
    from kcheck.errors import UsageError, describe_os_error
    from kcheck.gate.paths import check_output_file

    if output is None:
        sys.stdout.write(text)
        return
    check_output_file(output, what)
    try:
        output.parent.mkdir(parents=True, exist_ok=True)
        output.write_text(text, encoding="utf-8", errors="backslashreplace")
    except OSError as exc:
        raise UsageError(f"{what} {output}: {describe_os_error(exc)}") from None


def discard_stdout() -> None:
    """The reader of standard output went away: what is still written to it (the rest of
    the report, what the buffer holds) goes to the null device, so the run goes on to its
    verdict and its exit code (Python's recipe, "Note on SIGPIPE" in :mod:`signal`)."""
    discard(sys.stdout)


def discard(stream: TextIO | None) -> None:
    """What is still written to ``stream`` (standard output or error) goes to the null
    device: its reader went away."""
    if stream is None:
        return
    try:
        fd = stream.fileno()
    except (OSError, ValueError):
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)


def reader_gone(stream: TextIO | None) -> bool:
    """Whether ``stream`` is a pipe whose reader went away (its write end polls as an error).
    Where :func:`select.poll` does not exist, any stream may be the one: True."""
    import select

    if stream is None:
        return False
    try:
        fd = stream.fileno()
    except (OSError, ValueError):
        return False
    poll = getattr(select, "poll", None)
    if poll is None:
        return True
    watch = poll()
    watch.register(fd, 0)  # errors and hang-ups are reported whatever is asked for
    return any(events & select.POLLERR for _, events in watch.poll(0))


def discard_gone() -> None:
    """After a BrokenPipeError: each standard stream whose reader went away writes to the
    null device from now on, so the run goes on to its verdict and its exit code (a `kcheck
    check ... 2>&1 | head`, or a progress line's terminal closed, changes no exit code)."""
    for stream in (sys.stdout, sys.stderr):
        if reader_gone(stream):
            discard(stream)


def open_closed_streams() -> None:
    """A closed standard output or error (``kcheck check ... >&-``: Python then has
    ``sys.stdout`` None) is the null device: the run writes nothing there, never fails on it,
    and its exit code is still the verdict's. The descriptor is the null device too, so no
    report file or worker takes descriptor 1 or 2."""
    for name, fd in (("stdout", 1), ("stderr", 2)):
        if getattr(sys, name) is not None:
            continue
        devnull = os.open(os.devnull, os.O_WRONLY)
        if devnull != fd:
            os.dup2(devnull, fd)
            os.close(devnull)
        setattr(
            sys, name, open(fd, "w", encoding="utf-8", errors="backslashreplace", closefd=False)
        )  # noqa: SIM115


#: Report files being written: the stream's id -> (its temporary file, the file it replaces).
_REPLACING: dict[int, tuple[str, str]] = {}


def open_replacing(path: Path) -> TextIO:
    """A text stream for the file ``path`` (its folder made) that holds nothing of the new
    text until :func:`close_replacing` keeps it: it writes a temporary file beside ``path``
    that then replaces it in one rename, so an interrupted run (Ctrl-C) or a failed write
    leaves ``path`` as it was, never half written. A symbolic link's file is replaced, the
    link kept; what is not a regular file (``/dev/null``, a named pipe) is written directly.
    """
    import stat  # (not tempfile: its imports cost about 10 ms of a start, issue 24)

    path.parent.mkdir(parents=True, exist_ok=True)
    target = os.path.realpath(path)
    try:
        mode: int | None = os.stat(target).st_mode
    except FileNotFoundError:
        mode = None
    if mode is not None and not stat.S_ISREG(mode):
        return path.open("w", encoding="utf-8", errors="backslashreplace")
    folder, name = os.path.split(target)
    for attempt in range(1000):
        temporary = os.path.join(folder, f".{name}.{os.getpid()}-{attempt}.part")
        try:  # a new file gets the mode open() would give it (0o666 less the umask)
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:
            continue
    else:
        raise FileExistsError(errno.EEXIST, "no free temporary name", temporary)
    try:
        if mode is not None:  # the file it replaces keeps its mode
            os.fchmod(fd, stat.S_IMODE(mode))
        # A scene's path or text may hold lone surrogates (a file name that is not UTF-8).
        stream = open(fd, "w", encoding="utf-8", errors="backslashreplace")  # noqa: SIM115
    except BaseException:
        os.close(fd)
        os.unlink(temporary)
        raise
    _REPLACING[id(stream)] = (temporary, target)
    return stream


def close_replacing(stream: TextIO, keep: bool) -> None:
    """Close a stream of :func:`open_replacing`: ``keep`` puts its text in place of the file,
    else the file stays as it was. OSError if the text cannot be written or renamed (the
    temporary file is removed then too)."""
    temporary, target = _REPLACING.pop(id(stream), (None, None))
    try:
        stream.close()
        if temporary is not None and target is not None and keep:
            os.replace(temporary, target)
            temporary = None
    finally:
        if temporary is not None:
            try:
                os.unlink(temporary)
            except OSError:
                pass
