"""Shared test helpers: scenes written as real YAML files, and the CLI called in-process."""

from __future__ import annotations

import json
import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

from kcheck.cli import main

ROOT = Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "fixtures"


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("kcheck fuzz (issue 13, tests/fuzz)")
    group.addoption(
        "--fuzz-long",
        type=int,
        default=0,
        metavar="N",
        help="also run the long fuzz campaign with N inputs (e.g. 10000; one core, an hour)",
    )
    group.addoption(
        "--fuzz-seed",
        type=int,
        default=None,
        metavar="SEED",
        help="seed of the fuzz tests (default: fixed for the normal run, the clock for the "
        "long one); every problem names the input to regenerate it",
    )


@pytest.fixture(autouse=True)
def _plain_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    """Reports in tests are plain text, unwrapped (no COLUMNS: a pipe's lines stay whole)."""
    monkeypatch.setenv("NO_COLOR", "1")
    monkeypatch.delenv("COLUMNS", raising=False)
    monkeypatch.delenv("FORCE_COLOR", raising=False)


@pytest.fixture(autouse=True)
def _own_cache(monkeypatch: pytest.MonkeyPatch, tmp_path_factory: pytest.TempPathFactory) -> None:
    """Each test starts with an empty mass-property cache of its own (never ~/.cache)."""
    monkeypatch.setenv("KCHECK_CACHE_DIR", str(tmp_path_factory.mktemp("kcheck-cache")))


@pytest.fixture
def write_scene(tmp_path: Path) -> Callable[..., Path]:
    """Write a scene file (dedented YAML text) into tmp_path; return its path."""

    def write(text: str, name: str = "scene.kcheck.yaml") -> Path:
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
        return path

    return write


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., tuple[int, str, str]]:
    """Run ``kcheck`` in-process; return (exit code, stdout, stderr)."""

    def run(*args: str) -> tuple[int, str, str]:
        try:
            code = main(list(args))
        except SystemExit as exc:  # argparse usage errors and --version
            code = int(exc.code or 0)
        out, err = capsys.readouterr()
        return code, out, err

    return run


@pytest.fixture
def cli_json(cli: Callable[..., tuple[int, str, str]]) -> Callable[..., tuple[int, dict]]:
    """Run ``kcheck check --format json`` in-process; return (exit code, document)."""

    def run(*args: str) -> tuple[int, dict]:
        code, out, _ = cli("check", "--format", "json", *args)
        return code, json.loads(out)

    return run


PLANAR_SCENE = """
version: 1
name: planar block (methods.md §7)
units: mm
body:
  mass: 1
  center_of_mass: [50, 30, 0]
  inertia: 0.001
supports:
  - {name: y1, position: [20, 0, 0], normal: [0, 1, 0]}
  - {name: y2, position: [80, 0, 0], normal: [0, 1, 0]}
  - {name: x1, position: [0, 30, 0], normal: [1, 0, 0]}
friction: 0.1
load:
  magnitude: 1
  angle: 225
"""


@pytest.fixture(autouse=True)
def _mpmath_precision_restored():
    """mpmath's precision is global: a test that raises it must not change the next test's
    reference values (the order of tests is not part of a result)."""
    import mpmath

    dps = mpmath.mp.dps
    yield
    mpmath.mp.dps = dps
