"""kcheck.cli.exit_now: the process ends as the interpreter's exit would end it (exit code,
atexit functions, flushed output, threads waited for), without tearing the interpreter down."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

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
