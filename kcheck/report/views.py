"""What a report says about a result, whatever the output format.

The text and HTML reports (and any other) draw from here: the verdict word of a check (a
failing check of severity ``warning`` is a warning), the key number of a scene, the reasons
a check failed (its findings, or its message), where checks of one scene disagree, and the
tables, with every number written through :mod:`kcheck.fmt` in the scene's units.

Nothing here knows a check by its id: tables are built from the fields the cases carry and
the documented detail keys (``design_margin_deg``, ``safe_solid_angle_fraction``,
``limitations``, ``motion``, ...), so a third-party check is shown like a built-in one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from kcheck.fmt import (
    NOISE_RTOL,
    clean,
    describe_sweep,
    format_angle,
    format_direction,
    format_number,
    format_point,
    format_ranges,
)
from kcheck.result import CheckResult, Finding, SceneResult, Status
from kcheck.units import LENGTH_TO_M

__all__ = [
    "ANGLE_CONVENTION",
    "Reason",
    "Table",
    "verdict",
    "scene_verdict",
    "counts",
    "run_line",
    "headline",
    "reasons",
    "disagreements",
    "limitations",
    "location",
    "short_summary",
    "case_table",
    "forces_table",
    "mass_lines",
    "mass_view",
    "MassView",
    "sweep_text",
    "motion_text",
    "fixed",
    "duration",
    "plain_error",
    "error_line",
    "default_sweep",
]

#: The angle convention, stated once per report (and in every picture).
ANGLE_CONVENTION = (
    "angles in degrees, counter-clockwise about the sweep plane's normal from its 0° "
    "(planar scenes: from +x towards +y, seen from +z); a range a–b runs counter-clockwise "
    "from a to b, both in [0°, 360°), and says “through 0°” when it passes 0°"
)

#: Verdict words in the order a summary counts them.
VERDICTS = ("pass", "warn", "fail", "error")


def verdict(check: CheckResult) -> str:
    """``pass``, ``warn`` (failed, severity warning), ``fail``, ``error`` or ``n/a``."""
    if check.status is Status.SKIPPED:
        return "n/a"
    if check.status is Status.FAIL and check.severity == "warning":
        return "warn"
    return check.status.value


def scene_verdict(scene: SceneResult) -> str:
    """The scene's status as a word: ``pass``, ``warn``, ``fail`` or ``error``."""
    return scene.status.value


def counts(scenes: Sequence[SceneResult]) -> dict[str, int]:
    """How many scenes have each verdict."""
    out = dict.fromkeys(VERDICTS, 0)
    for scene in scenes:
        out[scene_verdict(scene)] = out.get(scene_verdict(scene), 0) + 1
    return out


def duration(seconds: float) -> str:
    """A wall time as people read it: ``0.35 s``, ``2.1 s``, ``98 s``, ``4 min 05 s``."""
    if seconds < 1:
        return f"{seconds:.2f} s"
    if seconds < 10:
        return f"{seconds:.1f} s"
    if seconds < 600:
        return f"{seconds:.0f} s"
    minutes, rest = divmod(round(seconds), 60)
    return f"{minutes} min {rest:02d} s"


def run_line(scenes: Sequence[SceneResult], elapsed_s: float) -> str:
    """The last line of a run: ``13 scenes: 10 passed, 3 failed in 98 s``."""
    n = counts(scenes)
    words = {"pass": "passed", "warn": "with warnings", "fail": "failed", "error": "with errors"}
    parts = [f"{n['pass']} passed"] + [
        f"{n[k]} {words[k]}" for k in ("warn", "fail", "error") if n[k]
    ]
    noun = "scene" if len(scenes) == 1 else "scenes"
    return f"{len(scenes)} {noun}: {', '.join(parts)} in {duration(elapsed_s)}"


def _checks(scene: SceneResult) -> list[CheckResult]:
    return [c for c in scene.checks if c.status is not Status.SKIPPED]


def _range_width(ranges: Sequence[Sequence[float]]) -> float:
    return sum((e - s) % 360.0 if e - s < 360.0 else 360.0 for s, e in ranges)


def _nothing_safe(check: CheckResult) -> bool:
    """Whether a check found no safe direction at all (its margin then means nothing)."""
    fraction = check.details.get("safe_solid_angle_fraction")
    if isinstance(fraction, (int, float)):
        return fraction <= 0
    return check.safe_ranges_deg is not None and len(check.safe_ranges_deg) == 0


