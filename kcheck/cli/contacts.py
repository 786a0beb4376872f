"""``kcheck contacts``: a scene from an assembly: where the body touches its base, the fitted
surfaces there, the coupling elements they make, written as a commented scene."""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path
from typing import Any

from kcheck.cli.common import ExitCode, fail, write_text

__all__ = ["add_parser", "run", "scene_text"]

#: Two binary STL files read at once, in two threads (:func:`_read_all`), scipy imported
#: meanwhile: 2.59 s wall against 2.98 s one after the other at load 1.3-2.2 on the 2-core
#: machine, for 0.1 s more CPU; at load 5-6 it went either way (the threads wait for the GIL
#: on busy cores). benchmarks/bench_contacts_command.py times both.
READ_IN_THREADS = True


def add_parser(sub: Any) -> None:
    """Register the ``contacts`` command."""
    p = sub.add_parser(
        "contacts",
        help="find the contacts of a body seated on its base (two meshes in assembly position) "
        "and write a scene",
        description="Find where BODY touches BASE (meshes in assembly position), fit a plane, "
        "sphere, cylinder, cone or torus to each side of each contact, recognise the coupling "
        "elements (ball-vee, ball-flat, ball-trihedral, ball-cone, ball-cylinders, ball-sphere, "
        "canoe balls, crossed cylinders) "
        "and write a commented scene that checks as written. The report goes to standard "
        "error. Exit 2 on bad input (no contact, interpenetration, unreadable or open mesh); "
        "exit 1 when the contacts found are not a kinematic coupling (a line or area contact, "
        "not 6 point contacts): the report says why and no scene is written. Two extrusions "
        "touching along 3 parallel lines make a planar coupling: a planar scene is written, a "
        "support at each line's middle (the assembly turned so that the lines run along z).",
    )
    p.add_argument(
        "base",
        type=Path,
        help="the base's mesh (STL, OBJ, ...; STEP with the extra), or the assembly file that "
        "holds both parts (with --base-part and --body-part)",
    )
    p.add_argument("body", type=Path, nargs="?", help="the body's mesh, in the same coordinates")
    p.add_argument(
        "--base-part",
        metavar="NAME",
        help="the base's part in an assembly file (STEP, glTF, 3MF): its name there",
    )
    p.add_argument("--body-part", metavar="NAME", help="the body's part in an assembly file")
    p.add_argument(
        "--units", default="m", help="length unit of both files and the scene (default: m)"
    )
    p.add_argument(
        "--gap",
        type=float,
        help="gap tolerance in --units: surfaces closer than this touch (default: 1e-3 of the "
        "assembly's size)",
    )
    p.add_argument(
        "--material", default="aluminium", help="the body's material (default: aluminium)"
    )
    p.add_argument("--friction", type=float, default=0.1, help="Coulomb coefficient (default 0.1)")
    p.add_argument("--output", "-o", type=Path, help="write the scene here (default: stdout)")
    p.set_defaults(handler=run)


def _num(x: float) -> str:
    v = float(f"{x:.12g}")
    return repr(v + 0.0)


def _flow(obj: Any) -> str:
    """YAML flow text of plain data (dicts, lists, numbers, strings)."""
    import numpy as np

    if isinstance(obj, dict):
        return "{" + ", ".join(f"{k}: {_flow(v)}" for k, v in obj.items()) + "}"
    if isinstance(obj, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_flow(v) for v in obj) + "]"
    if isinstance(obj, str):
        return obj
    return _num(float(obj))


def _scaled(obj: Any, scale: float, key: str = "") -> Any:
    """A shorthand's fields (m) in scene units: lengths divided, directions and angles kept."""
    import numpy as np

    if isinstance(obj, dict):
        return {k: _scaled(v, scale, k) for k, v in obj.items()}
    if isinstance(obj, tuple):  # a cylinder (point, axis, radius) or sphere (centre, radius)
        if len(obj) == 3:
            return {"point": obj[0] / scale, "axis": obj[1], "radius": obj[2] / scale}
        return {"center": obj[0] / scale, "radius": obj[1] / scale}
    if isinstance(obj, list):
        return [_scaled(v, scale, key) for v in obj]
    if key in ("center", "radius", "point", "surface_radii"):
        return np.asarray(obj) / scale if isinstance(obj, np.ndarray) else obj / scale
    return obj


def _mm(x: float, scale: float, units: str) -> str:
    return f"{x / scale:.4g} {units}"


