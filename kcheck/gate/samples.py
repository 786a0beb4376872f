"""Sample maps (:mod:`kcheck.plugin.samples`) on the executors of ``kcheck study``: local
worker processes (:mod:`kcheck.gate.pool`, each task within a time and memory budget) or a
Dask cluster (a ``distributed.Client``: a ``LocalCluster`` or an existing scheduler).

The chunks a check hands over are grouped into a few tasks per worker (contiguous runs of
chunks, so one task costs one message each way); each task applies the check's function to
its chunks, and the results come back in chunk order. The grouping changes no number: each
chunk's result depends on the chunk alone.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from kcheck.plugin import SampleMap, serial

__all__ = ["SampleWorkerError", "groups", "local_samples", "dask_samples"]

T = TypeVar("T")
R = TypeVar("R")

#: Tasks per worker: enough to even out chunks of different cost, few enough that sending
#: them costs little next to solving them.
TASKS_PER_WORKER = 4


class SampleWorkerError(RuntimeError):
    """A task of sample chunks did not come back (a worker crashed, was killed, or ran past
    its budget); the check reports it as its error."""


def groups(chunks: Sequence[T], tasks: int) -> list[list[T]]:
    """``chunks`` cut into at most ``tasks`` contiguous runs of nearly equal length."""
    n = len(chunks)
    tasks = max(1, min(tasks, n))
    cuts = [n * i // tasks for i in range(tasks + 1)]
    return [list(chunks[a:b]) for a, b in zip(cuts, cuts[1:], strict=False) if b > a]


def _run_group(function: Callable[[T], R], group: Sequence[T]) -> list[R]:
    """One task: the function on each of its chunks (module-level, so Dask can send it)."""
    return [function(c) for c in group]


def _flatten(parts: list[list[R]]) -> list[R]:
    return [r for part in parts for r in part]


def local_samples(jobs: int, time_s: float | None, memory_bytes: int | None) -> SampleMap:
    """Chunks in ``jobs`` forked worker processes, each task within ``time_s`` seconds and
    ``memory_bytes`` of address space (None: no limit); here, in turn, when ``jobs`` < 1,
    when there is one chunk, or where fork is not available."""
    from kcheck.gate import pool

    def run(function: Callable[[T], R], chunks: Sequence[T], /) -> list[R]:
        if jobs < 1 or len(chunks) < 2 or not pool.available():
            return serial(function, chunks)
        tasks = groups(chunks, TASKS_PER_WORKER * jobs)

        def work(group: list[T]) -> list[R]:
            return _run_group(function, group)

        budget = pool.Budget(time_s, memory_bytes)
        parts: list[list[R]] = []
        for out in pool.run_in_workers(tasks, work, jobs=jobs, budget=budget):
            if isinstance(out, pool.BudgetExceeded):
                raise SampleWorkerError(
                    f"a worker solving sample chunks stopped ({out.kind}: {out.detail})"
                )
            parts.append(out)
        return _flatten(parts)

    return run


def dask_samples(client: Any) -> SampleMap:
    """Chunks on a Dask cluster (``client``: a ``distributed.Client``); here, in turn, when
    there is one chunk. The workers must import kcheck (the same version)."""

    def run(function: Callable[[T], R], chunks: Sequence[T], /) -> list[R]:
        if len(chunks) < 2:
            return serial(function, chunks)
        workers = max(1, len(client.scheduler_info().get("workers", {})))
        tasks = groups(chunks, TASKS_PER_WORKER * workers)
        futures = client.map(_run_group, [function] * len(tasks), tasks, pure=False)
        try:
            parts: list[list[R]] = client.gather(futures)
        except Exception as exc:
            raise SampleWorkerError(
                f"a Dask task solving sample chunks failed ({type(exc).__name__}: {exc})"
            ) from exc
        return _flatten(parts)

    return run
