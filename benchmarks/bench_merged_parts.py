"""Timing of ``kcheck contacts``' merged-parts finding (a body file of several closed
bodies: each named, and whether it looks like part of the base):
``python benchmarks/bench_merged_parts.py``.

The assembly is ``bench_contacts.py``'s (491,520 faces per part; the body is 5 closed
bodies: three balls, a plate and a block). Paired, interleaved in the same run, against the
previous implementation (``benchmarks/merged_pieces_before.py``, a frozen copy: trimesh's
``split`` into submeshes, then the full contact regions, with fits, of each touching piece
against the whole rest of the body); both must give the same answer.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import merged_pieces_before  # noqa: E402
from bench_contacts import assembly, paired  # noqa: E402

from kcheck.body.contact_regions import merged_pieces  # noqa: E402
from kcheck.numerics.thresholds import CONTACT_GAP_RTOL  # noqa: E402


def main() -> None:
    base, body = assembly()
    size = float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    gap = CONTACT_GAP_RTOL * size

    def now(base, body):
        return merged_pieces(body, base, gap)

    def before(base, body):
        return merged_pieces_before.merged_pieces(body, base, gap)

    a, b = now(base, body), before(base, body)
    same = len(a) == len(b) and all(
        x[1] == y[1]
        and np.isclose(x[0].volume, y[0].volume, rtol=1e-12)
        and np.array_equal(x[0].bounds, y[0].bounds)
        for x, y in zip(a, b, strict=True)
    )
    print(f"body {len(body.faces):,} faces, {len(a)} closed bodies; same answer as before: {same}")
    t = paired({"now": now, "before": before}, base, body)
    for name, what in (("now", "merged-parts finding"), ("before", "previous implementation")):
        wall, cpu = t[name]
        ratio = f", {t[name][1] / t['now'][1]:.2f}x the CPU time" if name != "now" else ""
        print(f"{what}: {wall:.2f} s wall, {cpu:.2f} s CPU (medians of 3{ratio})")
    print(f"load average after: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
