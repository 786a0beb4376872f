"""``kcheck mass``: mass properties of a mesh, as a CAD package reports them."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from kcheck.cli.common import ExitCode

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``mass`` command."""
    mass = sub.add_parser("mass", help="mass properties of a mesh, as a CAD package reports them")
    mass.add_argument("mesh", type=Path, help="mesh file (any format trimesh reads)")
    mass.add_argument(
        "--units",
        required=True,
        choices=("m", "cm", "mm", "um", "in"),
        help="length unit of the mesh file (never guessed)",
    )
    group = mass.add_mutually_exclusive_group(required=True)
    group.add_argument("--material", help="name from the built-in material table")
    group.add_argument("--density", type=float, help="density in kg/m^3")
    mass.add_argument(
        "--format", choices=("text", "json"), default="text", help="output format (default: text)"
    )
    mass.add_argument(
        "--color",
        choices=("auto", "always", "never"),
        default="auto",
        help="colour in the text output (default: auto)",
    )
    mass.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    """Load one mesh, gate it, and print its mass properties."""
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
        render_mass(console, props, units=args.units)
    return ExitCode.OK
