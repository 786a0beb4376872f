"""Immutable results and their documented, versioned JSON form (SI units, angles in degrees).

A check's verdict comes with located :class:`Finding` objects: one sentence each saying why
it failed (or what a warning is about) and, where the check can tell, what to change. The
runner fills in each finding's line from the scene file, so every output format (text, JSON,
SARIF, JUnit, GitHub annotations, ...) can point at the offending support or field.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

from kcheck.errors import FieldPath, format_path
from kcheck.records import dataclass

if TYPE_CHECKING:
    import numpy as np

__all__ = [
    "JSON_FORMAT_VERSION",
    "Severity",
    "SEVERITIES",
    "Status",
    "Finding",
    "MassProperties",
    "CaseResult",
    "CheckResult",
    "SceneResult",
    "ranges_json",
    "to_json_value",
    "run_json",
]

#: Version of the JSON result layout; bumped when a name or meaning changes.
JSON_FORMAT_VERSION = 3

#: How much a failing check matters: ``error`` fails the run, ``warning`` is shown and fails
#: it only with ``--strict`` (or ``fail_on = "warning"``).
Severity = Literal["error", "warning"]
SEVERITIES: tuple[Severity, ...] = ("error", "warning")


class Status(str, enum.Enum):
    """Verdict of a check or scene.

    A check is ``pass``, ``marginal`` (it passes, but its margin is below the minimum margin
    its options ask for: docs/checks.md, "Marginal results"), ``fail``, ``skipped`` or
    ``error`` (it crashed). A scene is ``pass``, ``marginal`` (some check is marginal and
    nothing is worse), ``warn`` (only checks of severity ``warning`` failed, or the scene has
    sanity warnings), ``fail`` (a check of severity ``error`` failed) or ``error`` (bad input,
    or a crash). From best to worst: pass, marginal, warn, fail, error. A marginal result fails
    the run only with ``--strict`` (``fail_on = "warning"``), as a warning does.
    """

    PASS = "pass"
    MARGINAL = "marginal"
    WARN = "warn"
    FAIL = "fail"
    SKIPPED = "skipped"
    ERROR = "error"


@dataclass(frozen=True)
class Finding:
    """One located, human-readable reason: why a check failed, what a warning is about, or
    what is wrong with the input.

    ``message`` is a sentence for an engineer ("retract y1 → jams at μ = 0.6; it closes for
    μ ≤ 0.122"); ``hint`` says what to change, when the check can tell; ``code`` is a stable
    short id (``jams``, ``loses-contact``, ``units-slip``) for machine formats (SARIF rule ids);
    ``field`` is the scene field it concerns, e.g. ``("supports", 2)``; ``line`` and ``column``
    (1-based) are filled in by the runner from the scene file.
    """

    message: str
    code: str | None = None
    field: FieldPath | None = None
    hint: str | None = None
    line: int | None = None
    column: int | None = None
    #: Why this failure does not fail the run (an inline suppression's reason, a per-path
    #: ignore, the baseline); None for a failure that counts.
    suppressed: str | None = None

    def to_json(self) -> dict[str, Any]:
        """JSON form: ``field`` rendered like ``supports[2].normal``; None fields omitted."""
        out: dict[str, Any] = {"message": self.message}
        if self.code is not None:
            out["code"] = self.code
        if self.field is not None:
            out["field"] = format_path(self.field)
        for name in ("hint", "line", "column", "suppressed"):
            value = getattr(self, name)
            if value is not None:
                out[name] = value
        return out


#: How a suppression that is not in the scene (``Finding.suppressed``) begins: a per-path
#: ignore of the configuration, or the baseline file.
PER_PATH_REASON = "per-path-ignores: "
BASELINE_REASON = "in the baseline "


def is_external(reason: str) -> bool:
    """Whether a suppression's reason comes from outside the scene (SARIF ``external``)."""
    return reason.startswith((PER_PATH_REASON, BASELINE_REASON))


Ranges = tuple[tuple[float, float], ...]


def _frozen(mapping: Mapping[str, Any] | None) -> Mapping[str, Any]:
    return MappingProxyType(dict(mapping or {}))


def to_json_value(value: Any) -> Any:
    """Plain JSON value: numpy to lists/floats, non-finite floats to null, mappings to dicts."""
    # The plain built-in types first, by exact type (a report's 350 values a scene went
    # through ``hasattr`` and the ABC checks below: most of the JSON report's time); any
    # other type (numpy's, subclasses, enums) takes the general path, the same values.
    kind = type(value)
    if kind is float:
        return value if math.isfinite(value) else None
    if kind is str or kind is int or kind is bool or value is None:
        return value
    if kind is dict or kind is MappingProxyType:
        return {str(k): _json_item(v) for k, v in value.items()}
    if kind is list or kind is tuple:
        return [_json_item(v) for v in value]
    return _general_json_value(value)


def _json_item(value: Any) -> Any:
    """:func:`to_json_value` of a container's item, a plain float or text without the call
    (most of a report's values are the leaves of lists and mappings)."""
    kind = type(value)
    if kind is float:
        return value if math.isfinite(value) else None
    if kind is str:
        return value
    return to_json_value(value)


def _general_json_value(value: Any) -> Any:
    """:func:`to_json_value` of any value."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): to_json_value(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_value(v) for v in value]
    if isinstance(value, enum.Enum):
        return value.value
    return value


def ranges_json(ranges: Ranges) -> list[list[float]]:
    """Arc ranges in degrees as JSON lists ``[start, end]``: start in [0, 360), end in (0, 360].

    The range runs counter-clockwise from ``start`` to ``end``; ``end < start`` means it passes
    through 0°. The full circle is ``[0, 360]``. (:func:`kcheck.fmt.normalise_range`.)
    """
    from kcheck.fmt import normalise_range

    return [list(normalise_range(s, e)) for s, e in ranges]


def _is_ranges(value: Any) -> bool:
    """Whether a value is a list of ``(start, end)`` numbers (not bools)."""
    if not isinstance(value, (list, tuple)):
        return False
    for r in value:
        if not isinstance(r, (list, tuple)) or len(r) != 2:
            return False
        for x in r:
            if type(x) is not float and (isinstance(x, bool) or not isinstance(x, (int, float))):
                return False
    return True


def details_json(details: Mapping[str, Any]) -> dict[str, Any]:
    """A check's further fields as JSON; lists of ranges in degrees (keys ending in ``_deg``)
    follow :func:`ranges_json`, as ``safe_ranges_deg`` does."""
    return {
        str(key): ranges_json(value)
        if key.endswith("_deg") and value and _is_ranges(value)
        else _json_item(value)
        for key, value in details.items()
    }


@dataclass(frozen=True)
class CaseResult:
    """One retracted support.

    ``acceleration`` is the acceleration (m/s^2) of the retracted contact point towards its
    support at the design direction; ``normal_forces`` in N; ``limiting_friction`` is ``inf``
    when no coefficient stops the case. ``details`` holds further check-specific JSON fields.
    """

    retracted: str
    outcome: str
    cos_maxwell: float | None = None
    normal_forces: Mapping[str, float] | None = None
    acceleration: float | None = None
    limiting_friction: float | None = None
    safe_ranges_deg: Ranges | None = None
    details: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "details", _frozen(self.details))
        if self.normal_forces is not None:
            object.__setattr__(self, "normal_forces", _frozen(self.normal_forces))

    def to_json(self) -> dict[str, Any]:
        """JSON form; fields that are None are omitted."""
        out: dict[str, Any] = {"retracted": self.retracted, "outcome": self.outcome}
        for name in ("cos_maxwell", "normal_forces", "acceleration", "limiting_friction"):
            value = getattr(self, name)
            if value is not None:
                out[name] = to_json_value(value)
        if self.safe_ranges_deg is not None:
            out["safe_ranges_deg"] = ranges_json(self.safe_ranges_deg)
        out.update(details_json(self.details))
        return out


#: How the message of a check that could not run for want of input begins ("not checked:
#: material of v1's ball unknown", "not checked, because ..."): status ``skipped``, but unlike
#: a check that does not apply (``n/a``) it says what to supply. Reports print it as "not
#: checked" with its reason (:attr:`CheckResult.not_checked`).
NOT_CHECKED = "not checked"


@dataclass(frozen=True)
class CheckResult:
    """Result of one check on one scene.

    ``message`` is the one-line verdict; ``findings`` say why it failed (one per reason,
    located). ``error_estimate`` estimates the numerical error of what the check reports, in
    the unit its documentation states (degrees for safe ranges); None where no estimate
    means anything. ``runtime_s`` and ``severity`` are set by the runner.
    """

    id: str
    status: Status
    message: str
    runtime_s: float = 0.0
    error_estimate: float | None = None
    safe_ranges_deg: Ranges | None = None
    cases: tuple[CaseResult, ...] = ()
    details: Mapping[str, Any] = field(default_factory=dict)
    findings: tuple[Finding, ...] = ()
    severity: Severity = "error"
    #: Failures accepted by a suppression (each finding's ``suppressed`` says why): reported,
    #: not failing the run.
    suppressed: tuple[Finding, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "details", _frozen(self.details))
        object.__setattr__(self, "cases", tuple(self.cases))
        object.__setattr__(self, "findings", tuple(self.findings))
        object.__setattr__(self, "suppressed", tuple(self.suppressed))

    @property
    def not_checked(self) -> bool:
        """Skipped for want of input (its message says what to supply: :data:`NOT_CHECKED`),
        as opposed to a check that does not apply to the scene."""
        return self.status is Status.SKIPPED and self.message.startswith(NOT_CHECKED)

    def to_json(self) -> dict[str, Any]:
        """JSON form; fields the check has no use for are omitted."""
        out: dict[str, Any] = {
            "id": self.id,
            "status": self.status.value,
            "severity": self.severity,
            "message": self.message,
            "runtime_s": self.runtime_s,
        }
        if self.findings:
            out["findings"] = [f.to_json() for f in self.findings]
        if self.suppressed:
            out["suppressed"] = [f.to_json() for f in self.suppressed]
        if self.error_estimate is not None:
            out["error_estimate"] = to_json_value(self.error_estimate)
        if self.safe_ranges_deg is not None:
            out["safe_ranges_deg"] = ranges_json(self.safe_ranges_deg)
        if self.cases:
            out["cases"] = [c.to_json() for c in self.cases]
        out.update(details_json(self.details))
        return out


@dataclass(frozen=True)
class MassProperties:
    """Mass (kg), centre of mass (m), inertia tensor about the centre of mass (kg m^2).

    ``bounds`` (m, rows min and max) is the axis-aligned box of the meshes in the scene's
    frame, when mass properties come from meshes, and ``part_bounds`` the box of each mesh
    part in order; ``warnings`` are findings for the scene's warnings (a repaired mesh).
    """

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    source: Literal["mesh", "explicit"]
    volume: float | None = None
    notes: tuple[str, ...] = ()
    bounds: np.ndarray | None = None
    warnings: tuple[Finding, ...] = ()
    part_bounds: tuple[np.ndarray, ...] = ()

    def to_json(self) -> dict[str, object]:
        """The documented JSON form (SI units)."""
        import numpy as np  # only where mass properties exist: results need no numpy

        out: dict[str, object] = {
            "mass": self.mass,
            "center_of_mass": self.center_of_mass.tolist(),
            # numpy's stubs take no None here; numpy makes an object array of it (JSON null).
            "inertia": np.where(  # type: ignore[call-overload]
                np.isfinite(self.inertia), self.inertia, None
            ).tolist(),
            "source": self.source,
        }
        if self.volume is not None:
            out["volume"] = self.volume
        if self.notes:
            out["notes"] = list(self.notes)
        return out


@dataclass(frozen=True)
class SceneResult:
    """Everything kcheck found about one scene file.

    ``errors`` are the input errors (every one found, located); ``error`` is the first, as
    text. ``warnings`` are sanity warnings about the scene (a units slip, reversed normals).
    ``units`` is the scene's length unit, for reports (JSON stays SI). ``supports`` are the
    scene's supports as checked (SI), each saying which coupling shorthand made it. ``sweep`` is
    the sweep plane as ``(normal, zero)`` unit vectors: angles turn counter-clockwise about
    ``normal`` from ``zero`` (reports state it; None when the file could not be read).
    """

    path: str
    status: Status
    name: str | None = None
    kind: str | None = None
    error: str | None = None
    mass_properties: MassProperties | None = None
    checks: tuple[CheckResult, ...] = ()
    notes: tuple[str, ...] = ()
    plots: tuple[str, ...] = ()
    errors: tuple[Finding, ...] = ()
    warnings: tuple[Finding, ...] = ()
    units: str | None = None
    runtime_s: float = 0.0
    supports: tuple[Mapping[str, Any], ...] = ()
    sweep: tuple[tuple[float, ...], tuple[float, ...]] | None = None

    def to_json(self) -> dict[str, Any]:
        """JSON form of one scene."""
        out: dict[str, Any] = {
            "path": self.path,
            "name": self.name,
            "kind": self.kind,
            "status": self.status.value,
            "error": self.error,
            "mass_properties": None
            if self.mass_properties is None
            else to_json_value(self.mass_properties.to_json()),
            "checks": [c.to_json() for c in self.checks],
            "warnings": [w.to_json() for w in self.warnings],
            "runtime_s": self.runtime_s,
        }
        if self.errors:
            out["errors"] = [e.to_json() for e in self.errors]
        if self.units is not None:
            out["units"] = self.units
        if self.supports:
            out["supports"] = [to_json_value(s) for s in self.supports]
        if self.sweep is not None:
            out["sweep"] = {"normal": list(self.sweep[0]), "zero": list(self.sweep[1])}
        if self.notes:
            out["notes"] = list(self.notes)
        if self.plots:
            out["plots"] = list(self.plots)
        return out


def run_json(scenes: Sequence[SceneResult], version: str) -> dict[str, Any]:
    """The whole document written by ``kcheck check --format json``."""
    return {
        "kcheck_version": version,
        "format_version": JSON_FORMAT_VERSION,
        "scenes": [s.to_json() for s in scenes],
    }
