"""Options shared by more than one built-in check (a check's own options live beside it)."""

from __future__ import annotations

from pydantic import Field

from kcheck.plugin import Options

__all__ = ["AnalyticalOptions"]


class AnalyticalOptions(Options):
    """Options of the analytical checks."""

    min_margin_deg: float = Field(
        0.0, ge=0, description="Least angular distance of the design direction from a boundary"
    )
