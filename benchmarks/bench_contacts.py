"""Timing of ``kcheck contacts``' core (finding the contact regions of two meshes, fitting
their patches, recognising the elements): ``python benchmarks/bench_contacts.py``.

The assembly is the three-vee coupling of ``tests/contact_assemblies.py`` refined to 491,520
faces per part (the issue's target: 500,000 faces per part in 2 s), with a plate under the
vees and a block on the body's plate that come nowhere near the contacts (as a real base and
body have). Paired, interleaved in the same run, against the previous implementation
(``benchmarks/contact_regions_before.py``, a frozen copy: every sample point measured
against the triangles of its 8 nearest samples) and against scipy's KD-tree nearest-vertex
query of every body vertex among the base's (the cheapest, inexact way to see where two
meshes come close). Reading the files is not timed (``kcheck mass`` benchmarks cover it).
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import contact_regions_before  # noqa: E402
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
            base.append(refined(flat(c, n), 6))
        body.append(trimesh.creation.icosphere(subdivisions=6, radius=R).apply_translation(c))
    under = trimesh.creation.box(extents=[130, 130, 6]).apply_translation([0, 0, -30])
    base.append(refined(under, 7))
    plate = trimesh.creation.box(extents=[130, 130, 6]).apply_translation([0, 0, 9])
    block = trimesh.creation.box(extents=[40, 40, 20]).apply_translation([0, 0, 22])
    body += [refined(plate, 7), refined(block, 6)]
    return trimesh.util.concatenate(base), trimesh.util.concatenate(body)


def fresh(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """The mesh without trimesh's caches (face adjacency, normals), as a file just read."""
    return trimesh.Trimesh(mesh.vertices.copy(), mesh.faces.copy(), process=False)


def paired(fns: dict, base: trimesh.Trimesh, body: trimesh.Trimesh, repeats: int = 3) -> dict:
    """Median wall and CPU time of each function on fresh copies of the meshes (nothing
    cached between calls), the functions interleaved in each round (a shared machine's load
    falls on all of them alike)."""
    times: dict = {name: [] for name in fns}
    cpu: dict = {name: [] for name in fns}
    for _ in range(repeats):
        for name, fn in fns.items():
            a, b = fresh(base), fresh(body)
            start, start_cpu = time.perf_counter(), time.process_time()
            fn(a, b)
            times[name].append(time.perf_counter() - start)
            cpu[name].append(time.process_time() - start_cpu)
    return {name: (statistics.median(times[name]), statistics.median(cpu[name])) for name in fns}


def main() -> None:
    base, body = assembly()
    size = float(np.linalg.norm(np.ptp(np.vstack([base.bounds, body.bounds]), axis=0)))
    gap = CONTACT_GAP_RTOL * size

    def ours(base, body):
        regions, _ = contact_regions(base, body, gap)
        return recognise(regions, gap)

    def before(base, body):
        regions, _ = contact_regions_before.contact_regions(base, body, gap)
        return recognise(regions, gap)

    def baseline(base, body):
        return cKDTree(base.vertices).query(body.vertices, distance_upper_bound=gap)

    found, old = ours(fresh(base), fresh(body)), before(fresh(base), fresh(body))
    print(f"base {len(base.faces):,} faces, body {len(body.faces):,} faces, gap {gap:.3g} mm")
    print(f"found: {[e.kind for e in found.elements]}, {found.contact_count} contacts")
    worst = max(
        float(np.linalg.norm(a.point - b.point))
        for e, f in zip(found.elements, old.elements, strict=True)
        for a, b in zip(e.contacts, f.contacts, strict=True)
    )
    print(f"largest difference of a contact point from the previous implementation: {worst:.3g} mm")
    t = paired({"now": ours, "before": before, "vertex": baseline}, base, body)
    for name, what in (
        ("now", "kcheck contacts core"),
        ("before", "previous implementation"),
        ("vertex", "baseline, KD-tree nearest vertex"),
    ):
        wall, cpu = t[name]
        ratio = f", {t[name][0] / t['now'][0]:.2f}x the wall time" if name != "now" else ""
        print(f"{what}: {wall:.2f} s wall, {cpu:.2f} s CPU (medians of 3{ratio})")
    print(f"load average after: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
