"""The folder tree is the architecture (docs/architecture.md): the import-linter contracts in
pyproject.toml hold, and they cover every package and every built-in check, so that a new
folder or check cannot slip past them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
CONTRACTS = {c["type"]: c for c in PYPROJECT["tool"]["importlinter"]["contracts"]}
CHECKS = sorted(
    v.split(":")[0] for v in PYPROJECT["project"]["entry-points"]["kcheck.checks"].values()
)


def _layer_modules() -> list[str]:
    return [
        name.strip()
        for layer in CONTRACTS["layers"]["layers"]
        for name in layer.replace("|", ":").split(":")
    ]


def test_import_contracts_hold():
    # import-linter reads the contracts from pyproject.toml: layers, independent checks, no
    # drawing below the pictures, no import circle in any package.
    exe = Path(sys.executable).with_name("lint-imports")
    proc = subprocess.run(
        [str(exe)], cwd=ROOT, capture_output=True, text=True, timeout=300, check=False
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]


def test_every_package_sits_in_a_layer():
    layered = set(_layer_modules())
    packages = {
        f"kcheck.{p.name}" for p in (ROOT / "kcheck").iterdir() if (p / "__init__.py").exists()
    }
    assert packages <= layered, f"not in a layer: {sorted(packages - layered)}"
    top_modules = {
        f"kcheck.{p.stem}"
        for p in (ROOT / "kcheck").glob("*.py")
        if p.stem not in ("__init__", "__main__")
    }
    assert top_modules <= layered, f"not in a layer: {sorted(top_modules - layered)}"
    checks_folder = ROOT / "plugins" / "kcheck_checks"
    plugin_modules = {
        f"kcheck_checks.{p.stem}" for p in checks_folder.glob("*.py") if p.stem != "__init__"
    } | {f"kcheck_checks.{p.name}" for p in checks_folder.iterdir() if (p / "__init__.py").exists()}
    assert plugin_modules <= layered, f"not in a layer: {sorted(plugin_modules - layered)}"


def test_every_built_in_check_is_independent_and_draws_nothing():
    assert sorted(CONTRACTS["independence"]["modules"]) == CHECKS
    drawing = CONTRACTS["forbidden"]
    assert set(CHECKS) <= set(drawing["source_modules"])
    assert {"kcheck.mechanics", "kcheck.analysis"} <= set(drawing["source_modules"])
    assert {"matplotlib", "kcheck.pictures", "kcheck_checks.pictures"} <= set(
        drawing["forbidden_modules"]
    )
    cycles = CONTRACTS["acyclic_siblings"]
    assert set(cycles["ancestors"]) == {"kcheck", "kcheck_checks"}


def test_layers_run_from_the_command_line_down_to_the_result_model():
    layers = _layer_modules()
    order = [
        "kcheck.cli",
        "kcheck.gate",
        "kcheck_checks.pictures",
        "kcheck_checks.maxwell",
        "kcheck.report",
        "kcheck.plugin",
        "kcheck.analysis",
        "kcheck.mechanics",
        "kcheck.body",
        "kcheck.scene",
        "kcheck.result",
    ]
    assert [layers.index(m) for m in order] == sorted(layers.index(m) for m in order)
