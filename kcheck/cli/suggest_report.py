"""What ``kcheck suggest`` prints (text or JSON) and the scene it writes (``--write``)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from kcheck.numerics.thresholds import NO_SAFE_DIRECTION_SLACK

if TYPE_CHECKING:
    import numpy as np

    from kcheck.analysis.suggest import Candidate, Search
    from kcheck.scene import Scene

__all__ = ["Report", "margin_text", "write_scene"]

# Candidate points kept (best first) for the least-force search when nothing is safe.
LEAST_FORCE_POINTS = 200


def margin_text(margin: float, short: bool = False) -> str:
    """A margin (rad) for people: negative ones are how far the force is from being safe;
    -180° means some retracted support cannot close in any direction at that point."""
    import numpy as np

    from kcheck.fmt import format_angle

    if margin <= -np.pi + NO_SAFE_DIRECTION_SLACK:
        return "none" if short else "no direction is safe at this point"
    text = format_angle(np.degrees(margin))
    if short or margin > 0:
        return text if short else f"margin {text}"
    return f"margin {text} (no direction is safe here)"


class Report:
    """What ``kcheck suggest`` prints, as text or JSON."""

    def __init__(
        self,
        args: argparse.Namespace,
        scene: Scene,
        mass: Any,
        base: Scene,
        design: tuple[np.ndarray, np.ndarray] | None,
        design_margin: float | None,
        found: Search,
        magnitude: float,
    ) -> None:
        self.args, self.scene, self.mass, self.base = args, scene, mass, base
        self.design, self.found, self.magnitude = design, found, magnitude
        self.least: float | None = None
        self.runtime = 0.0
        self.design_margin = design_margin

    def least_force(self) -> float | None:
        """When no candidate is safe: the least force at which one is (None otherwise)."""
        import numpy as np

        from kcheck.analysis.suggest import least_force

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
            import numpy as np

            # Distinct points: a box of one point (all lo == hi) is searched at that point only.
            n = len(np.unique(self.found.points, axis=0))
            return f"{n} point{'s' if n != 1 else ''} in the box"
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
                f"{format_vector(direction, 3)}: {margin_text(self.design_margin)}"
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
                margin_text(c.margin, short=True),
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
    from kcheck.scene.yamlio import dump_yaml, load_yaml

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
