"""Cost of the issue 26 compliant-seat tests: ``python benchmarks/bench_compliant_hold.py``.

CPU time (``time.process_time``, median of 5 rounds of 200 calls) of
:func:`tests.plugins.compliant_hold.compliant_hold` (one release, three tangential/normal
ratios at once) and :func:`~tests.plugins.compliant_hold.slip_hold` (one ratio, followed
through local slip), on 20 random spatial seats (6 contacts, one retracted), paired in the same
rounds with a plain 6 x 6 ``numpy.linalg.solve`` as the yardstick of this machine's numpy
call cost. Neither function is on a check's path (docs/validation.md, "Compliant contacts").
Run from the project's root.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from kcheck.mechanics.kinematics import wrenches  # noqa: E402
from tests.plugins.compliant_hold import compliant_hold, slip_hold  # noqa: E402


def _seats(count: int) -> list[tuple[np.ndarray, ...]]:
    rng = np.random.default_rng(1)
    seats = []
    while len(seats) < count:
        points = rng.uniform(-1, 1, (6, 3))
        normals = -points + rng.normal(0, 0.5, (6, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        rows = wrenches(points, normals)
        if np.linalg.cond(rows) > 1e4:
            continue
        seated = rng.uniform(1, 10, 6)  # the seat pressing every contact (its load: -N @ rows)
        seats.append((points, normals, seated, rows))
    return seats


def main() -> None:
    seats = _seats(20)
    mu, k = np.full(6, 0.3), np.ones(6)
    calls = {
        "numpy.linalg.solve 6 x 6": lambda s: np.linalg.solve(s[3].T, s[2]),
        "compliant_hold, 3 ratios": lambda s: compliant_hold(
            s[0], s[1], mu, s[2], 0, k, [2 / 3, 0.8, 1.0]
        ),
        "slip_hold, 1 ratio": lambda s: slip_hold(s[0], s[1], mu, s[2], 0, k, 2 / 3),
    }
    times: dict[str, list[float]] = {name: [] for name in calls}
    for _ in range(5):
        for name, call in calls.items():  # interleaved: each round times every call
            start = time.process_time()
            for _ in range(10):
                for seat in seats:
                    call(seat)
            times[name].append((time.process_time() - start) / (10 * len(seats)))
    base = statistics.median(times["numpy.linalg.solve 6 x 6"])
    for name, values in times.items():
        median = statistics.median(values)
        print(f"{name:28s} {median * 1e6:8.1f} us  ({median / base:6.1f} x the solve)")


if __name__ == "__main__":
    main()
