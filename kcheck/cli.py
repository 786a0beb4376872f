"""Command line: ``kcheck check``, ``kcheck mass``, ``kcheck schema``, ``kcheck plugins``.

Exit codes: 0 every check passed, 1 a check failed, 2 bad input or usage (every other scene
in a batch is still checked). Only this module prints errors and chooses exit codes.
"""

from __future__ import annotations

import argparse
import enum
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from kcheck import __version__
from kcheck.errors import KcheckError

__all__ = ["ExitCode", "main"]


class ExitCode(enum.IntEnum):
    """Process exit status."""

    OK = 0
    CHECKS_FAILED = 1
    USAGE_OR_INPUT = 2


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        print(f"kcheck: error: {message}", file=sys.stderr)
        raise SystemExit(ExitCode.USAGE_OR_INPUT)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="kcheck", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"kcheck {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    check = sub.add_parser("check", help="check scene files (default: every *.kcheck.yaml in .)")
    check.add_argument(
        "paths",
        nargs="*",
        default=["."],
        type=Path,
        help="scene files and folders (searched recursively)",
    )
    check.add_argument("--format", choices=("text", "json"), default="text")
    check.add_argument("--output", "-o", type=Path, help="write the report to this file")
    check.add_argument(
        "--plots",
        type=Path,
        metavar="DIR",
        help="write pictures (PNG and SVG) into DIR (needs the `plot` extra)",
    )
    check.add_argument(
        "--select", metavar="IDS", help="comma-separated check ids to run (default: all installed)"
    )
    check.add_argument("--color", choices=("auto", "always", "never"), default="auto")
    check.add_argument(
        "--allow-outside-paths",
        action="store_true",
        help="let scenes use meshes outside their own folder",
    )

    mass = sub.add_parser("mass", help="mass properties of a mesh, as a CAD package reports them")
    mass.add_argument("mesh", type=Path)
    mass.add_argument(
        "--units",
        required=True,
        choices=("m", "cm", "mm", "um", "in"),
        help="length unit of the mesh file (never guessed)",
    )
    group = mass.add_mutually_exclusive_group(required=True)
    group.add_argument("--material", help="name from the built-in table")
    group.add_argument("--density", type=float, help="kg/m^3")
    mass.add_argument("--format", choices=("text", "json"), default="text")
    mass.add_argument("--color", choices=("auto", "always", "never"), default="auto")

    sub.add_parser("schema", help="print the JSON Schema of scene files")
    sub.add_parser("plugins", help="list the installed checks")
    return parser


def _write(text: str, output: Path | None) -> None:
    if output is None:
        sys.stdout.write(text)
    else:
        output.parent.mkdir(parents=True, exist_ok=True)
        output.write_text(text, encoding="utf-8")


def _cmd_check(args: argparse.Namespace) -> int:
    from kcheck.plugin import load_checks
    from kcheck.result import Status, run_json
    from kcheck.runner import check_scene, discover

    checks = load_checks()
    if args.select:
        wanted = [s.strip() for s in args.select.split(",") if s.strip()]
        known = {lc.spec.name for lc in checks}
        unknown = [w for w in wanted if w not in known]
        if unknown:
            print(
                f"kcheck: error: unknown check(s) {', '.join(unknown)}; installed: "
                f"{', '.join(sorted(known))}",
                file=sys.stderr,
            )
            return ExitCode.USAGE_OR_INPUT
        checks = [lc for lc in checks if lc.spec.name in wanted]
    files, missing = discover(args.paths)
    if args.plots is not None:
        args.plots.mkdir(parents=True, exist_ok=True)
    results = missing + [
        check_scene(f, checks, allow_outside=args.allow_outside_paths, plots=args.plots)
        for f in files
    ]
    if args.format == "json":
        _write(json.dumps(run_json(results, __version__), indent=2) + "\n", args.output)
    else:
        from kcheck.report import make_console, render

        if args.output is not None:
            args.output.parent.mkdir(parents=True, exist_ok=True)
            with args.output.open("w", encoding="utf-8") as fh:
                render(make_console("never", file=fh), results)
        else:
            render(make_console(args.color), results)
    for r in results:
        if r.status is Status.ERROR and r.error:
            print(f"kcheck: error: {r.error}", file=sys.stderr)
    states = {r.status for r in results}
    if Status.ERROR in states:
        return ExitCode.USAGE_OR_INPUT
    return ExitCode.CHECKS_FAILED if Status.FAIL in states else ExitCode.OK


def _cmd_mass(args: argparse.Namespace) -> int:
    from kcheck.errors import MeshError
    from kcheck.mass import load_mesh, mesh_mass_properties
    from kcheck.units import LENGTH_TO_M, MATERIALS, density_of

    if args.material is not None:
        density = density_of(args.material)
        if density is None:
            print(
                f"kcheck: error: unknown material `{args.material}`; known: "
                f"{', '.join(sorted(MATERIALS))}",
                file=sys.stderr,
            )
            return ExitCode.USAGE_OR_INPUT
    else:
        density = args.density
        if not density > 0:
            print("kcheck: error: --density must be positive (kg/m^3)", file=sys.stderr)
            return ExitCode.USAGE_OR_INPUT
    if not args.mesh.is_file():
        print(f"kcheck: error: {args.mesh}: no such file", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT
    try:
        mesh = load_mesh(args.mesh, LENGTH_TO_M[args.units], "mesh")
        props = mesh_mass_properties(mesh, density, args.mesh, "mesh")
    except MeshError as exc:
        print(f"kcheck: error: {exc.path}: {exc.message}", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT
    if args.format == "json":
        from kcheck.mass import principal_axes
        from kcheck.result import to_json_value

        moments, axes = principal_axes(props.inertia)
        doc = props.to_json() | {
            "principal_moments": moments,
            "principal_axes": axes.T,
            "density": density,
            "units": "SI (kg, m, kg m^2)",
        }
        print(json.dumps(to_json_value(doc), indent=2))
    else:
        from kcheck.report import make_console, render_mass

        console = make_console(args.color)
        console.print(f"{args.mesh} ({args.units}, {density:g} kg/m^3)")
        render_mass(console, props)
    return ExitCode.OK


def _cmd_schema(args: argparse.Namespace) -> int:
    from kcheck.scene import scene_json_schema

    print(json.dumps(scene_json_schema(), indent=2))
    return ExitCode.OK


def _cmd_plugins(args: argparse.Namespace) -> int:
    from kcheck.plugin import load_checks
    from kcheck.report import make_console

    console = make_console("auto")
    for lc in load_checks():
        c = lc.check
        console.print(f"{lc.spec.name}  ({lc.spec.package} {lc.spec.version})", style="bold")
        console.print(f"    {c.summary}")
        console.print(
            f"    applies to: {c.applies_to}; needs mass properties: "
            f"{'yes' if c.needs_mass else 'no'}"
        )
        fields = c.options.model_fields
        if fields:
            opts = ", ".join(f"{k} (default {v.default!r})" for k, v in fields.items())
            console.print(f"    options: {opts}")
    return ExitCode.OK


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    args = _parser().parse_args(argv)
    handler = {
        "check": _cmd_check,
        "mass": _cmd_mass,
        "schema": _cmd_schema,
        "plugins": _cmd_plugins,
    }[args.command]
    try:
        return int(handler(args))
    except KcheckError as exc:
        print(f"kcheck: error: {exc}", file=sys.stderr)
        return ExitCode.USAGE_OR_INPUT
    except BrokenPipeError:
        return ExitCode.OK


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
