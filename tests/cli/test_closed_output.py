"""Standard output that goes away or is closed: the exit code is still the verdict's, in
every format, and nothing prints a traceback (docs/ci.md, "Exit codes")."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from tests.conftest import FIXTURES

PASSING = FIXTURES / "thesis-block-4-2"  # every check passes (tests/golden/fixtures.json)
FAILING = FIXTURES / "thesis-appendix-a"  # a check of severity error fails


def _kcheck(*args: str, **kwargs: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run(  # type: ignore[call-overload]
        [sys.executable, "-m", "kcheck", "check", *args],
        stderr=subprocess.PIPE,
        text=True,
        **kwargs,
    )


@pytest.mark.parametrize("fmt", ["text", "json"])
@pytest.mark.parametrize(("scene", "code"), [(PASSING, 0), (FAILING, 1)])
@pytest.mark.parametrize("to_file", [False, True], ids=["report", "summary-line"])
def test_a_reader_that_went_away_keeps_the_verdict(fmt, scene, code, to_file, tmp_path):
    extra = ["-o", str(tmp_path / "report")] if to_file else []  # stdout: the summary line
    read, write = os.pipe()
    os.close(read)  # the reader goes away before anything is written
    try:
        done = _kcheck(str(scene), "--format", fmt, *extra, stdout=write)
    finally:
        os.close(write)
    assert done.returncode == code
    assert "Traceback" not in done.stderr and "BrokenPipe" not in done.stderr
    assert not to_file or (tmp_path / "report").read_text()  # the file report is whole


@pytest.mark.parametrize(("scene", "code"), [(PASSING, 0), (FAILING, 1)])
def test_closed_standard_output_keeps_the_verdict(scene, code, tmp_path):
    report = tmp_path / "report.json"
    done = _kcheck(str(scene), preexec_fn=lambda: os.close(1))
    assert done.returncode == code
    assert done.stderr == ""
    # A report file is still written whole, and not onto descriptor 1.
    done = _kcheck(
        str(scene), "--format", "json", "-o", str(report), preexec_fn=lambda: os.close(1)
    )
    assert done.returncode == code and done.stderr == ""
    assert json.loads(report.read_text())["scenes"]


@pytest.mark.parametrize(("scene", "code"), [(PASSING, 0), (FAILING, 1)])
@pytest.mark.parametrize(
    "extra",
    [["--progress", "always"], ["--format", "json", "--progress", "always"], ["-q"]],
    ids=["progress-line", "json-progress-line", "summary-on-stderr"],
)
def test_a_stderr_reader_that_went_away_keeps_the_verdict(scene, code, extra, tmp_path):
    # The progress line (forced on a pipe) and the summary line (stderr when a `json:-`
    # report holds stdout) write to stderr, whose reader is gone before anything is written.
    if extra == ["-q"]:
        extra = ["--output-format", "json:-", "-o", str(tmp_path / "report.txt")]
    read, write = os.pipe()
    os.close(read)
    try:
        done = subprocess.run(
            [sys.executable, "-m", "kcheck", "check", str(scene), *extra],
            stdout=subprocess.DEVNULL,
            stderr=write,
        )
    finally:
        os.close(write)
    assert done.returncode == code


def test_a_reader_of_both_streams_that_went_away_keeps_the_verdict():
    # `kcheck check ... 2>&1 | head -c0`: one pipe for both, its reader gone.
    read, write = os.pipe()
    os.close(read)
    try:
        done = subprocess.run(
            [sys.executable, "-m", "kcheck", "check", str(FAILING), "--progress", "always"],
            stdout=write,
            stderr=write,
        )
    finally:
        os.close(write)
    assert done.returncode == 1
