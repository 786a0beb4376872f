"""The pre-commit hook (.pre-commit-hooks.yaml), run by pre-commit itself on a throw-away
repository: passing, failing and broken scenes, and a changed mesh re-checking its scene.

The throw-away repository's ``.pre-commit-config.yaml`` points at a snapshot of this working
tree, as a user's points at kcheck's repository; pre-commit installs kcheck from it into a
fresh virtualenv once (pip, from PyPI or pip's cache: about 40 s, most of this test) and
reuses it for every run. (``pre-commit try-repo`` does the same but installs anew on every
call, in a temporary store.)
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli.test_end_to_end import git, make_repository
from tests.conftest import ROOT

pytestmark = pytest.mark.skipif(shutil.which("git") is None, reason="needs git")


def snapshot(dest: Path) -> Path:
    """This working tree as it is (committed or not, ignored files left out), committed in a
    repository of its own, so pre-commit installs exactly what is being tested."""
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=ROOT,
        check=True,
        capture_output=True,
    ).stdout.decode()
    for name in filter(None, listed.split("\0")):
        source = ROOT / name
        if source.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, dest / name)
    git(dest, "init", "-q")
    git(dest, "add", "-A")
    git(dest, "commit", "-qm", "snapshot")
    return dest


@pytest.mark.slow
def test_hook_on_a_throwaway_repository(tmp_path):
    kcheck_repo = snapshot(tmp_path / "kcheck")
    repo = make_repository(tmp_path)
    # a second scene using the passing scene's mesh, failing at a bad design angle
    scene = (repo / "couplings/pass/block.kcheck.yaml").read_text()
    (repo / "couplings/pass/bad-angle.kcheck.yaml").write_text(
        scene.replace("angle: 225", "angle: 45")
    )
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "bad angle")
    env = {
        **os.environ,
        "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home"),
        "PRE_COMMIT_COLOR": "never",
    }

    rev = git(kcheck_repo, "rev-parse", "HEAD").strip()
    (repo / ".pre-commit-config.yaml").write_text(
        f"repos:\n  - repo: {kcheck_repo}\n    rev: {rev}\n    hooks:\n"
        "      - id: kcheck\n        verbose: true\n        args: [--format, concise]\n"
    )

    def hook(*files: str) -> tuple[int, str]:
        proc = subprocess.run(
            [sys.executable, "-m", "pre_commit", "run", "--files", *files],
            cwd=repo, env=env, capture_output=True, text=True, timeout=600,
        )  # fmt: skip
        return proc.returncode, proc.stdout + proc.stderr

    # pre-commit's exit code and kcheck's own output (verbose: true shows it), not pre-commit's
    # words around it ("Passed", "- exit code: 1"), which are pre-commit's to change.
    code, out = hook("couplings/pass/block.kcheck.yaml", "couplings/warn.kcheck.yaml")
    assert code == 0 and "kcheck (kinematic couplings)" in out, out  # the hook's name
    # maxwell is a warning by the repository's configuration
    assert "2 scenes: 1 passed, 1 with warnings, 0 failed, 0 with errors" in out

    code, out = hook("couplings/fail.kcheck.yaml")
    assert code == 1 and "1 scene: 0 passed, 0 with warnings, 1 failed, 0 with errors" in out, out
    assert re.search(r"couplings/fail.kcheck.yaml:\d+: analytical-2d: ", out)

    code, out = hook("couplings/broken.kcheck.yaml")
    assert code == 1 and "1 scene: 0 passed, 0 with warnings, 0 failed, 1 with errors" in out, out
    assert "couplings/broken.kcheck.yaml:14:3: input-error: field `load.magnitude`" in out

    # Only the mesh changed: the two scenes that use it are checked, one fails.
    code, out = hook("couplings/pass/block.stl")
    assert code == 1, out
    assert re.search(r"couplings/pass/bad-angle.kcheck.yaml:\d+: analytical-2d: ", out)
    assert "2 scenes: 1 passed, 0 with warnings, 1 failed, 0 with errors" in out

    # A file the hook does not match is not passed to kcheck; the hook still runs (a change
    # to the configuration changes every verdict), and no scene is affected by this one.
    (repo / "README.md").write_text("couplings\n")
    code, out = hook("README.md")
    assert code == 0 and "0 scenes: 0 passed" in out, out