def report_lines(found: Any, scale: float, units: str) -> list[str]:
    """The report: each element with its fits and contacts, then what could not be used."""
    lines = []
    for e in found.elements:
        head = f"{e.name}: {e.kind}"
        canoe = e.contacts[0].canoe if e.contacts else None
        if canoe is not None:
            head += (
                f", canoe ball on the {e.ball_on} (torus fit RMS {_mm(canoe.rms, scale, units)}, "
                f"circle radius {_mm(canoe.radius, scale, units)}, tube radius "
                f"{_mm(canoe.tube, scale, units)})"
            )
        elif e.ball is not None:
            head += (
                f", ball radius {_mm(e.ball.radius, scale, units)} on the {e.ball_on}"
                f" (sphere fit RMS {_mm(e.ball.rms, scale, units)})"
            )
        lines.append(head)
        for k, c in enumerate(e.contacts, start=1):
            mate = c.mate
            fit = f"{mate.kind} fit RMS {_mm(mate.rms, scale, units)}"
            if mate.kind == "cone":
                fit += f", half-angle {math.degrees(mate.half_angle):.6g} deg"
            elif mate.kind != "plane":
                fit += f", radius {_mm(mate.radius, scale, units)}"
            p = ", ".join(f"{v / scale:.6g}" for v in c.point)
            n = ", ".join(f"{v:.6f}" for v in c.normal)
            lines.append(
                f"  contact {k}: at ({p}) {units}, normal ({n}); on {fit}; fitted gap "
                f"{_mm(c.gap, scale, units)}; fitted contact to the meshes' nearest touch "
                f"{_mm(c.to_mesh, scale, units)}"
            )
    for u in found.unusable:
        where = ", ".join(f"{v / scale:.4g}" for v in u.region.points.mean(axis=0))
        cost = f" (removes {u.constraints} freedoms)" if u.constraints else ""
        lines.append(f"not used: {u.what} near ({where}) {units}: {u.why}{cost}")
    return lines


def scene_text(
    found: Any,
    mesh: str,
    scale: float,
    units: str,
    material: str,
    friction: float,
    command: str,
    notes: list[str],
    flat: Any = None,
) -> str:
    """A scene (commented YAML) from recognised elements (``flat``: unused, the planar
    scene's argument)."""
    import numpy as np

    out = [
        f"# Written by `{command}`:",
        "# the contacts found in the assembly, each side's surface fitted (plane, sphere,",
        "# cylinder) and recognised as the elements below (lengths in the scene's units).",
    ]
    out += [f"#   {line}" for line in report_lines(found, scale, units) + notes]
    out += [
        "version: 1",
        f"units: {units}",
        f"body: {{mesh: {mesh}, material: {material}}}   # CHANGE the material if it differs",
    ]
    shorthands = [e for e in found.elements if e.fields is not None]
    explicit = [e for e in found.elements if e.fields is None]
    if explicit:
        out.append("supports:")
        for e in explicit:
            what = "crossed cylinders" if e.kind == "cylinder-crossed" else "fitted contacts"
            out.append(f"  # {e.name}: {what}, written out (no shorthand reproduces them)")
            for k, c in enumerate(e.contacts, start=1):
                out.append(
                    f"  - {{name: {e.name}.{k}, position: {_flow(c.point / scale)}, "
                    f"normal: {_flow(c.normal)}}}"
                )
    if shorthands:
        out.append("couplings:")
        for e in shorthands:
            assert e.fields is not None
            entry = {"name": e.name, "type": e.kind}
            if e.ball_on == "base":
                entry["ball_on"] = "base"
            entry.update(_scaled(e.fields, scale))
            out.append(f"  - {_flow(entry)}")
    normals = np.array([c.normal for e in found.elements for c in e.contacts])
    push = -normals.sum(axis=0)
    push = push / np.linalg.norm(push) if np.linalg.norm(push) > 1e-9 else np.array([0, 0, -1.0])
    out += [
        f"friction: {_num(friction)}                 # CHANGE: Coulomb coefficient of the contacts",
        "gravity: [0, 0, -9.81]        # CHANGE if the assembly's z is not up",
        "load:                         # CHANGE: the closing force; this one pushes the body",
        "  magnitude: 10               # into its seat (against the sum of the normals), N",
        f"  direction: {_flow(push)}",
    ]
    return "\n".join(out) + "\n"


