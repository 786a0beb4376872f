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

if TYPE_CHECKING:
    import numpy as np

    from kcheck.scene import Scene
    from kcheck.suggest import Candidate, Search

__all__ = ["add_parser", "run", "write_scene"]

# Candidate points kept (best first) for the least-force search when nothing is safe.
LEAST_FORCE_POINTS = 200


def add_parser(sub: Any) -> None:
    """Register the ``suggest`` command."""
    p = sub.add_parser(
        "suggest",
        help="where to put the closing force: the attachment point and direction with the "
        "largest margin",
        description="Search attachment points (on the body's surface, or in a box) and force "
        "directions for the largest angular margin over every retracted support, and print the "
        "best candidates with their margins and limiting friction (spatial scenes).",
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
    from kcheck.paths import check_output_file

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

    from kcheck.chebyshev import lobatto
    from kcheck.friction_range import FrictionPath

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
    (:mod:`kcheck.range_analysis`)."""
    from kcheck.analysis import analyse
    from kcheck.suggest import with_load

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

    from kcheck.candidates import BoxSampler, SuggestError, SurfaceSampler
    from kcheck.errors import KcheckError
    from kcheck.mass import body_mass_properties
    from kcheck.scene import load_scene
    from kcheck.suggest import search, with_load

    problem = _usage(args)
    if problem:
        return fail(problem)
    started = time.perf_counter()
    try:
        scene = load_scene(args.scene, allow_outside=args.allow_outside_paths)
        if scene.kind != "spatial":
            return fail(f"{args.scene}: kcheck suggest searches spatial (6-support) scenes")
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
    report = _Report(args, scene, mass, base, design, found, magnitude)
    report.least = report.least_force()
    report.runtime = time.perf_counter() - started
    if args.format == "json":
        print(json.dumps(report.to_json(), indent=2))
    else:
        report.print_text()
    if args.plot is not None:
        from kcheck.plots_suggest import plot_suggestion

        for path in plot_suggestion(scene, found, design, args.plot):
            print(f"wrote {path}", file=sys.stderr)
    if args.write is not None and found.best:
        write_scene(scene, found.best[0], magnitude, args.write)
        print(f"wrote {args.write}", file=sys.stderr)
    return ExitCode.OK if found.best and found.best[0].margin > 0 else ExitCode.CHECKS_FAILED


def _margin_text(margin: float, short: bool = False) -> str:
    """A margin (rad) for people: negative ones are how far the force is from being safe;
    -180° means some retracted support cannot close in any direction at that point."""
    import numpy as np

    from kcheck.fmt import format_angle

    if margin <= -np.pi + 1e-9:
        return "none" if short else "no direction is safe at this point"
    text = format_angle(np.degrees(margin))
    if short or margin > 0:
        return text if short else f"margin {text}"
    return f"margin {text} (no direction is safe here)"


class _Report:
    """What ``kcheck suggest`` prints, as text or JSON."""

    def __init__(
        self,
        args: argparse.Namespace,
        scene: Scene,
        mass: Any,
        base: Scene,
        design: tuple[np.ndarray, np.ndarray] | None,
        found: Search,
        magnitude: float,
    ) -> None:
        self.args, self.scene, self.mass, self.base = args, scene, mass, base
        self.design, self.found, self.magnitude = design, found, magnitude
        self.least: float | None = None
        self.runtime = 0.0
        self.design_margin = self._design_margin()

    def _design_margin(self) -> float | None:

        from kcheck.analysis import problem_for
        from kcheck.arcs import cap_margins
        from kcheck.suggest import caps_at, point_caps

        if self.design is None:
            return None
        point, direction = self.design
        if _frictions(self.scene, self.args) is not None:
            return _range_margin(self.base, self.mass, point, direction)
        caps = point_caps(problem_for(self.base, self.mass), None)
        return float(cap_margins(caps.a, caps_at(caps, point[None])[0], direction[None])[0])

    def least_force(self) -> float | None:
        """When no candidate is safe: the least force at which one is (None otherwise)."""
        import numpy as np

        from kcheck.suggest import least_force

        if self.found.best and self.found.best[0].margin > 0:
            return None
        order = np.argsort(-self.found.margins)[:LEAST_FORCE_POINTS]
        return least_force(
            self.base,
            self.mass,
            self.found.points[order],
            start=self.magnitude,
            directions=self.args.directions,
        )

    def _where(self) -> str:
        a = self.args
        if a.box is not None:
            return f"{len(self.found.points)} points in the box"
        return f"{len(self.found.points)} points on the body's surface (seed {a.seed})"

    def candidate_json(self, c: Candidate) -> dict[str, Any]:
        """One candidate, SI units and degrees."""
        import numpy as np

        out: dict[str, Any] = {
            "point": c.point.tolist(),
            "direction": c.direction.tolist(),
            "margin_deg": float(np.degrees(c.margin)),
            "limiting_friction": c.limiting_friction,
        }
        if c.normal is not None:
            out["surface_normal"] = c.normal.tolist()
            out["pushes"] = c.pushes
        return out

    def to_json(self) -> dict[str, Any]:
        """The JSON document of ``kcheck suggest --format json`` (SI, degrees)."""
        import numpy as np

        from kcheck.result import to_json_value

        doc: dict[str, Any] = {
            "scene": str(self.args.scene),
            "magnitude": self.magnitude,
            "candidates_searched": len(self.found.points),
            "candidate_source": "box" if self.args.box is not None else "surface",
            "directions": self.args.directions,
            "friction": list(self.found.frictions),
            "runtime_s": self.runtime,
            "best": [self.candidate_json(c) for c in self.found.best],
        }
        if self.design is not None and self.design_margin is not None:
            doc["design"] = {
                "point": self.design[0].tolist(),
                "direction": self.design[1].tolist(),
                "margin_deg": float(np.degrees(self.design_margin)),
            }
        if self.least is not None:
            doc["least_force"] = self.least
        return to_json_value(doc)

    def print_text(self) -> None:
        """The text report: what was searched, the design's margin, the best candidates."""
        import numpy as np
        from rich.table import Table

        from kcheck.fmt import clean, format_angle, format_number, format_vector
        from kcheck.report import make_console

        console = make_console(self.args.color)
        s, units = self.scene, self.scene.units
        console.print(
            f"{s.name} ({self.args.scene}): {self._where()}, {self.args.directions} directions "
            f"each, {format_number(self.magnitude)} N, {self.runtime:.2f} s"
        )
        if len(self.found.frictions) > 1:
            lo, hi = self.found.frictions[0], self.found.frictions[-1]
            console.print(
                f"kinetic friction range {lo:g}–{hi:g}: searched at {len(self.found.frictions)} "
                "values, margins exact over the whole range"
            )
        if self.design is not None and self.design_margin is not None:
            point, direction = self.design
            console.print(
                f"design: at {format_vector(point / s.scale)} {units} along "
                f"{format_vector(direction, 3)}: {_margin_text(self.design_margin)}"
            )
        table = Table(title=None, box=None, pad_edge=False)
        for column in ("#", f"point ({units})", "direction", "margin", "limiting μ", ""):
            table.add_column(column, justify="right" if column in ("#", "margin") else "left")
        for i, c in enumerate(self.found.best, 1):
            mu = "–" if c.limiting_friction is None else format_number(c.limiting_friction, 3)
            side = "" if c.pushes is None else ("pushes" if c.pushes else "pulls")
            table.add_row(
                str(i),
                format_vector(c.point / s.scale),
                format_vector(clean(c.direction, 1e3), 3),  # SLSQP's last digits are noise
                _margin_text(c.margin, short=True),
                mu,
                side,
            )
        console.print(table)
        best = self.found.best[0] if self.found.best else None
        if best is not None and best.margin > 0:
            console.print(
                f"best: margin {format_angle(np.degrees(best.margin))} — the force may turn "
                "that far in any direction before a retracted support fails to close"
            )
        else:
            console.print(f"no candidate point is safe with {format_number(self.magnitude)} N.")
            if self.least is not None:
                console.print(
                    f"the least closing force with a safe placement among the best "
                    f"{LEAST_FORCE_POINTS} points is about {format_number(self.least, 3)} N; "
                    "rerun with a larger --magnitude"
                )
            else:
                console.print("no force up to 1000× this one is safe anywhere searched")


def write_scene(scene: Scene, best: Candidate, magnitude: float, target: Path) -> None:
    """Write the scene file with its load moved to a candidate (point and direction in the
    scene's units, the magnitude used); mesh paths are rewritten relative to the new file."""
    import os

    import numpy as np

    from kcheck.cli.common import write_text
    from kcheck.yamlio import dump_yaml, load_yaml

    data, _ = load_yaml(scene.path)
    load = dict(data.get("load") or {})
    load.pop("angle", None)
    load["point"] = [round(float(x), 9) for x in best.point / scene.scale]
    load["magnitude"] = float(magnitude)
    load["direction"] = [round(float(x), 12) for x in best.direction]
    data["load"] = load
    target = target.resolve()
    source = scene.path.resolve().parent

    def moved(name: str) -> str:
        return os.path.relpath(source / name, target.parent)

    body = data.get("body")
    if isinstance(body, dict):
        if isinstance(body.get("mesh"), str):
            body["mesh"] = moved(body["mesh"])
        for part in body.get("parts") or []:
            if isinstance(part, dict) and isinstance(part.get("mesh"), str):
                part["mesh"] = moved(part["mesh"])
    header = (
        f"# Written by kcheck suggest from {scene.path.name}: the load moved to the best "
        f"candidate (margin {np.degrees(best.margin):.2f} deg).\n"
    )
    # kcheck's own writer: YAML 1.2 scalars, as the scene is read back (a name `1e3` quoted).
    write_text(header + dump_yaml(data), target, "--write")
