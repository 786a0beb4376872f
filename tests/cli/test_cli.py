"""The command line as users and CI gates run it: exit codes, batches, formats, colour."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from kcheck import __version__
from tests.conftest import FIXTURES, PLANAR_SCENE


def test_fixtures_run_and_report(cli):
    code, out, err = cli("check", str(FIXTURES))
    assert code in (0, 1), err
    count = len(list(FIXTURES.rglob("*.kcheck.yaml")))
    assert "short summary" in out and f"{count} scenes:" in out
    assert "planar rectangular block" in out and "3-2-1 block" in out
    assert "Traceback" not in out + err


def test_json_document_layout(cli_json, write_scene):
    code, doc = cli_json(str(write_scene(PLANAR_SCENE)))
    assert code == 0
    assert doc["kcheck_version"] == __version__ and doc["format_version"] == 3
    (scene,) = doc["scenes"]
    assert scene["status"] == "pass" and scene["error"] is None and scene["kind"] == "planar"
    assert scene["mass_properties"]["source"] == "explicit"
    assert scene["mass_properties"]["mass"] == 1
    checks = {c["id"]: c for c in scene["checks"]}
    assert checks["analytical-3d"]["status"] == "skipped"
    assert "spatial" in checks["analytical-3d"]["message"]
    a2 = checks["analytical-2d"]
    assert set(a2) >= {
        "id",
        "status",
        "message",
        "runtime_s",
        "error_estimate",
        "safe_ranges_deg",
        "cases",
    }
    assert a2["runtime_s"] > 0 and a2["error_estimate"] < 1e-9
    for start, end in a2["safe_ranges_deg"]:  # both in [0, 360); end < start wraps through 0
        assert 0 <= start < 360 and 0 <= end < 360 and start != end
    x1 = next(c for c in a2["cases"] if c["retracted"] == "x1")
    # methods.md §7: N1 = 0.388909 N, N2 = 0.318198 N, a = 0.636396 m/s^2 at 225 deg.
    assert x1["outcome"] == "closes"
    assert x1["normal_forces"] == pytest.approx({"y1": 0.388909, "y2": 0.318198}, abs=1e-6)
    assert x1["acceleration"] == pytest.approx(0.636396, abs=1e-6)
    assert "cos_maxwell" not in x1  # fields a check has no use for are omitted
    assert checks["maxwell"]["cases"][0]["cos_maxwell"] > 0


def test_exit_1_when_a_check_fails(cli, write_scene):
    path = write_scene(PLANAR_SCENE.replace("angle: 225", "angle: 45"))
    code, out, _ = cli("check", str(path))
    assert code == 1 and "FAIL" in out


def test_batch_keeps_going_past_bad_input(cli_json, write_scene):
    good = write_scene(PLANAR_SCENE, "a/good.kcheck.yaml")
    write_scene(PLANAR_SCENE.replace("magnitude: 1", "magnitude: lots"), "b/bad.kcheck.yaml")
    code, doc = cli_json(str(good.parent.parent))
    assert code == 2
    by_name = {os.path.basename(s["path"]): s for s in doc["scenes"]}
    assert by_name["good.kcheck.yaml"]["status"] == "pass"
    bad = by_name["bad.kcheck.yaml"]
    assert bad["status"] == "error" and bad["checks"] == []
    assert "bad.kcheck.yaml:14:3: field `load.magnitude`" in bad["error"]


def test_bad_input_messages_on_stderr_without_traceback(cli, write_scene):
    path = write_scene(PLANAR_SCENE.replace("[1, 0, 0]", "[0, 0, 0]"))
    code, out, err = cli("check", str(path))
    assert code == 2
    # The text report on stdout shows the error once; stderr repeats it only when stdout
    # carries another format.
    assert f"{path}:11:38" in out and "field `supports[2].normal`: expected a non-zero" in out
    assert err == ""
    code, out, err = cli("check", str(path), "--format", "json")
    assert f"{path}:11:38: field `supports[2].normal`: expected a non-zero vector" in err
    assert "Traceback" not in out + err


def test_bad_mesh_points_at_the_scene_field(cli, write_scene, tmp_path):
    import trimesh

    mesh = trimesh.creation.box(extents=(100.0, 60.0, 20.0))
    mesh.invert()
    mesh.export(tmp_path / "inv.stl")
    text = (
        PLANAR_SCENE.replace(
            "  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n",
            "  mesh: inv.stl\n  material: aluminium\n",
        )
        .replace("[0, 0]", "[0, 10]")
        .replace("[0, 10], normal: [1", "[0, 10], normal: [1")
    )
    text = text.replace(", 0], normal", ", 10], normal")
    path = write_scene(text)
    code, out, _ = cli("check", str(path))
    assert code == 2
    assert f"{path}:5" in out and "field `body.mesh`:" in out and "inverted" in out


def test_missing_path_and_empty_folder(cli, tmp_path, write_scene):
    good = write_scene(PLANAR_SCENE)
    (tmp_path / "empty").mkdir()
    code, out, err = cli("check", str(good), str(tmp_path / "nope"), str(tmp_path / "empty"))
    assert code == 2
    assert "no such file or folder" in out and "no *.kcheck.yaml files found" in out
    assert "planar block" in out  # the good scene was still checked


def test_unknown_check_options_and_select(cli, write_scene):
    path = write_scene(PLANAR_SCENE + "checks:\n  maxwel: {min_cos: 0.5}\n")
    code, out, _ = cli("check", str(path))
    assert code == 2 and "field `checks.maxwel`: options for unknown check" in out
    path = write_scene(PLANAR_SCENE + "checks:\n  maxwell: {min_cos: 2}\n", "b.kcheck.yaml")
    code, out, _ = cli("check", str(path))
    assert code == 2 and "checks.maxwell.min_cos" in out and ":17" in out
    path = write_scene(PLANAR_SCENE, "c.kcheck.yaml")
    code, doc_text, _ = cli("check", str(path), "--select", "maxwell", "--format", "json")
    assert code == 0 and [c["id"] for c in json.loads(doc_text)["scenes"][0]["checks"]] == [
        "maxwell"
    ]
    assert cli("check", str(path), "--select", "nonsense")[0] == 2


def test_usage_errors_are_exit_2(cli):
    assert cli("check", "--format", "yaml")[0] == 2
    assert cli("frobnicate")[0] == 2
    assert cli("--version")[0] == 0


def test_output_file(cli, write_scene, tmp_path):
    path = write_scene(PLANAR_SCENE)
    out_file = tmp_path / "out" / "report.json"
    code, out, _ = cli("check", str(path), "--format", "json", "--output", str(out_file))
    # The report is in the file; the terminal still gets the run's last line.
    assert code == 0 and out.startswith("1 scene: 1 passed in ") and out.count("\n") == 1
    assert str(out_file) in out
    assert json.loads(out_file.read_text())["scenes"][0]["status"] == "pass"


def test_schema_command(cli):
    code, out, _ = cli("schema")
    schema = json.loads(out)
    assert code == 0 and schema["title"].startswith("kcheck scene")


def test_plugins_command(cli):
    code, out, _ = cli("plugins")
    assert code == 0
    assert "maxwell  (kcheck " in out and "min_cos (default 0.7)" in out


def _run(args, **env):
    full = {**os.environ, **env}
    full.pop("NO_COLOR", None)
    full.pop("FORCE_COLOR", None)
    full.update({k: v for k, v in env.items() if v is not None})
    return subprocess.run(
        [sys.executable, "-m", "kcheck", *args], capture_output=True, text=True, env=full
    )


def test_colour_follows_tty_no_color_and_flag(write_scene):
    path = str(write_scene(PLANAR_SCENE))
    assert "\x1b[" not in _run(["check", path]).stdout  # not a TTY: plain
    assert "\x1b[" in _run(["check", path, "--color", "always"]).stdout
    assert "\x1b[" in _run(["check", path], FORCE_COLOR="1").stdout
    assert "\x1b[" not in _run(["check", path], FORCE_COLOR="1", NO_COLOR="1").stdout


def test_an_ascii_terminal_gets_escapes_not_a_traceback():
    # Fuzz finding (issue 13): with an ASCII stdout the text report died on the first '±'.
    # What the terminal cannot show is escaped (the text report may choose better words).
    kelvin = str(FIXTURES / "kelvin")
    proc = _run(["check", kelvin], PYTHONIOENCODING="ascii")
    assert proc.returncode == 0 and "Traceback" not in proc.stderr
    assert "Kelvin coupling" in proc.stdout
