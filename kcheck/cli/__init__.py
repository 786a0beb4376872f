"""Command line: one module per command, each with ``add_parser`` and ``run``.

Exit codes: 0 every check passed, 1 a check failed, 2 bad input or usage (every other scene
in a batch is still checked). Only this package prints errors and chooses exit codes.
Command modules import nothing heavy at module level: ``kcheck --help`` stays fast.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from kcheck import __version__
from kcheck.cli import check, expand, info, init, mass
from kcheck.cli.common import ExitCode, Parser
from kcheck.errors import KcheckError

__all__ = ["ExitCode", "main"]

COMMANDS = (check, init, expand, mass, info)


def _parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="kcheck",
        description="Check the repositioning behaviour of kinematic couplings from CAD exports.",
        epilog="exit codes: 0 every check passed, 1 a check failed, 2 bad input or usage",
    )
    parser.add_argument("--version", action="version", version=f"kcheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command in COMMANDS:
        command.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    args = _parser().parse_args(argv)
    try:
        return int(args.handler(args))
    except KcheckError as exc:
        print(f"kcheck: error: {exc}", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT
    except BrokenPipeError:
        return ExitCode.OK
