"""Incremental runs give the full run's verdict (issue 23): real git repositories in a
temporary folder, one per case, where a change that an incremental run could miss is made —
a mesh deleted or renamed while a scene names it, a mesh named only by a scene that does not
parse, only the configuration changed, a branch behind main. In every case
``--changed-only`` (the change staged), ``--since main`` (the change committed on a branch)
and the pre-commit hook (run by pre-commit itself, on the staged change and with
``--from-ref main --to-ref HEAD`` on the branch) return the exit code and the failing scenes
of ``kcheck check`` on the same tree.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.cli.test_end_to_end import git
from tests.conftest import FIXTURES, PLANAR_SCENE

pytestmark = pytest.mark.skipif(shutil.which("git") is None, reason="needs git")

PYPROJECT = """
[project]
name = "couplings"

[tool.kcheck]
paths = ["couplings"]
jobs = 1
"""
SCENE = textwrap.dedent(PLANAR_SCENE).lstrip()


def make_repository(root: Path, hook_config: str | None = None) -> Path:
    """main: a scene using a mesh (its mass properties are needed: a mesh that is gone is an
    input error), a scene of explicit mass properties, both passing; the hook configured."""
    repo = root / "repo"
    couplings = repo / "couplings"
    shutil.copytree(FIXTURES / "planar-block", couplings / "block")
    (couplings / "point.kcheck.yaml").write_text(SCENE)
    (repo / "pyproject.toml").write_text(textwrap.dedent(PYPROJECT).lstrip())
    if hook_config is not None:
        (repo / ".pre-commit-config.yaml").write_text(hook_config)
    git(repo, "init", "-q", "-b", "main")
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "couplings")
    return repo


def delete_mesh(repo: Path) -> None:
    git(repo, "rm", "-q", "couplings/block/block.stl")


def rename_mesh(repo: Path) -> None:
    git(repo, "mv", "couplings/block/block.stl", "couplings/block/renamed.stl")


def unparseable_user(repo: Path) -> None:
    """Already on main: a scene that does not parse, naming a mesh no other scene uses (the
    full run fails on main too); the change is to that mesh only."""
    scene = repo / "couplings/other/broken.kcheck.yaml"
    scene.parent.mkdir()
    shutil.copy(repo / "couplings/block/block.stl", scene.parent / "part.stl")
    text = (repo / "couplings/block/block.kcheck.yaml").read_text()
    scene.write_text(text.replace("block.stl", "part.stl").replace("supports:", "supports: [", 1))
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "a scene that does not parse", "--no-verify")
    with open(scene.parent / "part.stl", "ab") as fh:
        fh.write(b"\n")  # an ASCII STL may end with whitespace: same part, new bytes
    git(repo, "add", "-A")


def configuration_only(repo: Path) -> None:
    pyproject = repo / "pyproject.toml"
    pyproject.write_text(
        pyproject.read_text() + "\n[tool.kcheck.checks.analytical-2d]\nmin_margin_deg = 80\n"
    )
    git(repo, "add", "-A")


def kcheck_toml_only(repo: Path) -> None:
    (repo / "kcheck.toml").write_text(
        'paths = ["couplings"]\n[checks.analytical-2d]\nmin_margin_deg = 80\n'
    )
    git(repo, "add", "-A")


def branch_behind_main(repo: Path) -> None:
    """The branch breaks a scene; main then took the same change and moved
    on, so against main's tip the broken scene looks unchanged: only the merge-base shows it."""
    scene = repo / "couplings/point.kcheck.yaml"
    scene.write_text(SCENE.replace("angle: 225", "angle: 45"))
    git(repo, "add", "-A")


CASES: dict[str, Callable[[Path], None]] = {
    "mesh deleted": delete_mesh,
    "mesh renamed": rename_mesh,
    "mesh of an unparseable scene": unparseable_user,
    "[tool.kcheck] changed": configuration_only,
    "kcheck.toml added": kcheck_toml_only,
    "branch behind main": branch_behind_main,
}


def commit_on_branch(repo: Path, case: str) -> None:
    """Commit the staged change on branch `feature`; for the branch behind main, main then
    takes the same change and a further commit."""
    git(repo, "commit", "-qm", case, "--no-verify")
    if case == "branch behind main":
        git(repo, "checkout", "-q", "main")
        branch_behind_main(repo)  # the same change, a commit of main's own
        git(repo, "commit", "-qm", "the same change on main", "--no-verify")
        (repo / "couplings/later.kcheck.yaml").write_text(SCENE)
        git(repo, "add", "-A")
        git(repo, "commit", "-qm", "later on main", "--no-verify")
        git(repo, "checkout", "-q", "feature")


def verdict(code: int, doc: dict) -> tuple[int, list[str]]:
    failing = sorted(s["path"] for s in doc["scenes"] if s["status"] in ("fail", "error"))
    return code, failing


@pytest.fixture
def run(cli) -> Callable[..., tuple[int, list[str], list[str]]]:
    def run(*args: str) -> tuple[int, list[str], list[str]]:
        code, out, err = cli("check", "--format", "json", *args)
        assert "Traceback" not in err
        doc = json.loads(out)
        return (*verdict(code, doc), sorted(s["path"] for s in doc["scenes"]))

    return run


