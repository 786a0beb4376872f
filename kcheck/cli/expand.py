"""``kcheck expand``: a scene with every coupling shorthand written out as explicit supports."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from kcheck.cli.common import ExitCode, write_text

__all__ = ["add_parser", "run", "expanded_text"]


def add_parser(sub: Any) -> None:
    """Register the ``expand`` command."""
    expand = sub.add_parser(
        "expand",
        help="print a scene with its coupling shorthands expanded into explicit supports",
        description="Print the scene with every `couplings:` entry expanded into explicit "
        "supports (named <coupling>.<k>, positions in the scene's units). The output is a "
        "valid scene that checks identically; write it next to the original so that mesh "
        "paths still resolve.",
    )
    expand.add_argument("scene", type=Path, help="a *.kcheck.yaml file")
    expand.add_argument("--output", "-o", type=Path, help="write to this file (default: stdout)")
    expand.add_argument(
        "--allow-outside-paths",
        action="store_true",
        help="let the scene use meshes outside its own folder",
    )
    expand.set_defaults(handler=run)


def _in_units(value_si: float, scale: float) -> float:
    """The number x with ``x * scale == value_si`` exactly (so reloading gives the same
    metres); the nearest float to ``value_si / scale`` when none is found nearby."""
    import numpy as np

    x = value_si / scale
    candidates = [x]
    for direction in (np.inf, -np.inf):
        y = x
        for _ in range(4):
            y = float(np.nextafter(y, direction))
            candidates.append(y)
    return next((c for c in candidates if c * scale == value_si), x)


def _contact(g: Any, scale: float) -> dict[str, Any] | None:
    """An expanded support's `contact` (scene units), so that `hertz` checks it as before;
    None for a line contact (ball-cone), which an explicit point contact cannot describe."""
    import numpy as np

    if g.line_contact:
        return None
    seat, ball = (g.base, g.body) if g.ball_on == "body" else (g.body, g.base)
    out: dict[str, Any] = {"ball_radius": _in_units(g.ball_radius, scale), "ball_on": g.ball_on}
    if ball.radii != (g.ball_radius, g.ball_radius):  # a canoe ball
        out["ball_radii"] = [_in_units(r, scale) for r in ball.radii]
        if ball.direction is not None:
            out["ball_direction"] = [float(v) for v in ball.direction]
    if any(np.isfinite(seat.radii)):
        out["seat_radii"] = [None if np.isinf(r) else _in_units(r, scale) for r in seat.radii]
    if seat.direction is not None:
        out["seat_direction"] = [float(v) for v in seat.direction]
    for side in ("ball_material", "seat_material"):
        if getattr(g, side) is not None:
            out[side] = getattr(g, side)
    return out


def expanded_text(path: Path, *, allow_outside: bool = False) -> str:
    """The scene file's text with its couplings expanded (validated first)."""
    import numpy as np

    from kcheck.fmt import justified
    from kcheck.scene import load_scene
    from kcheck.scene.yamlio import dump_yaml, read_yaml

    scene = load_scene(path, allow_outside=allow_outside)
    data = read_yaml(path).data
    raw_couplings = data.get("couplings") or []
    with_friction = {c["name"] for c in raw_couplings if "friction" in c}
    expanded = []
    # Only the digits the input justifies: positions to COMPUTED_DIGITS of the supports' reach
    # (0.3 - 0.1 is written 0.2, not 0.19999999999999998), unit normals of 1.
    size = max((float(np.abs(s.position).max()) for s in scene.supports), default=0.0)
    for s in scene.supports:
        if s.geometry is None:
            continue
        entry: dict[str, Any] = {
            "name": s.name,
            "position": justified(
                [_in_units(float(v), scene.scale) for v in s.position], size / scene.scale
            ),
            "normal": justified(s.normal, 1.0),
        }
        if s.geometry.coupling in with_friction:
            entry["friction"] = s.coefficients.to_yaml()
        contact = _contact(s.geometry, scene.scale)
        if contact is not None:
            entry["contact"] = contact
        expanded.append(entry)
    out: dict[str, Any] = {}
    for key, value in data.items():
        if key == "couplings":
            if "supports" not in data:
                out["supports"] = expanded
        elif key == "supports":
            out["supports"] = [*value, *expanded]
        else:
            out[key] = value
    header = (
        f"# Expanded by `kcheck expand` from {path.name}: every coupling shorthand written as\n"
        f"# explicit supports (positions in {scene.units}, unit normals into the body).\n"
    )
    return header + dump_yaml(out, flow_items=("supports",))


def run(args: argparse.Namespace) -> int:
    """Print (or write) the expanded scene."""
    write_text(expanded_text(args.scene, allow_outside=args.allow_outside_paths), args.output)
    return ExitCode.OK
