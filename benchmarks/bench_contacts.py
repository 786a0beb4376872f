"""Timing of ``kcheck contacts``' core (finding the contact regions of two meshes, fitting
their patches, recognising the elements): ``python benchmarks/bench_contacts.py``.

The assembly is the three-vee coupling of ``tests/contact_assemblies.py`` refined to about
500,000 faces per part (the issue's target: 2 s). Paired against a baseline on the same
meshes: scipy's KD-tree nearest-vertex query of every body vertex against the base's
vertices (the cheapest, inexact way to see where two meshes come close; trimesh's own
``proximity.closest_point`` needs the ``rtree`` package, not installed here). Reading the
files is not timed (``kcheck mass`` benchmarks cover it).
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from contact_assemblies import THREE_VEE_CENTERS, R, flat, unit, vee_normals  # noqa: E402

from kcheck.body.contact_regions import contact_regions  # noqa: E402
from kcheck.body.coupling_elements import recognise  # noqa: E402
from kcheck.numerics.thresholds import CONTACT_GAP_RTOL  # noqa: E402


def refined(mesh: trimesh.Trimesh, times: int) -> trimesh.Trimesh:
    for _ in range(times):
        mesh = mesh.subdivide()
    return mesh


def assembly() -> tuple[trimesh.Trimesh, trimesh.Trimesh]:
    base, body = [], []
    for c in THREE_VEE_CENTERS:
        for n in vee_normals(unit([c[0], c[1], 0]), [0, 0, 1], 45.0):
            base.append(refined(flat(c, n), 5))
        body.append(trimesh.creation.icosphere(subdivisions=6, radius=R).apply_translation(c))
    plate = trimesh.creation.box(extents=[130, 130, 6]).apply_translation([0, 0, 9])
    body.append(refined(plate, 7))
    return trimesh.util.concatenate(base), trimesh.util.concatenate(body)


def median_time(fn, repeats: int = 3) -> float:
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    base, body = assembly()
    size = float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    gap = CONTACT_GAP_RTOL * size

    def ours():
        regions, _ = contact_regions(base, body, gap)
        return recognise(regions, gap)

    def baseline():
        return cKDTree(base.vertices).query(body.vertices, distance_upper_bound=gap)

    found = ours()
    print(f"base {len(base.faces):,} faces, body {len(body.faces):,} faces, gap {gap:.3g} mm")
    print(f"found: {[e.kind for e in found.elements]}, {found.contact_count} contacts")
    print(f"kcheck contacts core: {median_time(ours):.2f} s (median of 3)")
    print(f"baseline, KD-tree nearest vertex: {median_time(baseline):.2f} s (median of 3)")


if __name__ == "__main__":
    main()
