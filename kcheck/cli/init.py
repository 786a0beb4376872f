"""``kcheck init``: a commented template scene for a coupling family, from a mesh or not."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck.cli.common import ExitCode, fail
from kcheck.records import dataclass

if TYPE_CHECKING:
    import numpy as np

__all__ = ["add_parser", "run", "guess_units", "template"]

COUPLINGS = ("maxwell", "kelvin", "321", "planar")


def add_parser(sub: Any) -> None:
    """Register the ``init`` command."""
    init = sub.add_parser(
        "init",
        help="write a commented template scene (from a mesh: bounds and centre of mass filled in)",
        description="Write a template scene for a coupling family that loads and checks as it "
        "is; edit the supports to your design. With --mesh, the mesh's length unit is guessed "
        "from its size (and the guess is said in a comment), and its bounds and centre of mass "
        "are filled in.",
    )
    init.add_argument("--coupling", choices=COUPLINGS, help="(default: maxwell)")
    init.add_argument("--mesh", type=Path, help="the moving body's mesh (STL, OBJ, STEP, ...)")
    init.add_argument(
        "--assembly",
        nargs="+",
        type=Path,
        metavar="FILE",
        help="instead of a template: the base's and the body's meshes in assembly position "
        "(BASE BODY), or one assembly file with --base-part and --body-part; the contacts are "
        "found and fitted as `kcheck contacts` does",
    )
    init.add_argument("--base-part", metavar="NAME", help="with --assembly FILE: the base's part")
    init.add_argument("--body-part", metavar="NAME", help="with --assembly FILE: the body's part")
    init.add_argument(
        "--units", default="m", help="with --assembly: the meshes' length unit (default: m)"
    )
    init.add_argument(
        "--gap", type=float, help="with --assembly: the gap tolerance (see `kcheck contacts`)"
    )
    init.add_argument(
        "--friction",
        type=float,
        default=0.1,
        help="with --assembly: Coulomb coefficient (default 0.1)",
    )
    init.add_argument(
        "--material", default="aluminium", help="material of the body (default: aluminium)"
    )
    init.add_argument(
        "--output",
        "-o",
        help="scene file to write (default: <mesh name>.kcheck.yaml next to the mesh, or "
        "coupling.kcheck.yaml); `-` for stdout",
    )
    init.add_argument("--force", action="store_true", help="overwrite an existing file")
    init.set_defaults(handler=run)


def guess_units(extent: float) -> tuple[str, str]:
    """A mesh's likely length unit from its largest extent in file units, and why."""
    if extent < 2.0:
        return "m", f"largest extent {extent:.4g}: {extent * 1e3:.4g} mm if metres"
    if extent < 5000.0:
        return (
            "mm",
            f"largest extent {extent:.4g}: {extent:.4g} mm, or {extent * 25.4:.4g} mm if inches",
        )
    return "um", f"largest extent {extent:.4g}: {extent / 1e3:.4g} mm if µm"


@dataclass(frozen=True)
class _Body:
    """What the template knows of the body, in scene units."""

    lines: list[str]
    lo: np.ndarray
    hi: np.ndarray
    com: np.ndarray
    units: str


def _n(x: float) -> str:
    # Formatting: a computed value below 1e-9 is rounding of a zero and is written 0.
    return f"{float(x):.6g}" if abs(x) >= 1e-9 else "0"


def _v(values: Any) -> str:
    return "[" + ", ".join(_n(x) for x in values) + "]"


