"""Random streams of fixed-size chunks: a Monte Carlo of ``n`` samples is cut into chunks of a
fixed size, and chunk ``i`` draws from its own generator, seeded by the run's seed and ``i``
(numpy's ``SeedSequence`` spawn key: the ``i``-th child of ``SeedSequence(seed)``). A sample's
numbers then depend on the seed and its chunk alone — not on which process drew them, nor on
how many processes shared the chunks — so a run gives the same answer on any executor.
"""

from __future__ import annotations

import numpy as np

__all__ = ["chunk_bounds", "chunk_generator"]


def chunk_bounds(count: int, size: int) -> list[tuple[int, int]]:
    """``[start, stop)`` of each chunk of ``count`` samples cut into chunks of ``size`` (the
    last one shorter)."""
    return [(start, min(start + size, count)) for start in range(0, count, size)]


def chunk_generator(seed: int, index: int) -> np.random.Generator:
    """The generator of chunk ``index`` of a run seeded with ``seed``: the same stream as
    ``np.random.default_rng(np.random.SeedSequence(seed).spawn(index + 1)[index])``."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))
