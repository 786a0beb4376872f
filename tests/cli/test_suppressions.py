"""Accepted failures and a scene on standard input (issue 23, point 7): inline suppressions
with a required reason, per-path ignores, the baseline file, `kcheck check -`."""

from __future__ import annotations

import io
import json
import shutil
import sys

import pytest

from tests.conftest import FIXTURES, PLANAR_SCENE
from tests.kcheck.test_report_formats import validate_sarif

FAILING = PLANAR_SCENE.replace("angle: 225", "angle: 45")
SERVICE = "  # kcheck: ignore[analytical-2d] -- retracted only in service"


def _lines(text: str) -> list[str]:
    import textwrap

    return textwrap.dedent(text).lstrip().splitlines()


def _suppressed_scene() -> str:
    """The failing planar scene: graphical-2d suppressed for the whole scene (a comment at the
    top), analytical-2d on each line it fails on."""
    lines = _lines(FAILING)
    out = ["# kcheck: ignore[graphical-2d] -- advisory for this part"]
    for line in lines:
        located = line.lstrip().startswith("- {name:") or line.strip().startswith("angle:")
        out.append(line + (SERVICE if located else ""))
    return "\n".join(out) + "\n"


def _json(cli, *args):
    code, out, err = cli("check", "--isolated", "--format", "json", *args)
    return code, json.loads(out), err


def _check(doc, check_id, scene=0):
    return next(c for c in doc["scenes"][scene]["checks"] if c["id"] == check_id)


def test_inline_suppressions_accept_failures_and_say_why(cli, write_scene):
    failing = str(write_scene(FAILING, "fail.kcheck.yaml"))
    assert cli("check", "--isolated", failing)[0] == 1
    path = str(write_scene(_suppressed_scene(), "sup.kcheck.yaml"))
    code, doc, _ = _json(cli, path)
    assert code == 0
    scene = doc["scenes"][0]
    assert scene["status"] == "pass"
    analytical = _check(doc, "analytical-2d")
    assert analytical["status"] == "pass" and "findings" not in analytical
    reasons = {f["suppressed"] for f in analytical["suppressed"]}
    assert reasons == {"retracted only in service"}
    assert {f["line"] for f in analytical["suppressed"]} == {10, 11, 12, 16}
    graphical = _check(doc, "graphical-2d")
    assert len(graphical["suppressed"]) == 3
    assert {f["suppressed"] for f in graphical["suppressed"]} == {"advisory for this part"}
    # The text report shows each suppressed failure with its reason.
    code, out, _ = cli("check", "--isolated", path)
    assert code == 0
    assert out.count("suppressed analytical-2d: retract") == 3
    assert out.count("suppressed graphical-2d: retract") == 3
    assert "— retracted only in service" in out and "— advisory for this part" in out
    # SARIF: the results are there, with suppressions and their justification.
    code, out, _ = cli("check", "--isolated", "--format", "sarif", path)
    sarif = json.loads(out)
    validate_sarif(sarif)
    results = sarif["runs"][0]["results"]
    assert len(results) == 7
    assert all(r["suppressions"][0]["kind"] == "inSource" for r in results)
    assert {r["suppressions"][0]["justification"] for r in results} == {
        "retracted only in service",
        "advisory for this part",
    }
    # Line formats leave suppressed failures out.
    code, out, _ = cli("check", "--isolated", "--format", "concise", path)
    assert "analytical-2d" not in out and "graphical-2d" not in out


def test_a_suppression_covers_only_its_line_and_its_check(cli, write_scene):
    lines = _lines(FAILING)
    y1 = next(k for k, line in enumerate(lines) if "name: y1" in line)
    lines[y1] += "  # kcheck: ignore[analytical-2d/opens-loses-contact] -- y1 is pinned"
    path = str(write_scene("\n".join(lines) + "\n", "one.kcheck.yaml"))
    code, doc, _ = _json(cli, path)
    assert code == 1
    analytical = _check(doc, "analytical-2d")
    assert analytical["status"] == "fail"
    assert [f["line"] for f in analytical["suppressed"]] == [y1 + 1]
    assert y1 + 1 not in {f["line"] for f in analytical["findings"]}
    assert len(analytical["findings"]) == 3
    assert "suppressed" not in _check(doc, "graphical-2d")  # another check: not covered


