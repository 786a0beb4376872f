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
