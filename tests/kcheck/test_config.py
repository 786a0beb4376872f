"""Configuration files: where they are found, what they may say, how they are overridden."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from kcheck.gate.config import ConfigError, find_config, load_config
from tests.conftest import PLANAR_SCENE


@pytest.fixture
def project(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A repository root with a nested working directory."""
    (tmp_path / "repo" / ".git").mkdir(parents=True)
    work = tmp_path / "repo" / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    return tmp_path / "repo"


def test_found_upwards_kcheck_toml_first_and_pyproject_only_with_table(project):
    (project / "pyproject.toml").write_text("[tool.kcheck]\njobs = 3\n")
    (project / "a" / "pyproject.toml").write_text('[project]\nname = "x"\n')  # no table: skipped
    path, table = find_config()
    assert path == project / "pyproject.toml" and table == {"jobs": 3}
    (project / "a" / "kcheck.toml").write_text("jobs = 4\n")
    (project / "a" / "pyproject.toml").write_text("[tool.kcheck]\njobs = 5\n")
    path, table = find_config()
    assert path == project / "a" / "kcheck.toml" and table == {"jobs": 4}


def test_search_stops_at_the_repository_root(project):
    (project.parent / "kcheck.toml").write_text("jobs = 7\n")  # outside the repository
    assert find_config() is None
    config = load_config()
    assert config.file is None and config["jobs"] == 0 and config.sources["jobs"] == "default"


def test_relative_paths_are_relative_to_the_file(project):
    (project / "kcheck.toml").write_text(
        'paths = ["scenes"]\ncache_dir = "cache"\noutput_format = ["sarif:out/k.sarif"]\n'
    )
    config = load_config()
    assert config["paths"] == (str(project / "scenes"),)
    assert config["cache_dir"] == str(project / "cache")
    assert config["output_format"] == (f"sarif:{project / 'out/k.sarif'}",)
    assert config.sources["paths"] == str(project / "kcheck.toml")


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("jbos = 2", "unknown key `jbos` (did you mean `jobs`?)"),
        ('jobs = "many"', "`jobs`: expected a whole number of worker processes"),
        ("jobs = -1", "`jobs`: expected a whole number"),
        ('fail_on = "warn"', '`fail_on`: expected "error" or "warning", got \'warn\''),
        ("select = []", "`select`: expected a non-empty list of check ids"),
        ('select = "maxwell"', None),  # one id as a string is fine
        ("timeout = 0", "`timeout`: expected a positive number (seconds)"),
        ("timeout = inf", "`timeout`: expected a finite positive number"),
        # Fuzz finding cli-4245-465: a budget below the worker's own size (1 MiB) let light
        # scenes pass and stalled others until their time budget (200 MiB did).
        ("memory_limit = 200", "`memory_limit`: expected at least 512 MiB"),
        ('output_format = ["sarif"]', '`output_format`: expected a list of "FORMAT:FILE"'),
        ("cache = 1", "`cache`: expected true or false"),
        ("checks = 3", "`checks`: expected a table per check id"),
        ("[tool", "not valid TOML"),
    ],
)
def test_bad_values_name_file_key_and_expectation(project, text, expected):
    (project / "kcheck.toml").write_text(text + "\n")
    if expected is None:
        assert load_config()["select"] == ("maxwell",)
        return
    with pytest.raises(ConfigError) as info:
        load_config()
    assert str(project / "kcheck.toml") in str(info.value) and expected in str(info.value)


def test_explicit_and_isolated(project, tmp_path):
    (project / "kcheck.toml").write_text("jobs = 3\n")
    other = tmp_path / "other.toml"
    other.write_text("jobs = 5\n")
    assert load_config(other)["jobs"] == 5
    assert load_config(isolated=True)["jobs"] == 0
    py = tmp_path / "pyproject.toml"
    py.write_text("[project]\n")
    with pytest.raises(ConfigError, match="no \\[tool.kcheck\\] table"):
        load_config(py)


def test_kcheck_config_shows_values_and_origins(project, cli):
    (project / "pyproject.toml").write_text(
        '[tool.kcheck]\njobs = 3\nfail_on = "warning"\n'
        '[tool.kcheck.checks.maxwell]\nseverity = "warning"\nmin_cos = 0.8\n'
    )
    code, out, _ = cli("config", "--json", "--jobs", "1", "--select", "maxwell")
    doc = json.loads(out)
    assert code == 0 and doc["file"] == str(project / "pyproject.toml")
    assert doc["values"]["jobs"] == 1 and doc["sources"]["jobs"] == "command line"
    assert doc["values"]["fail_on"] == "warning"
    assert doc["sources"]["fail_on"] == str(project / "pyproject.toml")
    assert doc["sources"]["timeout"] == "default"
    assert doc["checks"] == {"maxwell": {"severity": "warning", "min_cos": 0.8}}
    code, out, _ = cli("config")
    assert code == 0
    line = next(x for x in out.splitlines() if x.startswith("checks.maxwell.min_cos"))
    assert "0.8" in line and line.endswith(str(project / "pyproject.toml"))
    jobs = next(x for x in out.splitlines() if x.startswith("jobs"))
    assert jobs.split() == ["jobs", "3", str(project / "pyproject.toml")]


