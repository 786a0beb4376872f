"""Files found as users of ruff expect (issue 23): one cache default (platformdirs) said alike
by --help, `kcheck config` and the docs; mesh names matched in any case; .gitignore honoured;
`exclude` and `extend-exclude` as in ruff."""

from __future__ import annotations

import json
import shutil
import textwrap
from pathlib import Path

import pytest

from tests.cli.test_end_to_end import git
from tests.conftest import FIXTURES, PLANAR_SCENE, ROOT

SCENE = textwrap.dedent(PLANAR_SCENE).lstrip()
BROKEN = SCENE.replace("magnitude: 1", "magnitude: lots")


def checked(cli, *args: str) -> tuple[int, list[str]]:
    code, out, err = cli("check", "--format", "json", *args)
    assert "Traceback" not in err
    return code, sorted(s["path"] for s in json.loads(out)["scenes"])


def test_one_cache_default_in_help_config_and_docs(cli, monkeypatch, tmp_path):
    import platformdirs

    monkeypatch.delenv("KCHECK_CACHE_DIR")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "kcheck.toml").write_text("jobs = 1\n")  # a configuration file changes nothing
    expected = platformdirs.user_cache_dir("kcheck", appauthor=False)
    code, out, _ = cli("config", "--json")
    assert code == 0 and json.loads(out)["values"]["cache_dir"] is None
    code, out, _ = cli("config")
    assert f"(default: {expected})" in out
    code, help_text, _ = cli("check", "--help")
    flat = " ".join(help_text.split())
    assert "user cache folder found by platformdirs: ~/.cache/kcheck on Linux" in flat
    assert ".kcheck_cache" not in flat
    docs = " ".join((ROOT / "docs/ci.md").read_text().split())
    assert "the user cache folder found by platformdirs (`~/.cache/kcheck` on Linux" in docs


def test_mesh_names_in_any_case(cli, tmp_path, monkeypatch):
    folder = tmp_path / "parts"
    shutil.copytree(FIXTURES / "planar-block", folder)
    (folder / "block.stl").rename(folder / "BLOCK.STL")
    scene = folder / "block.kcheck.yaml"
    scene.write_text(scene.read_text().replace("block.stl", "BLOCK.STL"))
    monkeypatch.chdir(tmp_path)
    assert checked(cli, "parts/BLOCK.STL") == (0, ["parts/block.kcheck.yaml"])
    hook = (ROOT / ".pre-commit-hooks.yaml").read_text()
    assert "files: '(?i)" in hook  # the hook matches meshes in any case too


@pytest.fixture
def tree(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """good.kcheck.yaml, and broken scenes in places a search should pass over."""
    for name, text in {
        "good.kcheck.yaml": SCENE,
        "build/out.kcheck.yaml": BROKEN,
        "scratch.tmp.kcheck.yaml": BROKEN,
        "drafts/draft.kcheck.yaml": BROKEN,
        ".hidden/h.kcheck.yaml": BROKEN,
    }.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_gitignore_is_honoured_in_a_repository(cli, tree):
    (tree / ".gitignore").write_text("build/\n*.tmp.kcheck.yaml\n")
    (tree / "kcheck.toml").write_text('extend-exclude = ["drafts/"]\n')
    assert checked(cli) == (2, ["build/out.kcheck.yaml", "good.kcheck.yaml",
                                "scratch.tmp.kcheck.yaml"])  # fmt: skip  # no repository yet
    git(tree, "init", "-q")
    assert checked(cli) == (0, ["good.kcheck.yaml"])
    # a tracked file is never ignored (git's rule); a file given explicitly is checked
    git(tree, "add", "-f", "build/out.kcheck.yaml")
    assert checked(cli) == (2, ["build/out.kcheck.yaml", "good.kcheck.yaml"])
    assert checked(cli, "scratch.tmp.kcheck.yaml")[0] == 2
    (tree / "kcheck.toml").write_text('extend-exclude = ["drafts/"]\nrespect-gitignore = false\n')
    assert checked(cli)[1] == ["build/out.kcheck.yaml", "good.kcheck.yaml",
                               "scratch.tmp.kcheck.yaml"]  # fmt: skip


def test_exclude_and_extend_exclude_as_in_ruff(cli, tree):
    # the default passes over hidden folders, node_modules and __pycache__
    assert "drafts/draft.kcheck.yaml" in checked(cli)[1]
    assert ".hidden/h.kcheck.yaml" not in checked(cli)[1]
    # extend-exclude adds to the default
    (tree / "kcheck.toml").write_text(
        'extend-exclude = ["drafts/", "build", "*.tmp.kcheck.yaml"]\n'
    )
    assert checked(cli) == (0, ["good.kcheck.yaml"])
    # exclude replaces it: the hidden folder is searched again
    (tree / "kcheck.toml").write_text('exclude = ["drafts/", "build/", "/scratch.*"]\n')
    assert checked(cli)[1] == [".hidden/h.kcheck.yaml", "good.kcheck.yaml"]
    # a file given explicitly is checked whatever the patterns; --pre-commit excludes it
    # (as ruff's --force-exclude), for the full run would not check it
    assert checked(cli, "drafts/draft.kcheck.yaml") == (2, ["drafts/draft.kcheck.yaml"])
    git(tree, "init", "-q")
    git(tree, "add", "-A")
    git(tree, "commit", "-qm", "tree")
    assert checked(cli, "--pre-commit", "drafts/draft.kcheck.yaml") == (0, [])
    # a pattern of the wrong type is a located configuration error
    (tree / "kcheck.toml").write_text("exclude = [1]\n")
    code, _, err = cli("check")
    assert code == 2 and "kcheck.toml: `exclude`: expected a list of strings" in err
