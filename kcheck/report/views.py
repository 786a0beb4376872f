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

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from kcheck.fmt import (
    describe_sweep,
    format_angle,
    format_number,
    format_percent,
    format_ranges,
    format_share_bounds,
)
from kcheck.records import dataclass
from kcheck.result import NOT_CHECKED, CheckResult, Finding, SceneResult, Status

__all__ = [
    "ANGLE_CONVENTION",
    "Reason",
    "verdict",
    "scene_verdict",
    "worse",
    "margin_text",
    "margin_figure",
    "status_text",
    "scene_status_text",
    "counts",
    "run_line",
    "headline",
    "reasons",
    "disagreements",
    "limitations",
    "location",
    "short_summary",
    "sweep_text",
    "check_sweep_text",
    "duration",
    "plain_error",
    "error_line",
    "default_sweep",
]

#: The angle convention, stated once per report (and in every picture).
ANGLE_CONVENTION = (
    "angles in degrees, counter-clockwise about the sweep plane's normal from its 0° "
    "(planar scenes: from +x towards +y, seen from +z); a range a–b runs counter-clockwise "
    "from a to b (a in [0°, 360°), b in (0°, 360°]) and says “through 0°” when it passes 0°"
)

#: Verdict words in the order a summary counts them.
VERDICTS = ("pass", "marginal", "warn", "fail", "error")
#: Every verdict word from best to worst: ``marginal`` is a passing check closer to its
#: failure line than its minimum margin (docs/checks.md, "Marginal results").
SEVERITY_ORDER = ("n/a", "not checked", "pass", "marginal", "warn", "fail", "error")

# Case outcomes that are good news: the case closes (analytical, graphical), the layout is
# fine (maxwell), only ranges were asked for, or friction cannot hold the body (jamming).
GOOD_OUTCOMES = ("closes", "ok", "swept", "moves")


def verdict(check: CheckResult) -> str:
    """``pass``, ``marginal``, ``warn`` (failed, severity warning), ``fail``, ``error``,
    ``not checked`` (skipped for want of input: :attr:`CheckResult.not_checked`) or ``n/a``
    (does not apply)."""
    if check.status is Status.SKIPPED:
        return NOT_CHECKED if check.not_checked else "n/a"
    if check.status is Status.FAIL and check.severity == "warning":
        return "warn"
    return check.status.value


def message(check: CheckResult) -> str:
    """The check's one-line message after its verdict word: for a check not checked, without
    the words "not checked" the verdict already says (``material of v1's ball unknown``,
    ``because no point of interest is given ...``)."""
    if not check.not_checked:
        return check.message
    return check.message[len(NOT_CHECKED) :].lstrip(":, ") or check.message


def skipped_counts(checks: Sequence[CheckResult]) -> list[str]:
    """``2 not checked``, ``3 n/a``: how many checks gave no verdict, for want of input and
    because they do not apply (empty counts left out)."""
    skipped = [verdict(c) for c in checks if c.status is Status.SKIPPED]
    return [f"{n} {w}" for w in (NOT_CHECKED, "n/a") if (n := skipped.count(w))]


def worse(a: str, b: str) -> bool:
    """Whether verdict word ``a`` is worse than ``b`` (:data:`SEVERITY_ORDER`)."""
    rank = {w: i for i, w in enumerate(SEVERITY_ORDER)}
    return rank.get(a, len(rank)) > rank.get(b, len(rank))


def margin_text(check: CheckResult) -> str | None:
    """The check's design margin as a picture or summary says it: ``margin 7.59°`` (inside
    its safe set) or ``margin -3.10°`` (outside); None when the check reports none, or when
    nothing is safe (a margin then means nothing).

    One definition across checks, summary and docs: the angle from the design direction to
    the nearest edge of the set of directions the check calls safe, positive inside and
    negative outside (``design_margin_deg``)."""
    margin = check.details.get("design_margin_deg")
    if not isinstance(margin, (int, float)) or not math.isfinite(margin) or _nothing_safe(check):
        return None
    return f"margin {format_angle(float(margin))}"


def margin_figure(band: Mapping[str, Any]) -> str:
    """A check's margin against its marginal band (``details["margin"]``) as a figure:
    ``force-angle margin 0.29 (marginal below 5)``."""
    value, limit = band.get("value"), band.get("limit")
    if not isinstance(value, (int, float)) or not isinstance(limit, (int, float)):
        return str(band.get("quantity", "margin"))
    side = "below" if band.get("sense") == "at least" else "above"
    return (
        f"{band.get('quantity', 'margin')} {format_number(float(value), 3)} "
        f"(marginal {side} {format_number(float(limit), 3)})"
    )


def status_text(check: CheckResult, qualifier: str = "") -> str:
    """A check's verdict for a picture's title, from the same result the text reports:
    ``graphical-2d PASS (mass-free), margin 7.59°``; ``qualifier`` follows the word."""
    text = f"{check.id} {verdict(check).upper()}{qualifier}"
    margin = margin_text(check)
    return text if margin is None else f"{text}, {margin}"


