"""Every package under kcheck/ is listed in pyproject.toml, so a wheel ships it (an editable
install would hide a missing one)."""

from __future__ import annotations

import tomllib

from tests.conftest import ROOT


def test_every_kcheck_package_ships():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    listed = set(config["tool"]["setuptools"]["packages"])
    found = {
        ".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "kcheck").rglob("__init__.py")
    }
    assert found <= listed, sorted(found - listed)
