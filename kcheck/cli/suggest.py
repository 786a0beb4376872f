"""``kcheck suggest``: where to put the closing force (attachment point and direction) for the
largest angular margin over every retracted support (docs/suggest.md)."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck.cli.common import ExitCode, fail
from kcheck.cli.suggest_report import Report, write_scene

if TYPE_CHECKING:
    import numpy as np

    from kcheck.analysis.suggest import Search
    from kcheck.scene import Scene

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``suggest`` command."""
    p = sub.add_parser(
        "suggest",
        help="where to put the closing force: the attachment point and direction with the "
        "largest margin",
        description="Search attachment points (on the body's surface, or in a box) and force "
        "directions for the largest angular margin over every retracted support, and print the "
        "best candidates with their margins and limiting friction (spatial and planar scenes).",
    )
    p.add_argument("scene", type=Path, help="a scene file (*.kcheck.yaml)")
    p.add_argument(
        "--box",
        nargs=6,
        type=float,
        metavar=("XMIN", "YMIN", "ZMIN", "XMAX", "YMAX", "ZMAX"),
        help="search a regular grid in this box (scene units) instead of the body's surface",
    )
    p.add_argument("--points", type=int, default=2000, help="candidate points (default 2000)")
    p.add_argument(
        "--directions",
        type=int,
        default=500,
        help="force directions per point on the coarse pass (default 500, about 9° apart)",
    )
    p.add_argument("--magnitude", type=float, help="closing force in N (default: the scene's)")
    p.add_argument(
        "--friction",
        nargs=2,
        type=float,
        metavar=("MIN", "MAX"),
        help="a kinetic friction range for the scene's rough supports, instead of the scene's "
        "own `friction` (which may itself be a range)",
    )
    p.add_argument(
        "--friction-samples",
        type=int,
        default=5,
        help="coefficients of a friction range the search samples (default 5, the ends "
        "included); the reported margins are exact over the whole range",
    )
    p.add_argument("--top", type=int, default=5, help="candidates to print (default 5)")
    p.add_argument("--seed", type=int, default=0, help="seed of the surface sampling")
    p.add_argument("--jobs", "-j", type=int, default=1, help="processes (default 1)")
    p.add_argument(
        "--plot",
        type=Path,
        metavar="FILE",
        help="picture of the margin over the candidate points, PNG or SVG by the file's suffix",
    )
    p.add_argument(
        "--write", type=Path, metavar="FILE", help="write the scene with the best candidate's load"
    )
    p.add_argument(
        "--format", choices=("text", "json"), default="text", help="output (default: text)"
    )
    p.add_argument(
        "--color",
        choices=("auto", "always", "never"),
        default="auto",
        help="colour in the text output (default: auto)",
    )
    p.add_argument(
        "--allow-outside-paths",
        action="store_true",
        help="let the scene use meshes outside its own folder",
    )
    p.set_defaults(handler=run)


def _usage(args: argparse.Namespace) -> str | None:
    from kcheck.scene.limits import LIMITS

    top_force = LIMITS["force"].high  # as a scene's load
    if args.points < 1 or args.directions < 10 or args.top < 1 or args.jobs < 1:
        return "--points, --top and --jobs must be at least 1 and --directions at least 10"
    if args.magnitude is not None and not 0 < args.magnitude <= top_force:
        return f"--magnitude must be positive and at most {top_force:g} (N)"
    if args.friction is not None:
        lo, hi = args.friction
        top_mu = LIMITS["friction"].high  # as a scene's friction
        if not 0 <= lo <= hi <= top_mu:
            return f"--friction needs 0 <= MIN <= MAX <= {top_mu:g}"
        if args.friction_samples < 1:
            return "--friction-samples must be at least 1"
    if args.box is not None and any(a > b for a, b in zip(args.box[:3], args.box[3:], strict=True)):
        return "--box needs XMIN <= XMAX, YMIN <= YMAX and ZMIN <= ZMAX"
    if args.plot is not None and args.plot.suffix.lower() not in (".png", ".svg"):
        return f"--plot {args.plot}: expected a .png or .svg file"
    from kcheck.gate.paths import check_output_file

    if args.plot is not None:
        check_output_file(args.plot, "--plot")  # before the search, not after it
    if args.write is not None:
        check_output_file(args.write, "--write")
    return None


def _friction_scene(scene: Scene, args: argparse.Namespace) -> Scene:
    """The scene whose kinetic coefficients the search uses: its own (a number or a range),
    or ``--friction MIN MAX`` on its rough supports (on every one when it is frictionless)."""
    import dataclasses

    import numpy as np

    from kcheck.scene import Friction

    if args.friction is None:
        return scene
    lo, hi = args.friction
    mu = scene.friction_range("kinetic")[1]
    rough = (mu > 0) if np.any(mu > 0) else np.ones(len(mu), bool)
    spec = Friction((lo, hi), (lo, hi))
    supports = tuple(
        dataclasses.replace(s, friction=hi, friction_spec=None if lo == hi else spec)
        if r
        else dataclasses.replace(s, friction=0.0, friction_spec=None)
        for s, r in zip(scene.supports, rough, strict=True)
    )
    return dataclasses.replace(scene, supports=supports)