def scene_status_text(
    check: CheckResult,
    scene_word: str,
    checks: Sequence[CheckResult],
    warnings: Sequence[Finding] = (),
) -> str | None:
    """Where the scene's verdict is worse than ``check``'s, that verdict and why, as the text
    report says it beside the check: ``scene FAIL: analytical-2d FAIL — retract x3 → y1
    loses contact (N = -0.0866 N), maxwell WARN``; None when the scene is no worse."""
    own = verdict(check)
    if not worse(scene_word, own):
        return None
    parts = []
    for other in checks:
        word = verdict(other)
        if other is check or other.id == check.id or not worse(word, own):
            continue
        part = f"{other.id} {word.upper()}"
        if word in ("fail", "error"):
            part += f" — {reasons(other)[0].text.split('; ')[0]}"
        parts.append(part)
    if warnings:
        parts.append(f"{len(warnings)} scene warning{'s' if len(warnings) > 1 else ''}")
    return f"scene {scene_word.upper()}: {', '.join(parts)}"


def scene_verdict(scene: SceneResult) -> str:
    """The scene's status as a word: ``pass``, ``marginal``, ``warn``, ``fail`` or ``error``."""
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
    words = {
        "pass": "passed",
        "marginal": "marginal",
        "warn": "with warnings",
        "fail": "failed",
        "error": "with errors",
    }
    parts = [f"{n['pass']} passed"] + [
        f"{n[k]} {words[k]}" for k in ("marginal", "warn", "fail", "error") if n[k]
    ]
    noun = "scene" if len(scenes) == 1 else "scenes"
    return f"{len(scenes)} {noun}: {', '.join(parts)} in {duration(elapsed_s)}"


def _checks(scene: SceneResult) -> list[CheckResult]:
    return [c for c in scene.checks if c.status is not Status.SKIPPED]


def _range_width(ranges: Sequence[Sequence[float]]) -> float:
    return sum((e - s) % 360.0 if e - s < 360.0 else 360.0 for s, e in ranges)


def _share(check: CheckResult) -> tuple[float, float] | None:
    """The safe share of the sphere a check reports, as ``(low, high)``: equal when exact,
    else its lower and upper bound (``safe_solid_angle_fraction_upper``); None without one."""
    low = check.details.get("safe_solid_angle_fraction")
    if not isinstance(low, (int, float)):
        return None
    high = check.details.get("safe_solid_angle_fraction_upper", low)
    return float(low), float(high) if isinstance(high, (int, float)) else float(low)


def _swept(check: CheckResult) -> str:
    """What the check's directions are: ``gravity`` when it sweeps gravity, else ``force``."""
    return "gravity" if check.details.get("swept_direction") == "gravity" else "force"


def _nothing_safe(check: CheckResult) -> bool:
    """Whether a check found no safe direction at all (its margin then means nothing): an
    exact share of 0, an upper bound of 0, or no safe range."""
    share = _share(check)
    if share is not None:
        return share[1] <= 0
    return check.safe_ranges_deg is not None and len(check.safe_ranges_deg) == 0


def headline(scene: SceneResult) -> str:
    """The scene's key numbers on one line, each figure after the check it comes from
    (``analytical-3d: design margin 19.93°, 7.05% of force directions safe``): the smallest
    design margin over the checks that report one (:func:`margin_text`'s definition), the
    smallest safe share of the sphere, or the narrowest safe range; n/a checks. "No safe
    direction" names the checks that say so and what they sweep (force or gravity)."""
    parts: list[str] = []
    checks = _checks(scene)
    nothing = [c for c in checks if _nothing_safe(c)]
    if nothing:
        what = {_swept(c) for c in nothing}
        word = what.pop() if len(what) == 1 else "force or gravity"
        parts.append(f"no safe {word} direction ({', '.join(c.id for c in nothing)})")
    said: dict[str, list[str]] = {}  # figures by the check they come from, in order
    margins = [
        (float(c.details["design_margin_deg"]), c)
        for c in checks
        if margin_text(c) is not None and not _nothing_safe(c)
    ]
    if margins and not nothing:
        value, source = min(margins, key=lambda x: x[0])
        said.setdefault(source.id, []).append(f"design margin {format_angle(value)}")
    shares = [(share[1], share[0], c) for c in checks if (share := _share(c)) is not None]
    if shares and not nothing:
        high, low, source = min(shares, key=lambda x: x[:2])  # the smallest, and who says so
        said.setdefault(source.id, []).append(
            f"{format_share_bounds(low, high)} of {_swept(source)} directions safe"
        )
    for c in checks:  # contact stress (`max_utilisation` with the `materials` it is of)
        used, materials = c.details.get("max_utilisation"), c.details.get("materials")
        if isinstance(used, (int, float)) and isinstance(materials, str):
            figure = f"contact stress {format_percent(float(used))} of allowable ({materials})"
            said.setdefault(c.id, []).append(figure)
    parts += [f"{check}: {', '.join(figures)}" for check, figures in said.items()]
    if not parts:
        ranged = [c for c in checks if c.safe_ranges_deg is not None]
        if ranged:
            narrowest = min(ranged, key=lambda c: _range_width(c.safe_ranges_deg or ()))
            parts.append(f"{narrowest.id}: safe {format_ranges(narrowest.safe_ranges_deg)}")
    parts += skipped_counts(scene.checks)
    if scene.notes:
        parts.append(f"{len(scene.notes)} note{'s' if len(scene.notes) > 1 else ''}")
    return "; ".join(parts)


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
    if not check.findings:
        return [Reason(check.message)]
    out = [_reason(f) for f in check.findings]
    # The same hint after each of a run of findings says it once, after the run.
    return [
        dataclasses.replace(r, hint=None) if r.hint and r.hint == nxt.hint else r
        for r, nxt in zip(out, [*out[1:], Reason("")], strict=True)
    ]