def planar_report(found: Any, flat: Any, scale: float, units: str) -> list[str]:
    """The report of a planar coupling: its axis, each line contact as the cross-section's
    point contact, then what could not be used besides the lines."""
    import numpy as np

    turn = flat.rotation
    along = turn.T @ flat.axis  # the lines' axis in the assembly
    tilt = math.degrees(math.acos(min(1.0, abs(float(along[2])))))
    a = ", ".join(_short(v) for v in along)
    lines = [
        f"planar coupling: {len(flat.lines)} line contacts along ({a}) ({tilt:.3g} deg from z), "
        "both parts extrusions along it; each line is a point contact of the cross-section"
    ]
    turned = not np.allclose(turn, np.eye(3), rtol=0.0, atol=0.0)
    if turned:
        angle, k = _axis_angle(turn)
        lines.append(
            f"  the scene is the assembly turned by {_short(angle)} deg about "
            f"({', '.join(_short(v) for v in k)}), so that the lines run along z; "
            "the coordinates below are the scene's"
        )
    for k, (line, _) in enumerate(flat.lines, start=1):
        half = line.half_length * line.axis
        ends = [line.point - half, line.point + half]
        fits = "; ".join(
            f"{side} {p.kind} fit RMS {_mm(p.rms, scale, units)}"
            + (f", radius {_mm(p.radius, scale, units)}" if p.kind == "cylinder" else "")
            for side, p in (("body", line.body_fit), ("base", line.base_fit))
        )
        p = ", ".join(_short(v / scale) for v in line.point[:2])
        n = ", ".join(f"{round(float(v), 9) + 0.0:.6f}" for v in _in_plane(line.normal))
        lines.append(
            f"  s{k}: the body's {line.body_fit.kind} on the base's {line.base_fit.kind}, "
            f"a line along z from {_short(ends[0][2] / scale)} to "
            f"{_short(ends[1][2] / scale)} {units}: in the plane at ({p}) {units}, normal ({n}); "
            f"{fits}; fitted gap {_mm(line.gap, scale, units)}"
        )
    for u in flat.slides:
        where = ", ".join(_short(v / scale) for v in turn @ u.region.points.mean(axis=0))
        lines.append(
            f"  the plane of motion: the body's plane on the base's near ({where}) {units}, "
            "square to the lines (the body slides on it; not a contact of the planar coupling: "
            "its friction is not in the scene)"
        )
    used = {id(u) for _, u in flat.lines} | {id(u) for u in flat.slides}
    for u in found.unusable:
        if id(u) in used:
            continue
        if _line_end(u, along):
            where = ", ".join(_short(v / scale) for v in turn @ u.region.points.mean(axis=0))
            lines.append(
                f"  a line's end near ({where}) {units}: a cylinder along the lines meets a "
                "plane square to them (the edge of the plane of motion), not a contact"
            )
        else:
            where = ", ".join(f"{v / scale:.4g}" for v in turn @ u.region.points.mean(axis=0))
            lines.append(f"not used: {u.what} near ({where}) {units}: {u.why}")
    return lines


def _axis_angle(r: Any) -> tuple[float, Any]:
    """A rotation matrix's angle (deg) and unit axis."""
    import numpy as np

    angle = math.acos(max(-1.0, min(1.0, (float(np.trace(r)) - 1) / 2)))
    k = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return math.degrees(angle), k / np.linalg.norm(k)


def _line_end(u: Any, axis: Any) -> bool:
    """Whether an unusable region (constraining nothing) is a plane square to the planar
    coupling's ``axis`` meeting a cylinder along it: where a pin stands on the plane of
    motion, beside the body that slides on it."""
    from kcheck.numerics.thresholds import EXTRUSION_DEG

    fits = {f.kind: f for f in (u.region.body_fit, u.region.base_fit) if f is not None}
    if u.constraints or set(fits) != {"plane", "cylinder"}:
        return False
    square = math.cos(math.radians(EXTRUSION_DEG))
    return all(abs(float(f.axis @ axis)) >= square for f in fits.values())


def _short(x: float) -> str:
    """A number to 6 digits, rounding below 1e-9 (of the unit) to 0."""
    return f"{round(float(x), 9) + 0.0:.6g}"


def _in_plane(v: Any) -> Any:
    """A direction's xy components, made a unit vector again (z = 0)."""
    import numpy as np

    w = np.array([v[0], v[1], 0.0])
    return w / np.linalg.norm(w) + 0.0  # no -0.0