def headline(scene: SceneResult) -> str:
    """The scene's key numbers on one line: the smallest design margin over the checks that
    report one, the safe share of the sphere, or the narrowest safe range; n/a checks."""
    parts: list[str] = []
    checks = _checks(scene)
    nothing = any(_nothing_safe(c) for c in checks)
    if nothing:
        parts.append("no safe force direction")
    margins = [
        c.details["design_margin_deg"]
        for c in checks
        if isinstance(c.details.get("design_margin_deg"), (int, float))
        and math.isfinite(c.details["design_margin_deg"])
        and not _nothing_safe(c)
    ]
    if margins and not nothing:
        parts.append(f"design margin {format_angle(min(margins))}")
    fractions = [
        c.details["safe_solid_angle_fraction"]
        for c in checks
        if isinstance(c.details.get("safe_solid_angle_fraction"), (int, float))
    ]
    if fractions and not nothing:
        parts.append(f"{100 * min(fractions):.2f}% of directions safe")
    if not parts:
        ranged = [c for c in checks if c.safe_ranges_deg is not None]
        if ranged:
            narrowest = min(ranged, key=lambda c: _range_width(c.safe_ranges_deg or ()))
            parts.append(f"safe {format_ranges(narrowest.safe_ranges_deg)}")
    skipped = sum(1 for c in scene.checks if c.status is Status.SKIPPED)
    if skipped:
        parts.append(f"{skipped} n/a")
    if scene.notes:
        parts.append(f"{len(scene.notes)} note{'s' if len(scene.notes) > 1 else ''}")
    return ", ".join(parts)


@dataclass(frozen=True)
class Reason:
    """One reason a check failed: the sentence, what to change, and where in the file."""

    text: str
    hint: str | None = None
    line: int | None = None
    column: int | None = None
    field: str | None = None


def _reason(finding: Finding) -> Reason:
    from kcheck.errors import format_path

    return Reason(
        finding.message,
        finding.hint,
        finding.line,
        finding.column,
        None if finding.field is None else format_path(finding.field),
    )


def reasons(check: CheckResult) -> list[Reason]:
    """Why a check failed or erred: its findings, or its one-line message when it has none."""
    if check.findings:
        return [_reason(f) for f in check.findings]
    return [Reason(check.message)]


def limitations(check: CheckResult) -> list[str]:
    """What the check cannot see, as it declares in ``details["limitations"]``."""
    found = check.details.get("limitations") or ()
    return [str(x) for x in found]


def _answers_ranges(check: CheckResult) -> bool:
    return check.safe_ranges_deg is not None or "design_margin_deg" in check.details


def disagreements(scene: SceneResult, check: CheckResult) -> list[str]:
    """For a passing check that judges force directions, every other such check of the scene
    that failed: ``analytical-2d: FAIL — <its first reason>``."""
    if check.status is not Status.PASS or not _answers_ranges(check):
        return []
    out = []
    for other in scene.checks:
        if other is check or other.status is not Status.FAIL or not _answers_ranges(other):
            continue
        out.append(f"{other.id}: {verdict(other).upper()} — {reasons(other)[0].text}")
    return out


def location(path: str, line: int | None, column: int | None = None) -> str:
    """``path:line:column`` (the parts that are known), as compilers write it."""
    out = path
    if line is not None:
        out += f":{line}"
        if column is not None:
            out += f":{column}"
    return out


def short_summary(scenes: Sequence[SceneResult]) -> list[tuple[str, str, str]]:
    """One ``(verdict, path, reason)`` per failing, warning or erring check of every scene,
    and one per scene with input errors."""
    out: list[tuple[str, str, str]] = []
    for scene in scenes:
        if scene.status is Status.PASS:
            continue
        if scene.errors or (scene.error and not scene.checks):
            n = len(scene.errors) or 1
            first = scene.errors[0] if scene.errors else Finding(scene.error or "")
            where, message = error_line(scene.path, first)
            more = f" (and {n - 1} more)" if n > 1 else ""
            out.append(("error", where, f"{message}{more}"))
            continue
        for check in scene.checks:
            word = verdict(check)
            if word in ("fail", "warn", "error"):
                first = reasons(check)[0]
                out.append((word, location(scene.path, first.line), f"{check.id}: {first.text}"))
        for warning in scene.warnings:
            out.append(("warn", location(scene.path, warning.line), warning.message))
    return out


def error_line(path: str, error: Finding) -> tuple[str, str]:
    """An input error as ``(path:line:col, field `x`: message)``, compiler style."""
    from kcheck.errors import format_path

    what = f"field `{format_path(error.field)}`: " if error.field else ""
    return location(path, error.line, error.column), what + plain_error(error.message, path)


