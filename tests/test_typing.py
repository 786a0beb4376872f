"""kcheck and the built-in checks type-check: mypy at the strictness of [tool.mypy] in
pyproject.toml (issue 20), run from the repository root as CI and developers run it."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

from tests.conftest import ROOT


@pytest.mark.static
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
    # mypy's exit code says it all (1: errors found, 2: a usage or configuration problem);
    # its wording is its own.
    assert proc.returncode == 0, output