def planar_scene_text(
    found: Any,
    mesh: str,
    scale: float,
    units: str,
    material: str,
    friction: float,
    command: str,
    notes: list[str],
    flat: Any = None,
) -> str:
    """A planar scene (commented YAML) from the line contacts of two extrusions along z
    (``flat``, a :class:`kcheck.body.coupling_elements.Planar`): a support at each line's
    middle, all at their mean height, normals in the xy-plane."""
    import numpy as np

    out = [
        f"# Written by `{command}`:",
        "# the contacts found in the assembly: parallel lines, both parts extrusions along them,",
        "# so a planar coupling in the scene's xy-plane (the lines along z): a support at each",
        "# line's middle, at the lines' mean height, its normal the fitted surfaces' (lengths",
        "# in the scene's units).",
    ]
    out += [f"#   {line}" for line in planar_report(found, flat, scale, units) + notes]
    out += [
        "version: 1",
        f"units: {units}",
    ]
    if np.allclose(flat.rotation, np.eye(3), rtol=0.0, atol=0.0):
        out.append(
            f"body: {{mesh: {mesh}, material: {material}}}   # CHANGE the material if it differs"
        )
    else:
        angle, k = _axis_angle(flat.rotation)
        turn = {"rotate": {"axis": np.round(k, 12) + 0.0, "angle": angle}}
        out += [
            "body:                         # the assembly turned: its lines along z",
            f"  parts: [{{mesh: {mesh}, material: {material}, transform: {_flow(turn)}}}]"
            "   # CHANGE the material if it differs",
        ]
    out.append("supports:")
    z = float(np.mean([line.point[2] for line, _ in flat.lines]))
    normals = []
    for k, (line, _) in enumerate(flat.lines, start=1):
        position = [line.point[0] / scale, line.point[1] / scale, z / scale]
        normals.append(_in_plane(line.normal))
        out.append(f"  - {{name: s{k}, position: {_flow(position)}, normal: {_flow(normals[-1])}}}")
    push = -np.sum(normals, axis=0)
    push = push / np.linalg.norm(push) if np.linalg.norm(push) > 1e-9 else -normals[0]
    out += [
        f"friction: {_num(friction)}                 # CHANGE: Coulomb coefficient of the contacts",
        "# gravity: [0, -9.81, 0]      # CHANGE: add it, in the xy-plane, if the plane of motion",
        "#                             # is not horizontal (a planar scene ignores its z)",
        "load:                         # CHANGE: the closing force; this one pushes the body",
        "  magnitude: 10               # into its seat (against the sum of the normals), N",
        f"  direction: {_flow(push)}",
    ]
    return "\n".join(out) + "\n"


def _read_all(sources: Any, scale: float) -> list[Any]:
    """For each (path, what, part) of ``sources``, a function giving its mesh (a
    :class:`kcheck.body.meshio.Surface`, its shared edges worked out) and its triangles'
    arrays (:class:`~kcheck.body.contact_regions.Faces`), or raising its error.
    With :data:`READ_IN_THREADS`, two binary STL files are read at once, in two threads
    (kcheck's own reader is numpy calls that release the GIL: the file read, the vertex
    merge's sort, the edges' sort) while the main thread imports scipy's modules the finding
    and the fits use; otherwise, and for other files, one after the other (trimesh and the
    STEP reader are not known to be thread-safe, and import in a thread). Errors are raised
    in the files' order."""
    import threading

    from kcheck.body.contact_regions import Faces
    from kcheck.body.meshio import load_surface

    def read(path: Path, what: str, part: str | None) -> Any:
        step = path.suffix.lower() in (".step", ".stp")
        mesh = load_surface(path, 1.0 if step else scale, what, part=part)
        mesh.edges  # noqa: B018  (watertightness: one sort, in this thread)
        # The triangles' arrays for the finding too (numpy, so in parallel in the threads:
        # 0.1 s of wall time a 500,000-face file).
        return mesh, Faces.of(mesh)

    def later(path: Path, what: str, part: str | None) -> Any:
        return lambda: read(path, what, part)

    if (
        not READ_IN_THREADS
        or len(sources) != 2
        or any(part is not None or not _binary_stl_file(path) for path, _, part in sources)
    ):
        return [later(*source) for source in sources]
    done: dict[int, Any] = {}

    def keep(k: int) -> None:
        try:
            done[k] = (True, read(*sources[k]))
        except BaseException as exc:  # raised again in the main thread, in order
            done[k] = (False, exc)

    readers = [threading.Thread(target=keep, args=(k,), daemon=True) for k in (0, 1)]
    for reader in readers:
        reader.start()
    # Meanwhile, what the finding and the fits import (the GIL is free while numpy works).
    import scipy.optimize
    import scipy.sparse.csgraph
    import scipy.spatial  # noqa: F401

    import kcheck.scene.couplings  # noqa: F401  (the shorthands' geometry, for recognise)

    for reader in readers:
        reader.join()

    def result(k: int) -> Any:
        ok, value = done[k]
        if not ok:
            raise value
        return value

    return [lambda: result(0), lambda: result(1)]