def test_an_own_line_suppression_covers_the_next_field(cli, write_scene):
    lines = _lines(FAILING)
    angle = next(k for k, line in enumerate(lines) if line.strip().startswith("angle:"))
    lines.insert(angle, "  # kcheck: ignore[analytical-2d/design-outside] -- load is nominal")
    path = str(write_scene("\n".join(lines) + "\n", "own.kcheck.yaml"))
    code, doc, _ = _json(cli, path)
    suppressed = _check(doc, "analytical-2d")["suppressed"]
    assert [(f["line"], f["suppressed"]) for f in suppressed] == [(angle + 2, "load is nominal")]


@pytest.mark.parametrize(
    "comment, expected",
    [
        ("# kcheck: ignore[analytical-2d]", "gives no reason"),
        ("# kcheck: ignore[analytical-2d] --   ", "gives no reason"),
        ("# kcheck: ignore[] -- why", "names no check"),
        ("# kcheck: ignor[analytical-2d] -- why", "malformed kcheck comment"),
    ],
)
def test_a_suppression_without_a_reason_is_bad_input(cli, write_scene, comment, expected):
    lines = _lines(FAILING)
    lines[8] += "  " + comment
    path = str(write_scene("\n".join(lines) + "\n", "bad.kcheck.yaml"))
    code, doc, err = _json(cli, path)
    assert code == 2
    (error,) = doc["scenes"][0]["errors"]
    assert expected in error["message"]
    assert error["line"] == 9 and error["column"] == len(lines[8]) - len(comment) + 1
    assert doc["scenes"][0]["checks"] == []
    assert f"bad.kcheck.yaml:9:{error['column']}:" in err
    assert "Traceback" not in err


def test_an_unused_suppression_is_a_scene_warning(cli, write_scene):
    text = "# kcheck: ignore[maxwell] -- nothing to suppress\n" + "\n".join(_lines(PLANAR_SCENE))
    path = str(write_scene(text + "\n", "unused.kcheck.yaml"))
    code, doc, _ = _json(cli, path)
    assert code == 0
    (warning,) = doc["scenes"][0]["warnings"]
    assert warning["code"] == "unused-suppression" and warning["line"] == 1
    assert doc["scenes"][0]["status"] == "warn"
    assert cli("check", "--isolated", "--strict", path)[0] == 1  # as RUF100 with --strict
    code, out, _ = cli("check", "--isolated", "--format", "concise", path)
    assert "/unused.kcheck.yaml:1: scene-warning/unused-suppression (warning):" in out


def test_per_path_ignores(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "legacy").mkdir()
    (tmp_path / "legacy" / "old.kcheck.yaml").write_text("\n".join(_lines(FAILING)) + "\n")
    (tmp_path / "new.kcheck.yaml").write_text("\n".join(_lines(FAILING)) + "\n")
    (tmp_path / "pyproject.toml").write_text(
        '[tool.kcheck]\nper-path-ignores = {"legacy/**" = ["analytical-2d", "graphical-2d"]}\n'
    )
    code, out, _ = cli("check", "--format", "json", "legacy")
    assert code == 0
    doc = json.loads(out)
    reasons = {f["suppressed"] for f in _check(doc, "analytical-2d")["suppressed"]}
    assert reasons == {"per-path-ignores: 'legacy/**' ignores analytical-2d"}
    assert cli("check", "new.kcheck.yaml")[0] == 1  # not under legacy/
    code, out, _ = cli("check", "--format", "sarif", "legacy")
    kinds = {r["suppressions"][0]["kind"] for r in json.loads(out)["runs"][0]["results"]}
    assert kinds == {"external"}
    (tmp_path / "pyproject.toml").write_text('[tool.kcheck]\nper-path-ignores = ["legacy"]\n')
    code, _, err = cli("check", "legacy")
    assert code == 2 and "per-path-ignores" in err and "Traceback" not in err


