"""kcheck: check the repositioning behaviour of kinematic couplings from CAD exports."""

from __future__ import annotations

__all__ = ["__version__"]

__version__ = "0.1.0"
