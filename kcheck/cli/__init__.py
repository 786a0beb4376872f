"""Command line: one module per command, each with ``add_parser`` and ``run``.

Exit codes: 0 every check passed, 1 a check failed, 2 bad input or usage (every other scene
in a batch is still checked). Only this package prints errors and chooses exit codes.
Command modules import nothing heavy at module level: ``kcheck --help`` stays fast.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import types
from collections.abc import Sequence
from typing import NoReturn

from kcheck import __version__
from kcheck.cli.common import ExitCode, Parser, discard_gone, discard_stdout, open_closed_streams
from kcheck.errors import KcheckError

__all__ = ["ExitCode", "main", "run"]

#: Every command, in the order ``kcheck --help`` lists them, with the module (in this
#: package) whose ``add_parser`` adds it.
COMMANDS = {
    "check": "check",
    "config": "config",
    "init": "init",
    "contacts": "contacts",
    "expand": "expand",
    "mass": "mass",
    "suggest": "suggest",
    "study": "study",
    "schema": "info",
    "plugins": "info",
}

#: Thread counts of the BLAS/OpenMP libraries numpy may load. kcheck's matrices are tiny
#: (3x3 to 6x36): threads only add overhead, and parallelism comes from --jobs processes.
BLAS_THREAD_VARIABLES = (
    "OPENBLAS_NUM_THREADS",
    "OMP_NUM_THREADS",
    "MKL_NUM_THREADS",
    "BLIS_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
    "NUMEXPR_NUM_THREADS",
)


def pin_blas_threads() -> None:
    """One BLAS thread, unless the user chose otherwise; effective only before numpy loads."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


def skip_pydantic_plugins() -> None:
    """No pydantic plugins, unless the user chose otherwise: kcheck's models use none, and
    looking for them scans every installed distribution at the first validation (about
    50 ms of every start).

    With every plugin disabled pydantic's plugin loader answers "none" without looking, yet
    importing it imports :mod:`importlib.metadata` (email, zipfile, csv, socket: 30-40 ms of
    every start). So, unless pydantic has loaded it already, the loader pydantic gets is one
    whose ``get_plugins`` answers "none" and that hands any other name to the real loader
    (imported then).
    """
    os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")
    name = "pydantic.plugin._loader"
    if os.environ["PYDANTIC_DISABLE_PLUGINS"] != "__all__" or name in sys.modules:
        return

    def get_plugins() -> tuple[()]:
        return ()

    def real(attr: str) -> object:
        if attr.startswith("__"):  # the import system asking (__path__, ...), not pydantic
            raise AttributeError(attr)
        sys.modules.pop(name, None)
        return getattr(importlib.import_module(name), attr)

    loader = types.ModuleType(name, "pydantic's plugin loader while every plugin is disabled")
    loader.get_plugins = get_plugins  # type: ignore[attr-defined]
    # A module's __getattr__ (PEP 562) is an attribute; typeshed has ModuleType's as a method.
    loader.__getattr__ = real  # type: ignore[method-assign]
    sys.modules[name] = loader


