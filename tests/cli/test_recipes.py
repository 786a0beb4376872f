"""The CI recipes of docs/ci.md install kcheck (issue 23): no recipe runs `pip install
kcheck` (no such package is published), and the GitHub and GitLab recipes' own install
commands, run as written in a fresh virtualenv with ``KCHECK_SOURCE`` pointing at a snapshot
of this working tree (``git+file://``: no network beyond PyPI for the dependencies), give a
working ``kcheck``; the GitLab recipe's check command then runs on a throw-away repository."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import venv
from pathlib import Path

import pytest
import yaml

from tests.cli.test_end_to_end import make_repository
from tests.conftest import ROOT

pytestmark = [
    pytest.mark.skipif(shutil.which("git") is None, reason="needs git"),
    pytest.mark.slow,
]


def recipes() -> dict[str, dict]:
    """The YAML blocks of docs/ci.md by the section they are in."""
    text = (ROOT / "docs/ci.md").read_text()
    found = {}
    for section in re.split(r"^## ", text, flags=re.M)[1:]:
        title = section.splitlines()[0].strip()
        for block in re.findall(r"```yaml\n(.*?)```", section, re.S):
            found[title] = yaml.safe_load(block)
    return found


def install_commands() -> dict[str, tuple[dict[str, str], list[str]]]:
    """Each recipe's variables and its commands that install kcheck."""
    found = recipes()
    github = found["GitHub Actions"]
    steps = github["jobs"]["kcheck"]["steps"]
    gitlab = found["GitLab CI"]["kcheck"]
    return {
        "github": (github["env"], [s["run"] for s in steps if "pip install" in s.get("run", "")]),
        "gitlab": (gitlab["variables"], [c for c in gitlab["script"] if "pip install" in c]),
    }


def test_no_recipe_installs_an_unpublished_name():
    text = (ROOT / "docs/ci.md").read_text()
    assert not re.search(r"pip install\s+['\"]?kcheck(\[[a-z,]+\])?['\"]?(\s|$)", text)
    for variables, commands in install_commands().values():
        assert commands and all("$KCHECK_SOURCE" in c for c in commands)
        assert variables["KCHECK_SOURCE"].startswith("git+")


@pytest.mark.parametrize("recipe", ["github", "gitlab"])
def test_recipe_installs_kcheck_in_a_fresh_venv(recipe, tmp_path):
    from tests.cli.test_precommit import snapshot

    source = snapshot(tmp_path / "kcheck")
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    variables, commands = install_commands()[recipe]
    env = {
        **os.environ,
        **{k: str(v) for k, v in variables.items()},
        "KCHECK_SOURCE": f"git+{source.as_uri()}",  # the repository, as a git URL
        "PATH": f"{env_dir / 'bin'}{os.pathsep}{os.environ['PATH']}",
        "VIRTUAL_ENV": str(env_dir),
        "PIP_DISABLE_PIP_VERSION_CHECK": "1",
    }
    for command in commands:
        proc = subprocess.run(
            ["bash", "-ec", command], cwd=tmp_path, env=env, capture_output=True, text=True,
            timeout=900,
        )  # fmt: skip
        assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    kcheck = env_dir / "bin" / "kcheck"
    assert kcheck.exists() and Path(sys.executable) != env_dir / "bin" / "python"
    version = subprocess.run([kcheck, "--version"], capture_output=True, text=True, env=env)
    assert version.returncode == 0 and "0.1.0" in version.stdout + version.stderr
    if recipe == "gitlab":  # the recipe's check, on a throw-away repository: exit 2 (broken)
        repo = make_repository(tmp_path)
        (check,) = [c for c in recipes()["GitLab CI"]["kcheck"]["script"] if "kcheck check" in c]
        proc = subprocess.run(["bash", "-c", check], cwd=repo, env=env, capture_output=True,
                              text=True, timeout=600)  # fmt: skip
        assert proc.returncode == 2, proc.stderr
        assert (repo / "kcheck-junit.xml").exists() and (repo / "kcheck.sarif").exists()
        assert (repo / ".kcheck_cache").is_dir()  # KCHECK_CACHE_DIR: the cache CI keeps
