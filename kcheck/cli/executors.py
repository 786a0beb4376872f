"""Where the work runs, on the command line: the Dask client of ``kcheck study`` and the
sample executors of ``kcheck check`` (the Monte Carlo checks' chunks of samples on local
worker processes or Dask; docs/checks.md, "Samples on several processes or a cluster")."""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterator
from typing import Any

from kcheck.errors import UsageError

__all__ = ["add_sample_options", "dask_client", "close_client", "sample_map"]

DASK_MISSING = "Dask executors need distributed: pip install 'kcheck[dask]'"


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of workers, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected 1 or more workers, got {value}")
    return value


def add_sample_options(parser: argparse.ArgumentParser) -> None:
    """``--sample-jobs N``, ``--dask-local N``, ``--scheduler ADDRESS`` (one of them)."""
    group = parser.add_argument_group(
        "Monte Carlo samples (tolerances, pose-error)",
        "Run the sample chunks of the Monte Carlo checks on the executors of kcheck study; "
        "the scenes are then checked in this process, one after another. The results are "
        "the same on every executor.",
    )
    where = group.add_mutually_exclusive_group()
    where.add_argument(
        "--sample-jobs", type=_count, metavar="N", help="local worker processes for the samples"
    )
    where.add_argument(
        "--dask-local",
        type=_count,
        metavar="N",
        help="start a Dask LocalCluster of N workers for the samples (needs kcheck[dask])",
    )
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="an existing Dask scheduler for the samples (tcp://HOST:8786; its workers must "
        "have kcheck installed)",
    )


def dask_client(dask_local: int | None, scheduler: str | None) -> Any:
    """A ``distributed.Client`` of an existing scheduler or of a new ``LocalCluster`` (one
    thread per worker process); None when distributed is not installed."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        return None
    if scheduler is not None:
        return Client(scheduler)
    cluster = LocalCluster(
        n_workers=dask_local, threads_per_worker=1, processes=True, dashboard_address=None
    )
    return Client(cluster)


def close_client(client: Any) -> None:
    """Close a client and the LocalCluster it started (an existing scheduler stays up)."""
    cluster = getattr(client, "cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()


@contextlib.contextmanager
def sample_map(
    args: argparse.Namespace, time_s: float | None, memory_bytes: int | None
) -> Iterator[Any]:
    """The sample map the options ask for (None: none asked for), and its cluster closed at
    the end. Raises UsageError when Dask is asked for and not installed."""
    jobs = getattr(args, "sample_jobs", None)
    local = getattr(args, "dask_local", None)
    scheduler = getattr(args, "scheduler", None)
    if jobs is not None:
        from kcheck.gate.samples import local_samples

        yield local_samples(jobs, time_s, memory_bytes)
        return
    if local is None and scheduler is None:
        yield None
        return
    client = dask_client(local, scheduler)
    if client is None:
        raise UsageError(DASK_MISSING)
    from kcheck.gate.samples import dask_samples

    try:
        yield dask_samples(client)
    finally:
        close_client(client)