def test_config_options_are_defaults_under_the_scene(project, cli_json, write_scene):
    # maxwell's min_cos from configuration applies unless the scene sets its own: the
    # planar block's worst cos is 0.894 (methods.md §7 layout), so 0.95 fails it, 0.5 passes.
    (project / "kcheck.toml").write_text("[checks.maxwell]\nmin_cos = 0.95\n")
    plain = write_scene(PLANAR_SCENE, "plain.kcheck.yaml")
    own = write_scene(PLANAR_SCENE + "checks:\n  maxwell: {min_cos: 0.5}\n", "own.kcheck.yaml")
    code, doc = cli_json(str(plain), str(own))
    status = {
        Path(s["path"]).name: {c["id"]: c["status"] for c in s["checks"]} for s in doc["scenes"]
    }
    assert status["plain.kcheck.yaml"]["maxwell"] == "fail"
    assert status["own.kcheck.yaml"]["maxwell"] == "pass"
    assert code == 0  # maxwell's severity is `warning`: a failure alone does not fail the run


def test_severity_from_configuration_and_strict(project, cli, write_scene):
    (project / "kcheck.toml").write_text('[checks.maxwell]\nmin_cos = 0.95\nseverity = "warning"\n')
    path = str(write_scene(PLANAR_SCENE))
    code, out, _ = cli("check", path, "--format", "concise")
    assert code == 0 and "maxwell (warning)" in out and "1 with warnings" in out
    assert cli("check", path, "--strict")[0] == 1
    assert cli("check", path, "--fail-on", "warning")[0] == 1
    (project / "kcheck.toml").write_text(
        'fail_on = "warning"\n[checks.maxwell]\nmin_cos = 0.95\nseverity = "warning"\n'
    )
    assert cli("check", path)[0] == 1
    assert cli("check", path, "--fail-on", "error")[0] == 0  # the command line wins
    assert cli("check", path, "--isolated")[0] == 0  # no min_cos 0.95: passes


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        ("[checks.maxwel]\nmin_cos = 0.5\n", "unknown check `maxwel` (did you mean `maxwell`?)"),
        ("[checks.maxwell]\nmin_cos = 2\n", "`checks.maxwell.min_cos`:"),
        ("[checks.maxwell]\nmin_coss = 0.5\n", "`checks.maxwell.min_coss`: unknown field"),
        ('[checks.maxwell]\nseverity = "fatal"\n', '`checks.maxwell.severity`: expected "error"'),
        ('select = ["maxwell"]\nignore = ["maxwell"]\n', "no check left to run"),
        ('ignore = ["nope"]\n', "`ignore`: unknown check `nope`"),
    ],
)
def test_check_tables_validated_against_installed_checks(project, cli, table, expected):
    (project / "kcheck.toml").write_text(table)
    code, _, err = cli("check", ".")
    assert code == 2 and expected in err, err


@pytest.mark.parametrize("target", ["/dev/zero", "pipe"])
def test_a_device_or_pipe_as_configuration_is_refused_at_once(project, target):
    # Fuzz finding (issue 13): `--config /dev/zero` read until 23 GB of memory were taken,
    # and `--config pipe` waited forever for a writer.
    import os

    if target == "pipe":
        os.mkfifo(project / "pipe")
        target = str(project / "pipe")
    with pytest.raises(ConfigError) as info:
        load_config(Path(target))
    assert "not a regular file" in str(info.value)


def test_configuration_that_is_not_utf8(project):
    (project / "kcheck.toml").write_bytes("select = ['maxwell']  # Größe\n".encode("latin-1"))
    with pytest.raises(ConfigError) as info:
        load_config()
    assert "not UTF-8" in str(info.value)


def test_kcheck_config_refuses_an_unknown_format(project, cli):
    # Fuzz finding (issue 13): `kcheck config --format nope` showed the value and exited 0,
    # where `kcheck check` refuses it.
    code, _, err = cli("config", "--format", "jsn")
    assert code == 2 and "unknown format `jsn` (did you mean `json`?)" in err
    (project / "kcheck.toml").write_text('format = "nope"\n')
    code, _, err = cli("config")
    assert code == 2 and "kcheck.toml: `format`: unknown format `nope`" in err


@pytest.mark.parametrize(
    ("xdg", "home", "expected"),
    [
        (None, "/home/someone", "/home/someone/.cache/kcheck"),
        # Empty counts as unset (XDG Base Directory Specification); platformdirs 2.0 answered
        # a relative "kcheck" here, later versions the spec's folder.
        ("", "/home/someone", "/home/someone/.cache/kcheck"),
        ("/var/tmp/xdg-cache", "/home/someone", "/var/tmp/xdg-cache/kcheck"),
        ("/var/tmp/xdg-cache/", None, "/var/tmp/xdg-cache/kcheck"),
        ("relative/cache", "/home/someone", None),  # platformdirs decides (4.x: ignored)
        (None, None, None),  # no HOME: platformdirs decides
    ],
)
def test_default_cache_folder_follows_the_xdg_specification(
    monkeypatch: pytest.MonkeyPatch, xdg: str | None, home: str | None, expected: str | None
) -> None:
    # Issue 24: the common Linux cases are answered without importing platformdirs, as the
    # XDG Base Directory Specification says ($XDG_CACHE_HOME when absolute, else
    # $HOME/.cache); anything else is platformdirs' own answer.
    import platformdirs

    from kcheck.gate.config import user_cache_dir

    monkeypatch.delenv("KCHECK_CACHE_DIR", raising=False)
    for name, value in (("XDG_CACHE_HOME", xdg), ("HOME", home)):
        if value is None:
            monkeypatch.delenv(name, raising=False)
        else:
            monkeypatch.setenv(name, value)
    if sys.platform != "linux":
        expected = None
    if expected is None:
        expected = platformdirs.user_cache_dir("kcheck", appauthor=False)
    assert user_cache_dir() == Path(expected)
