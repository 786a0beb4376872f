"""Where a check's Monte Carlo samples run: the *sample map*, a service the caller hands a
check through its :class:`~kcheck.plugin.Inputs`.

A check cuts its samples into fixed-size chunks (each drawing from its own stream,
:mod:`kcheck.numerics.streams`), describes each chunk by a small picklable value, and asks the
sample map to apply a pure, module-level function to every chunk; it gets the results back in
chunk order. The default runs them here, one after another. ``kcheck check --sample-jobs N``,
``--dask-local N`` and ``--scheduler ADDRESS`` give maps that run the chunks on the executors
of ``kcheck study`` (:mod:`kcheck.gate.samples`). A check never knows which one ran: its
answer is the same on every one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol, TypeVar

__all__ = ["SampleMap", "serial"]

T = TypeVar("T")
R = TypeVar("R")


class SampleMap(Protocol):
    """``map(function, chunks)``: ``[function(c) for c in chunks]``, wherever it runs.
    ``function`` must be a module-level function (it may be sent to another process by
    reference) and each chunk a picklable value; the results come back in chunk order."""

    def __call__(self, function: Callable[[T], R], chunks: Sequence[T], /) -> list[R]: ...


def serial(function: Callable[[T], R], chunks: Sequence[T], /) -> list[R]:
    """Every chunk in this process, in turn (the default sample map)."""
    return [function(c) for c in chunks]
