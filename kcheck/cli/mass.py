"""``kcheck mass``: mass properties and bounds of meshes, in the units asked for."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck.cli.common import ExitCode, fail

if TYPE_CHECKING:
    from kcheck.result import MassProperties

__all__ = ["add_parser", "run"]

UNITS = ("m", "cm", "mm", "um", "in")


def add_parser(sub: Any) -> None:
    """Register the ``mass`` command."""
    mass = sub.add_parser(
        "mass",
        help="mass properties and bounds of meshes, as a CAD package reports them",
        description="Mass, centre of mass, inertia and bounds of each mesh (and of all "
        "together), with lengths in the units asked for, so positions for a scene can be "
        "read off in the model's units.",
    )
    mass.add_argument("meshes", nargs="+", type=Path, metavar="MESH", help="mesh files")
    mass.add_argument(
        "--units",
        choices=UNITS,
        help="length unit of the mesh files (never guessed; STEP files declare their own)",
    )
    mass.add_argument(
        "--report-units",
        choices=UNITS,
        help="length unit of the answer (default: --units, or mm for STEP files)",
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


def _in_units(props: MassProperties, unit_m: float) -> dict[str, Any]:
    """Mass properties with lengths in a unit of ``unit_m`` metres, noise cleaned."""
    from kcheck.body.mass import principal_axes
    from kcheck.fmt import clean

    inertia = props.inertia / unit_m**2
    moments, axes = principal_axes(props.inertia)
    size = None if props.bounds is None else float(abs(props.bounds).max()) / unit_m
    out: dict[str, Any] = {
        "mass": props.mass,
        "center_of_mass": clean(props.center_of_mass / unit_m, size),
        "inertia": clean(inertia),
        "principal_moments": clean(moments / unit_m**2),
        "principal_axes": clean(axes.T),
    }
    if props.volume is not None:
        out["volume"] = props.volume / unit_m**3
    if props.bounds is not None:
        out["bounds"] = clean(props.bounds / unit_m, size)
    return out


def _text(console: Any, title: str, values: dict[str, Any], unit: str) -> None:
    from kcheck.fmt import format_number, format_vector

    console.print(title, style="bold")
    if "bounds" in values:
        lo, hi = values["bounds"]
        spans = ", ".join(
            f"{axis} {format_number(a)} … {format_number(b)}"
            for axis, a, b in zip("xyz", lo, hi, strict=True)
        )
        size = " × ".join(format_number(b - a) for a, b in zip(lo, hi, strict=True))
        console.print(f"  bounds {spans} {unit} (size {size} {unit})")
    volume = values.get("volume")
    console.print(
        f"  mass {format_number(values['mass'])} kg"
        + (f", volume {format_number(volume)} {unit}^3" if volume is not None else "")
    )
    console.print(f"  centre of mass {format_vector(values['center_of_mass'])} {unit}")
    console.print(f"  inertia about the centre of mass (kg {unit}^2):")
    for row in values["inertia"]:
        console.print("    [" + "  ".join(f"{format_number(v):>11}" for v in row) + " ]")
    console.print(f"  principal moments {format_vector(values['principal_moments'])} kg {unit}^2")
    for i, axis in enumerate(values["principal_axes"]):
        console.print(f"    axis {i + 1} {format_vector(axis)}")
    for note in values.get("notes", ()):
        console.print(f"  note: {note}", style="yellow")


def run(args: argparse.Namespace) -> int:
    """Load each mesh, gate it, and print its mass properties and bounds."""
    from kcheck.body.mass import combine, part_mass_properties
    from kcheck.errors import MeshError
    from kcheck.scene import Part
    from kcheck.scene.materials import MATERIALS, density_of
    from kcheck.scene.units import LENGTH_TO_M

    if args.material is not None:
        density = density_of(args.material)
        if density is None:
            return fail(
                f"unknown material `{args.material}`; known: {', '.join(sorted(MATERIALS))}"
            )
    else:
        density = args.density
        if not 1.0 <= density <= 3e4:
            return fail("--density must lie between 1 and 30000 kg/m^3")
    step = [m for m in args.meshes if m.suffix.lower() in (".step", ".stp")]
    if args.units is None and len(step) < len(args.meshes):
        return fail("give --units: STL, OBJ and PLY files carry no length unit")
    report = args.report_units or args.units or "mm"
    unit_m = LENGTH_TO_M[report]
    results = []
    for mesh in args.meshes:
        if not mesh.is_file():
            return fail(f"{mesh}: no such file")
        units = "m" if mesh in step else args.units
        part = Part(mesh.resolve(), density, (), LENGTH_TO_M[units], units)
        try:
            results.append((mesh, part_mass_properties(part)))
        except MeshError as exc:
            return fail(f"{exc.path}: {exc.message}")
    entries = [(str(mesh), props) for mesh, props in results]
    if len(results) > 1:
        entries.append((f"all {len(results)} meshes together", combine([p for _, p in results])))
    if args.format == "json":
        from kcheck.result import to_json_value

        doc = {
            "units": {"length": report, "mass": "kg", "inertia": f"kg {report}^2"},
            "density": density,
            "meshes": [
                {"mesh": name, **_in_units(props, unit_m), "notes": list(props.notes)}
                for name, props in entries
            ],
        }
        print(json.dumps(to_json_value(doc), indent=2))
        return ExitCode.OK
    from kcheck.report import make_console

    console = make_console(args.color)
    console.print(
        f"lengths in {report}, mass in kg, inertia in kg {report}^2; density {density:g} kg/m^3"
        + (f"; files in {args.units}" if args.units else "")
    )
    for name, props in entries:
        _text(console, name, {**_in_units(props, unit_m), "notes": props.notes}, report)
    return ExitCode.OK
