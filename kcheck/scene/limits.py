"""Physical ranges the loader accepts, in SI units (the "Limits" table of
docs/scene-format.md lists :data:`LIMITS`; a test keeps the two in step).

They are wide engineering bounds, not design rules: their job is to refuse nonsense (an
infinite load, a normal of 1e300, a density of 1e308) before any algebra sees it, and to name
the allowed range when they do.
"""

from __future__ import annotations

from kcheck.records import dataclass

__all__ = [
    "Range",
    "LIMITS",
    "MAX_DIRECTION",
    "MIN_DIRECTION",
    "MIN_FORCE",
    "INERTIA_SYMMETRY_RTOL",
]


@dataclass(frozen=True)
class Range:
    """Allowed values ``low`` ≤ x ≤ ``high`` in ``unit`` (``open``: both ends excluded)."""

    low: float
    high: float
    unit: str
    what: str
    open: bool = False
    hint: str = ""  # said after a value out of range

    def contains(self, value: float) -> bool:
        """Whether a value lies in the range (NaN never does)."""
        if self.open:
            return bool(self.low < value < self.high)
        return bool(self.low <= value <= self.high)

    def text(self) -> str:
        """The range for a message, e.g. ``0 ≤ μ ≤ 2``."""
        sign = "<" if self.open else "≤"
        unit = f" {self.unit}" if self.unit else ""
        return f"{self.low:g} {sign} {self.what} {sign} {self.high:g}{unit}"


LIMITS: dict[str, Range] = {
    "coordinate": Range(-1e3, 1e3, "m", "each coordinate"),
    "radius": Range(1e-6, 10.0, "m", "radius"),
    "mass": Range(1e-9, 1e6, "kg", "mass"),
    "density": Range(1.0, 3e4, "kg/m^3", "density"),
    "inertia": Range(1e-18, 1e9, "kg m^2", "principal moment"),
    "force": Range(0.0, 1e7, "N", "force"),
    "torque": Range(0.0, 1e7, "N m", "torque"),
    "gravity": Range(
        0.0, 1e3, "m/s^2", "|g|", hint="gravity is in m/s² whatever `units` says (Earth: 9.81)"
    ),
    "friction": Range(0.0, 100.0, "", "μ"),
    "angle": Range(-360.0, 360.0, "deg", "angle"),
    "half_angle": Range(0.0, 90.0, "deg", "half angle", open=True),
    "tolerance_length": Range(0.0, 1.0, "m", "± position"),
    "tolerance_angle": Range(0.0, 30.0, "deg", "± angle"),
    # The supports' largest distance from their centroid (the length the algebra divides by):
    # below a micrometre no coupling is meant, and at 1e-300 m its squares underflow. The
    # upper end is never reached: coordinates lie within 1000 m.
    "layout": Range(1e-6, 1e4, "m", "L"),
}

#: A direction's largest component must lie in [MIN_DIRECTION, MAX_DIRECTION] (its squared
#: norm then neither overflows nor underflows; the length itself does not matter).
MAX_DIRECTION = 1e150
MIN_DIRECTION = 1e-150
#: A force (load, preload) is either zero or at least this (N): a micronewton closes nothing,
#: and a load of 1e-300 N against a body's weight overflows any ratio taken of them.
MIN_FORCE = 1e-6
#: Relative tolerance of the inertia tensor's symmetry, on the largest entry.
INERTIA_SYMMETRY_RTOL = 1e-6