def _mesh_body(mesh_path: Path, scene_path: Path, material: str) -> _Body:
    import numpy as np

    from kcheck.body.mass import load_mesh, mesh_mass_properties, step_length_unit
    from kcheck.fmt import MESH_DIGITS, justified
    from kcheck.scene.materials import density_of
    from kcheck.scene.units import LENGTH_TO_M

    density = density_of(material) or 0.0
    step = mesh_path.suffix.lower() in (".step", ".stp")
    mesh = load_mesh(mesh_path, 1.0, "mesh")
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    if step:
        units = "mm"
        why = [
            f"# units: STEP declares its own ({step_length_unit(mesh_path) or 'unknown'}); "
            "the scene's coordinates are in mm"
        ]
        mesh.apply_scale(1.0)
        to_scene = 1e3
    else:
        units, reason = guess_units(extent)
        why = [
            f"# units: {units} is a GUESS from the mesh's size ({reason}).",
            "#   STL, OBJ and PLY carry no unit: check it; for inches write `units: in`.",
        ]
        mesh.apply_scale(LENGTH_TO_M[units])
        to_scene = 1 / LENGTH_TO_M[units]
    props = mesh_mass_properties(mesh, density, mesh_path, "mesh")
    assert props.bounds is not None  # a mesh's properties have its bounds
    # Only the digits a float32 mesh carries (a centre of mass of 3e-08 on a 140 mm part is 0).
    size = max(extent * (1e3 if step else 1.0), float(np.abs(props.bounds * to_scene).max()))
    lo, hi = np.array(justified(props.bounds * to_scene, size, MESH_DIGITS))
    com = np.array(justified(props.center_of_mass * to_scene, size, MESH_DIGITS))
    try:
        relative = mesh_path.resolve().relative_to(scene_path.resolve().parent)
    except ValueError:
        relative = mesh_path.resolve()
    lines = [
        *why,
        f"# The mesh spans x {_n(lo[0])} … {_n(hi[0])}, y {_n(lo[1])} … {_n(hi[1])}, "
        f"z {_n(lo[2])} … {_n(hi[2])} {units};",
        f"# its centre of mass is {_v(com)} {units}, its mass {props.mass:.4g} kg as "
        f"{material} (`kcheck mass` tells more).",
        f"units: {units}",
        "body:",
        f"  mesh: {relative.as_posix()}",
        f"  material: {material}            # CHANGE to the body's material (or density: kg/m^3)",
    ]
    return _Body(lines, lo, hi, com, units)


def _placeholder_body(material: str) -> _Body:
    import numpy as np

    lo, hi = np.zeros(3), np.array([100.0, 100.0, 20.0])
    com = (lo + hi) / 2
    mass = 2700.0 * 0.1 * 0.1 * 0.02
    ixx = mass * (0.1**2 + 0.02**2) / 12
    izz = mass * (0.1**2 + 0.1**2) / 12
    lines = [
        "# No mesh given: a placeholder 100 x 100 x 20 mm aluminium plate with explicit mass",
        "# properties. Replace them by `mesh: your-part.stl` and `material:` (or run",
        "# `kcheck init --mesh your-part.stl`).",
        "units: mm",
        "body:",
        f"  mass: {_n(mass)}                  # kg",
        f"  center_of_mass: {_v(com)}",
        f"  inertia: [[{ixx:.6g}, 0, 0], [0, {ixx:.6g}, 0], [0, 0, {izz:.6g}]]   # kg m^2",
    ]
    return _Body(lines, lo, hi, com, "mm")


def _ring(body: _Body) -> tuple[np.ndarray, float, float]:
    """Centre of the ball circle (under the body), its radius and the balls' radius."""
    import numpy as np

    size = body.hi - body.lo
    span = float(min(size[0], size[1]))
    ball = float(f"{0.05 * span:.2g}")
    arm = float(f"{0.35 * span:.3g}")
    centre = np.array(
        [(body.lo[0] + body.hi[0]) / 2, (body.lo[1] + body.hi[1]) / 2, body.lo[2] - ball]
    )
    return centre, arm, ball


def _balls(body: _Body) -> list[np.ndarray]:
    import numpy as np

    centre, arm, _ = _ring(body)
    return [
        centre + arm * np.array([np.cos(np.radians(a)), np.sin(np.radians(a)), 0.0])
        for a in (90.0, 210.0, 330.0)
    ]


def _closing(body: _Body, magnitude: float = 10.0) -> list[str]:
    top = [(body.lo[0] + body.hi[0]) / 2, (body.lo[1] + body.hi[1]) / 2, body.hi[2]]
    return [
        "friction: 0.1                      # CHANGE: Coulomb coefficient of the contacts",
        "gravity: [0, 0, -9.81]             # m/s^2 in the scene's axes",
        "load:                              # the closing force (a spring, a push, a clamp)",
        f"  point: {_v(top)}",
        f"  magnitude: {_n(magnitude)}                     # N",
        "  direction: [0, 0, -1]            # the design's direction; kcheck reports its margin",
        "sweep: {normal: [0, -1, 0], zero: [0, 0, -1]}   # angles reported in the xz-plane",
    ]


