"""Run kcheck as ``python -m kcheck``."""

from __future__ import annotations

from kcheck.cli import run

run()
