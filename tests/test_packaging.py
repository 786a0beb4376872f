"""What `pip install .` ships: every package of the source tree, and the report's style sheet.

An explicit package list in pyproject.toml (needed for the ``plugins/`` → ``kcheck_checks``
mapping) silently leaves out a new subpackage; a wheel without ``kcheck.cli`` installs a
``kcheck`` command that cannot start. Checked against the source tree, without a build.
"""

from __future__ import annotations

import sys

from tests.conftest import ROOT

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    tomllib = None


def _setuptools() -> dict:
    import pytest

    if tomllib is None:
        pytest.skip("tomllib needs Python 3.11")
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def test_every_package_is_listed():
    config = _setuptools()
    packages = set(config["packages"])
    for init in (ROOT / "kcheck").rglob("__init__.py"):
        name = ".".join(init.parent.relative_to(ROOT).parts)
        assert name in packages, f"{name} is missing from [tool.setuptools] packages"
    assert "kcheck_checks" in packages


def test_style_sheet_is_package_data():
    patterns = _setuptools()["package-data"]["kcheck"]
    sheets = list((ROOT / "kcheck" / "report").glob("*.css"))
    assert sheets and "report/*.css" in patterns
