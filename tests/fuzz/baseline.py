"""The fixtures' own verdicts, from one run of kcheck on ``fixtures/``: what every rewrite of
a fixture that must keep its verdict is compared with."""

from __future__ import annotations

import functools
import json
import subprocess
import sys
from pathlib import Path

from tests.fuzz.scenes import FIXTURES

__all__ = ["Baseline", "baseline", "exit_code_of"]

#: fixture folder name -> (scene status, {check id: check status})
Baseline = dict[str, tuple[str, dict[str, str]]]


@functools.cache
def baseline() -> Baseline:
    """Run kcheck once on every fixture (in its own folder, as a user would)."""
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "kcheck",
            "check",
            "--format",
            "json",
            "--isolated",
            "-j",
            "1",
            "--no-cache",
            str(FIXTURES),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    if proc.returncode not in (0, 1):
        raise RuntimeError(f"the fixtures do not check: {proc.stderr[-2000:]}")
    out: Baseline = {}
    for scene in json.loads(proc.stdout)["scenes"]:
        name = Path(scene["path"]).parent.name
        out[name] = (scene["status"], {c["id"]: c["status"] for c in scene["checks"]})
    return out


def exit_code_of(name: str) -> int:
    """The exit code of ``kcheck check`` on one fixture alone."""
    return 1 if baseline()[name][0] == "fail" else 0