def test_baseline_accepts_recorded_failures_and_fails_on_new_ones(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "part.kcheck.yaml"
    scene.write_text("\n".join(_lines(FAILING)) + "\n")
    code, _, err = cli("check", "--isolated", "part.kcheck.yaml", "--write-baseline", "b.json")
    assert code == 0 and "7 failures recorded in b.json" in err
    baseline = json.loads((tmp_path / "b.json").read_text())
    assert baseline["version"] == 1 and len(baseline["failures"]) == 7
    assert all("line" not in e for e in baseline["failures"])
    assert {e["path"] for e in baseline["failures"]} == {"part.kcheck.yaml"}
    assert {"path": "part.kcheck.yaml", "rule": "analytical-2d/design-outside",
            "field": "load.angle"} in baseline["failures"]  # fmt: skip
    code, doc, _ = _json(cli, "part.kcheck.yaml", "--baseline", "b.json")
    assert code == 0
    assert all(f["suppressed"] == "in the baseline b.json"
               for f in _check(doc, "analytical-2d")["suppressed"])  # fmt: skip
    # Lines moved: the entries still hold.
    scene.write_text("# a comment\n\n" + scene.read_text())
    assert cli("check", "--isolated", "part.kcheck.yaml", "--baseline", "b.json")[0] == 0
    # A new failing scene fails the run, and only its failures are reported.
    other = tmp_path / "other.kcheck.yaml"
    other.write_text("\n".join(_lines(FAILING)) + "\n")
    code, out, _ = cli(
        "check", "--isolated", "--format", "concise", ".", "--baseline", "b.json", "--jobs", "1"
    )
    assert code == 1
    assert "other.kcheck.yaml" in out and "part.kcheck.yaml:" not in out


def test_stale_baseline_entries_are_named_once(cli, tmp_path, monkeypatch):
    """A baseline entry no failure matches any more (the design was fixed) is warned about,
    once, with the count and which; entries of scenes or checks the run left out are not."""
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "part.kcheck.yaml"
    scene.write_text("\n".join(_lines(FAILING)) + "\n")
    other = tmp_path / "other.kcheck.yaml"
    other.write_text("\n".join(_lines(FAILING)) + "\n")
    code, _, err = cli("check", "--isolated", ".", "--write-baseline", "b.json", "--jobs", "1")
    recorded = json.loads((tmp_path / "b.json").read_text())["failures"]
    assert code == 0 and len(recorded) == 14
    # Nothing fixed: no warning.
    code, _, err = cli("check", "--isolated", ".", "--baseline", "b.json", "--jobs", "1")
    assert code == 0 and "baseline" not in err
    # part is fixed (the passing planar scene): its 7 entries are stale, other's are not.
    scene.write_text("\n".join(_lines(PLANAR_SCENE)) + "\n")
    code, _, err = cli("check", "--isolated", ".", "--baseline", "b.json", "--jobs", "1")
    assert code == 0
    warnings = [line for line in err.splitlines() if "baseline" in line]
    assert len(warnings) == 1, err
    stale = [e for e in recorded if e["path"] == "part.kcheck.yaml"]
    assert "7 baseline entries match no failure" in warnings[0]
    assert "part.kcheck.yaml analytical-2d/design-outside (load.angle)" in warnings[0]
    assert "and 2 more" in warnings[0] and "other.kcheck.yaml" not in warnings[0]
    assert "--write-baseline" in warnings[0] and len(stale) == 7
    # Only other checked, or only maxwell selected: part's entries are not judged.
    code, _, err = cli("check", "--isolated", "other.kcheck.yaml", "--baseline", "b.json")
    assert code == 0 and "baseline" not in err
    code, _, err = cli("check", "--isolated", ".", "--baseline", "b.json", "--select", "maxwell")
    assert code == 0 and "baseline" not in err


def test_a_bad_baseline_is_a_usage_error(cli, write_scene, tmp_path):
    path = str(write_scene(FAILING, "fail.kcheck.yaml"))
    code, _, err = cli("check", "--isolated", path, "--baseline", str(tmp_path / "none.json"))
    assert code == 2 and "--baseline" in err and "cannot read" in err
    (tmp_path / "bad.json").write_text('{"version": 1, "failures": [{"path": 3}]}')
    code, _, err = cli("check", "--isolated", path, "--baseline", str(tmp_path / "bad.json"))
    assert code == 2 and "failures[0]" in err and "Traceback" not in err
    (tmp_path / "text.json").write_text("not json")
    code, _, err = cli("check", "--isolated", path, "--baseline", str(tmp_path / "text.json"))
    assert code == 2 and "not a kcheck baseline" in err


def _stdin(monkeypatch, text: str) -> None:
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text.encode("utf-8"))))


