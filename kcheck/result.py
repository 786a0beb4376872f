"""Immutable results and their documented, versioned JSON form (SI units, angles in degrees)."""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from kcheck.mass import MassProperties

__all__ = [
    "JSON_FORMAT_VERSION",
    "Status",
    "CaseResult",
    "CheckResult",
    "SceneResult",
    "ranges_json",
    "to_json_value",
    "run_json",
]

#: Version of the JSON result layout; bumped when a name or meaning changes.
JSON_FORMAT_VERSION = 1


class Status(str, enum.Enum):
    """Verdict of a check or scene."""

    PASS = "pass"
    FAIL = "fail"
    SKIPPED = "skipped"
    ERROR = "error"


Ranges = tuple[tuple[float, float], ...]


def _frozen(mapping: Mapping[str, Any] | None) -> Mapping[str, Any]:
    return MappingProxyType(dict(mapping or {}))


def to_json_value(value: Any) -> Any:
    """Plain JSON value: numpy to lists/floats, non-finite floats to null, mappings to dicts."""
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
    """Arc ranges in degrees as JSON lists."""
    return [[float(s), float(e)] for s, e in ranges]


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
        out.update(to_json_value(self.details))
        return out


@dataclass(frozen=True)
class CheckResult:
    """Result of one check on one scene.

    ``error_estimate`` bounds the numerical error of what the check reports, in the unit its
    documentation states (degrees for safe ranges). ``runtime_s`` is measured by the runner.
    """

    id: str
    status: Status
    message: str
    runtime_s: float = 0.0
    error_estimate: float | None = None
    safe_ranges_deg: Ranges | None = None
    cases: tuple[CaseResult, ...] = ()
    details: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "details", _frozen(self.details))
        object.__setattr__(self, "cases", tuple(self.cases))

    def to_json(self) -> dict[str, Any]:
        """JSON form; fields the check has no use for are omitted."""
        out: dict[str, Any] = {
            "id": self.id,
            "status": self.status.value,
            "message": self.message,
            "runtime_s": self.runtime_s,
        }
        if self.error_estimate is not None:
            out["error_estimate"] = to_json_value(self.error_estimate)
        if self.safe_ranges_deg is not None:
            out["safe_ranges_deg"] = ranges_json(self.safe_ranges_deg)
        if self.cases:
            out["cases"] = [c.to_json() for c in self.cases]
        out.update(to_json_value(self.details))
        return out


@dataclass(frozen=True)
class SceneResult:
    """Everything kcheck found about one scene file."""

    path: str
    status: Status
    name: str | None = None
    kind: str | None = None
    error: str | None = None
    mass_properties: MassProperties | None = None
    checks: tuple[CheckResult, ...] = ()
    notes: tuple[str, ...] = ()
    plots: tuple[str, ...] = ()

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
        }
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
