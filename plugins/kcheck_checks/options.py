"""Options shared by more than one built-in check (a check's own options live beside it)."""

from __future__ import annotations

from kcheck.numerics.margins import MARGINAL_ANGLE_DEG
from kcheck.plugin import Field, Options

__all__ = ["AnalyticalOptions"]


class AnalyticalOptions(Options):
    """Options of the analytical checks."""

    min_margin_deg: float = Field(
        0.0, ge=0, description="Least angular distance of the design direction from a boundary"
    )
    marginal_deg: float = Field(
        MARGINAL_ANGLE_DEG,
        ge=0,
        le=180,
        description="A pass whose design margin is below this (degrees) is marginal "
        "(0: no marginal band)",
    )