def limitations(check: CheckResult) -> list[str]:
    """What the check cannot see, as it declares in ``details["limitations"]`` (those its
    message does not already say)."""
    found = check.details.get("limitations") or ()
    return [str(x) for x in found if str(x) not in check.message]


def _answers_ranges(check: CheckResult) -> bool:
    return check.safe_ranges_deg is not None or "design_margin_deg" in check.details


def disagreements(scene: SceneResult, check: CheckResult) -> list[str]:
    """For a passing (or marginal) check that judges force directions, every other such check
    of the scene that failed: ``analytical-2d: FAIL — <its first reason>``."""
    if check.status not in (Status.PASS, Status.MARGINAL) or not _answers_ranges(check):
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
    """One ``(verdict, path, reason)`` per marginal, failing, warning or erring check of every
    scene, and one per scene with input errors."""
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
            if word in ("marginal", "fail", "warn", "error"):
                why = reasons(check)
                more = f" (and {len(why) - 1} more)" if len(why) > 1 else ""
                text = f"{check.id}: {why[0].text}{more}"
                out.append((word, location(scene.path, why[0].line), text))
        for warning in scene.warnings:
            out.append(("warn", location(scene.path, warning.line), f"scene: {warning.message}"))
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


def friction_text(scene: SceneResult) -> str | None:
    """The supports' friction as the checks used it: "friction: μ = 0.15 at every support",
    "friction: μ 0.1–0.2 at every support (a range: ...)", static and kinetic apart, or per
    support when they differ; None without supports."""

    def coefficient(record: Mapping[str, Any]) -> str:
        static, kinetic = record.get("friction_static"), record.get("friction_kinetic")
        if not static or not kinetic:
            return f"μ = {format_number(float(record.get('friction', 0.0)), 3)}"

        def span(pair: Sequence[float]) -> str:
            lo, hi = (format_number(float(v), 3) for v in pair)
            return lo if lo == hi else f"{lo}–{hi}"

        if list(static) == list(kinetic):
            return f"μ = {span(static)}" if static[0] == static[1] else f"μ {span(static)}"
        return f"static μ {span(static)}, kinetic μ {span(kinetic)}"

    supports = getattr(scene, "supports", ()) or ()
    if not supports:
        return None
    said = [coefficient(s) for s in supports]
    ranged = any(
        (s.get("friction_static") or (0, 0))[0] != (s.get("friction_static") or (0, 0))[1]
        or (s.get("friction_kinetic") or (0, 0))[0] != (s.get("friction_kinetic") or (0, 0))[1]
        for s in supports
    )
    if len(set(said)) == 1:
        text = f"friction: {said[0]} at every support"
    else:
        text = "friction: " + ", ".join(
            f"{s['name']} {c}" for s, c in zip(supports, said, strict=True)
        )
    if ranged:
        text += (
            " (a range: a check passes only if it passes for every μ in it; its tables show"
            " each case at the μ worst for it)"
        )
    return text


def sweep_text(scene: SceneResult) -> str | None:
    """Where 0° is and which way angles turn in this scene's sweep plane, or None."""
    sweep = getattr(scene, "sweep", None)
    if sweep is None:
        return None
    return f"sweep plane: {describe_sweep(sweep[0], sweep[1])}"


def check_sweep_text(scene: SceneResult, check: CheckResult) -> str | None:
    """The sweep plane a spatial check's angles refer to, when it reports one of its own that
    the scene does not state (a scene without `sweep:`), e.g. "sweep plane: 0° along +x, ...
    (through the design and most robust directions)"; None otherwise."""
    plane = check.details.get("sweep_plane")
    if not isinstance(plane, Mapping) or "normal" not in plane or "zero" not in plane:
        return None
    own = getattr(scene, "sweep", None)
    if (
        own is not None
        and np.allclose(own[0], plane["normal"])
        and np.allclose(own[1], plane["zero"])
    ):
        return None
    text = f"sweep plane: {describe_sweep(plane['normal'], plane['zero'])}"
    chosen = plane.get("chosen")
    return f"{text} ({chosen})" if chosen else text


def default_sweep(scene: SceneResult) -> bool:
    """Whether the scene sweeps angles from +x towards +y (the convention's default)."""
    sweep = getattr(scene, "sweep", None)
    if sweep is None:
        return True
    return bool(np.allclose(sweep[0], (0, 0, 1)) and np.allclose(sweep[1], (1, 0, 0)))
