"""The `reseat` check without its extra: selecting it says what to install (exit 2, no
traceback); a default run neither selects it nor imports MuJoCo. MuJoCo's absence is made in a
fresh interpreter (``sys.modules["mujoco"] = None``: importlib finds no such module)."""

from __future__ import annotations

import os
import subprocess
import sys

from tests.conftest import FIXTURES

ABSENT = (
    "import sys; sys.modules['mujoco'] = None; from kcheck.cli import main; "
    "sys.exit(main(sys.argv[1:]))"
)


def _kcheck_without_mujoco(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", ABSENT, *args],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NO_COLOR": "1"},
    )


def test_selecting_reseat_without_the_extra_names_the_extra() -> None:
    done = _kcheck_without_mujoco("check", str(FIXTURES / "planar-block"), "--select", "reseat")
    assert done.returncode == 2
    assert "kcheck[sim]" in done.stderr
    assert "Traceback" not in done.stdout + done.stderr


def test_a_default_run_without_the_extra_runs_the_other_checks() -> None:
    done = _kcheck_without_mujoco("check", str(FIXTURES / "planar-block"), "--format", "json")
    assert done.returncode in (0, 1), done.stderr
    assert '"reseat"' not in done.stdout
    assert '"analytical-2d"' in done.stdout


def test_a_default_run_does_not_import_mujoco() -> None:
    """Even with MuJoCo installed, a run that does not select reseat never imports it."""
    code = (
        "import sys; from kcheck.cli import main; "
        f"main(['check', {str(FIXTURES / 'planar-block')!r}, '--jobs', '1']); "
        "print('mujoco' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stdout.strip().splitlines()[-1] == "False", done.stderr
