"""The gate's command line: --select, located path errors, outputs checked before the run,
several reports at once, worker budgets, and serial/parallel runs giving the same report."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

import kcheck.gate.pool
from tests.conftest import FIXTURES, PLANAR_SCENE

pytestmark = pytest.mark.skipif(
    not kcheck.gate.pool.available(), reason="worker processes need fork"
)


# -- --select ------------------------------------------------------------------------------


@pytest.mark.parametrize("selection", [",", " ", "maxwell,", ", ,"])
def test_empty_selection_is_a_usage_error(cli, write_scene, selection):
    code, out, err = cli("check", str(write_scene(PLANAR_SCENE)), "--select", selection)
    assert code == 2 and out == ""
    assert "--select: selects no check" in err and "analytical-2d, analytical-3d" in err


def test_unknown_selection_says_did_you_mean(cli, write_scene):
    code, _, err = cli("check", str(write_scene(PLANAR_SCENE)), "--select", "maxwel,analytical-2d")
    assert code == 2 and "unknown check `maxwel` (did you mean `maxwell`?)" in err
    from kcheck.plugin import find_checks

    installed = ", ".join(sorted(spec.name for spec in find_checks()))
    assert f"installed: {installed}" in err


def test_options_of_unselected_checks_are_no_error(cli_json):
    # The README's own example on the bundled fixtures: some scenes carry options for checks
    # other than maxwell; only maxwell runs, and no scene is an input error.
    code, doc = cli_json(str(FIXTURES), "--select", "maxwell")
    assert all(s["status"] != "error" for s in doc["scenes"]), doc["scenes"]
    assert {c["id"] for s in doc["scenes"] for c in s["checks"]} == {"maxwell"}
    assert code in (0, 1)


def test_invalid_options_of_unselected_checks_are_still_reported(cli_json, write_scene):
    path = write_scene(PLANAR_SCENE + "checks:\n  analytical-2d: {min_margin_degs: 5}\n")
    code, doc = cli_json(str(path), "--select", "maxwell")
    assert code == 2
    assert "checks.analytical-2d.min_margin_degs" in doc["scenes"][0]["error"]


def test_unknown_check_in_scene_says_did_you_mean(cli, write_scene):
    code, out, _ = cli("check", str(write_scene(PLANAR_SCENE + "checks:\n  maxwel: {}\n")))
    assert code == 2 and "options for unknown check `maxwel` (did you mean `maxwell`?)" in out


# -- scene paths ---------------------------------------------------------------------------


def test_dangling_symlink_loop_and_long_path_are_located_errors(cli_json, write_scene, tmp_path):
    good = write_scene(PLANAR_SCENE, "d/good.kcheck.yaml")
    (tmp_path / "d" / "dangling.kcheck.yaml").symlink_to(tmp_path / "nowhere.kcheck.yaml")
    (tmp_path / "d" / "loop.kcheck.yaml").symlink_to(tmp_path / "d" / "loop.kcheck.yaml")
    long = tmp_path / ("x" * 300 + ".kcheck.yaml")
    code, doc = cli_json(str(good.parent), str(long))
    errors = {Path(s["path"]).name: s["error"] for s in doc["scenes"] if s["status"] == "error"}
    assert code == 2
    assert "a symbolic link to" in errors["dangling.kcheck.yaml"]
    assert "which does not exist" in errors["dangling.kcheck.yaml"]
    assert "symlink loop" in errors["loop.kcheck.yaml"]
    assert "too long" in errors[long.name]
    assert any(s["status"] == "pass" for s in doc["scenes"])  # the good scene still ran


def test_unreadable_folder_is_an_error_not_a_silent_skip(cli_json, write_scene, monkeypatch):
    # Running as root defeats chmod 000, so the folder read fails the way it would for a user.
    good = write_scene(PLANAR_SCENE, "top/good.kcheck.yaml")
    write_scene(PLANAR_SCENE, "top/locked/hidden.kcheck.yaml")
    real_scandir = os.scandir

    def scandir(path):
        if str(path).endswith("locked"):
            raise PermissionError(13, "Permission denied", str(path))
        return real_scandir(path)

    monkeypatch.setattr(os, "scandir", scandir)
    code, doc = cli_json(str(good.parent))
    assert code == 2
    locked = next(s for s in doc["scenes"] if s["path"].endswith("locked"))
    assert locked["error"].endswith("cannot read this folder: permission denied")


def test_a_folder_given_as_a_file_and_a_path_below_a_file(cli_json, write_scene, tmp_path):
    good = write_scene(PLANAR_SCENE)
    code, doc = cli_json(str(good), str(good / "child.kcheck.yaml"))
    (bad,) = [s for s in doc["scenes"] if s["status"] == "error"]
    assert code == 2 and "a part of the path is a file" in bad["error"]


def test_a_pipe_is_an_error_not_a_hang(cli_json, write_scene, tmp_path):
    good = write_scene(PLANAR_SCENE, "d/good.kcheck.yaml")
    os.mkfifo(tmp_path / "d" / "pipe.kcheck.yaml")
    os.mkfifo(tmp_path / "given.kcheck.yaml")
    code, doc = cli_json(str(good.parent), str(tmp_path / "given.kcheck.yaml"))
    errors = {Path(s["path"]).name: s["error"] for s in doc["scenes"] if s["status"] == "error"}
    assert code == 2 and set(errors) == {"pipe.kcheck.yaml", "given.kcheck.yaml"}
    assert all("not a regular file" in e for e in errors.values())


def test_hidden_folders_are_not_searched(cli_json, write_scene):
    good = write_scene(PLANAR_SCENE, "top/good.kcheck.yaml")
    write_scene("not: [a scene", "top/.venv/lib/odd.kcheck.yaml")
    write_scene("not: [a scene", "top/node_modules/odd.kcheck.yaml")
    code, doc = cli_json(str(good.parent))
    assert code == 0 and [Path(s["path"]).name for s in doc["scenes"]] == ["good.kcheck.yaml"]
    code, doc = cli_json(str(good.parent / ".venv"))  # given explicitly, it is searched
    assert code == 2


# -- outputs -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("target", "expected"),
    [
        ("/proc/kcheck-report.json", "cannot write a report under /proc"),
        ("/dev/full", "no space left on the device"),
        ("{scene}/below.json", "is a file, not a folder"),
        ("{tmp}", "is a folder; give a file name"),
    ],
)
def test_outputs_are_checked_before_the_run(cli, write_scene, tmp_path, target, expected):
    scene = write_scene(PLANAR_SCENE)
    target = target.format(scene=scene, tmp=tmp_path)
    for option in (["--output", target], ["--output-format", f"sarif:{target}"]):
        code, out, err = cli("check", str(scene), "--format", "json", *option)
        assert code == 2 and expected in err, err
        assert out == ""  # nothing ran


def test_unwritable_output_and_plots(cli, write_scene, tmp_path, monkeypatch):
    scene = write_scene(PLANAR_SCENE)
    locked = tmp_path / "locked"
    locked.mkdir()
    real_access = os.access
    monkeypatch.setattr(
        os, "access", lambda p, m: False if str(p) == str(locked) else real_access(p, m)
    )
    code, _, err = cli("check", str(scene), "--output", str(locked / "r.json"))
    assert code == 2 and "permission denied" in err
    code, _, err = cli("check", str(scene), "--plots", str(scene))
    assert code == 2 and "--plots" in err and "is a file, not a folder" in err
    code, _, err = cli("check", str(scene), "--plots", "/proc/kcheck-plots")
    assert code == 2 and "under /proc" in err


def test_unknown_output_format(cli, write_scene, tmp_path):
    code, _, err = cli("check", str(write_scene(PLANAR_SCENE)), "--output-format", "sarf:x.s")
    assert code == 2 and "unknown format `sarf` (did you mean `sarif`?)" in err


def test_several_reports_at_once(cli, write_scene, tmp_path):
    scene = write_scene(PLANAR_SCENE)
    sarif, junit = tmp_path / "out" / "k.sarif", tmp_path / "out" / "k.xml"
    code, out, _ = cli(
        "check", str(scene), "--format", "concise",
        "--output-format", f"sarif:{sarif}", "--output-format", f"junit:{junit}",
    )  # fmt: skip
    assert (
        code == 0 and out.strip() == "1 scene: 1 passed, 0 with warnings, 0 failed, 0 with errors"
    )
    assert json.loads(sarif.read_text())["version"] == "2.1.0"
    assert junit.read_text().startswith('<?xml version="1.0" encoding="utf-8"?>\n<testsuites')


# -- budgets and workers ---------------------------------------------------------------------


def _patch_maxwell(monkeypatch, behaviour):
    """Make the maxwell check misbehave on scenes whose name contains 'bad' (the worker,
    being forked, inherits the patch)."""
    from kcheck_checks.maxwell import Maxwell

    original = Maxwell.run

    def run(self, inputs):
        if "bad" in inputs.scene.name:
            behaviour()
        return original(self, inputs)

    monkeypatch.setattr(Maxwell, "run", run)


def _batch(write_scene, n_good=3):
    def scene(name: str, file: str) -> Path:
        return write_scene(PLANAR_SCENE.replace("name: planar", f"name: {name}"), file)

    paths = [scene(f"good{i}", f"g{i}.kcheck.yaml") for i in range(n_good)]
    paths.insert(1, scene("bad", "b.kcheck.yaml"))
    return [str(p) for p in paths]


def _statuses(doc):
    return [(Path(s["path"]).name, s["status"]) for s in doc["scenes"]]


def test_a_scene_past_its_time_budget_is_an_error_and_the_batch_goes_on(
    cli_json, write_scene, monkeypatch
):
    import time

    _patch_maxwell(monkeypatch, lambda: time.sleep(30))
    started = time.monotonic()
    concise = write_scene("", "report.txt")
    code, doc = cli_json(
        *_batch(write_scene), "--timeout", "1", "--jobs", "2",
        f"--output-format=concise:{concise}",
    )  # fmt: skip
    assert time.monotonic() - started < 15
    assert code == 2
    assert _statuses(doc) == [
        ("g0.kcheck.yaml", "pass"),
        ("b.kcheck.yaml", "error"),
        ("g1.kcheck.yaml", "pass"),
        ("g2.kcheck.yaml", "pass"),
    ]
    assert "exceeded its time budget of 1 s" in doc["scenes"][1]["error"]
    assert "--timeout" in doc["scenes"][1]["error"]
    # a rule of its own, not an input error's
    (line,) = [x for x in concise.read_text().splitlines() if "b.kcheck.yaml" in x]
    assert ": budget-exceeded/time: " in line and "input-error" not in line


def test_a_scene_past_its_memory_budget_is_an_error(cli_json, write_scene, monkeypatch):
    _patch_maxwell(monkeypatch, lambda: bytearray(3 * 2**30))
    sarif = write_scene("", "report.sarif")
    code, doc = cli_json(
        *_batch(write_scene), "--memory-limit", "1500", "--jobs", "1",
        f"--output-format=sarif:{sarif}",
    )  # fmt: skip
    assert code == 2
    assert [s for _, s in _statuses(doc)] == ["pass", "error", "pass", "pass"]
    assert "exceeded its memory budget of 1500 MiB" in doc["scenes"][1]["error"]
    (result,) = json.loads(sarif.read_text())["runs"][0]["results"]
    assert result["ruleId"] == "budget-exceeded/memory"
    (rule,) = json.loads(sarif.read_text())["runs"][0]["tool"]["driver"]["rules"]
    assert "--memory-limit" in rule["fullDescription"]["text"]


def test_a_worker_that_dies_is_replaced(cli_json, write_scene, monkeypatch):
    _patch_maxwell(monkeypatch, lambda: os._exit(9))
    code, doc = cli_json(*_batch(write_scene, n_good=4), "--jobs", "2")
    assert code == 2
    assert [s for _, s in _statuses(doc)] == ["pass", "error", "pass", "pass", "pass"]
    assert "the worker process checking it ended (exit status 9)" in doc["scenes"][1]["error"]


def _without_timings(text: str) -> str:
    return re.sub(r'"runtime_s": [0-9.e-]+', '"runtime_s": 0', text)


def test_jobs_2_gives_the_report_of_jobs_1(cli, tmp_path):
    runs = {}
    for jobs in ("1", "2"):
        code, out, _ = cli("check", str(FIXTURES), "--format", "json", "--jobs", jobs)
        runs[jobs] = (code, _without_timings(out))
    assert runs["1"] == runs["2"]
    assert len(json.loads(runs["1"][1])["scenes"]) >= 10


# -- chunks: a worker given several scene files at once ---------------------------------------


def _chunks_of(monkeypatch, size):
    """Give each worker ``size`` scene files at a time (the default gives small batches one
    file a time: :func:`kcheck.gate.runner.chunk_size`)."""
    import kcheck.gate.runner

    monkeypatch.setattr(kcheck.gate.runner, "chunk_size", lambda files, jobs: size)


@pytest.mark.parametrize(
    ("behaviour", "options", "expected"),
    [
        ("sleep", ("--timeout", "1"), "exceeded its time budget of 1 s"),
        ("allocate", ("--memory-limit", "1500"), "exceeded its memory budget of 1500 MiB"),
        ("exit", (), "the worker process checking it ended (exit status 9)"),
    ],
)
def test_a_chunk_with_a_scene_past_its_budget_checks_the_others(
    cli_json, write_scene, monkeypatch, behaviour, options, expected
):
    """Chunks of three (the bad scene second in the first): the bad scene gets its budget
    result, every other scene of its chunk and after it its own result."""
    import time

    action = {
        "sleep": lambda: time.sleep(30),
        "allocate": lambda: bytearray(3 * 2**30),
        "exit": lambda: os._exit(9),
    }[behaviour]
    _patch_maxwell(monkeypatch, action)
    _chunks_of(monkeypatch, 3)
    started = time.monotonic()
    code, doc = cli_json(*_batch(write_scene, n_good=5), *options, "--jobs", "2")
    assert time.monotonic() - started < 20  # the hung scene is killed, not waited for
    assert code == 2
    assert [s for _, s in _statuses(doc)] == ["pass", "error", *["pass"] * 4]
    assert expected in doc["scenes"][1]["error"]
    assert all(s["checks"] for k, s in enumerate(doc["scenes"]) if k != 1)


@pytest.mark.slow
def test_chunked_workers_give_the_report_of_one_worker_and_of_one_scene_at_a_time(
    cli, write_scene, monkeypatch
):
    """Every fixture, a scene with bad input (exit 2) and a failing one: ``-j 2`` with
    chunks of four, ``-j 1`` with one file a time, and each file checked alone give the same
    scenes, floats by their repr (the JSON text), run times aside."""
    bad = write_scene(PLANAR_SCENE.replace("friction: 0.1", "friction: -1"), "bad.kcheck.yaml")
    failing = write_scene(
        PLANAR_SCENE.replace("friction: 0.1", "friction: 0.9"), "failing.kcheck.yaml"
    )
    paths = [str(FIXTURES), str(bad), str(failing)]

    def scenes(*args: str) -> tuple[int, list[str]]:
        code, out, _ = cli("check", *args, "--format", "json", "--no-cache")
        return code, [json.dumps(s) for s in json.loads(_without_timings(out))["scenes"]]

    _chunks_of(monkeypatch, 4)
    chunked = scenes(*paths, "--jobs", "2")
    _chunks_of(monkeypatch, 1)
    one_worker = scenes(*paths, "--jobs", "1")
    assert chunked == one_worker
    code, found = chunked
    assert code == 2 and len(found) >= 12
    statuses = [json.loads(s)["status"] for s in found]
    assert statuses[-2:] == ["error", "fail"] and "pass" in statuses
    alone = [scenes(json.loads(s)["path"], "--jobs", "1")[1] for s in found]
    assert [s for (s,) in alone] == found


def test_blas_pinned_to_one_thread_unless_the_user_chose():
    import subprocess
    import sys

    probe = (
        "import os, sys\n"
        "from kcheck.cli import main\n"
        "main(['config'])\n"
        "print(os.environ['OPENBLAS_NUM_THREADS'], os.environ['OMP_NUM_THREADS'], "
        "'numpy' in sys.modules, file=sys.stderr)\n"
    )
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    proc = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True)
    # main() pins first, before any command imports numpy (`config` never does)
    assert proc.stderr.split()[-3:] == ["1", "1", "False"]
    proc = subprocess.run(
        [sys.executable, "-c", probe],
        env={**env, "OPENBLAS_NUM_THREADS": "4"},
        capture_output=True,
        text=True,
    )
    assert proc.stderr.split()[-3:-1] == ["4", "1"]


def test_pydantic_plugins_skipped_unless_the_user_chose():
    import subprocess
    import sys

    probe = (
        "import os, sys\n"
        "from kcheck.cli import main\n"
        "main(['config'])\n"
        "print(os.environ['PYDANTIC_DISABLE_PLUGINS'], file=sys.stderr)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYDANTIC_DISABLE_PLUGINS"}
    proc = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True)
    assert proc.stderr.split()[-1] == "__all__"
    chosen = {**env, "PYDANTIC_DISABLE_PLUGINS": "logfire"}
    proc = subprocess.run([sys.executable, "-c", probe], env=chosen, capture_output=True, text=True)
    assert proc.stderr.split()[-1] == "logfire"


# -- fuzz findings (issue 13) --------------------------------------------------------------


def test_two_reports_to_one_file_is_a_usage_error(cli, write_scene, tmp_path):
    # The fuzzer found `--output a.json --output-format junit:a.json` exiting 0 with a JSON
    # file that held JUnit XML: each report overwrote the other.
    scene = str(write_scene(PLANAR_SCENE))
    a = str(tmp_path / "a.json")
    for options in (
        ["--output", a, "--output-format", f"junit:{a}"],
        ["--output-format", f"sarif:{a}", "--output-format", f"junit:{tmp_path}/./a.json"],
    ):
        code, out, err = cli("check", scene, "--format", "json", *options)
        assert code == 2 and out == "" and "the same file as" in err
    code, _, _ = cli("check", scene, "--output", "/dev/null", "--output-format", "sarif:/dev/null")
    assert code == 0  # a device may take both


def test_a_pipe_nobody_reads_as_output_is_an_error_not_a_hang(cli, write_scene, tmp_path):
    os.mkfifo(tmp_path / "pipe")
    code, _, err = cli("check", str(write_scene(PLANAR_SCENE)), "--output", str(tmp_path / "pipe"))
    assert code == 2 and "a pipe that nobody reads" in err


def test_file_size_limits_from_configuration(cli_json, write_scene, tmp_path):
    # `max_file_size` was read from the configuration but never reached the loader.
    import trimesh

    scene = write_scene(
        PLANAR_SCENE.replace(
            "  mass: 1\n  center_of_mass: [50, 30, 0]\n  inertia: 0.001\n", ""
        ).replace("body:\n", "body: {mesh: box.stl, material: aluminium}\n")
    )
    trimesh.creation.box(extents=(100, 60, 20)).export(tmp_path / "box.stl")
    config = tmp_path / "k.toml"
    config.write_text("max_file_size = 0.0001\n")  # 105 bytes
    code, doc = cli_json(str(scene), "--config", str(config))
    assert code == 2 and "larger than 9.91821e-05 MiB" in doc["scenes"][0]["error"]
    assert "max_file_size" in doc["scenes"][0]["error"]
    config.write_text("max_mesh_size = 0.0001\n")
    code, doc = cli_json(str(scene), "--config", str(config))
    assert code == 2 and "684 bytes, more than the limit of 104 bytes" in doc["scenes"][0]["error"]
    assert doc["scenes"][0]["errors"][0]["field"] == "body.mesh"


@pytest.mark.parametrize("option", [["--timeout", "1e300"], ["--memory-limit", "1e30"]])
def test_budgets_too_large_to_matter_are_no_budget(cli_json, write_scene, option):
    # Fuzz findings (issue 13): `--timeout 1e300` overflowed select()'s time_t in the pool
    # (a traceback), and `--memory-limit 1e30` made every worker die on setrlimit.
    code, doc = cli_json(str(write_scene(PLANAR_SCENE)), "-j", "1", *option)
    assert code == 0 and doc["scenes"][0]["status"] == "pass"


def test_a_wrong_format_in_the_configuration_is_an_error_even_when_overridden(
    cli, write_scene, tmp_path
):
    # Fuzz finding cli-4244-365 (issue 13): `format = "nope"` in the configuration passed
    # silently when the command line gave `--format json`.
    scene = str(write_scene(PLANAR_SCENE))
    config = tmp_path / "k.toml"
    config.write_text('format = "nope"\n')
    code, out, err = cli("check", scene, "--format", "json", "--config", str(config))
    assert code == 2 and out == "" and "k.toml" in err and "unknown format `nope`" in err


@pytest.mark.parametrize("budget", ["1", "200", "511"])
def test_a_memory_budget_below_the_worker_itself_is_a_usage_error(cli, write_scene, budget):
    # Fuzz finding cli-4245-465 (issue 13): `--memory-limit 1` passed a scene with explicit
    # mass properties (it allocated nothing new in its worker) and failed others; 200 MiB
    # stalled the tool changer until its 120 s time budget. Below 512 MiB it is refused.
    code, _, err = cli("check", str(write_scene(PLANAR_SCENE)), "--memory-limit", budget)
    assert code == 2 and "expected at least 512 MiB" in err
