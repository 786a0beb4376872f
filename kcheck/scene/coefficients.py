"""Friction coefficients of a scene file: a number, a range ``{min, max}`` or
``{static, kinetic}`` (each a number or a range), checked and turned into
:class:`~kcheck.scene.types.Friction`."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from kcheck.fmt import format_number
from kcheck.scene.accept import is_model
from kcheck.scene.types import Friction
from kcheck.scene.validate import Problems
from kcheck.scene.yamlio import FieldPath

if TYPE_CHECKING:  # records of kcheck.scene.accept read like them
    from kcheck.scene.models import FrictionPairModel, FrictionRangeModel

__all__ = ["resolve_friction"]


def _range(value: Any, where: FieldPath, p: Problems) -> tuple[float, float]:
    """``(low, high)`` of a number or a range; an error (kept as given) when min > max."""
    if is_model(value, "FrictionRangeModel"):
        if value.min > value.max:
            p.add(
                where,
                f"a friction range needs min ≤ max, got min {format_number(value.min, 6)} > "
                f"max {format_number(value.max, 6)}",
            )
        return float(value.min), float(value.max)
    return float(value), float(value)


def _text(span: tuple[float, float]) -> str:
    low, high = (format_number(x, 6) for x in span)
    return low if span[0] == span[1] else f"{low}–{high}"


def resolve_friction(
    value: float | FrictionRangeModel | FrictionPairModel, where: FieldPath, p: Problems
) -> Friction:
    """The coefficients of a ``friction`` field; errors recorded at ``where`` (min > max, or
    static below kinetic)."""
    if not is_model(value, "FrictionPairModel"):  # a record of kcheck.scene.accept
        span = _range(value, where, p)
        return Friction(span, span)
    pair: Any = value
    static = _range(pair.static, (*where, "static"), p)
    kinetic = _range(pair.kinetic, (*where, "kinetic"), p)
    if static[0] < kinetic[0] or static[1] < kinetic[1]:
        p.add(
            where,
            "static friction must be at least the kinetic one (the force that starts sliding "
            f"is at least the one that keeps it going), got static {_text(static)} below "
            f"kinetic {_text(kinetic)}; swap them?",
        )
    return Friction(static, kinetic)