def _maxwell(body: _Body) -> list[str]:
    import numpy as np

    _, _, r = _ring(body)
    out = [
        "# The balls belong to the body: in its mesh, or as `point_masses` under `body`.",
        "couplings:   # three balls under the body in radial 90-degree V-grooves of the base",
    ]
    for k, c in enumerate(_balls(body)):
        radial = c[:2] - np.array([(body.lo[0] + body.hi[0]) / 2, (body.lo[1] + body.hi[1]) / 2])
        out.append(
            f"  - {{name: g{k + 1}, type: ball-vee, ball: {{center: {_v(c)}, radius: {_n(r)}}},"
        )
        out.append(f"     groove: {{axis: {_v([*radial, 0])}, up: [0, 0, 1], half_angle: 45}}}}")
    return out + _closing(body)


def _kelvin(body: _Body) -> list[str]:

    _, _, r = _ring(body)
    a, b, c = _balls(body)
    return [
        "# The balls belong to the body: in its mesh, or as `point_masses` under `body`.",
        "couplings:   # Kelvin: a trihedral socket, a V-groove aimed at it, a flat",
        f"  - {{name: socket, type: ball-trihedral, ball: {{center: {_v(a)}, radius: {_n(r)}}},",
        "     up: [0, 0, 1], half_angle: 54.7356, reference: [0, 1, 0]}",
        f"  - {{name: vee, type: ball-vee, ball: {{center: {_v(b)}, radius: {_n(r)}}},",
        f"     groove: {{axis: {_v([*(a - b)[:2], 0])}, up: [0, 0, 1], half_angle: 45}}}}",
        f"  - {{name: flat, type: ball-flat, ball: {{center: {_v(c)}, radius: {_n(r)}}}, "
        "normal: [0, 0, 1]}",
        *_closing(body),
    ]


def _321(body: _Body) -> list[str]:
    import numpy as np

    lo, hi = body.lo, body.hi
    s, mid = hi - lo, (lo + hi) / 2

    def at(fx: float, fy: float, fz: float) -> str:
        return _v(lo + s * np.array([fx, fy, fz]))

    return [
        "supports:    # 3-2-1: three under the body (z), two on its side (y), one at its end (x)",
        f"  - {{name: x1, position: {at(0, 0.5, 0.5)}, normal: [1, 0, 0]}}",
        f"  - {{name: y1, position: {at(0.2, 0, 0.5)}, normal: [0, 1, 0]}}",
        f"  - {{name: y2, position: {at(0.8, 0, 0.5)}, normal: [0, 1, 0]}}",
        f"  - {{name: z1, position: {at(0.15, 0.2, 0)}, normal: [0, 0, 1]}}",
        f"  - {{name: z2, position: {at(0.85, 0.2, 0)}, normal: [0, 0, 1]}}",
        f"  - {{name: z3, position: {at(0.5, 0.85, 0)}, normal: [0, 0, 1]}}",
        "friction: 0.1                      # CHANGE: Coulomb coefficient of the contacts",
        "load:                              # a pusher into the x1/y1/y2 corner, and down",
        f"  point: {_v([mid[0], mid[1], hi[2]])}",
        "  magnitude: 10                    # N",
        "  direction: [-0.6, -0.6, -0.53]",
    ]


def _planar(body: _Body) -> list[str]:
    lo, hi = body.lo, body.hi
    s = hi - lo
    z = body.com[2]
    return [
        "supports:    # planar: two under the long edge (y), one at the end (x), at the centre "
        "of mass's height",
        f"  - {{name: y1, position: {_v([lo[0] + 0.2 * s[0], lo[1], z])}, normal: [0, 1, 0]}}",
        f"  - {{name: y2, position: {_v([lo[0] + 0.8 * s[0], lo[1], z])}, normal: [0, 1, 0]}}",
        f"  - {{name: x1, position: {_v([lo[0], lo[1] + 0.5 * s[1], z])}, normal: [1, 0, 0]}}",
        "friction: 0.1                      # CHANGE: Coulomb coefficient of the contacts",
        "load:                              # the closing force, at the centre of mass",
        "  magnitude: 1                     # N",
        "  angle: 225                       # deg from +x: down and to the left, into the corner",
    ]