def _binary_stl_file(path: Path) -> bool:
    """Whether ``path`` looks like a binary STL file (its name, and its length as its header
    announces it), which kcheck reads by numpy alone, without trimesh."""
    from kcheck.body.meshio import stl_triangle_count

    if path.suffix.lower() != ".stl":
        return False
    try:
        with open(path, "rb") as handle:
            head = handle.read(84)
        size = os.stat(path).st_size
    except OSError:
        return False
    return stl_triangle_count(head, size) is not None


def _mesh_field(body: Path, output: Path | None) -> str:
    """The body's mesh as the scene names it: relative to the scene's folder (or the current
    folder when the scene goes to stdout)."""
    folder = output.parent if output is not None else Path.cwd()
    return os.path.relpath(body.resolve(), folder.resolve()).replace(os.sep, "/")


def run(args: argparse.Namespace) -> int:
    from kcheck.body.contact_regions import contact_regions
    from kcheck.body.coupling_elements import Planar, onto_z, planar, recognise
    from kcheck.body.meshio import not_watertight, reuse_freed_memory
    from kcheck.errors import MeshError
    from kcheck.numerics.thresholds import CONTACT_GAP_RTOL, EXTRUSION_DEG
    from kcheck.scene.materials import density_of, known_names
    from kcheck.scene.units import LENGTH_TO_M as LENGTH_UNITS

    units = args.units
    if units not in LENGTH_UNITS:
        return fail(f"--units {units}: expected one of {', '.join(LENGTH_UNITS)}")
    if density_of(args.material) is None:
        return fail(f"unknown material `{args.material}`; known: {known_names()}")
    if not (math.isfinite(args.friction) and 0 <= args.friction <= 100):
        return fail(f"--friction {args.friction}: expected a number from 0 to 100")
    if args.gap is not None and not (math.isfinite(args.gap) and args.gap > 0):
        return fail(f"--gap {args.gap}: expected a positive length in {units}")
    scale = LENGTH_UNITS[units]
    parts = (getattr(args, "base_part", None), getattr(args, "body_part", None))
    if args.body is None:
        if None in parts:
            return fail(
                "give BASE and BODY files, or one assembly file with --base-part NAME and "
                "--body-part NAME"
            )
        sources = ((args.base, "BASE", parts[0]), (args.base, "BODY", parts[1]))
        # The parts by name in what is said and in the scene's command line.
        args.base, args.body = (Path(f"{args.base}#{name}") for name in parts)
    elif parts != (None, None):
        return fail(
            "--base-part and --body-part name the parts of one assembly file: give one file"
        )
    else:
        sources = ((args.base, "BASE", None), (args.body, "BODY", None))
    reuse_freed_memory()  # large temporaries, each made many times
    meshes, arrays = [], []
    for (path, what, _), read in zip(sources, _read_all(sources, scale), strict=True):
        try:
            mesh, mesh_faces = read()
            if not mesh.is_watertight:
                raise not_watertight(mesh.trimesh(), path, what, scale, units)
        except MeshError as exc:
            return fail(str(exc))
        meshes.append(mesh)
        arrays.append(mesh_faces)
    base, body = meshes
    import numpy as np

    size = float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    gap = args.gap * scale if args.gap is not None else CONTACT_GAP_RTOL * size
    faces = (arrays[0], arrays[1])  # made once, for the finding and merged parts
    touch_faces: list = []
    regions, depth = contact_regions(base, body, gap, faces, touch_faces)
    if depth > gap:
        return fail(
            f"{args.body} and {args.base} interpenetrate by {_mm(depth, scale, units)}, more "
            f"than the gap tolerance {_mm(gap, scale, units)}: place the body on its seat "
            "(touching, not overlapping), or raise --gap"
        )
    touching = [r for r in regions if r.least_distance <= gap]
    if not touching:
        from kcheck.body.contact_regions import NEAR_GAPS

        if regions:
            near = min(r.least_distance for r in regions)
            said = f"they come no closer than {_mm(near, scale, units)}"
        else:
            said = f"they come nowhere within {_mm(NEAR_GAPS * gap, scale, units)} of each other"
        return fail(
            f"{args.body} does not touch {args.base}: {said}, and the gap tolerance is "
            f"{_mm(gap, scale, units)}; export both in assembly position (the body seated), "
            "or raise --gap"
        )
    found = recognise(regions, gap)
    notes = _merged_parts(body, args.body, base, gap, scale, units, faces, touch_faces[0])
    flat = planar(found, {"base": faces[0].normals, "body": faces[1].normals})
    if isinstance(flat, Planar):
        if math.degrees(math.acos(min(1.0, float(flat.axis[2])))) > EXTRUSION_DEG:
            # A planar scene moves in the xy-plane: the scene is the assembly turned.
            flat = onto_z(flat)
        report = planar_report(found, flat, scale, units) + notes
        print("\n".join(report), file=sys.stderr)
    else:
        report = report_lines(found, scale, units) + notes
        count = found.contact_count
        problems = []
        over = [u for u in found.unusable if u.constraints]
        if over:
            removed = sum(u.constraints for u in over)
            problems.append(
                f"{len(over)} line or area contact(s), together removing {removed} freedoms: "
                "over-constrained, not a kinematic coupling"
            )
        if isinstance(flat, str):
            problems.append(flat)
        if count != 6 and flat is None:
            problems.append(
                f"{count} point contact(s) found; a spatial kinematic coupling has exactly 6"
            )
        print("\n".join(report), file=sys.stderr)
        if problems:
            print("kcheck: no scene written: " + "; ".join(problems), file=sys.stderr)
            return ExitCode.CHECKS_FAILED
    command = f"kcheck contacts {args.base} {args.body} --units {units}"
    # Every option that shaped the scene, so that the line re-makes it.
    if args.gap is not None:
        command += f" --gap {_num(args.gap)}"
    if args.material != "aluminium":
        command += f" --material {args.material}"
    if args.friction != 0.1:
        command += f" --friction {_num(args.friction)}"
    body_file = args.body
    if parts[1] is not None:
        # A scene's mesh is a file of its own: the body's part written beside the scene (in
        # the scene's units), so that the scene checks as written.
        folder = args.output.parent if args.output is not None else Path.cwd()
        body_file = folder / f"{sources[1][0].stem}.{parts[1]}.stl"
        try:
            body.trimesh().copy().apply_scale(1.0 / scale).export(body_file)
        except OSError as exc:
            return fail(f"cannot write the body's mesh {body_file}: {exc.strerror}")
        print(f"kcheck: wrote the body's part `{parts[1]}` to {body_file}", file=sys.stderr)
    text = (planar_scene_text if isinstance(flat, Planar) else scene_text)(
        found,
        _mesh_field(body_file, args.output),
        scale,
        units,
        args.material,
        args.friction,
        command,
        notes,
        flat,
    )
    write_text(text, args.output)
    return ExitCode.OK


def _merged_parts(
    body: Any,
    path: Path,
    base: Any,
    gap: float,
    scale: float,
    units: str,
    faces: Any = None,
    touching: Any = None,
) -> list[str]:
    """Findings on a body mesh of several closed bodies: each named (volume, bounds), and
    whether it looks like part of the base (:func:`kcheck.body.contact_regions.merged_pieces`)."""
    from kcheck.body.contact_regions import merged_pieces

    pieces = merged_pieces(body, base, gap, faces, touching)
    if not pieces:
        return []
    lines = [f"{path.name}: {len(pieces)} disconnected closed bodies:"]
    for k, (piece, swallowed) in enumerate(pieces, start=1):
        lo = ", ".join(f"{v / scale:.4g}" for v in piece.bounds[0])
        hi = ", ".join(f"{v / scale:.4g}" for v in piece.bounds[1])
        line = (
            f"  body {k}: volume {piece.volume / scale**3:.4g} {units}^3, bounds ({lo}) to ({hi})"
        )
        if swallowed:
            line += (
                ": it touches the base and sits in grooves of the rest of the body, so it looks "
                "like part of the base exported with the body; its mass is counted as the body's"
            )
        lines.append(line)
    return lines
