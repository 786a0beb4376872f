"""Tables and mass properties as text cells, for every report: one number of decimals per
column, noise below rounding set to zero, lengths in the scene's units, directions named.

Built from the fields the cases carry (a third-party check's cases are shown like the
built-ins'); what is a number is marked so a report right-aligns it and never wraps it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import field
from typing import Any

import numpy as np

from kcheck.fmt import (
    NOISE_RTOL,
    clean,
    format_direction,
    format_number,
    format_point,
    format_ranges,
)
from kcheck.records import dataclass
from kcheck.result import CheckResult
from kcheck.scene.units import LENGTH_TO_M

__all__ = [
    "Table",
    "MassView",
    "fixed",
    "motion_text",
    "case_table",
    "forces_table",
    "mass_view",
    "mass_lines",
]


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
        # Not redundant, whatever mypy says: an int is a float to it (numeric promotion).
        if v is None or (isinstance(v, float) and math.isnan(v)):  # type: ignore[redundant-expr]
            out.append("–")
        elif not math.isfinite(c):
            out.append("∞" if c > 0 else "-∞")
        else:
            text = f"{c:.{decimals}f}"
            # A value that rounds to zero has no sign to show ("-0.0000" is rounding noise).
            out.append(text.lstrip("-") if float(text) == 0 else text)
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
    if pole is not None and (motion == "rotation" or details.get("sense") in ("ccw", "cw")):
        p = np.asarray(pole, float) / scale
        return f"{details.get('sense')} about {format_point(p, 2)} {units}"
    if motion == "rotation" and "axis" in details:  # spatial: a screw without pitch
        return f"pure rotation about {format_direction(details['axis'])}"
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
        headers.append(str(check.details.get("case_ranges_label", "safe force angles")))
        numeric.append(False)
        columns.append([_ranges_cell(c.safe_ranges_deg) for c in cases])
    table = Table(f"{check.id} per retracted support", headers, numeric)
    for i, c in enumerate(cases):
        outcome = c.outcome.replace("_", " ")
        if c.details.get("friction_may_hold"):  # rest is a second answer (jamming's)
            outcome += " or held"
        table.rows.append([c.retracted, outcome, *(col[i] for col in columns)])
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
    from kcheck.body.mass import POINT_MASS_NOTE

    added = any(str(n).startswith(POINT_MASS_NOTE) for n in mass.notes)
    source = f"{mass.source} + point masses" if added else mass.source
    facts = [("mass", f"{format_number(mass.mass, 6)} kg ({source})")]
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
