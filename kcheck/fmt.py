"""How numbers are written for people: angles and ranges, lengths in the scene's units, and
numerical noise cleaned away. Checks use it for their messages, every report for its tables,
so one convention holds everywhere.

Angle convention: degrees, counter-clockwise about the sweep plane's normal from its zero
direction (a planar scene: from +x towards +y). A range ``[start, end]`` runs counter-clockwise
from ``start`` to ``end``, ``start`` in [0°, 360°) and ``end`` in (0°, 360°] (360 for a range
that ends at 0°); a range that passes 0° is written "292.41°–5.00° (through 0°)". The full
circle is ``[0, 360]``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from kcheck.numerics.thresholds import FULL_TURN_SLACK_DEG, NOISE_RTOL

__all__ = [
    "FULL_TURN",
    "normalise_range",
    "rounded_bound",
    "format_angle",
    "format_range",
    "format_ranges",
    "clean",
    "clean3",
    "format_number",
    "format_share",
    "format_percent",
    "format_share_bounds",
    "format_length",
    "format_vector",
    "format_direction",
    "format_point",
    "describe_sweep",
    "MESH_DIGITS",
    "COMPUTED_DIGITS",
    "justified",
]

FULL_TURN = 360.0


def normalise_range(start: float, end: float) -> tuple[float, float]:
    """A range in degrees as ``(start, end)``, ``start`` in [0, 360) and ``end`` in (0, 360]:
    ``(0, 360)`` for a full turn, ``end = 360`` for a range that ends at 0°.

    ``end < start`` afterwards means the range passes through 0°.
    """
    width = end - start
    if width >= FULL_TURN - FULL_TURN_SLACK_DEG:
        return 0.0, FULL_TURN
    s = float(start % FULL_TURN)
    e = float(end % FULL_TURN)
    # Rounding can put an end a hair below 360: keep it in [0, 360).
    s, e = (0.0 if s >= FULL_TURN else s), (0.0 if e >= FULL_TURN else e)
    # A range that ends at 0° ends at 360° (it does not pass through 0°).
    return s, (FULL_TURN if e == 0.0 and width > 0 else e)


def format_angle(value: float, decimals: int = 2) -> str:
    """An angle in degrees, e.g. ``292.41°``; ``-0.00`` is written ``0.00``."""
    text = f"{value:.{decimals}f}"
    if float(text) == 0.0:
        text = f"{0.0:.{decimals}f}"
    return text + "°"


def format_range(start: float, end: float, decimals: int = 2) -> str:
    """One range, e.g. ``292.41°–5.00° (through 0°)`` or ``every direction``.

    Ends are compared as written: a start that rounds to 360° is written 0°, and an end that
    rounds to 0° (or 360°) closes the turn, ``184.78°–360.00°``, without "through 0°".
    """
    s, e = normalise_range(start, end)
    if (s, e) == (0.0, FULL_TURN):
        return "every direction"
    s, e = round(s, decimals) % FULL_TURN, round(e, decimals)
    if e in (0.0, FULL_TURN):
        e = FULL_TURN
    text = f"{format_angle(s, decimals)}–{format_angle(e, decimals)}"
    return text + (" (through 0°)" if e < s else "")


def format_ranges(ranges: Iterable[Sequence[float]] | None, decimals: int = 2) -> str:
    """A set of ranges, comma-separated; ``none`` when empty, ``–`` when not computed."""
    if ranges is None:
        return "–"
    parts = [format_range(r[0], r[1], decimals) for r in ranges]
    return ", ".join(parts) if parts else "none"


def clean(values: np.ndarray | Sequence[float] | float, scale: float | None = None) -> np.ndarray:
    """Values with rounding noise set to exactly zero.

    An entry counts as noise when its magnitude is below ``NOISE_RTOL`` times ``scale``
    (default: the largest magnitude among ``values``); ``-0.0`` becomes ``0.0``.
    """
    array = np.array(values, dtype=float, copy=True)
    finite = np.isfinite(array)
    if scale is None:
        scale = float(np.abs(array[finite]).max()) if np.any(finite) else 0.0
    array[finite & (np.abs(array) <= NOISE_RTOL * scale)] = 0.0
    return array + 0.0  # turns -0.0 into 0.0


def clean3(values: list[float], scale: float | None = None) -> list[float]:
    """:func:`clean` of a few floats, in plain float arithmetic (the same bits; for a few
    values numpy's per-call overhead is most of the time)."""
    if scale is None:
        scale = max((abs(x) for x in values if math.isfinite(x)), default=0.0)
    limit = NOISE_RTOL * scale
    return [(0.0 if math.isfinite(x) and abs(x) <= limit else x) + 0.0 for x in values]


def format_number(value: float | None, digits: int = 4) -> str:
    """A number with ``digits`` significant digits; ``–`` for None, ``∞`` for infinity."""
    if value is None:
        return "–"
    # Not redundant, whatever mypy says: an int is a float to it (numeric promotion).
    if isinstance(value, float) and not math.isfinite(value):  # type: ignore[redundant-expr]
        return "–" if math.isnan(value) else ("∞" if value > 0 else "-∞")
    if value == 0:
        return "0"
    return f"{value:.{digits}g}"


def format_share(fraction: float, decimals: int = 2) -> str:
    """A share (0..1) as a percentage with ``decimals`` decimals, e.g. ``6.20%``. A share
    strictly between 0 and 1 is never written ``0.00%`` or ``100.00%``: near either end it
    gets two significant digits of itself (``0.0056%``) or of what it lacks to the whole
    (``99.9990%``); below 1e-10 % it is written ``1.0e-18%``."""
    percent = 100.0 * fraction
    if not math.isfinite(percent):
        return "–"
    if percent <= 0 or percent >= 100:
        return f"{max(min(percent, 100.0), 0.0):g}%"
    gap = float(f"{min(percent, 100.0 - percent):.6g}")  # 100 - 99.999: 0.001, not 0.00099…
    if gap < 1e-10:
        return f"{percent:.1e}%" if percent < 50 else f"{100 - 1e-10:.10f}%"
    places = max(decimals, 1 - math.floor(math.log10(gap)))
    return f"{percent:.{places}f}%"


def format_percent(fraction: float) -> str:
    """A ratio (1 = 100 %) as a whole percentage, ``37%``; below 1 % with two significant
    digits, ``0.36%`` (a ratio never reads ``0%`` unless it is zero)."""
    percent = 100.0 * fraction
    if not math.isfinite(percent):
        return "–"
    if percent == 0 or abs(percent) >= 0.995:
        return f"{percent:.0f}%"
    return f"{percent:.2g}%"


def format_share_bounds(low: float, high: float, decimals: int = 2) -> str:
    """A share known between bounds: ``0%–0.090%``, or one share when both write the same."""
    low_text, high_text = format_share(low, decimals), format_share(high, decimals)
    return low_text if low_text == high_text else f"{low_text}–{high_text}"


def format_length(value_m: float, scale: float, units: str, decimals: int | None = None) -> str:
    """A length given in metres, written in the scene's units (``scale`` metres per unit)."""
    value = value_m / scale
    text = format_number(value) if decimals is None else f"{value:.{decimals}f}"
    return f"{text} {units}"


def format_vector(values: Sequence[float] | np.ndarray, digits: int = 4) -> str:
    """A vector with noise cleaned, e.g. ``(0, 1, 0)``."""
    return "(" + ", ".join(format_number(float(v), digits) for v in clean(values)) + ")"


_AXIS_NAMES = {
    (1, 0, 0): "+x", (-1, 0, 0): "−x", (0, 1, 0): "+y",
    (0, -1, 0): "−y", (0, 0, 1): "+z", (0, 0, -1): "−z",
}  # fmt: skip


def format_direction(values: Sequence[float] | np.ndarray, decimals: int = 3) -> str:
    """A unit direction: ``+x``, ``−z`` for a coordinate axis, else ``(0.707, 0.000, -0.707)``."""
    v = clean(values)
    key = tuple(int(round(x)) for x in v) + (0,) * (3 - len(v))  # a planar (x, y) too
    if key in _AXIS_NAMES and np.allclose(v, key[: len(v)], atol=NOISE_RTOL):
        return _AXIS_NAMES[key]
    return format_point(v, decimals)


def format_point(values: Sequence[float] | np.ndarray, decimals: int = 3) -> str:
    """Coordinates with ``decimals`` decimals, noise cleaned, never ``-0.00``:
    ``(50.00, 45.50)``."""
    parts = []
    for x in clean(values):
        text = f"{x:.{decimals}f}"
        parts.append(text[1:] if text.startswith("-") and float(text) == 0 else text)
    return "(" + ", ".join(parts) + ")"


def describe_sweep(normal: Sequence[float] | np.ndarray, zero: Sequence[float] | np.ndarray) -> str:
    """Where 0° is and which way angles turn in a sweep plane:
    ``0° along +x, 90° along +y, counter-clockwise about +z``."""
    n, z = np.asarray(normal, float), np.asarray(zero, float)
    return (
        f"0° along {format_direction(z)}, 90° along {format_direction(np.cross(n, z))}, "
        f"counter-clockwise about {format_direction(n)}"
    )


def rounded_bound(value: float, digits: int, up: bool) -> float:
    """``value`` (non-zero) to ``digits`` significant digits, strictly above (``up``) or below
    it by at least a millionth: a bound a designer can type in and still be on the right side."""
    if value == 0 or not math.isfinite(value):
        raise ValueError(f"a rounded bound needs a finite non-zero value, not {value!r}")
    scale = 10.0 ** (digits - 1 - math.floor(math.log10(abs(value))))
    if up:
        return (math.floor(value * scale * (1 + 1e-6)) + 1) / scale
    return (math.ceil(value * scale * (1 - 1e-6)) - 1) / scale


#: Significant digits a mesh carries, of its extent: STL and most CAD exports store float32
#: coordinates (a 24-bit mantissa, 7.2 digits), one digit kept back for the sums that give
#: mass properties. ``kcheck mass`` and ``kcheck init`` print no digit past these.
MESH_DIGITS = 6
#: Significant digits of a number computed in double precision from typed input, of its
#: scale: arithmetic noise sits in the last two or three of a double's 16 digits (0.1 + 0.2
#: is 0.30000000000000004). ``kcheck expand`` prints no digit past these.
COMPUTED_DIGITS = 12


def justified(
    values: np.ndarray | Sequence[float] | float,
    scale: float | None = None,
    digits: int = COMPUTED_DIGITS,
) -> Any:
    """``values`` rounded to ``digits`` significant digits of ``scale`` (default: the largest
    finite magnitude among them), so that they print with only the digits their input
    justifies (0.1 + 0.2 prints 0.3); ``-0.0`` becomes ``0.0``. A float for a number, else a
    nested list of floats (ready for JSON or YAML)."""
    array = np.asarray(values, dtype=float)
    finite = array[np.isfinite(array)]
    if scale is None:
        scale = float(np.abs(finite).max()) if finite.size else 0.0
    if not math.isfinite(scale) or scale == 0.0:
        return (array + 0.0).tolist()
    decimals = digits - 1 - math.floor(math.log10(abs(scale)))
    # Python's round is correctly rounded: the result is the double nearest the decimal.
    rounded = [
        round(float(v), decimals) + 0.0 if math.isfinite(v) else float(v) for v in array.flat
    ]
    return np.array(rounded).reshape(array.shape).tolist()
