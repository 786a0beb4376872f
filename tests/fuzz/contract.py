"""The scene format's documented contract, written out independently of the loader: which
values a field takes and which it must refuse (docs/scene-format.md, "Limits" and the field
tables). The fuzzer's oracle: a value this module calls invalid must give an input error at
its field; one it calls valid may still be refused for a relation between fields, but must
then be refused with a located message, and must never crash a check.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from tests.fuzz.model import ANY, Claim, Expect

__all__ = ["UNIT_SCALE", "MATERIALS", "judge_number_field", "fmt_path", "field_name", "kind_of"]

UNIT_SCALE = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 0.0254}


def _material_table() -> tuple[str, ...]:
    """Every material name of the table in docs/scene-format.md ("Materials (kg/m³): ...")."""
    doc = (Path(__file__).resolve().parents[2] / "docs" / "scene-format.md").read_text()
    text = " ".join(doc.split("Materials (kg/m³):", 1)[1].split("\n\n", 1)[0].split())
    names = []
    for item in text.rstrip(".").split(","):
        names.extend(item.split()[0].split("/"))
    return tuple(names)


#: Every name of the material table: any other is an error at its `material`, with a mesh
#: or without one.
MATERIALS = _material_table()

COORDINATE_FIELDS = {"position", "center_of_mass", "center", "point", "translate"}
DIRECTION_FIELDS = {"normal", "axis", "up", "reference", "direction", "zero"}
RADIUS_FIELDS = {"radius"}
# name -> (low, high, open); SI after unit conversion where the field is a length.
SCALAR_RANGES: dict[str, tuple[float, float, bool]] = {
    "mass": (1e-9, 1e6, False),
    "density": (1.0, 3e4, False),
    "friction": (0.0, 100.0, False),
    "angle": (-360.0, 360.0, False),
    "half_angle": (0.0, 90.0, True),
    "radius": (1e-6, 10.0, False),
}
# Vectors judged by their length: name -> (high, least non-zero length).
VECTOR_RANGES = {"gravity": (1e3, 0.0), "torque": (1e7, 0.0), "force": (1e7, 1e-6)}
MAX_DIRECTION, MIN_DIRECTION = 1e150, 1e-150
MAX_INT = 10**300
NEAR = 1e-9  # values this close (relative) to a boundary may go either way


def fmt_path(path: tuple[Any, ...]) -> str:
    """A field path as kcheck writes it: ``supports[1].normal``."""
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out


def field_name(path: tuple[Any, ...]) -> tuple[tuple[Any, ...], str | None]:
    """The named field holding ``path`` (a vector's path for one of its components) and its
    name (the last key)."""
    p = tuple(path)
    while p and isinstance(p[-1], int):
        p = p[:-1]
    return p, (p[-1] if p and isinstance(p[-1], str) else None)


def kind_of(path: tuple[Any, ...]) -> str:
    """What a field holds: ``coordinate``, ``direction``, ``scalar``, ``vector`` (judged by
    length), ``inertia``, ``options`` (a check's own), or ``other``."""
    if path and path[0] == "checks":
        return "options"
    _, name = field_name(path)
    if name in COORDINATE_FIELDS:
        return "coordinate"
    if name in DIRECTION_FIELDS:
        return "direction"
    if name == "inertia":
        return "inertia"
    if name in VECTOR_RANGES:
        return "vector"
    if name == "magnitude":
        return "magnitude"
    if name in SCALAR_RANGES:
        return "scalar"
    return "other"


def _get(data: Any, path: tuple[Any, ...]) -> Any:
    for part in path:
        data = data[part]
    return data


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _near(x: float, bound: float) -> bool:
    return abs(x - bound) <= NEAR * max(abs(bound), 1e-300)


def _range_verdict(x: float, low: float, high: float, open_: bool) -> str:
    """``ok``, ``bad`` or ``edge`` (too close to a boundary to say)."""
    if _near(x, low) or _near(x, high):
        return "edge"
    inside = low < x < high if open_ else low <= x <= high
    return "ok" if inside else "bad"


def _claim(path: tuple[Any, ...], why: str) -> Expect:
    return Expect("invalid", (Claim(fmt_path(path), why, numeric=True),))


def judge_number_field(data: dict, path: tuple[Any, ...]) -> Expect:
    """What the contract says about the numeric field holding ``path`` in ``data`` (a whole
    scene as plain data): invalid (with the claim), or ``any``."""
    value = _get(data, path)
    if isinstance(value, float) and not math.isfinite(value):
        return _claim(path, "every number must be finite")
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > MAX_INT:
        return _claim(path, "an integer too large to be a physical quantity")
    where, name = field_name(path)
    kind = kind_of(path)
    if path[:1] == ("tolerances",) and len(path) == 2:
        return _judge_tolerance(data, path)
    if name in ("min", "max", "static", "kinetic") and "friction" in path:
        kind, name = "scalar", "friction"  # a coefficient of a range or a pair
    if kind == "inertia":
        return _judge_inertia(data, where)
    holder = _get(data, where)
    units = data.get("units", "m") if isinstance(data, dict) else "m"
    scale = UNIT_SCALE.get(units, 1.0) if isinstance(units, str) else 1.0
    numbers = holder if isinstance(holder, list) else [holder]
    if not all(_is_number(x) for x in numbers):
        return ANY
    if any(isinstance(x, int) and abs(x) > MAX_INT for x in numbers) or not all(
        math.isfinite(x) for x in numbers
    ):
        return ANY  # another component is the culprit; judged there
    if kind == "coordinate":
        if not isinstance(holder, list) or len(holder) != 3:
            return ANY
        verdicts = [_range_verdict(abs(float(x) * scale), -1e3, 1e3, False) for x in holder]
        if "bad" in verdicts and "edge" not in verdicts:
            return _claim(where, "coordinates |x| ≤ 1000 m")
        return ANY
    if kind == "direction":
        if not isinstance(holder, list) or len(holder) != 3:
            return ANY
        largest = max(abs(float(x)) for x in holder)
        if largest == 0:
            return _claim(where, "a direction must not be zero")
        v = _range_verdict(largest, MIN_DIRECTION, MAX_DIRECTION, False)
        return _claim(where, "direction components 1e-150…1e150") if v == "bad" else ANY
    if kind == "vector":
        if not isinstance(holder, list) or len(holder) != 3:
            return ANY
        high, least = VECTOR_RANGES[name]  # type: ignore[index]
        comps = np.abs(np.asarray(holder, dtype=float))
        if comps.max() > high * (1 + NEAR):
            return _claim(where, f"length ≤ {high:g}")
        with np.errstate(all="ignore"):
            length = float(np.linalg.norm(comps))
        if _range_verdict(length, least, high, False) == "bad" and length != 0:
            return _claim(where, f"length 0 or {least:g}…{high:g}")
        return ANY
    if kind == "magnitude" and path[:1] == ("load",) and len(path) == 2:
        x = float(value)
        if x == 0:
            return ANY
        if _range_verdict(x, 1e-6, 1e7, False) == "bad":
            return _claim(path, "a load is 0 or 1e-6…1e7 N")
        return ANY
    if kind == "scalar" and not isinstance(holder, list):
        low, high, open_ = SCALAR_RANGES[name]  # type: ignore[index]
        x = float(value) * (scale if name in RADIUS_FIELDS else 1.0)
        if name in ("mass", "radius") and float(value) <= 0:
            return _claim(path, f"{name} must be positive")
        if _range_verdict(x, low, high, open_) == "bad":
            return _claim(path, f"{name} within {low:g}…{high:g}")
        return ANY
    return ANY


def _judge_tolerance(data: dict, path: tuple[Any, ...]) -> Expect:
    """`tolerances.position` (a length in the scene's units, 0 to 1 m) or an angle (0 to 30
    deg)."""
    value = _get(data, path)
    if not _is_number(value):
        return ANY
    if path[1] == "position":
        units = data.get("units", "m")
        scale = UNIT_SCALE.get(units, 1.0) if isinstance(units, str) else 1.0
        verdict = _range_verdict(float(value) * scale, 0.0, 1.0, False)
        return _claim(path, "a position tolerance of 0 to 1 m") if verdict == "bad" else ANY
    verdict = _range_verdict(float(value), 0.0, 30.0, False)
    return _claim(path, "an angle tolerance of 0 to 30 deg") if verdict == "bad" else ANY


def _judge_inertia(data: dict, where: tuple[Any, ...]) -> Expect:
    value = _get(data, where)
    if _is_number(value):
        x = float(value)
        if x <= 0 or _range_verdict(x, 1e-18, 1e9, False) == "bad":
            return _claim(where, "a moment of inertia within 1e-18…1e9 kg m²")
        return ANY
    try:
        tensor = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return ANY
    if tensor.shape != (3, 3) or not np.all(np.isfinite(tensor)):
        return ANY
    largest = float(np.abs(tensor).max())
    if largest > 1e9 * (1 + NEAR):
        return _claim(where, "inertia entries |I| ≤ 1e9 kg m²")
    asym = float(np.abs(tensor - tensor.T).max())
    if asym > 1e-6 * largest * 1.01:
        return _claim(where, "a symmetric inertia tensor (to 1e-6)")
    if asym > 1e-6 * largest * 0.99:
        return ANY
    eig = np.linalg.eigvalsh((tensor + tensor.T) / 2)
    if eig.min() < -1e-9 * largest:
        return _claim(where, "a positive definite inertia tensor")
    if 1e-9 * largest < eig.min() and _range_verdict(float(eig.min()), 1e-18, 1e9, False) == "bad":
        return _claim(where, "principal moments within 1e-18…1e9 kg m²")
    a, b, c = np.sort(eig)
    if a + b < c * (1 - 1e-4):
        return _claim(where, "principal moments satisfying the triangle inequality")
    return ANY