def template(coupling: str, mesh: Path | None, scene_path: Path, material: str) -> str:
    """The template scene's text."""
    body = _placeholder_body(material) if mesh is None else _mesh_body(mesh, scene_path, material)
    family = {"maxwell": _maxwell, "kelvin": _kelvin, "321": _321, "planar": _planar}[coupling]
    header = [
        f"# A {coupling} coupling, written by `kcheck init`: it loads and checks as it is.",
        "# Edit the supports to your design (docs/scene-format.md lists every field), then run",
        f"# `kcheck check {scene_path.name}`.",
        "version: 1",
        f"name: '{scene_path.name.removesuffix('.kcheck.yaml')}'",
    ]
    return "\n".join([*header, *body.lines, *family(body), ""])


def run(args: argparse.Namespace) -> int:
    """Write the template scene."""
    from kcheck.errors import MeshError
    from kcheck.scene.materials import density_of, known_names

    if args.assembly is not None:
        return _from_assembly(args)
    if args.coupling is None:
        args.coupling = "maxwell"
    if density_of(args.material) is None:
        return fail(f"unknown material `{args.material}`; known: {known_names()}")
    if args.mesh is not None and not args.mesh.is_file():
        return fail(f"{args.mesh}: no such file")
    if args.output == "-":
        target = None
        scene_path = (
            Path("coupling.kcheck.yaml")
            if args.mesh is None
            else args.mesh.with_name(args.mesh.stem + ".kcheck.yaml")
        )
    else:
        if args.output is not None:
            scene_path = Path(args.output)
        elif args.mesh is not None:
            scene_path = args.mesh.with_name(args.mesh.stem + ".kcheck.yaml")
        else:
            scene_path = Path("coupling.kcheck.yaml")
        target = scene_path
        if target.exists() and not args.force:
            return fail(f"{target} exists; pass --force to overwrite it")
    try:
        text = template(args.coupling, args.mesh, scene_path, args.material)
    except MeshError as exc:
        return fail(f"{exc.path}: {exc.message}")
    if target is None:
        sys.stdout.write(text)
    else:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
        print(f"wrote {target} ({args.coupling}); check it with `kcheck check {target}`")
    return ExitCode.OK


def _from_assembly(args: argparse.Namespace) -> int:
    """``kcheck init --assembly BASE BODY``: the scene of ``kcheck contacts BASE BODY``,
    written where ``init`` writes (next to the body unless ``-o``; ``-`` for stdout)."""
    from kcheck.cli import contacts

    if args.mesh is not None or args.coupling is not None:
        which = "--mesh" if args.mesh is not None else "--coupling"
        return fail(f"{which} and --assembly exclude each other: --assembly finds the coupling")
    if len(args.assembly) > 2:
        return fail("--assembly takes BASE BODY, or one assembly file with --base-part/--body-part")
    base, body = (*args.assembly, None) if len(args.assembly) == 1 else args.assembly
    if args.output == "-":
        output = None
    else:
        named = body if body is not None else base  # next to the body, or the assembly
        output = (
            Path(args.output)
            if args.output is not None
            else named.with_name(named.stem + ".kcheck.yaml")
        )
        if output.exists() and not args.force:
            return fail(f"{output} exists; pass --force to overwrite it")
    found = argparse.Namespace(
        base=base,
        body=body,
        base_part=args.base_part,
        body_part=args.body_part,
        units=args.units,
        gap=args.gap,
        material=args.material,
        friction=args.friction,
        output=output,
    )
    code = contacts.run(found)
    if code == ExitCode.OK and output is not None:
        print(f"wrote {output}; check it with `kcheck check {output}`", file=sys.stderr)
    return code
