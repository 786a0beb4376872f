"""kcheck and the built-in checks type-check: mypy at the strictness of [tool.mypy] in
pyproject.toml (issue 20), run from the repository root as CI and developers run it."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

from tests.conftest import ROOT


def test_mypy():
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed (the `test` extra installs it)")
    proc = subprocess.run(
        [sys.executable, "-m", "mypy"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
    )
    output = proc.stdout + proc.stderr
    assert proc.returncode == 0, output
    assert "Success: no issues found" in proc.stdout, output
