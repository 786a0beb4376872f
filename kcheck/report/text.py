"""Terminal report with rich: per scene the verdict, mass properties and a table per check.

Rendering only: results come in finished; nothing here computes physics. Tables are built
from whatever fields the cases carry, so a third-party check is shown like a built-in one.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from typing import Any, TextIO

import numpy as np
from rich.console import Console
from rich.table import Table
from rich.text import Text

from kcheck.mass import MassProperties, principal_axes
from kcheck.report import ReportOptions
from kcheck.result import CheckResult, SceneResult, Status

__all__ = ["TextReporter", "make_console", "render", "render_mass"]

STYLE = {
    Status.PASS: "bold green",
    Status.WARN: "bold yellow",
    Status.FAIL: "bold red",
    Status.ERROR: "bold magenta",
    Status.SKIPPED: "dim",
}


def make_console(color: str = "auto", file: TextIO | None = None, stderr: bool = False) -> Console:
    """A console honouring ``--color``: ``auto`` follows the TTY and FORCE_COLOR, and a
    non-empty NO_COLOR turns off every ANSI style, not only colours (plain logs in CI)."""
    kwargs: dict[str, Any] = {"markup": False, "highlight": False, "emoji": False}
    if color == "always":
        kwargs["force_terminal"] = True
    elif color == "never" or os.environ.get("NO_COLOR"):
        kwargs["no_color"] = True
        kwargs["color_system"] = None
    console = Console(file=file, stderr=stderr, **kwargs)
    if not console.is_terminal and file is None:
        # Logs and CI pages are wider than 80 columns; avoid wrapping tables there.
        console = Console(file=file, stderr=stderr, width=120, **kwargs)
    return console


def _fmt(value: Any) -> str:
    if value is None:
        return "–"
    if isinstance(value, float):
        if not np.isfinite(value):
            return "∞" if value > 0 else "-∞"
        return f"{value:.4g}"
    return str(value)


def _vec(values: Any) -> str:
    return "(" + ", ".join(f"{v:.5g}" for v in np.asarray(values, dtype=float)) + ")"


def render_mass(console: Console, mass: MassProperties, indent: str = "  ") -> None:
    """Mass properties as an engineer reads them from a CAD package (SI units)."""
    console.print(
        f"{indent}mass {mass.mass:.6g} kg ({mass.source})"
        + (f", volume {mass.volume:.6g} m^3" if mass.volume is not None else "")
    )
    console.print(f"{indent}centre of mass {_vec(mass.center_of_mass)} m")
    inertia = mass.inertia
    if np.all(np.isfinite(inertia)):
        console.print(f"{indent}inertia about the centre of mass (kg m^2):")
        for row in inertia:
            console.print(f"{indent}  [" + "  ".join(f"{v:12.6g}" for v in row) + " ]")
        moments, axes = principal_axes(inertia)
        console.print(f"{indent}principal moments {_vec(moments)} kg m^2")
        for i in range(3):
            console.print(f"{indent}  axis {i + 1} {_vec(axes[:, i])}")
    else:
        console.print(f"{indent}I_zz about the centre of mass {inertia[2, 2]:.6g} kg m^2")
    for note in mass.notes:
        console.print(f"{indent}note: {note}", style="yellow")


def _ranges(ranges: Sequence[Sequence[float]] | None) -> str:
    if ranges is None:
        return "–"
    if not ranges:
        return "none"
    return ", ".join(f"{s:.2f}–{e:.2f}" for s, e in ranges)


_CASE_COLUMNS = (
    ("cos_maxwell", "cos θ"),
    ("acceleration", "accel. m/s²"),
    ("limiting_friction", "μ limit"),
    ("normal_forces", "normal forces N"),
    ("safe_ranges_deg", "safe angles °"),
)


def _case_table(check: CheckResult) -> Table:
    table = Table(show_header=True, header_style="bold", box=None, pad_edge=False, padding=(0, 2))
    table.add_column("retracted")
    table.add_column("outcome")
    present = [
        (attr, title)
        for attr, title in _CASE_COLUMNS
        if any(getattr(c, attr) is not None for c in check.cases)
    ]
    for _, title in present:
        table.add_column(title, overflow="fold")
    notes = any("diagnostic" in c.details for c in check.cases)
    if notes:
        table.add_column("diagnostic", overflow="fold")
    for case in check.cases:
        style = {"closes": "green", "ok": "green", "swept": "cyan"}.get(case.outcome, "red")
        row: list[Any] = [case.retracted, Text(case.outcome, style=style)]
        for attr, _ in present:
            value = getattr(case, attr)
            if attr == "normal_forces" and value is not None:
                row.append(" ".join(f"{k} {v:.4g}" for k, v in value.items()))
            elif attr == "safe_ranges_deg":
                row.append(_ranges(value))
            else:
                row.append(_fmt(value))
        if notes:
            row.append(str(case.details.get("diagnostic", "")))
        table.add_row(*row)
    return table


def render_scene(console: Console, scene: SceneResult) -> None:
    """One scene: verdict line, mass properties, then each check."""
    head = Text()
    head.append(f"{scene.status.value.upper():<5}", style=STYLE[scene.status])
    head.append(f"  {scene.name or scene.path}", style="bold")
    head.append(f"  {scene.path}" + (f"  [{scene.kind}]" if scene.kind else ""), style="dim")
    console.print(head)
    if scene.error:
        console.print(f"  error: {scene.error}", style="magenta")
        console.print()
        return
    if scene.mass_properties is not None:
        render_mass(console, scene.mass_properties)
    for note in scene.notes:
        if scene.mass_properties is None or note not in scene.mass_properties.notes:
            console.print(f"  note: {note}", style="yellow")
    for check in scene.checks:
        line = Text("  ")
        line.append(f"{check.status.value:<7}", style=STYLE[check.status])
        line.append(f" {check.id}", style="bold")
        line.append(f"  {check.message}")
        if check.status is not Status.SKIPPED:
            extra = f"  ({check.runtime_s * 1e3:.1f} ms"
            if check.error_estimate is not None:
                extra += f", error ≤ {check.error_estimate:.1e}"
            line.append(extra + ")", style="dim")
        console.print(line)
        if check.cases:
            table = _case_table(check)
            console.print(table, style=None)
    for plot in scene.plots:
        console.print(f"  plot written: {plot}", style="cyan")
    console.print()


def render(console: Console, scenes: Sequence[SceneResult]) -> None:
    """The whole report: every scene, then a summary across scenes."""
    for scene in scenes:
        render_scene(console, scene)
    render_summary(console, scenes)


def render_summary(console: Console, scenes: Sequence[SceneResult]) -> None:
    """A table of every scene's verdict and the counts."""
    counts = {s: sum(1 for x in scenes if x.status is s) for s in Status}
    summary = Table(title="Summary", show_header=True, header_style="bold")
    summary.add_column("scene")
    summary.add_column("verdict")
    summary.add_column("checks")
    for scene in scenes:
        checks = ", ".join(f"{c.id} {c.status.value}" for c in scene.checks) or (scene.error or "")
        summary.add_row(
            scene.name or scene.path, Text(scene.status.value, style=STYLE[scene.status]), checks
        )
    console.print(summary)
    console.print(
        f"{len(scenes)} scene(s): {counts[Status.PASS]} passed, {counts[Status.WARN]} with "
        f"warnings, {counts[Status.FAIL]} failed, {counts[Status.ERROR]} with errors"
    )


class TextReporter:
    """The terminal report: each scene as it finishes, then the summary."""

    def __init__(self, stream: TextIO, options: ReportOptions) -> None:
        color = "never" if options.to_file else options.color
        self.console = make_console(color, file=None if stream is sys.stdout else stream)
        self.options = options

    def start(self, total: int) -> None:
        """Nothing before the first scene."""

    def scene(self, result: SceneResult) -> None:
        """Print one scene."""
        render_scene(self.console, result)

    def finish(self, results: Sequence[SceneResult], elapsed_s: float) -> None:
        """Print the summary."""
        render_summary(self.console, results)