def plain_error(message: str, path: str) -> str:
    """An input error's message without a leading ``path[:line[:col]]: `` already shown."""
    if message.startswith(path):
        rest = message[len(path) :]
        while rest[:1] == ":" and rest[1:2].isdigit():
            rest = rest[1:].lstrip("0123456789")
        return rest.removeprefix(":").strip()
    return message


# --- tables --------------------------------------------------------------------------------


@dataclass
class Table:
    """A table of text cells: ``numeric[k]`` marks a right-aligned column never wrapped."""

    title: str
    headers: list[str]
    numeric: list[bool]
    rows: list[list[str]] = field(default_factory=list)
    styles: list[str | None] = field(default_factory=list)  # per row: the outcome, for colour


def fixed(values: Sequence[float | None], digits: int = 4, most: int = 4) -> list[str]:
    """Numbers of one column with the same number of decimals: enough for ``digits``
    significant digits of the largest (at most ``most``); noise below rounding is zero."""
    finite = [abs(v) for v in values if v is not None and math.isfinite(v)]
    top = max(finite, default=0.0)
    decimals = 0 if top == 0 else min(most, max(0, digits - 1 - math.floor(math.log10(top))))
    out = []
    cleaned = clean([v if v is not None else np.nan for v in values], scale=top or None)
    for v, c in zip(values, cleaned, strict=True):
        if v is None or (isinstance(v, float) and math.isnan(v)):
            out.append("–")
        elif not math.isfinite(c):
            out.append("∞" if c > 0 else "-∞")
        else:
            out.append(f"{c:.{decimals}f}")
    return out


def _scale(units: str | None) -> float:
    return LENGTH_TO_M.get(units or "m", 1.0)


def motion_text(details: Mapping[str, Any], units: str, planar: bool = False) -> str:
    """The free motion in words, lengths in scene units (``pure rotation`` for noise pitch);
    a planar scene's directions with two components."""
    scale = _scale(units)
    motion = details.get("motion")
    pole = details.get("pole")
    if motion == "translation" or details.get("sense") == "translation":
        direction = details.get("direction") or details.get("translation_direction")
        if direction is not None and planar:
            direction = list(direction)[:2]
        return "translation" + (
            "" if direction is None else f" along {format_direction(direction)}"
        )
    if motion == "rotation" or (pole is not None and details.get("sense") in ("ccw", "cw")):
        p = np.asarray(pole, float) / scale
        return f"{details.get('sense')} about {format_point(p, 2)} {units}"
    if motion == "screw":
        point = np.asarray(details.get("axis_point", (0, 0, 0)), float)
        pitch = float(details.get("pitch_m", 0.0))
        noise = NOISE_RTOL * max(float(np.linalg.norm(point)), scale)
        if abs(pitch) <= noise:
            return "pure rotation"
        return f"screw, pitch {format_number(pitch / scale, 3)} {units}"
    return "–"


def _ranges_cell(ranges: Sequence[Sequence[float]] | None) -> str:
    """Ranges one per line, so a cell never breaks inside a number."""
    return format_ranges(ranges).replace(", ", "\n")


def case_table(check: CheckResult, units: str | None, kind: str | None = None) -> Table | None:
    """Per retracted support: outcome, free motion, Maxwell's cos θ, safe force angles."""
    if not check.cases:
        return None
    units = units or "m"
    cases = check.cases
    headers, numeric = ["retracted", "outcome"], [False, False]
    columns: list[list[str]] = []
    if any("motion" in c.details or "sense" in c.details for c in cases):
        headers.append("free motion")
        numeric.append(False)
        columns.append([motion_text(c.details, units, kind == "planar") for c in cases])
    if any(c.cos_maxwell is not None for c in cases):
        headers += ["cos θ", "θ"]
        numeric += [True, True]
        columns.append(fixed([c.cos_maxwell for c in cases], 4, 3))
        thetas = [c.details.get("theta_deg") for c in cases]
        columns.append([t if t == "–" else f"{t}°" for t in fixed(thetas, 3, 1)])
    if any(c.safe_ranges_deg is not None for c in cases):
        headers.append("safe force angles")
        numeric.append(False)
        columns.append([_ranges_cell(c.safe_ranges_deg) for c in cases])
    table = Table(f"{check.id} per retracted support", headers, numeric)
    for i, c in enumerate(cases):
        table.rows.append([c.retracted, c.outcome.replace("_", " "), *(col[i] for col in columns)])
        table.styles.append(c.outcome)
    return table