@pytest.mark.parametrize("case", CASES)
def test_changed_only_and_since_give_the_full_verdict(case, tmp_path, monkeypatch, run):
    repo = make_repository(tmp_path)
    monkeypatch.chdir(repo)
    assert run()[:2] == (0, [])  # main passes
    git(repo, "checkout", "-q", "-b", "feature")
    CASES[case](repo)
    full = run()
    assert full[0] != 0, full  # every case breaks the full run
    if case != "branch behind main":  # staged, not committed: what --changed-only sees
        assert run("--changed-only")[:2] == full[:2]
        assert run("--pre-commit")[:2] == full[:2]
    commit_on_branch(repo, case)
    assert run()[:2] == full[:2]
    since = run("--since", "main")
    assert since[:2] == full[:2]
    if case == "branch behind main":
        # judged by its own change: main's later scene is not the branch's to check
        assert since[2] == ["couplings/point.kcheck.yaml"]
        # main's tip holds the same broken scene: compared with it, nothing changed
        assert git(repo, "diff", "--name-only", "main", "--", "couplings/point.kcheck.yaml") == ""


def test_a_pyproject_change_outside_tool_kcheck_checks_nothing_more(tmp_path, monkeypatch, run):
    repo = make_repository(tmp_path)
    monkeypatch.chdir(repo)
    pyproject = repo / "pyproject.toml"
    pyproject.write_text(pyproject.read_text().replace('name = "couplings"', 'name = "other"'))
    assert run("--changed-only") == (0, [], [])
    configuration_only(repo)
    assert run("--changed-only")[2] == [
        "couplings/block/block.kcheck.yaml",
        "couplings/point.kcheck.yaml",
    ]


def test_a_changed_baseline_rechecks_every_scene(tmp_path, monkeypatch, run):
    """Like a configuration change: main accepts a failing scene through its baseline; the
    branch drops the entry (the failure counts again) without touching the scene. The
    incremental modes see the baseline change and give the full run's verdict."""
    repo = make_repository(tmp_path)
    monkeypatch.chdir(repo)
    (repo / "couplings/point.kcheck.yaml").write_text(SCENE.replace("angle: 225", "angle: 45"))
    assert run("--write-baseline", "baseline.json")[0] == 0
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "an accepted failure", "--no-verify")
    assert run("--baseline", "baseline.json")[:2] == (0, [])
    git(repo, "checkout", "-q", "-b", "feature")
    (repo / "baseline.json").write_text('{"version": 1, "failures": []}\n')
    git(repo, "add", "-A")
    full = run("--baseline", "baseline.json")
    assert full[:2] == (1, ["couplings/point.kcheck.yaml"]), full
    for mode in (["--changed-only"], ["--pre-commit"]):
        assert run(*mode, "--baseline", "baseline.json") == full, mode
    git(repo, "commit", "-qm", "the baseline accepts nothing", "--no-verify")
    assert run("--since", "main", "--baseline", "baseline.json") == full
    # Without --baseline the file is not an input: an unchanged tree checks nothing.
    assert run("--changed-only") == (0, [], [])


def test_since_needs_a_common_ancestor(tmp_path, monkeypatch, cli):
    repo = make_repository(tmp_path)
    monkeypatch.chdir(repo)
    git(repo, "checkout", "-q", "--orphan", "unrelated")
    git(repo, "commit", "-qm", "unrelated")
    code, out, err = cli("check", "--since", "main")
    assert code == 2 and out == "" and "`main` and HEAD have no common ancestor" in err


@pytest.mark.slow
def test_the_pre_commit_hook_gives_the_full_verdict(tmp_path):
    """pre-commit itself, on the staged change (``pre-commit run``) and on the branch
    (``pre-commit run --from-ref main --to-ref HEAD``, as CI runs it): the hook's JSON report
    holds the verdict of the full run on the same tree."""
    from tests.cli.test_precommit import snapshot

    kcheck_repo = snapshot(tmp_path / "kcheck")
    rev = git(kcheck_repo, "rev-parse", "HEAD").strip()
    report = tmp_path / "hook.json"
    config = (
        f"repos:\n  - repo: {kcheck_repo}\n    rev: {rev}\n    hooks:\n      - id: kcheck\n"
        f"        args: [--format, json, --output, {report}]\n"
    )
    env = {
        **os.environ,
        "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home"),
        "PRE_COMMIT_COLOR": "never",
        "KCHECK_CACHE_DIR": str(tmp_path / "cache"),
    }

    def kcheck(repo: Path, *args: str) -> tuple[int, list[str]]:
        proc = subprocess.run(
            [sys.executable, "-m", "kcheck", "check", "--format", "json", *args],
            cwd=repo, env=env, capture_output=True, text=True, timeout=600,
        )  # fmt: skip
        return verdict(proc.returncode, json.loads(proc.stdout))

    def hook(repo: Path, *args: str) -> tuple[int, list[str]]:
        report.unlink(missing_ok=True)
        proc = subprocess.run(
            [sys.executable, "-m", "pre_commit", "run", *args],
            cwd=repo, env=env, capture_output=True, text=True, timeout=900,
        )  # fmt: skip
        assert report.exists(), proc.stdout + proc.stderr  # kcheck ran
        doc = json.loads(report.read_text())
        # pre-commit fails on any exit code but 0 (and exits 1); kcheck's own code is the
        # one its report implies: 2 with an input error, else 1 with a failed check
        statuses = {s["status"] for s in doc["scenes"]}
        code = 2 if "error" in statuses else 1 if "fail" in statuses else 0
        assert proc.returncode == min(code, 1), proc.stdout + proc.stderr
        return verdict(code, doc)

    for n, (case, change) in enumerate(CASES.items()):
        repo = make_repository(tmp_path / f"case{n}", config)
        git(repo, "checkout", "-q", "-b", "feature")
        change(repo)
        full = kcheck(repo)
        assert full[0] != 0, (case, full)
        if case != "branch behind main":
            assert hook(repo) == full, case
        commit_on_branch(repo, case)
        assert kcheck(repo) == full, case
        assert hook(repo, "--from-ref", "main", "--to-ref", "HEAD") == full, case
