"""Worker processes: results in task order whatever finishes first, budgets per task, and a
dead or hung worker replaced without losing the tasks after it."""

from __future__ import annotations

import os
import time

import pytest

from kcheck.gate.pool import Budget, BudgetExceeded, available, run_in_workers

pytestmark = pytest.mark.skipif(not available(), reason="worker processes need fork")


def work(task: tuple[str, float]) -> str:
    kind, value = task
    if kind == "sleep":
        time.sleep(value)
    elif kind == "exit":
        os._exit(int(value))
    elif kind == "allocate":
        bytearray(int(value))
    elif kind == "raise":
        raise ValueError("boom")
    return f"{kind} {value} in {os.getpid()}"


def test_results_in_task_order_when_later_tasks_finish_first():
    tasks = [("sleep", 0.3), ("sleep", 0.0), ("sleep", 0.1), ("sleep", 0.0), ("sleep", 0.0)]
    results = list(run_in_workers(tasks, work, jobs=3, budget=Budget()))
    assert [r.split(" in ")[0] for r in results] == [f"sleep {v}" for _, v in tasks]
    assert len({r.split(" in ")[1] for r in results}) > 1  # more than one worker did work
    assert os.getpid() not in {int(r.split(" in ")[1]) for r in results}


def test_budgets_and_deaths_are_outcomes_and_the_rest_goes_on():
    tasks = [
        ("sleep", 5.0),  # past the time budget
        ("allocate", 2**31),  # past the memory budget
        ("exit", 3),  # the worker dies
        ("raise", 0),  # the task raises: a crash, told by name
        ("sleep", 0.0),
        ("sleep", 0.0),
    ]
    started = time.monotonic()
    out = list(run_in_workers(tasks, work, jobs=2, budget=Budget(0.5, 1024 * 2**20)))
    assert time.monotonic() - started < 4
    kinds = [o.kind if isinstance(o, BudgetExceeded) else "ok" for o in out]
    assert kinds == ["time", "memory", "died", "crashed", "ok", "ok"]
    assert out[2].detail.endswith("(exit status 3)")
    assert out[3].detail == "ValueError: boom"


def test_one_worker_runs_everything_in_turn():
    tasks = [("sleep", 0.0)] * 4
    out = list(run_in_workers(tasks, work, jobs=1, budget=Budget(10, None)))
    assert len({r.split(" in ")[1] for r in out}) == 1


FORK_PROBE = """
import json, os, sys, warnings
warnings.simplefilter("error", DeprecationWarning)
threads = []
real_fork = os.fork

def fork():
    if os.getpid() == parent:  # the parent, at each worker's fork: its OS threads
        threads.append(len(os.listdir("/proc/self/task")))
    return real_fork()

parent = os.getpid()
os.fork = fork
from kcheck.cli import main
code = main(["check", *sys.argv[1:], "--jobs", "2", "--progress", "always", "--format", "json",
             "--output", os.devnull])
print(json.dumps({"code": code, "threads": threads}))
"""


@pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="counts threads in /proc")
def test_no_fork_while_a_thread_runs(tmp_path):
    """Workers are forked from a process running one thread only, even with the progress line
    shown (its clock is redrawn by the batch's wait, not by a thread): Python 3.12 warns of a
    fork in a multi-threaded process (a DeprecationWarning, here an error), and on every
    version such a fork may deadlock the child. The count is taken from /proc, so it holds on
    Python 3.11 too, where no warning exists."""
    import json
    import subprocess
    import sys

    from tests.conftest import FIXTURES

    scenes = [str(FIXTURES / "planar-block"), str(FIXTURES / "kelvin")]
    proc = subprocess.run(
        [sys.executable, "-W", "error::DeprecationWarning", "-c", FORK_PROBE, *scenes],
        capture_output=True, text=True, timeout=300,
        # kcheck's own default of one BLAS thread (a user who sets OPENBLAS_NUM_THREADS above
        # 1 gets OpenBLAS's threads in the parent too: docs/ci.md says so)
        env={k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")},
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "DeprecationWarning" not in proc.stderr
    result = json.loads(proc.stdout.splitlines()[-1])
    assert result["code"] in (0, 1)
    assert len(result["threads"]) == 2 and set(result["threads"]) == {1}, result


_HELD: list[bytearray] = []


def grow(task: int) -> tuple[int, int, int]:
    """Keep 40 MB more per task (as a worker drawing pictures keeps caches); return the task's
    own answer (its square), the worker and how many tasks that worker has held."""
    _HELD.append(bytearray(40 * 2**20))
    _HELD[-1][::4096] = b"\x01" * len(range(0, 40 * 2**20, 4096))  # resident, not just mapped
    return task * task, os.getpid(), len(_HELD)


def test_a_worker_past_its_resident_threshold_is_replaced_after_its_task():
    from kcheck.gate.pool import resident_bytes

    # A fresh worker's own resident memory (not the parent's: file pages are not shared).
    (start,) = run_in_workers([None], lambda _: resident_bytes(), jobs=1, budget=Budget())
    assert isinstance(start, int) and start > 0
    # Past start + 100 MB: a worker retires after its third task (40 MB each).
    budget = Budget(recycle_bytes=start + 100 * 2**20)
    results = list(run_in_workers(list(range(10)), grow, jobs=2, budget=budget))
    assert [r[0] for r in results] == [t * t for t in range(10)]  # every answer, in order
    assert max(r[2] for r in results) == 3  # no worker held more than three tasks
    assert len({r[1] for r in results}) >= 4  # so fresh workers took over
    # Without a threshold, one worker keeps growing.
    kept = list(run_in_workers(list(range(5)), grow, jobs=1, budget=Budget()))
    assert [r[2] for r in kept] == [1, 2, 3, 4, 5] and len({r[1] for r in kept}) == 1


def work_chunk(chunk):
    return [work(task) for task in chunk]


def test_chunks_keep_each_tasks_outcome_and_the_task_order():
    """Chunks of three: the tasks of a chunk that ran out of a budget, died or raised are run
    again one by one, so each gets its own outcome, as with chunks of one."""
    from kcheck.gate.pool import run_chunks_in_workers

    tasks = [
        ("sleep", 0.0),
        ("sleep", 5.0),  # past the time budget
        ("sleep", 0.0),
        ("allocate", 2**31),  # past the memory budget
        ("sleep", 0.0),
        ("exit", 3),  # the worker dies
        ("raise", 0),  # the task raises
        ("sleep", 0.0),
        ("sleep", 0.0),
        ("sleep", 0.0),
    ]
    budget = Budget(0.5, 1024 * 2**20)
    started = time.monotonic()
    out = list(run_chunks_in_workers(tasks, work_chunk, jobs=2, budget=budget, chunk=3))
    assert time.monotonic() - started < 6
    kinds = [o.kind if isinstance(o, BudgetExceeded) else o.split(" in ")[0] for o in out]
    assert kinds == [
        "sleep 0.0", "time", "sleep 0.0", "memory", "sleep 0.0", "died", "crashed",
        "sleep 0.0", "sleep 0.0", "sleep 0.0",
    ]  # fmt: skip
    assert out[5].detail.endswith("(exit status 3)")
    assert out[6].detail == "ValueError: boom"


def test_a_chunk_goes_to_one_worker_at_once():
    from kcheck.gate.pool import chunks_of, run_chunks_in_workers

    assert chunks_of(7, 3) == [(0, 1, 2), (3, 4, 5), (6,)]
    assert chunks_of(2, 0) == [(0,), (1,)]
    out = list(
        run_chunks_in_workers([("sleep", 0.0)] * 7, work_chunk, jobs=2, budget=Budget(), chunk=3)
    )
    workers = [int(r.split(" in ")[1]) for r in out]
    assert len(out) == 7
    assert workers[0] == workers[1] == workers[2] and workers[3] == workers[4] == workers[5]


def test_a_chunk_answering_for_fewer_tasks_is_run_again_task_by_task():
    from kcheck.gate.pool import run_chunks_in_workers

    def short(chunk):
        return [work(t) for t in chunk][: 1 if len(chunk) > 1 else None]

    out = list(run_chunks_in_workers([("sleep", 0.0)] * 5, short, jobs=2, budget=Budget(), chunk=2))
    assert [r.split(" in ")[0] for r in out] == ["sleep 0.0"] * 5


def test_a_worker_past_its_resident_threshold_is_replaced_after_its_chunk():
    from kcheck.gate.pool import resident_bytes, run_chunks_in_workers

    (start,) = run_in_workers([None], lambda _: resident_bytes(), jobs=1, budget=Budget())
    assert isinstance(start, int) and start > 0
    # Past start + 100 MB: a worker retires after its second chunk of two (40 MB a task).
    budget = Budget(recycle_bytes=start + 100 * 2**20)

    def grow_chunk(chunk):
        return [grow(t) for t in chunk]

    results = list(
        run_chunks_in_workers(list(range(10)), grow_chunk, jobs=2, budget=budget, chunk=2)
    )
    assert [r[0] for r in results] == [t * t for t in range(10)]
    assert max(r[2] for r in results) == 4  # no worker held more than two chunks
    assert len({r[1] for r in results}) >= 3


def test_after_a_chunk_ran_out_of_time_the_rest_goes_one_task_at_a_time():
    from kcheck.gate.pool import run_chunks_in_workers

    def sized(chunk):
        return [(work(t).split(" in ")[0], len(chunk)) for t in chunk]

    tasks = [("sleep", 0.0), ("sleep", 5.0), *[("sleep", 0.0)] * 7]
    out = list(run_chunks_in_workers(tasks, sized, jobs=1, budget=Budget(0.5, None), chunk=3))
    assert isinstance(out[1], BudgetExceeded) and out[1].kind == "time"
    assert [o for k, o in enumerate(out) if k != 1] == [("sleep 0.0", 1)] * 8


def test_the_last_chunk_split_after_a_crash_goes_to_a_fresh_worker():
    """The worker given the last chunk is told to end with it; when that chunk raises, its
    tasks are run again one by one by a fresh worker, each with its own outcome."""
    from kcheck.gate.pool import run_chunks_in_workers

    tasks = [("sleep", 0.0), ("sleep", 0.0), ("raise", 0), ("sleep", 0.0)]
    out = list(run_chunks_in_workers(tasks, work_chunk, jobs=1, budget=Budget(), chunk=2))
    assert isinstance(out[2], BudgetExceeded) and out[2].kind == "crashed"
    first, second, last = (int(out[k].split(" in ")[1]) for k in (0, 1, 3))
    assert first == second != last


def test_a_worker_that_ended_with_its_last_chunk_is_reaped_by_the_next_run():
    # The last worker is not waited for when the run ends (it exits by itself); the next
    # run reaps it, so ended workers do not pile up as zombies in a long-lived caller.
    (first,) = run_in_workers([("sleep", 0.0)], work, jobs=1, budget=Budget())
    pid = int(first.split(" in ")[1])
    (second,) = run_in_workers([("sleep", 0.0)], work, jobs=1, budget=Budget())
    assert int(second.split(" in ")[1]) != pid
    with pytest.raises(ChildProcessError):  # no such child left: reaped
        os.waitpid(pid, os.WNOHANG)


def test_a_worker_closes_its_descriptors_up_to_its_highest_open_one(tmp_path, monkeypatch):
    """Where ``close_range`` is missing (Linux < 5.9, old seccomp profiles) ``os.closerange``
    closes one number at a time: the worker's range must end at its highest open descriptor,
    not at 2**31 - 1 (about 195 s per worker exit there). The workers are forked from this
    process, so they call the ``os.closerange`` patched here; each writes its range down."""
    from kcheck.gate import pool

    log = tmp_path / "ranges"
    closerange = os.closerange

    def recorded(low: int, high: int) -> None:
        fd = os.open(log, os.O_WRONLY | os.O_APPEND | os.O_CREAT)
        os.write(fd, f"{low} {high} {fd}\n".encode())
        os.close(fd)
        closerange(low, high)

    monkeypatch.setattr(os, "closerange", recorded)
    out = list(run_in_workers([("sleep", 0.0)] * 3, work, jobs=2, budget=Budget(10, None)))
    pool.reap_exited(wait=True)
    assert len(out) == 3 and not any(isinstance(o, BudgetExceeded) for o in out)
    ranges = [tuple(map(int, line.split())) for line in log.read_text().splitlines()]
    assert ranges, "no worker closed its descriptors"
    for low, high, highest_open in ranges:
        assert low == 0  # stdin, stdout, stderr too: a pipe's reader sees its end
        assert highest_open < high <= pool.MAX_DESCRIPTORS_CLOSED


def test_without_a_list_of_open_descriptors_the_bound_is_the_capped_limit(monkeypatch):
    from kcheck.gate import pool

    read_end, write_end = os.pipe()
    try:
        assert write_end < pool._descriptor_bound() <= pool.MAX_DESCRIPTORS_CLOSED
    finally:
        os.close(read_end)
        os.close(write_end)

    def no_proc(path: str) -> list[str]:
        raise FileNotFoundError(path)

    monkeypatch.setattr(os, "listdir", no_proc)
    limit = os.sysconf("SC_OPEN_MAX")
    expected = limit if 0 < limit <= pool.MAX_DESCRIPTORS_CLOSED else pool.MAX_DESCRIPTORS_CLOSED
    assert pool._descriptor_bound() == expected
    monkeypatch.setattr(os, "sysconf", lambda name: 2**30)  # a container's huge limit
    assert pool._descriptor_bound() == pool.MAX_DESCRIPTORS_CLOSED


SLOW_READER_PROBE = """
import fcntl, os, sys, time
from kcheck.gate.pool import Budget, BudgetExceeded, run_in_workers

flags = fcntl.fcntl(1, fcntl.F_GETFL)  # fill the stdout pipe, whose reader starts later
fcntl.fcntl(1, fcntl.F_SETFL, flags | os.O_NONBLOCK)
try:
    while True:
        os.write(1, b"x" * 4096)
except BlockingIOError:
    pass
fcntl.fcntl(1, fcntl.F_SETFL, flags)
sys.stdout.write("buffered, flushed before the fork\\n")
sys.stderr.write("full\\n")
sys.stderr.flush()
(out,) = run_in_workers([0.1], time.sleep, jobs=1, budget=Budget(float(sys.argv[2]), None))
with open(sys.argv[1], "w") as fh:
    fh.write(out.kind if isinstance(out, BudgetExceeded) else "ok")
"""


def test_a_slow_reader_of_the_output_does_not_use_the_tasks_time_budget(tmp_path):
    """The pool flushes stdout before each fork; a reader that has not read yet (a pager, a
    full pipe) holds that flush up, and that wait is not the task's: a task of 0.1 s gets
    its result with a budget of 1 s although the flush waited 3 s (the budget's clock had
    started before the flush: a time-budget result; the review of lane startup6)."""
    import subprocess
    import sys

    verdict = tmp_path / "verdict"
    proc = subprocess.Popen(
        [sys.executable, "-c", SLOW_READER_PROBE, str(verdict), "1.0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        env={k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"},  # stdout buffered
    )  # fmt: skip
    assert proc.stderr is not None
    assert proc.stderr.readline() == b"full\n"  # imported, its stdout pipe full
    time.sleep(3.0)  # the reader starts late: the probe's flush waits until then
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 0, err.decode()
    assert out.endswith(b"buffered, flushed before the fork\n")
    assert verdict.read_text() == "ok"


def test_reaping_never_kills_a_child_that_is_still_running(monkeypatch):
    """A pid left to reap may be another child of the caller's by now (something else reaped
    the worker and the pid was reused): past the grace it is left for later, not killed."""
    import subprocess
    import sys

    from kcheck.gate import pool

    monkeypatch.setattr(pool, "EXIT_GRACE_S", 0.2)
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        with pool._EXITING_LOCK:
            pool._EXITING.append(other.pid)  # as if one of ours had ended with that pid
        pool.reap_exited(wait=True)
        assert other.poll() is None  # still running
        assert other.pid in pool._EXITING  # left for a later call
    finally:
        with pool._EXITING_LOCK:
            if other.pid in pool._EXITING:
                pool._EXITING.remove(other.pid)
        other.kill()
        other.wait()


def test_pools_in_several_threads_share_the_pids_left_to_reap():
    """Several threads reaping at once each take their own pids: none is reaped or removed
    twice (a plain list raised ValueError in ``remove`` when two took the same pid). The pids
    are past Linux's largest (2**22), so waitpid says at once that they are nobody's child."""
    import threading

    from kcheck.gate import pool

    fake = list(range(2**22 + 1, 2**22 + 1 + 20000))
    with pool._EXITING_LOCK:
        pool._EXITING.extend(fake)
    errors: list[BaseException] = []

    def reap() -> None:
        try:
            pool.reap_exited(wait=False)
        except BaseException as exc:  # noqa: BLE001 - collected, asserted below
            errors.append(exc)

    threads = [threading.Thread(target=reap) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    with pool._EXITING_LOCK:
        left = set(pool._EXITING) & set(fake)
        pool._EXITING[:] = [pid for pid in pool._EXITING if pid not in left]
    assert errors == [] and not left