def _parser(command: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser: every command's, or (``command`` given) only that one's.

    Only one command's: the other command modules are not imported and their parsers not
    built (about 10 ms of every start, issue 24). The usage line still names every command
    (the same ``metavar`` argparse would print), so errors read the same either way; only
    ``kcheck --help`` needs every command's help, and it builds the full parser.
    """
    parser = Parser(
        prog="kcheck",
        description="Check the repositioning behaviour of kinematic couplings from CAD exports.",
        epilog="exit codes: 0 every check passed, 1 a check failed, 2 bad input or usage",
    )
    parser.add_argument("--version", action="version", version=f"kcheck {__version__}")
    metavar = None if command is None else "{" + ",".join(COMMANDS) + "}"
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser, metavar=metavar)
    names = COMMANDS.values() if command is None else (COMMANDS[command],)
    for name in dict.fromkeys(names):
        importlib.import_module(f"kcheck.cli.{name}").add_parser(sub)
    return parser


def escape_unprintable() -> None:
    """Standard output and error escape what their encoding cannot carry (``\\xb1`` on an
    ASCII terminal, a lone surrogate from a file name that is not UTF-8) instead of raising
    in the middle of a report."""
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            try:
                reconfigure(errors="backslashreplace")
            except (ValueError, OSError):  # a closed or detached stream
                pass


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    pin_blas_threads()
    skip_pydantic_plugins()
    open_closed_streams()
    escape_unprintable()
    argv = sys.argv[1:] if argv is None else list(argv)
    # The command comes first (kcheck's own options, -h and --version, end the run).
    args = _parser(argv[0] if argv and argv[0] in COMMANDS else None).parse_args(argv)
    try:
        return int(args.handler(args))
    except KcheckError as exc:
        print(f"kcheck: error: {exc}", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT
    except BrokenPipeError:  # a command without a verdict (`kcheck check` handles its own)
        discard_stdout()
        return ExitCode.OK
    except KeyboardInterrupt:
        print("kcheck: interrupted", file=sys.stderr)
        return 130  # as a shell reports SIGINT


def run() -> NoReturn:
    """The ``kcheck`` command (console script and ``python -m kcheck``): :func:`main`, then
    :func:`exit_now` when this process is kcheck's alone (:func:`owns_process`), else the
    interpreter's own exit (a profiler's or tracer's report, a caller's code, still run)."""
    code = main()
    if owns_process(sys._getframe(1)):
        exit_now(code)
    sys.exit(code)


def owns_process(caller: types.FrameType | None) -> bool:
    """Whether nothing but kcheck runs in this process, so it may end without the
    interpreter's teardown: no profiler or tracer (``python -m cProfile -o``, ``python -m
    trace``, coverage, a debugger write their results after the program), and ``caller`` (the
    frame that called :func:`run`) is ``__main__`` itself, kcheck's own entry (the console
    script or ``kcheck.__main__``), started by nothing but the interpreter or :mod:`runpy`
    (not ``runpy.run_module("kcheck")`` from a caller's code, nor a profiler's ``-m``)."""
    if sys.getprofile() is not None or sys.gettrace() is not None or caller is None:
        return False
    main_module = sys.modules.get("__main__")
    if main_module is None or caller.f_globals is not vars(main_module):
        return False
    entry = getattr(getattr(main_module, "__spec__", None), "name", None)
    if not (entry == "kcheck.__main__" or vars(main_module).get("run") is run):
        return False
    runpy = sys.modules.get("runpy")
    outer = caller.f_back
    while outer is not None:
        if runpy is None or outer.f_globals is not vars(runpy):
            return False  # someone else's code runs kcheck and goes on after it
        outer = outer.f_back
    return True


def exit_now(code: int) -> NoReturn:
    """End the process with ``code`` as the interpreter would, without tearing it down.

    Python's own exit waits for threads, runs the ``atexit`` functions, flushes standard output
    and error, then frees every object and module one by one: with numpy and kcheck loaded,
    and their pages shared with a worker since the fork (each first write a page fault), that
    last part alone was about a fifth of a one-scene run's CPU (issue 24). Here the first three
    happen as they would, then the process ends (:func:`os._exit`). Report files are closed
    before :func:`main` returns. With another thread still running, or when a flush fails
    otherwise, the interpreter's own exit does it all, as before; a reader of standard output
    or error going away leaves ``code`` as it is (docs/ci.md).
    """
    import atexit
    import threading

    run_exitfuncs = getattr(atexit, "_run_exitfuncs", None)
    if run_exitfuncs is None or threading.active_count() > 1:
        sys.exit(code)
    run_exitfuncs()  # the registered functions run once: the interpreter's exit clears them
    try:
        for stream in (sys.stdout, sys.stderr):
            if stream is not None:
                try:
                    stream.flush()
                except BrokenPipeError:
                    discard_gone()  # its reader went away: the code is still `code`
                    stream.flush()
    except (OSError, ValueError):
        sys.exit(code)  # the interpreter's exit reports it, as it always did
    os._exit(code)
