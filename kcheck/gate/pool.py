"""Worker processes with a time and memory budget per task, results in task order.

A small fork-based pool (POSIX): each worker is forked from the parent, which has already
imported kcheck and the checks, so starting one costs a few milliseconds and no imports. A
worker runs one task at a time; the parent gives each task a deadline and kills a worker
that overruns it, and a worker's address space is capped (``RLIMIT_AS``) so a runaway
allocation raises ``MemoryError`` inside it (or kills it) instead of exhausting the machine.
A worker that dies is replaced and the batch goes on: the task it held gets a budget result.

Why not ``multiprocessing``/``concurrent.futures``: a pool there cannot kill one hung task
(``ProcessPoolExecutor`` breaks entirely when a worker dies), and importing it costs more
than this module does.
"""

from __future__ import annotations

import _thread
import copyreg
import io
import os
import pickle
import select
import signal
import struct
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from types import MappingProxyType
from typing import Any, Generic, TypeVar, cast

from kcheck.records import dataclass

__all__ = [
    "available",
    "Budget",
    "BudgetExceeded",
    "run_in_workers",
    "run_chunks_in_workers",
    "chunks_of",
    "resident_bytes",
    "reap_exited",
    "RECYCLE_RSS_BYTES",
]

T = TypeVar("T")
R = TypeVar("R")

_HEADER = struct.Struct("!Q")
#: Longest single wait for a worker, s (the loop waits again; a budget may be far longer).
MAX_WAIT_S = 3600.0
#: How long workers told to end are given to exit, s: :meth:`_Pool.close` kills one still
#: running then; :func:`reap_exited` waits that long at most, and never kills.
EXIT_GRACE_S = 5.0
#: Address-space budgets from this size on set no limit (2**63 would overflow rlim_t).
MAX_ADDRESS_SPACE = 2**62
#: Most descriptors a worker closes at its exit where it cannot list those it has open (no
#: ``/proc/self/fd``). Without the ``close_range`` system call (Linux < 5.9, glibc < 2.34,
#: older container seccomp profiles) :func:`os.closerange` makes one ``close`` per number:
#: up to 2**31 - 1 took about 195 s per worker exit (a two-job run hung).
MAX_DESCRIPTORS_CLOSED = 65536


def available() -> bool:
    """Whether worker processes can be used here (fork on Linux; elsewhere tasks run in
    the calling process, without budgets)."""
    return hasattr(os, "fork") and sys.platform.startswith("linux")


#: A worker whose resident memory has grown past this after a task is replaced by a fresh
#: fork (bytes): drawing pictures leaves matplotlib's caches and the allocator's free lists
#: behind, about 2 MB a scene (issue 22: 530 MB after 105 scenes). Freshly forked, a worker
#: holds 150-250 MB; the issue bounds a worker at 400 MB. A result never depends on which
#: worker computed it (every worker is the same fork of the parent), so recycling changes
#: no answer. ``benchmarks/bench_picture_memory.py`` measures it (docs/performance.md).
RECYCLE_RSS_BYTES = 300 * 2**20


@dataclass(frozen=True)
class Budget:
    """Per-task limits: wall time in seconds and address space in bytes (None: no limit);
    ``recycle_bytes``: the resident memory past which a worker is replaced after its task
    (None: never)."""

    time_s: float | None = None
    memory_bytes: int | None = None
    recycle_bytes: int | None = None