def forces_table(check: CheckResult) -> Table | None:
    """At the design direction: acceleration, limiting friction, and the normal force of every
    remaining support (one column each; "–" for the retracted one)."""
    cases = check.cases
    if not any(
        c.normal_forces is not None or c.acceleration is not None or c.limiting_friction
        for c in cases
    ):
        return None
    present = {n for c in cases for n in (c.normal_forces or {})}
    names = [c.retracted for c in cases if c.retracted in present]
    names += sorted(present - set(names))
    headers, numeric = ["retracted", "accel.", "μ limit"], [False, True, True]
    accel = fixed([c.acceleration for c in cases])
    mu = fixed([c.limiting_friction for c in cases], 4, 3)
    all_forces = [v for c in cases for v in (c.normal_forces or {}).values()]
    forces = fixed(all_forces) if all_forces else []
    by_value = iter(forces)
    cells = [{n: next(by_value) for n in (c.normal_forces or {})} for c in cases]
    headers += names
    numeric += [True] * len(names)
    title = (
        f"{check.id} at the design direction: acceleration of the retracted contact (m/s²), "
        "limiting friction μ, normal forces (N)"
    )
    table = Table(title, headers, numeric)
    for i, c in enumerate(cases):
        table.rows.append([c.retracted, accel[i], mu[i], *(cells[i].get(n, "–") for n in names)])
        table.styles.append(c.outcome)
    return table


@dataclass(frozen=True)
class MassView:
    """Mass properties as written: ``facts`` (label, value) in order, then the inertia
    matrix cells (None when only I_zz is known) in ``inertia_unit``, then the principal
    moments and axes (label, value)."""

    facts: list[tuple[str, str]]
    inertia: list[list[str]] | None
    inertia_unit: str
    principal: list[tuple[str, str]]


def mass_view(mass: Any, units: str | None) -> MassView:
    """Mass properties in the scene's units, noise cleaned, fixed decimals per block."""
    units = units or "m"
    scale = _scale(units)
    facts = [("mass", f"{format_number(mass.mass, 6)} kg ({mass.source})")]
    if mass.volume is not None:
        volume = mass.volume / scale**3
        text = f"{volume:.0f}" if 1e5 <= volume < 1e15 else format_number(volume, 6)
        facts.append(("volume", f"{text} {units}³"))
    com = clean(np.asarray(mass.center_of_mass, float) / scale)
    facts.append(("centre of mass", "(" + ", ".join(fixed(list(com))) + f") {units}"))
    inertia = np.asarray(mass.inertia, float) / scale**2
    unit = f"kg·{units}²"
    if not np.all(np.isfinite(inertia)):
        facts.append(("I_zz about the centre of mass", f"{format_number(inertia[2, 2], 6)} {unit}"))
        return MassView(facts, None, unit, [])
    cells = fixed(list(clean(inertia).ravel()), 6, 6)
    matrix = [cells[3 * r : 3 * r + 3] for r in range(3)]
    moments, axes = np.linalg.eigh(clean(inertia))
    principal = [("principal moments", ", ".join(fixed(list(moments), 6, 6)) + f" {unit}")]
    for i in range(3):
        axis = clean(axes[:, i])
        axis = axis if axis[np.argmax(np.abs(axis))] > 0 else -axis  # the sign is arbitrary
        principal.append((f"axis {i + 1}", f"along {format_direction(axis)}"))
    return MassView(facts, matrix, unit, principal)


def mass_lines(mass: Any, units: str | None) -> list[str]:
    """Mass properties as lines of text (see :func:`mass_view`)."""
    view = mass_view(mass, units)
    lines = [f"{label} {value}" for label, value in view.facts]
    if len(view.facts) > 1 and view.facts[1][0] == "volume":
        lines[:2] = [f"{lines[0]}, {lines[1]}"]  # mass and volume on one line
    if view.inertia is not None:
        width = max(len(c) for row in view.inertia for c in row)
        lines.append(f"inertia about the centre of mass ({view.inertia_unit}):")
        lines += ["  " + "  ".join(c.rjust(width) for c in row) for row in view.inertia]
    for label, value in view.principal:
        lines.append(f"{'  ' if label.startswith('axis') else ''}{label} {value}")
    return lines


def sweep_text(scene: SceneResult) -> str | None:
    """Where 0° is and which way angles turn in this scene's sweep plane, or None."""
    sweep = getattr(scene, "sweep", None)
    if sweep is None:
        return None
    return f"sweep plane: {describe_sweep(sweep[0], sweep[1])}"


def default_sweep(scene: SceneResult) -> bool:
    """Whether the scene sweeps angles from +x towards +y (the convention's default)."""
    sweep = getattr(scene, "sweep", None)
    if sweep is None:
        return True
    return bool(np.allclose(sweep[0], (0, 0, 1)) and np.allclose(sweep[1], (1, 0, 0)))
