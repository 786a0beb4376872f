"""The sphere map's pieces for a chunk of variants at once give what each gets alone, bit for
bit: ``caps.regions`` (cap sets stacked by their number of caps and pieces) against
``caps.region`` one set at a time, and ``deepest._best`` (accurate margins only near the
largest rough one) against the argmax of every point's accurate margin."""

from __future__ import annotations

import numpy as np

from kcheck.mechanics.caps import margin_in, region, regions
from kcheck.mechanics.deepest import _best
from kcheck.mechanics.sphere import fibonacci_sphere


def _conditions(count: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Random cap sets: 0-13 conditions, small and large caps, some holding nowhere or
    everywhere, some sets repeated (duplicate caps)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        k = int(rng.integers(0, 14))
        c = rng.normal(size=(k, 3))
        a = rng.normal(size=k) * rng.uniform(0.0, 1.2) * np.linalg.norm(c, axis=1)
        if rng.random() < 0.4:
            a = -np.abs(a)
        if k > 2 and rng.random() < 0.2:
            a[1], c[1] = a[0], c[0]
        out.append((a, c))
    return out


def test_stacked_regions_are_each_alone() -> None:
    conditions = _conditions(600, 4)
    together = regions(conditions)
    alone = [region(a, c) for a, c in conditions]
    kinds = {"empty": 0, "full": 0, "bounded": 0}
    for x, y in zip(together, alone, strict=True):
        assert (x.area, x.perimeter, x.empty, x.full) == (y.area, y.perimeter, y.empty, y.full)
        assert np.array_equal(x.bounding, y.bounding)
        assert np.array_equal(x.caps.source, y.caps.source)
        assert (x.lengths is None) == (y.lengths is None)
        assert x.lengths is None or np.array_equal(x.lengths, y.lengths)
        kinds["empty" if x.empty else "full" if x.full else "bounded"] += 1
    assert min(kinds.values()) > 20  # every kind of region is in the batch


def test_best_point_is_the_accurate_argmax() -> None:
    grid = fibonacci_sphere(400)
    checked = 0
    for a, c in _conditions(300, 9):
        caps = region(a, c).caps
        if not len(caps.radius):
            continue
        margins = margin_in(caps, grid)
        index, margin = _best(caps, grid)
        assert index == int(np.argmax(margins)) and margin == float(margins.max())
        checked += 1
    assert checked > 100
