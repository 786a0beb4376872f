"""An interrupted run (Ctrl-C) leaves a report file as it was, never half written: reports
are written beside the file and renamed onto it at the end (docs/ci.md, "Exit codes")."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from tests.conftest import FIXTURES


def _interrupted(tmp_path, fmt: str, wait_for: bytes | None) -> tuple[int, str]:
    """Run kcheck on every fixture with a report file, send SIGINT once its temporary file
    is there (``wait_for`` None) or once the progress line shows ``wait_for``; return the
    exit code and standard error."""
    report = tmp_path / "report.out"
    command = [sys.executable, "-m", "kcheck", "check", str(FIXTURES), "--format", fmt]
    run = subprocess.Popen(
        [*command, "-o", str(report), "--progress", "always", "--no-cache"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    assert run.stderr is not None
    seen = b""
    try:
        deadline = time.monotonic() + 120
        if wait_for is None:  # the new report is being written once its temporary is there
            while not list(tmp_path.glob(".report.out.*")):
                assert run.poll() is None and time.monotonic() < deadline
                time.sleep(0.005)
        else:
            while wait_for not in seen:
                chunk = os.read(run.stderr.fileno(), 4096)
                assert chunk and time.monotonic() < deadline, seen[-500:]
                seen += chunk
        run.send_signal(signal.SIGINT)
        _, err = run.communicate(timeout=120)
    finally:
        run.kill()
    return run.returncode, (seen + err).decode(errors="replace")


@pytest.mark.parametrize("fmt", ["json", "text"])
@pytest.mark.parametrize("wait_for", [None, b"[3/"], ids=["opening", "mid-run"])
def test_sigint_keeps_the_old_report(fmt, wait_for, tmp_path):
    report = tmp_path / "report.out"
    report.write_text("the report of an earlier run\n")
    code, err = _interrupted(tmp_path, fmt, wait_for)
    assert code == 130, err  # interrupted, as a shell reports SIGINT
    assert "Traceback" not in err
    assert report.read_text() == "the report of an earlier run\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.out"]  # no leftover


def test_sigint_writes_no_new_report(tmp_path):
    code, _ = _interrupted(tmp_path, "json", b"[2/")
    assert code == 130
    assert list(tmp_path.iterdir()) == []


def test_a_finished_run_replaces_the_report(tmp_path):
    report = tmp_path / "report.json"
    report.write_text("old")
    done = subprocess.run(
        [sys.executable, "-m", "kcheck", "check", str(FIXTURES / "thesis-block-4-2"),
         "--format", "json", "-o", str(report)],
        capture_output=True,
    )  # fmt: skip
    assert done.returncode == 0
    assert json.loads(report.read_text())["scenes"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.json"]