def _statm_bytes(field: int) -> int | None:
    """Field ``field`` of Linux's ``/proc/self/statm`` (0: mapped size, 1: resident) in
    bytes; None elsewhere."""
    try:
        with open("/proc/self/statm", "rb") as fh:
            return int(fh.read().split()[field]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return None


def resident_bytes() -> int | None:
    """This process's resident memory now (Linux ``/proc/self/statm``; None elsewhere)."""
    return _statm_bytes(1)


@dataclass(frozen=True)
class BudgetExceeded:
    """Why a task has no result: ``kind`` is ``time``, ``memory``, ``died`` (the worker
    ended) or ``crashed`` (the task raised); ``detail`` says what happened."""

    kind: str
    detail: str


def _mappingproxy(items: dict[Any, Any]) -> MappingProxyType[Any, Any]:
    return MappingProxyType(items)


def _reduce_mappingproxy(proxy: MappingProxyType[Any, Any]) -> tuple[Any, ...]:
    return (_mappingproxy, (dict(proxy),))


# Results are frozen dataclasses holding read-only mappings; pickle them as their dicts.
_DISPATCH = copyreg.dispatch_table.copy()
_DISPATCH[MappingProxyType] = _reduce_mappingproxy


def _dumps(obj: object) -> bytes:
    buffer = io.BytesIO()
    pickler = pickle.Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = _DISPATCH
    pickler.dump(obj)
    return buffer.getvalue()


def _write(fd: int, obj: object) -> None:
    data = _dumps(obj)
    view = memoryview(_HEADER.pack(len(data)) + data)
    while view:
        view = view[os.write(fd, view) :]


def _read_exact(fd: int, size: int) -> bytes | None:
    chunks = []
    while size:
        chunk = os.read(fd, min(size, 1 << 20))
        if not chunk:
            return None
        chunks.append(chunk)
        size -= len(chunk)
    return b"".join(chunks)


def _read(fd: int) -> object:
    """One message, or EOFError when the writer has gone."""
    head = _read_exact(fd, _HEADER.size)
    if head is None:
        raise EOFError
    body = _read_exact(fd, _HEADER.unpack(head)[0])
    if body is None:
        raise EOFError
    return pickle.loads(body)


def _descriptor_bound() -> int:
    """One past the highest file descriptor this process has open (Linux lists them in
    ``/proc/self/fd``); elsewhere the open-files limit, at most :data:`MAX_DESCRIPTORS_CLOSED`."""
    try:
        return max(int(name) for name in os.listdir("/proc/self/fd")) + 1
    except (OSError, ValueError, MemoryError):  # no /proc (or none listed): the limit
        pass
    try:
        limit = os.sysconf("SC_OPEN_MAX")
    except (OSError, ValueError):
        limit = -1
    return limit if 0 < limit <= MAX_DESCRIPTORS_CLOSED else MAX_DESCRIPTORS_CLOSED


def _child(
    tasks: int, results: int, work: Callable[[T], R], budget: Budget, first: object = None
) -> None:
    """The worker's loop, starting with ``first`` (its first message, given at the fork;
    None: read from ``tasks`` like the others); never returns."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    if budget.memory_bytes is not None:
        import resource

        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        # The budget is what a task may add to the address space the worker inherits: a
        # parent that has mapped much already (threads' stacks and arenas after a Dask
        # cluster ran in it, say) must not leave a forked worker over budget before its task.
        wanted = (_statm_bytes(0) or 0) + budget.memory_bytes
        limit = wanted if hard == resource.RLIM_INFINITY else min(hard, wanted)
        if limit < MAX_ADDRESS_SPACE:  # a larger budget is no limit (and overflows rlim_t)
            resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    code = 0
    try:
        while True:
            try:
                message, first = first if first is not None else _read(tasks), None
            except EOFError:
                break
            if message is None:
                break
            index, task = cast("tuple[int, T]", message)  # what the parent writes
            try:
                outcome: tuple[str, object] = ("ok", work(task))
            except MemoryError:
                outcome = ("memory", None)
            except Exception as exc:  # a bug in the task: say which
                outcome = ("crashed", f"{type(exc).__name__}: {exc}")
            # Past the threshold, say so with the result and end: the parent forks a fresh one.
            rss = resident_bytes() if budget.recycle_bytes is not None else None
            retire = (
                rss is not None
                and budget.recycle_bytes is not None
                and (rss > budget.recycle_bytes)
            )
            try:
                data = _dumps((index, *outcome, retire))
            except MemoryError:
                data = _dumps((index, "memory", None, retire))
            except Exception as exc:  # a result that cannot be sent: say which
                data = _dumps((index, "crashed", f"{type(exc).__name__}: {exc}", retire))
            view = memoryview(_HEADER.pack(len(data)) + data)
            while view:
                view = view[os.write(results, view) :]
            if retire:
                break
    except BaseException:  # noqa: BLE001 - a worker must exit, never unwind into the parent's code
        code = 70
    finally:
        # Every descriptor closed before the exit, which tears the address space down first
        # (about 1 ms): a reader of the output this worker shares with the parent (a pipe)
        # sees its end when the parent ends, which does not wait for this teardown either.
        os.closerange(0, _descriptor_bound())
        os._exit(code)


@dataclass
class _Worker(Generic[T]):
    """A worker process: its pid, the parent's ends of its two pipes, what it checks now."""

    pid: int
    tasks: int  # parent's write end
    results: int  # parent's read end
    forked: float  # time.monotonic() just before its fork: its first task's clock starts then
    held: tuple[int, ...] | None = None  # the indices of the tasks it checks now
    deadline: float = float("inf")
    ending: bool = False  # told to end after the chunk it holds (its last)


class _Pool(Generic[T, R]):
    def __init__(self, work: Callable[[T], R], budget: Budget) -> None:
        self.work = work
        self.budget = budget
        self.workers: list[_Worker[T]] = []
        if budget.memory_bytes is not None:
            # What each worker sets its budget with: imported here, before the forks (in a
            # forked worker an import costs about three times as much: about 0.5 ms, issue 24).
            import resource  # noqa: F401

    def spawn(self, first: object = None) -> _Worker[T]:
        """A fresh worker; ``first``: its first task's message, which it starts on at once
        (given through the fork: not written, read or unpickled, and not waiting for this
        process's bookkeeping after the fork; issue 24)."""
        task_r, task_w = os.pipe()
        result_r, result_w = os.pipe()
        # Flushed so that the worker does not write this process's buffered output again; the
        # flush waits for a slow reader (``| less``, a full pipe), which is not the task's time.
        sys.stdout.flush()
        sys.stderr.flush()
        forked = time.monotonic()
        pid = os.fork()
        if pid == 0:  # the child: keep only its own two ends
            for w in self.workers:
                for fd in (w.tasks, w.results):
                    os.close(fd)
            os.close(task_w)
            os.close(result_r)
            _child(task_r, result_w, self.work, self.budget, first)
        os.close(task_r)
        os.close(result_w)
        worker: _Worker[T] = _Worker(pid, task_w, result_r, forked)
        self.workers.append(worker)
        return worker

    def retire(self, worker: _Worker[T], kill: bool) -> str:
        """Stop a worker; return how it ended (for messages)."""
        if kill:
            try:
                os.kill(worker.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        for fd in (worker.tasks, worker.results):
            try:
                os.close(fd)
            except OSError:
                pass
        _, status = os.waitpid(worker.pid, 0)
        self.workers.remove(worker)
        if os.WIFSIGNALED(status):
            return f"killed by signal {os.WTERMSIG(status)}"
        return f"exit status {os.WEXITSTATUS(status)}"

    def close(self) -> None:
        for worker in list(self.workers):
            if worker.ending and worker.held is None:
                # Told to end with its last chunk, whose results are read: it exits by itself
                # and writes nothing more. Not waited for here (issue 24: a one-scene run
                # waited about 1 ms for the worker's address space to be torn down); reaped
                # now if it has exited, else by the next pool (reap_exited).
                for fd in (worker.tasks, worker.results):
                    os.close(fd)
                self.workers.remove(worker)
                with _EXITING_LOCK:
                    _EXITING.append(worker.pid)
                continue
            if worker.ending:  # told already; it may be gone (no write to a pipe without reader)
                continue
            try:
                _write(worker.tasks, None)
            except OSError:
                pass
        for worker in list(self.workers):
            os.close(worker.tasks)
            worker.tasks = -1
        deadline = time.monotonic() + EXIT_GRACE_S
        for worker in list(self.workers):
            # The worker's end of its result pipe closes when it exits: wait for that EOF.
            left = max(deadline - time.monotonic(), 0.0)
            ready, _, _ = select.select([worker.results], [], [], left)
            if not ready or os.read(worker.results, 1):
                os.kill(worker.pid, signal.SIGKILL)
            os.waitpid(worker.pid, 0)
            os.close(worker.results)
            self.workers.remove(worker)

    def kill_all(self) -> None:
        for worker in list(self.workers):
            self.retire(worker, kill=True)


#: Workers that were told to end and whose results were all read, not yet reaped (pids);
#: pools in several threads share it, under :data:`_EXITING_LOCK`.
_EXITING: list[int] = []
_EXITING_LOCK = _thread.allocate_lock()


def reap_exited(wait: bool = True) -> None:
    """Reap the workers that ended with their last chunk and were not waited for (each run
    reaps the earlier runs'): those that have exited, or (``wait``) those that exit within
    :data:`EXIT_GRACE_S` (such a worker has only to read its end message and exit). For a
    caller about to read ``RUSAGE_CHILDREN`` (a benchmark) or to leave no zombie behind.

    Never kills: a pid that something else reaped (a caller's ``SIGCHLD`` handler or
    ``os.wait``) may be another of the caller's children by now. One still running is left
    for the next call."""
    with _EXITING_LOCK:  # these pids are this call's now: another thread's call skips them
        pids = _EXITING[:]
        _EXITING.clear()
    deadline = time.monotonic() + (EXIT_GRACE_S if wait else 0.0)
    running = []
    for pid in pids:
        try:
            while os.waitpid(pid, os.WNOHANG) == (0, 0):
                if time.monotonic() >= deadline:
                    running.append(pid)
                    break
                time.sleep(0.001)
        except ChildProcessError:
            pass  # reaped by someone else (a caller's os.wait)
    if running:
        with _EXITING_LOCK:
            _EXITING.extend(running)


#: How often ``tick`` is called while the parent waits for workers, s.
TICK_S = 0.25


def run_in_workers(
    tasks: Sequence[T],
    work: Callable[[T], R],
    *,
    jobs: int,
    budget: Budget,
    tick: Callable[[], None] | None = None,
) -> Iterator[R | BudgetExceeded]:
    """Run ``work`` on every task in up to ``jobs`` worker processes; yield each result (or
    why it has none) in the order of ``tasks``, as soon as it and all before it are done.

    ``work`` must not raise (except ``MemoryError``, which becomes a budget result).
    ``tick`` is called about every :data:`TICK_S` while the parent waits (a progress line's
    clock): the parent runs no thread of its own, since workers are forked from it, and a
    fork while another thread runs may deadlock the child (Python 3.12 warns of it).
    """

    def one(chunk: Sequence[T]) -> list[R]:
        return [work(chunk[0])]

    return run_chunks_in_workers(tasks, one, jobs=jobs, budget=budget, chunk=1, tick=tick)


def chunks_of(count: int, size: int) -> list[tuple[int, ...]]:
    """Indices ``0 .. count - 1`` in consecutive chunks of at most ``size``."""
    size = max(1, size)
    return [tuple(range(s, min(s + size, count))) for s in range(0, count, size)]


def run_chunks_in_workers(
    tasks: Sequence[T],
    work: Callable[[Sequence[T]], Sequence[R]],
    *,
    jobs: int,
    budget: Budget,
    chunk: int,
    tick: Callable[[], None] | None = None,
) -> Iterator[R | BudgetExceeded]:
    """:func:`run_in_workers` with each worker given up to ``chunk`` consecutive tasks at a
    time: ``work`` gets them together and returns one result per task, in their order.

    Each task's outcome is still its own. A chunk of several tasks has one task's budget
    (``budget.time_s`` for all of them together, the memory budget while it runs); a chunk
    that runs out of it, whose worker dies, or whose ``work`` raises or answers with the
    wrong number of results is run again task by task, each in a chunk of its own with the
    whole budget, before any later chunk. So a hung or huge task gets its budget result
    alone, and the others of its chunk get theirs as if they had never been chunked. After a
    chunk ran out of time the remaining tasks go one at a time (tasks that slow gain nothing
    from chunks, and each such chunk would cost its budget twice).
    """
    reap_exited(wait=True)  # the last run's ended workers: gone long since
    pool: _Pool[Sequence[T], Sequence[R]] = _Pool(work, budget)
    pending: list[tuple[int, ...]] = chunks_of(len(tasks), chunk)
    pending.reverse()  # popped from the end
    done: dict[int, R | BudgetExceeded] = {}
    next_out = 0

    def assign(worker: _Worker[Sequence[T]] | None) -> None:
        """Give the next pending chunk to ``worker``, or (None) to a fresh worker forked
        with it."""
        if not pending:
            if worker is not None:
                worker.held = None
            return
        if worker is not None and worker.ending:  # it ends after its last chunk: a fresh
            worker.held = None  # one takes the rest
            pool.retire(worker, kill=False)
            worker = None
        indices = pending[-1]
        message = (indices[0], [tasks[i] for i in indices])
        if worker is None:
            worker = pool.spawn(message)
            started = worker.forked  # not before: spawn may wait for this process's output
        else:
            started = time.monotonic()
            try:
                _write(worker.tasks, message)
            except OSError:  # the worker died while idle: replace it, the chunk waits
                worker.held = None
                pool.retire(worker, kill=True)
                assign(None)
                return
        pending.pop()
        worker.held = indices
        worker.deadline = float("inf") if budget.time_s is None else started + budget.time_s
        if not pending:
            # The last chunk: the worker is told to end with it, so that it ends while this
            # process reads and reports its results instead of after (issue 24: a one-scene
            # run waited for its worker to wake and exit). A chunk that fails and is split
            # goes to fresh workers (above).
            try:
                _write(worker.tasks, None)
                worker.ending = True
            except OSError:
                pass  # it died: its chunk's result says so

    def fail(indices: tuple[int, ...], outcome: BudgetExceeded) -> None:
        """A chunk without results: one task's outcome, or its tasks again one by one."""
        if len(indices) == 1:
            done[indices[0]] = outcome
        else:
            pending.extend((i,) for i in reversed(indices))

    def replace(worker: _Worker[Sequence[T]], outcome: BudgetExceeded) -> None:
        indices = worker.held
        assert indices is not None  # a busy worker
        if outcome.kind == "time" and len(indices) > 1:
            # Tasks slow enough to overrun one task's budget together: the rest of the batch
            # one task at a time, so that such a chunk is wasted once, not once a chunk.
            pending[:] = [(i,) for chunk in pending for i in reversed(chunk)]
        fail(indices, outcome)
        worker.held = None
        pool.retire(worker, kill=True)
        if pending:
            assign(None)

    try:
        for _ in range(max(1, min(jobs, len(pending)))):
            assign(None)
        while next_out < len(tasks):
            while next_out in done:
                yield done.pop(next_out)
                next_out += 1
            if next_out >= len(tasks):
                break
            busy = [w for w in pool.workers if w.held is not None]
            if not busy:  # tasks split after the last worker retired: start one
                assert pending, "a task neither done, held nor pending"
                assign(None)
                continue
            # At most an hour at a time: a deadline of 1e300 s overflows select's time_t.
            wait = min(min(w.deadline for w in busy) - time.monotonic(), MAX_WAIT_S)
            if tick is not None:
                tick()
                wait = min(wait, TICK_S)
            ready, _, _ = select.select([w.results for w in busy], [], [], max(wait, 0))
            for worker in [w for w in busy if w.results in ready]:
                indices = worker.held
                assert indices is not None  # a busy worker
                try:
                    # what _child writes: (first index, status, work's results or why it has
                    # none, whether the worker ends after it: past its resident-memory
                    # threshold)
                    _, status, value, retiring = cast(
                        "tuple[int, str, object, bool]", _read(worker.results)
                    )
                except (EOFError, pickle.UnpicklingError, OSError):
                    how = pool.retire(worker, kill=True)
                    fail(
                        indices,
                        BudgetExceeded("died", f"the worker process checking it ended ({how})"),
                    )
                    if pending:
                        assign(None)
                    continue
                if status == "memory":
                    replace(worker, BudgetExceeded("memory", "it ran out of its memory budget"))
                    continue
                results = cast("Sequence[R]", value) if status == "ok" else None
                if results is None or len(results) != len(indices):
                    fail(indices, BudgetExceeded("crashed", str(value)))
                else:
                    done.update(zip(indices, results, strict=True))
                if retiring:  # it ends by itself: wait for it, fork a fresh one
                    worker.held = None
                    pool.retire(worker, kill=False)
                    if pending:
                        assign(None)
                    continue
                assign(worker)
            now = time.monotonic()
            for worker in [w for w in pool.workers if w.held is not None and w.deadline <= now]:
                replace(worker, BudgetExceeded("time", "it ran past its time budget"))
            # Chunks split above are first in line: give them to idle workers now.
            for worker in [w for w in pool.workers if w.held is None]:
                if not pending:
                    break
                assign(worker)
        pool.close()
        reap_exited(wait=False)
    finally:
        pool.kill_all()
