"""A throw-away repository of couplings (passing, failing, warning and broken scenes, one with
a real mesh) checked as a CI gate would: exit codes, located results in every format,
configuration honoured and overridden, serial and parallel runs alike, changed files only."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import textwrap
from pathlib import Path

import pytest

import kcheck.gate.pool
from tests.conftest import FIXTURES, PLANAR_SCENE
from tests.kcheck.test_report_formats import validate_sarif

pytestmark = pytest.mark.skipif(shutil.which("git") is None, reason="needs git")

PYPROJECT = """
[project]
name = "couplings"

[tool.kcheck]
paths = ["couplings"]
jobs = 2

[tool.kcheck.checks.maxwell]
severity = "warning"
"""
SCENE = textwrap.dedent(PLANAR_SCENE).lstrip()
BROKEN_LINE, BROKEN_COLUMN = 14, 3  # `magnitude: lots` in PLANAR_SCENE


def git(repo: Path, *args: str) -> str:
    return subprocess.run(
        ["git", "-c", "user.name=t", "-c", "user.email=t@example.com", *args],
        cwd=repo,
        check=True,
        capture_output=True,
        text=True,
    ).stdout


def make_repository(root: Path) -> Path:
    """The throw-away repository: couplings/{pass/block,fail,warn,broken}.kcheck.yaml."""
    repo = root / "repo"
    couplings = repo / "couplings"
    shutil.copytree(FIXTURES / "planar-block", couplings / "pass")
    (couplings / "fail.kcheck.yaml").write_text(SCENE.replace("angle: 225", "angle: 45"))
    # The layout's worst cos θ is 0.894 (methods.md §7): min_cos 0.95 fails maxwell only.
    (couplings / "warn.kcheck.yaml").write_text(SCENE + "checks:\n  maxwell: {min_cos: 0.95}\n")
    (couplings / "broken.kcheck.yaml").write_text(SCENE.replace("magnitude: 1", "magnitude: lots"))
    assert (couplings / "broken.kcheck.yaml").read_text().splitlines()[BROKEN_LINE - 1] == (
        "  magnitude: lots"
    )
    (repo / "pyproject.toml").write_text(textwrap.dedent(PYPROJECT).lstrip())
    git(repo, "init", "-q")
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "couplings")
    return repo


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    repo = make_repository(tmp_path)
    monkeypatch.chdir(repo)
    return repo


def test_exit_codes(repo, cli):
    c = "couplings/"
    assert cli("check")[0] == 2  # configuration `paths`: every scene, one is broken
    assert cli("check", c + "pass", c + "warn.kcheck.yaml")[0] == 0  # a warning passes...
    assert cli("check", c + "pass", c + "warn.kcheck.yaml", "--strict")[0] == 1  # ...unless strict
    assert cli("check", c + "fail.kcheck.yaml", c + "warn.kcheck.yaml")[0] == 1
    assert cli("check", c + "pass/block.kcheck.yaml")[0] == 0


def test_every_format_in_one_run(repo, cli):
    out = repo / "reports"
    formats = ("junit", "sarif", "github", "markdown", "concise")
    args = [f"--output-format={f}:{out / f}" for f in formats]
    code, stdout, stderr = cli("check", "--format", "json", *args)
    assert code == 2 and "Traceback" not in stderr
    doc = json.loads(stdout)
    status = {Path(s["path"]).name: s["status"] for s in doc["scenes"]}
    assert status == {
        "broken.kcheck.yaml": "error",
        "fail.kcheck.yaml": "fail",
        "block.kcheck.yaml": "pass",
        "warn.kcheck.yaml": "warn",
    }
    broken = "couplings/broken.kcheck.yaml"

    concise = (out / "concise").read_text().splitlines()
    where = f"{broken}:{BROKEN_LINE}:{BROKEN_COLUMN}"
    assert (
        f"{where}: input-error: field `load.magnitude`: expected a number, got 'lots'"
        in (concise[0])
    )
    # each failing finding at the line of its support or field
    assert any(re.match(r"couplings/fail.kcheck.yaml:\d+: analytical-2d: ", x) for x in concise)
    assert re.search(r"couplings/warn.kcheck.yaml:\d+: maxwell \(warning\): ", "\n".join(concise))
    assert concise[-1] == "4 scenes: 1 passed, 1 with warnings, 1 failed, 1 with errors"

    github = (out / "github").read_text()
    assert (
        f"::error file={broken},line={BROKEN_LINE},col={BROKEN_COLUMN},title=kcheck (input-error)::"
        in github
    )
    fail_at = r"::error file=couplings/fail.kcheck.yaml,line=\d+,title=kcheck \(analytical-2d/"
    assert re.search(fail_at, github)
    # maxwell's finding code is the check's id: the rule is `maxwell`, not `maxwell/maxwell`
    warn_at = r"::warning file=couplings/warn.kcheck.yaml,line=\d+,title=kcheck \(maxwell\)::"
    assert re.search(warn_at, github)

    markdown = (out / "markdown").read_text()
    assert markdown.startswith("## ❌ kcheck failed")
    assert (
        f"- `{broken}:{BROKEN_LINE}:{BROKEN_COLUMN}` **input-error**: field \\`load.magnitude\\`"
        in markdown
    )
    assert "| `couplings/warn.kcheck.yaml` planar block (methods.md §7) | ⚠️ warn |" in markdown

    from junitparser import Error, Failure, JUnitXml

    suites = {s.name: s for s in JUnitXml.fromfile(str(out / "junit"))}
    (input_case,) = suites[broken]
    assert isinstance(input_case.result[0], Error)
    assert input_case._elem.get("line") == str(BROKEN_LINE)
    assert (
        f"{broken}:{BROKEN_LINE}:{BROKEN_COLUMN}: field `load.magnitude`"
        in input_case.result[0].text
    )
    failing = {c.name: c for c in suites["couplings/fail.kcheck.yaml"]}
    assert isinstance(failing["analytical-2d"].result[0], Failure)
    warn = {c.name: c for c in suites["couplings/warn.kcheck.yaml"]}
    assert warn["maxwell"].is_passed and "warning:" in warn["maxwell"].system_out

    sarif = json.loads((out / "sarif").read_text())
    validate_sarif(sarif)
    results = sarif["runs"][0]["results"]
    located = {
        (
            r["ruleId"].split("/")[0],
            r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"],
        ): r
        for r in results
    }
    region = located[("input-error", broken)]["locations"][0]["physicalLocation"]["region"]
    assert region == {"startLine": BROKEN_LINE, "startColumn": BROKEN_COLUMN}
    assert located[("maxwell", "couplings/warn.kcheck.yaml")]["level"] == "warning"
    assert located[("analytical-2d", "couplings/fail.kcheck.yaml")]["level"] == "error"
    # a check's finding is located at its support's line, under a rule per kind of finding
    rule_ids = {r["ruleId"] for r in results}
    assert any(rule.startswith("analytical-2d/") for rule in rule_ids)
    assert sarif["runs"][0]["invocations"][0]["executionSuccessful"] is False


def test_configuration_honoured_and_overridden(repo, cli):
    warn = "couplings/warn.kcheck.yaml"
    # maxwell is a warning by configuration: the scene warns, the run passes
    code, out, _ = cli("check", warn, "--format", "concise")
    assert code == 0 and "maxwell (warning)" in out
    # configuration fail_on, and the command line over it
    pyproject = repo / "pyproject.toml"
    pyproject.write_text(pyproject.read_text().replace("jobs = 2", 'jobs = 2\nfail_on = "warning"'))
    assert cli("check", warn)[0] == 1
    assert cli("check", warn, "--fail-on", "error")[0] == 0
    # ignore from the command line: the failing checks do not run
    code, out, _ = cli(
        "check", "couplings/fail.kcheck.yaml", "--ignore", "analytical-2d,graphical-2d",
        "--format", "concise",
    )  # fmt: skip
    assert code == 0, out
    code, out, _ = cli("config")
    assert re.search(r"^fail_on\s+\"warning\"\s+.*pyproject.toml$", out, re.M)


@pytest.mark.skipif(not kcheck.gate.pool.available(), reason="worker processes need fork")
def test_jobs_2_equals_jobs_1(repo, cli):
    outputs = []
    for jobs in ("1", "2"):
        code, out, _ = cli("check", "--format", "json", "--jobs", jobs)
        outputs.append((code, re.sub(r'"runtime_s": [0-9.e-]+', "", out)))
    assert outputs[0] == outputs[1] and outputs[0][0] == 2


def test_a_mesh_checks_the_scenes_that_use_it(repo, cli):
    code, out, _ = cli("check", "couplings/pass/block.stl", "--format", "json")
    assert code == 0
    assert [s["path"] for s in json.loads(out)["scenes"]] == ["couplings/pass/block.kcheck.yaml"]


def test_changed_only_and_since(repo, cli):
    import trimesh

    def checked(*args: str) -> list[str]:
        code, out, err = cli("check", "--format", "json", *args)
        assert code in (0, 1, 2), err
        return sorted(s["path"] for s in json.loads(out)["scenes"])

    assert checked("--changed-only") == []  # nothing changed since the commit
    trimesh.creation.box(extents=(100.0, 60.0, 30.0)).export(repo / "couplings/pass/block.stl")
    (repo / "couplings" / "new.kcheck.yaml").write_text(SCENE)  # untracked
    assert checked("--changed-only") == [
        "couplings/new.kcheck.yaml",
        "couplings/pass/block.kcheck.yaml",
    ]
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "taller block")
    assert checked("--changed-only") == []
    assert checked("--since", "HEAD~1") == [
        "couplings/new.kcheck.yaml",
        "couplings/pass/block.kcheck.yaml",
    ]
    code, _, err = cli("check", "--since", "no-such-ref")
    assert code == 2 and "`no-such-ref` is not a commit of this git repository" in err


def test_changed_only_outside_a_repository(cli, tmp_path, monkeypatch):
    # kcheck says what is wrong; git's own message (its wording is git's) only follows.
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path.parent))
    code, out, err = cli("check", "--changed-only")
    assert code == 2 and out == ""
    assert err.startswith(
        "kcheck: error: --changed-only/--since need the working directory in a git repository git "
        "can read"
    )