def test_a_scene_on_standard_input(cli, tmp_path, monkeypatch):
    kelvin = tmp_path / "kelvin"
    shutil.copytree(FIXTURES / "kelvin", kelvin)
    text = (kelvin / "coupling.kcheck.yaml").read_text()
    monkeypatch.chdir(tmp_path)
    expected = json.loads(cli("check", "--isolated", "--format", "json", "kelvin")[1])
    # Meshes relative to the working directory...
    monkeypatch.chdir(kelvin)
    _stdin(monkeypatch, text)
    code, doc, _ = _json(cli, "-")
    assert doc["scenes"][0]["path"] == "-"
    statuses = {c["id"]: c["status"] for c in doc["scenes"][0]["checks"]}
    assert statuses == {c["id"]: c["status"] for c in expected["scenes"][0]["checks"]}
    assert code == (0 if expected["scenes"][0]["status"] in ("pass", "warn") else 1)
    # ...or to --stdin-filename's folder.
    monkeypatch.chdir(tmp_path)
    _stdin(monkeypatch, text)
    code2, doc, _ = _json(cli, "-", "--stdin-filename", "kelvin/coupling.kcheck.yaml")
    assert code2 == code and doc["scenes"][0]["path"] == "kelvin/coupling.kcheck.yaml"
    assert sorted(p.name for p in kelvin.iterdir()) == ["coupling.kcheck.yaml", "top-plate.stl"]
    # From elsewhere the mesh is not found: a located input error, and nothing left behind.
    _stdin(monkeypatch, text)
    code, doc, err = _json(cli, "-")
    assert code == 2 and doc["scenes"][0]["path"] == "-"
    body_line = next(k for k, line in enumerate(text.splitlines(), 1) if "top-plate.stl" in line)
    assert doc["scenes"][0]["errors"][0]["line"] == body_line and "top-plate.stl" in err
    assert ".kcheck-stdin" not in err
    assert not list(tmp_path.glob(".kcheck-stdin-*"))


def test_standard_input_usage_errors(cli, write_scene, monkeypatch):
    path = str(write_scene(FAILING, "fail.kcheck.yaml"))
    _stdin(monkeypatch, "version: 1\n")
    assert cli("check", "--isolated", "-", path)[0] == 2
    assert cli("check", "--isolated", path, "--stdin-filename", "x.kcheck.yaml")[0] == 2
    _stdin(monkeypatch, "supports: [\n")
    code, doc, err = _json(cli, "-")
    assert code == 2 and err.startswith("kcheck: error: -:2:")


def test_same_answer_with_one_or_two_workers(cli, write_scene):
    a = str(write_scene(_suppressed_scene(), "a.kcheck.yaml"))
    b = str(write_scene(FAILING, "b.kcheck.yaml"))
    docs = []
    for jobs in ("1", "2"):
        code, doc, _ = _json(cli, a, b, "--jobs", jobs)
        for scene in doc["scenes"]:
            scene.pop("runtime_s")
            for c in scene["checks"]:
                c.pop("runtime_s")
        docs.append((code, doc))
    assert docs[0] == docs[1] and docs[0][0] == 1