def _frictions(scene: Scene, args: argparse.Namespace) -> list[np.ndarray] | None:
    """Per-support coefficient sets the search samples along a kinetic friction range (its
    ends and Chebyshev–Lobatto points between: the supports move together, as the analytical
    checks take a range); None for one coefficient per support."""
    import numpy as np

    from kcheck.mechanics.friction_range import FrictionPath
    from kcheck.numerics.chebyshev import lobatto

    low, high = scene.friction_range("kinetic")
    if np.array_equal(low, high):
        return None
    path = FrictionPath(low, high)
    count = args.friction_samples
    ts = np.array([1.0]) if count == 1 else 0.5 * (lobatto(count) + 1.0)
    return [path.at(t) for t in ts]


def _exact_over_range(found: Search, scene: Scene, mass: Any) -> Search:
    """The best candidates with their margins exact over the friction range, best first."""
    import dataclasses

    best = [
        dataclasses.replace(c, margin=_range_margin(scene, mass, c.point, c.direction))
        for c in found.best
    ]
    best.sort(key=lambda c: -c.margin)
    return dataclasses.replace(found, best=tuple(best))


def _range_margin(scene: Scene, mass: Any, point: np.ndarray, direction: np.ndarray) -> float:
    """The exact margin (rad) of a load at ``point`` along ``direction`` over the scene's
    kinetic friction range: the least, over the cases, of the design margin over the range
    (:mod:`kcheck.analysis.friction_ranges`)."""
    from kcheck.analysis import analyse
    from kcheck.analysis.suggest import with_load

    analysis = analyse(with_load(scene, point, direction), mass)
    info = analysis.friction_range
    worst = [w[1] for w in getattr(info, "worst", ()) if w is not None]
    if len(worst) < len(scene.supports):
        return -float("inf")
    return float(min(worst))


class _Progress:
    """A progress bar on stderr when it is a terminal; nothing otherwise."""

    def __init__(self, total: int, what: str) -> None:
        self.bar = None
        if sys.stderr.isatty():
            from rich.progress import Progress

            self.bar = Progress(transient=True, console=None)
            self.bar.start()
            self.task = self.bar.add_task(what, total=total)

    def __call__(self, done: int) -> None:
        if self.bar is not None:
            self.bar.update(self.task, completed=done)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


def run(args: argparse.Namespace) -> int:
    """Load the scene, search, print the candidates; write the picture and scene if asked."""
    import numpy as np

    from kcheck.analysis.candidates import BoxSampler, SuggestError, SurfaceSampler
    from kcheck.analysis.suggest import search, with_load
    from kcheck.body.mass import body_mass_properties
    from kcheck.errors import KcheckError
    from kcheck.scene import load_scene

    problem = _usage(args)
    if problem:
        return fail(problem)
    started = time.perf_counter()
    try:
        scene = load_scene(args.scene, allow_outside=args.allow_outside_paths)
        if scene.body is None:
            return fail(f"{args.scene}: the scene has no `body` (mass properties are needed)")
        mass = body_mass_properties(scene.body, scene.scale)
        scene = _friction_scene(scene, args)
        load = scene.load
        magnitude = args.magnitude or (load.magnitude if load is not None else 0.0)
        if not magnitude > 0:
            return fail(f"{args.scene}: the scene has no closing load; give --magnitude (N)")
        design = None
        if load is not None and load.direction is not None:
            point = load.point if load.point is not None else mass.center_of_mass
            design = (point, load.direction)
        base = with_load(scene, np.zeros(3), np.array([0.0, 0.0, 1.0]), magnitude)
        if args.box is not None:
            box = np.asarray(args.box, float) * scene.scale
            sampler: Any = BoxSampler(box[:3], box[3:], args.points, args.seed)
        else:
            sampler = SurfaceSampler(scene, args.seed)
        progress = _Progress(args.points, "searching")
        try:
            found = search(
                base,
                mass,
                sampler,
                args.points,
                directions=args.directions,
                keep=args.top,
                frictions=_frictions(scene, args),
                jobs=args.jobs,
                progress=progress,
            )
        finally:
            progress.close()
        if _frictions(scene, args) is not None:
            found = _exact_over_range(found, base, mass)
    except SuggestError as exc:
        return fail(f"{args.scene}: {exc}")
    except KcheckError as exc:
        return fail(str(exc))
    report = Report(
        args,
        scene,
        mass,
        base,
        design,
        _design_margin(args, scene, mass, base, design),
        found,
        magnitude,
    )
    report.least = report.least_force()
    report.runtime = time.perf_counter() - started
    if args.format == "json":
        print(json.dumps(report.to_json(), indent=2))
    else:
        report.print_text()
    if args.plot is not None:
        from kcheck.pictures.suggest import plot_suggestion

        for path in plot_suggestion(scene, found, design, args.plot):
            print(f"wrote {path}", file=sys.stderr)
    if args.write is not None and found.best:
        write_scene(scene, found.best[0], magnitude, args.write)
        print(f"wrote {args.write}", file=sys.stderr)
    return ExitCode.OK if found.best and found.best[0].margin > 0 else ExitCode.CHECKS_FAILED


def _design_margin(
    args: argparse.Namespace,
    scene: Scene,
    mass: Any,
    base: Scene,
    design: tuple[np.ndarray, np.ndarray] | None,
) -> float | None:
    """The scene's own design's margin (rad): exact over its friction range when it has one."""
    from kcheck.analysis.cases import problem_for
    from kcheck.analysis.suggest import caps_at, point_caps
    from kcheck.mechanics.arcs import cap_margins

    if design is None:
        return None
    point, direction = design
    if _frictions(scene, args) is not None:
        return _range_margin(base, mass, point, direction)
    caps = point_caps(problem_for(base, mass), None)
    at = caps_at(caps, point[None])[0]
    return float(cap_margins(caps.a, at, direction[None, : scene.dim])[0])
