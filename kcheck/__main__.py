"""Run kcheck as ``python -m kcheck``."""

from __future__ import annotations

import sys

from kcheck.cli import main

sys.exit(main())
