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
    mass.add_argument(
        "meshes",
        nargs="+",
        metavar="MESH[:MATERIAL]",
        help="mesh files, each with its own material after a colon (plate.stl:aluminium "
        "balls.stl:steel); a file without one takes --material or --density",
    )
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
    group = mass.add_mutually_exclusive_group()
    group.add_argument(
        "--material", help="name from the built-in material table, for files without their own"
    )
    group.add_argument(
        "--density", type=float, help="density in kg/m^3, for files without their own material"
    )
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
    """Mass properties with lengths in a unit of ``unit_m`` metres, to the digits a mesh
    justifies (:data:`kcheck.fmt.MESH_DIGITS` of each quantity's scale)."""
    from kcheck.body.mass import principal_axes
    from kcheck.fmt import MESH_DIGITS, justified

    inertia = props.inertia / unit_m**2
    moments, axes = principal_axes(props.inertia)
    size = None if props.bounds is None else float(abs(props.bounds).max()) / unit_m
    out: dict[str, Any] = {
        "mass": justified(props.mass, digits=MESH_DIGITS),
        "center_of_mass": justified(props.center_of_mass / unit_m, size, MESH_DIGITS),
        "inertia": justified(inertia, digits=MESH_DIGITS),
        "principal_moments": justified(moments / unit_m**2, digits=MESH_DIGITS),
        "principal_axes": justified(axes.T, 1.0, MESH_DIGITS),
    }
    if props.volume is not None:
        out["volume"] = justified(props.volume / unit_m**3, digits=MESH_DIGITS)
    if props.bounds is not None:
        out["bounds"] = justified(props.bounds / unit_m, size, MESH_DIGITS)
    return out


def _text(console: Any, title: str, values: dict[str, Any], unit: str) -> None:
    from kcheck.fmt import format_number, format_vector

    console.print(title, style="bold")
    if "material" in values:
        console.print(f"  {values['material']}")
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


def split_material(arg: str) -> tuple[Path, str | None]:
    """``plate.stl:aluminium`` as the path and its material; a name that is itself an
    existing file, or whose last colon is followed by a path, has no material."""
    if Path(arg).exists() or ":" not in arg:
        return Path(arg), None
    path, material = arg.rsplit(":", 1)
    if not path or "/" in material or "\\" in material:
        return Path(arg), None
    return Path(path), material


def _densities(
    args: argparse.Namespace,
) -> tuple[list[tuple[Path, str | None, float]], list[str]]:
    """Each mesh with its material (None for --density) and density; the errors found."""
    from kcheck.scene.materials import density_of, known_names

    known = known_names()
    errors: list[str] = []
    default: float | None = None
    if args.material is not None:
        default = density_of(args.material)
        if default is None:
            errors.append(f"unknown material `{args.material}`; known: {known}")
    elif args.density is not None:
        default = args.density
        if not 1.0 <= default <= 3e4:
            errors.append("--density must lie between 1 and 30000 kg/m^3")
    meshes: list[tuple[Path, str | None, float]] = []
    for arg in args.meshes:
        path, material = split_material(arg)
        if material is None:
            if args.material is None and args.density is None:
                errors.append(
                    f"{path}: no material; give --material or --density, or write {path}:MATERIAL"
                )
            elif default is not None:
                meshes.append((path, args.material, default))
            continue
        density = density_of(material)
        if density is None:
            errors.append(f"{path}: unknown material `{material}`; known: {known}")
            continue
        meshes.append((path, material, density))
    return meshes, errors


def run(args: argparse.Namespace) -> int:
    """Load each mesh, gate it, and print its mass properties and bounds; every file that
    cannot be read or gated is reported (exit code 2), not only the first."""
    from kcheck.body.mass import combine, part_mass_properties
    from kcheck.errors import MeshError
    from kcheck.scene import Part
    from kcheck.scene.units import LENGTH_TO_M

    meshes, errors = _densities(args)
    if errors:
        for message in errors[:-1]:
            fail(message)
        return fail(errors[-1])
    step = {m for m, _, _ in meshes if m.suffix.lower() in (".step", ".stp")}
    if args.units is None and len(step) < len(meshes):
        return fail("give --units: STL, OBJ and PLY files carry no length unit")
    report = args.report_units or args.units or "mm"
    unit_m = LENGTH_TO_M[report]
    results: list[tuple[Path, str | None, float, MassProperties]] = []
    for mesh, material, density in meshes:
        if not mesh.is_file():
            errors.append(f"{mesh}: no such file")
            continue
        units = "m" if mesh in step else args.units
        part = Part(mesh.resolve(), density, (), LENGTH_TO_M[units], units)
        try:
            results.append((mesh, material, density, part_mass_properties(part)))
        except MeshError as exc:
            errors.append(f"{exc.path}: {exc.message}")
    densities = {density for _, _, density, _ in results}
    uniform = len({d for _, _, d in meshes}) == 1
    entries: list[tuple[str, MassProperties, str | None, float | None]] = [
        (str(mesh), props, material, density) for mesh, material, density, props in results
    ]
    if len(results) > 1 and not errors:
        entries.append(
            (
                f"all {len(results)} meshes together",
                combine([p for *_, p in results]),
                None,
                None,
            )
        )
    if args.format == "json":
        from kcheck.result import to_json_value

        doc: dict[str, Any] = {
            "units": {"length": report, "mass": "kg", "inertia": f"kg {report}^2"},
            "density": next(iter(densities)) if uniform and densities else None,
            "meshes": [
                {
                    "mesh": name,
                    **({} if density is None else {"material": material, "density": density}),
                    **_in_units(props, unit_m),
                    "notes": list(props.notes),
                }
                for name, props, material, density in entries
            ],
        }
        if errors:
            doc["errors"] = errors
        print(json.dumps(to_json_value(doc), indent=2))
    else:
        from kcheck.report import make_console

        console = make_console(args.color)
        head = f"lengths in {report}, mass in kg, inertia in kg {report}^2"
        if uniform and meshes:
            head += f"; density {meshes[0][2]:g} kg/m^3"
        console.print(head + (f"; files in {args.units}" if args.units else ""))
        for name, props, material, each in entries:
            values = {**_in_units(props, unit_m), "notes": props.notes}
            if not uniform and each is not None:
                values["material"] = f"{material or 'density'} {each:g} kg/m^3"
            _text(console, name, values, report)
    if errors:
        for message in errors[:-1]:
            fail(message)
        return fail(errors[-1])
    return ExitCode.OK
