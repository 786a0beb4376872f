"""Check discovery through entry points: built-ins and a real third-party distribution."""

from __future__ import annotations

import importlib.metadata
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from kcheck.errors import PluginError
from kcheck.plugin import CheckSpec, find_checks, load_checks
from tests.conftest import PLANAR_SCENE, ROOT

BUILTIN = {"maxwell", "analytical-2d", "analytical-3d"}


def test_builtins_come_through_entry_points():
    names = {s.name for s in find_checks()}
    assert BUILTIN <= names
    for spec in find_checks():
        if spec.name in BUILTIN:
            assert spec.package == "kcheck"
            assert spec.entry_point.group == "kcheck.checks"


def _spec(name: str, value: str, package: str = "other") -> CheckSpec:
    ep = importlib.metadata.EntryPoint(name, value, "kcheck.checks")
    return CheckSpec(package, "1.0", ep)


def test_duplicate_ids_name_both_distributions():
    specs = [
        _spec("maxwell", "kcheck_checks.maxwell:Maxwell", "kcheck"),
        _spec("maxwell", "kcheck_checks.maxwell:Maxwell", "imposter"),
    ]
    with pytest.raises(PluginError, match=r"kcheck\[maxwell\] and imposter\[maxwell\]"):
        load_checks(specs)


@pytest.mark.parametrize(
    ("value", "fragment"),
    [
        ("no_such_module:Thing", "cannot load check plugin other[x]"),
        ("kcheck.result:Status", "not a kcheck.plugin.Check subclass"),
        ("kcheck_checks.maxwell:Maxwell", "has id `maxwell` but is registered as `x`"),
    ],
)
def test_broken_plugins_are_named(value, fragment):
    with pytest.raises(PluginError, match=fragment.replace("[", r"\[").replace("]", r"\]")):
        load_checks([_spec("x", value)])


def test_broken_plugin_is_exit_2_not_a_traceback(tmp_path, write_scene):
    # A distribution on sys.path whose entry point cannot be imported.
    dist = tmp_path / "site" / "broken-1.0.dist-info"
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: broken\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text("[kcheck.checks]\nbroken = nowhere:Nothing\n")
    scene = write_scene(PLANAR_SCENE)
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "site")}
    proc = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(scene)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert proc.returncode == 2
    assert "cannot load check plugin broken[broken]" in proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.fixture(scope="module")
def installed_example(tmp_path_factory) -> Path:
    """Install tests/example_plugin with pip into a private target folder."""
    work = tmp_path_factory.mktemp("example")
    source = work / "src"
    shutil.copytree(ROOT / "tests" / "example_plugin", source)
    target = work / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--no-build-isolation",
            "--target",
            str(target),
            str(source),
        ],
        check=True,
    )
    return target


def test_third_party_check_is_listed_and_run(installed_example, write_scene):
    env = {**os.environ, "PYTHONPATH": str(installed_example), "NO_COLOR": "1"}
    listing = subprocess.run(
        [sys.executable, "-m", "kcheck", "plugins"],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    ).stdout
    assert "friction-ceiling  (kcheck-example 1.0)" in listing
    assert "maxwell" in listing

    scene = write_scene(PLANAR_SCENE + "checks:\n  friction-ceiling: {max_mu: 0.05}\n")
    proc = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(scene), "--format", "json"],
        capture_output=True,
        text=True,
        env=env,
    )
    doc = json.loads(proc.stdout)
    checks = {c["id"]: c for c in doc["scenes"][0]["checks"]}
    assert checks["friction-ceiling"]["status"] == "fail"  # mu = 0.1 > 0.05
    assert [c["outcome"] for c in checks["friction-ceiling"]["cases"]] == ["too_high"] * 3
    assert checks["maxwell"]["status"] == "pass"
    assert proc.returncode == 1


def test_entry_points_read_from_folders_equal_importlib_metadata():
    """kcheck.plugin.dist_info reads the metadata folders itself (sparing the start-up the import
    of importlib.metadata); the reference is importlib.metadata's own answer, taken by
    forcing the fallback: the same checks, packages, versions and targets. In a fresh
    interpreter: a package imported by another test (importlib_metadata, which Dask brings)
    may replace the standard finder, and then only the fallback can say."""
    code = (
        "import json, kcheck.plugin as p, kcheck.plugin.dist_info as d\n"
        "assert d.distributions() is not None  # this environment: the direct reading\n"
        "def listed():\n"
        "    return [[s.name, s.package, s.version, s.entry_point.value]"
        " for s in p.find_checks()]\n"
        "direct = listed()\n"
        "d.distributions = p.distributions = lambda: None\n"
        "print(json.dumps([direct, listed()]))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    direct, fallback = json.loads(done.stdout)
    assert direct == fallback and len(direct) >= 7
    import kcheck.plugin.dist_info as dists

    for name in ("trimesh", "numpy", "pydantic", "kcheck"):
        assert dists.version(name) == importlib.metadata.version(name)
    assert dists.version("no-such-distribution-here") is None


def test_entry_point_loads_like_importlib_metadata():
    from kcheck.plugin.dist_info import EntryPoint

    ep = EntryPoint("maxwell", "kcheck_checks.maxwell:Maxwell", "kcheck.checks")
    reference = importlib.metadata.EntryPoint("maxwell", ep.value, "kcheck.checks")
    assert ep.load() is reference.load()
    assert (
        EntryPoint("x", "os.path", "g").load()
        is importlib.metadata.EntryPoint("x", "os.path", "g").load()
    )
