"""kcheck.cli.exit_now: the process ends as the interpreter's exit would end it (exit code,
atexit functions, flushed output, threads waited for), without tearing the interpreter down."""

from __future__ import annotations

import json
import os
import pstats
import subprocess
import sys
from pathlib import Path

import pytest

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures"

PROBE = """
import atexit, sys, threading, time
from kcheck.cli import exit_now
atexit.register(lambda: print("atexit ran", flush=False))
sys.stdout.write("buffered " * 1000)  # larger than nothing, smaller than the buffer
if "thread" in sys.argv:
    threading.Thread(target=lambda: (time.sleep(0.2), print("thread done"))).start()
exit_now(int(sys.argv[1]))
"""


@pytest.mark.parametrize("code", [0, 1, 2])
def test_code_output_and_atexit_kept(code):
    done = subprocess.run([sys.executable, "-c", PROBE, str(code)], capture_output=True, text=True)
    assert done.returncode == code
    assert done.stdout == "buffered " * 1000 + "atexit ran\n"


def test_a_running_thread_is_waited_for():
    done = subprocess.run(
        [sys.executable, "-c", PROBE, "1", "thread"], capture_output=True, text=True
    )
    assert done.returncode == 1
    assert done.stdout.endswith("thread done\natexit ran\n")


def test_python_m_kcheck_writes_its_whole_output_to_a_pipe():
    done = subprocess.run([sys.executable, "-m", "kcheck", "schema"], capture_output=True)
    assert done.returncode == 0 and len(done.stdout) > 8192  # more than one buffer
    assert json.loads(done.stdout)["title"]


# A module whose object says, on standard error's descriptor, when the interpreter tears down.
TEARDOWN_PROBE = """
import os
class _Teardown:
    def __del__(self, write=os.write):
        write(2, b"teardown\\n")
probe = _Teardown()
"""


def _with_probe(tmp_path, monkeypatch):
    (tmp_path / "sitecustomize.py").write_text(TEARDOWN_PROBE)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([*sys.path[1:], str(tmp_path)]))


def test_python_m_kcheck_skips_the_teardown(tmp_path, monkeypatch):
    _with_probe(tmp_path, monkeypatch)
    done = subprocess.run([sys.executable, "-m", "kcheck", "schema"], capture_output=True)
    assert done.returncode == 0 and json.loads(done.stdout)["title"]
    assert b"teardown" not in done.stderr


def test_cprofile_writes_its_profile(tmp_path, monkeypatch):
    _with_probe(tmp_path, monkeypatch)
    profile = tmp_path / "kcheck.prof"
    command = [sys.executable, "-m", "cProfile", "-o", str(profile), "-m", "kcheck", "check"]
    done = subprocess.run([*command, str(FIXTURES / "thesis-block-4-2")], capture_output=True)
    assert done.returncode == 0, done.stderr
    stats = pstats.Stats(str(profile))
    assert any(name == "main" for _, _, name in stats.stats)  # type: ignore[attr-defined]
    assert b"teardown" in done.stderr  # the interpreter's own exit


def test_runpy_from_a_caller_returns_to_it(tmp_path):
    caller = (
        "import runpy, sys\n"
        "sys.argv = ['kcheck', 'schema']\n"
        "try:\n"
        "    runpy.run_module('kcheck', run_name='__main__', alter_sys=True)\n"
        "except SystemExit as exc:\n"
        "    print('caller goes on', exc.code, file=sys.stderr)\n"
    )
    done = subprocess.run([sys.executable, "-c", caller], capture_output=True, text=True)
    assert done.stderr.strip().endswith("caller goes on 0")
    assert json.loads(done.stdout)["title"]
