"""``kcheck schema`` and ``kcheck plugins``: what kcheck reads and which checks it has."""

from __future__ import annotations

import argparse
import json
from typing import Any

from kcheck.cli.common import ExitCode

__all__ = ["add_parser"]


def add_parser(sub: Any) -> None:
    """Register the ``schema`` and ``plugins`` commands."""
    schema = sub.add_parser("schema", help="print the JSON Schema of scene files")
    schema.set_defaults(handler=run_schema)
    plugins = sub.add_parser("plugins", help="list the installed checks")
    plugins.set_defaults(handler=run_plugins)


def run_schema(args: argparse.Namespace) -> int:
    """Print the scene JSON Schema."""
    from kcheck.scene import scene_json_schema

    print(json.dumps(scene_json_schema(), indent=2))
    return ExitCode.OK


def run_plugins(args: argparse.Namespace) -> int:
    """List installed checks with what they apply to and their options."""
    from kcheck.plugin import load_checks
    from kcheck.report import make_console

    console = make_console("auto")
    for lc in load_checks():
        c = lc.check
        console.print(f"{lc.spec.name}  ({lc.spec.package} {lc.spec.version})", style="bold")
        console.print(f"    {c.summary}")
        console.print(
            f"    applies to: {c.applies_to}; needs mass properties: "
            f"{'yes' if c.needs_mass else 'no'}; severity: {c.severity}"
        )
        fields = c.options.model_fields
        if fields:
            opts = ", ".join(f"{k} (default {v.default!r})" for k, v in fields.items())
            console.print(f"    options: {opts}")
    return ExitCode.OK
