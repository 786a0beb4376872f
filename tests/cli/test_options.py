"""Options users of ruff and mypy expect (issue 23): --exit-zero, --statistics, the GitLab
Code Quality format, and `--output-format FORMAT:-` writing to standard output."""

from __future__ import annotations

import json
import os
import re

from tests.conftest import PLANAR_SCENE
from tests.kcheck.test_report_formats import validate_sarif

FAILING = PLANAR_SCENE.replace("angle: 225", "angle: 45")
BROKEN = PLANAR_SCENE.replace("magnitude: 1", "magnitude: lots")


def test_exit_zero(cli, write_scene):
    failing = str(write_scene(FAILING, "fail.kcheck.yaml"))
    assert cli("check", failing)[0] == 1
    assert cli("check", failing, "--exit-zero")[0] == 0
    broken = str(write_scene(BROKEN, "broken.kcheck.yaml"))
    assert cli("check", broken, failing, "--exit-zero")[0] == 2  # bad input still is


def test_statistics(cli, write_scene):
    failing = str(write_scene(FAILING, "fail.kcheck.yaml"))
    broken = str(write_scene(BROKEN, "broken.kcheck.yaml"))
    code, out, err = cli("check", failing, broken, "--statistics", "--format", "concise")
    lines = [x for x in err.splitlines() if re.match(r"^\s*\d+  \S+$", x)]
    counts = {x.split()[1]: int(x.split()[0]) for x in lines}
    assert code == 2 and counts["input-error"] == 1
    concise_rules = re.findall(r": (analytical-2d|graphical-2d): ", out)
    assert sum(n for r, n in counts.items() if r.startswith("analytical-2d")) == (
        concise_rules.count("analytical-2d")
    )
    assert [int(x.split()[0]) for x in lines] == sorted((int(x.split()[0]) for x in lines),
                                                        reverse=True)  # fmt: skip
    assert "input-error" not in cli("check", failing)[2]  # only when asked for


def test_gitlab_code_quality(cli, write_scene):
    failing = str(write_scene(FAILING, "fail.kcheck.yaml"))
    broken = str(write_scene(BROKEN, "broken.kcheck.yaml"))
    code, out, _ = cli("check", failing, broken, "--format", "gitlab")
    entries = json.loads(out)
    assert code == 2 and entries
    for entry in entries:
        assert set(entry) == {"description", "check_name", "fingerprint", "severity", "location"}
        assert entry["severity"] in ("info", "minor", "major", "critical", "blocker")
        assert isinstance(entry["location"]["lines"]["begin"], int)
        assert entry["location"]["path"].endswith(".kcheck.yaml")
    assert len({e["fingerprint"] for e in entries}) == len(entries)
    by_rule = {e["check_name"]: e for e in entries}
    assert by_rule["input-error"]["severity"] == "blocker"
    assert by_rule["input-error"]["location"]["lines"]["begin"] == 14
    assert json.loads(cli("check", failing, broken, "--format", "gitlab")[1]) == entries


def test_a_report_to_standard_output(cli, write_scene, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    failing = str(write_scene(FAILING, "fail.kcheck.yaml"))
    code, out, _ = cli("check", failing, "--output-format", "sarif:-")
    assert code == 1 and not os.path.exists(tmp_path / "-")
    validate_sarif(json.loads(out))  # standard output holds the SARIF log alone
    code, out, _ = cli("check", failing, "--output-format", "sarif:-", "--output", "report.txt")
    validate_sarif(json.loads(out))
    assert "fail.kcheck.yaml" in (tmp_path / "report.txt").read_text()
    code, out, err = cli("check", failing, "--output-format", "sarif:-",
                         "--output-format", "junit:-")  # fmt: skip
    assert code == 2 and "only one report can go to standard output" in err
